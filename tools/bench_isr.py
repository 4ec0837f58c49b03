#!/usr/bin/env python3
"""Estimated cost of the two ISRs of every period on the F2812 (C28x, 150 MHz),
per identification state, the mean and the WORST SINGLE ISR, against the
budget of 10 000 cycles per 15 kHz period.  A cost model that errs high.

The two ISRs (firmware/isr.c): the control ISR (ADCINT; drive_isr: the fast
path, every period, not interruptible) and the slow ISR it forces (INT14;
drive_slow_isr: the slot's slow task, interruptible by the next control ISR).
Each is an ISR of its own (entry/exit each); the worst single ISR is the
larger of the two worsts, and the worst PERIOD (control + slow ISR of the
same period, which must end before the next control ISR ends) is reported
beside it.

Method (an estimate from an instrumented host build, not a measurement on a
board; BENCHMARKS.md section b states every assumption):
 1. isr_cost (host_sim/api/isr_cost.c, IQ_MATH build with gcov) runs the
    configured motor's identification closed loop through every state; for
    each class (state, slot of the multi-rate schedule) it samples single
    ISRs - the first two and last two of the class, K spread evenly, and
    every ISR that runs a basic block no earlier ISR of its class ran (a
    "coverage" sample: a test's verdict, a calibration's end, a state's
    entry), so that every block any ISR of a class runs is in one of the
    class's samples - and dumps that ISR's gcov line counts alone, with its
    IQmath calls.  A block that ran in an ISR but in none of its class's
    samples (none, unless the run's two passes differ) is listed with its
    line priced as run once and added to that class's worst ISR
    ("unsampled_lines" of --json).
 2. Each sampled ISR is costed line by line: every executed line of src/
    and include/, per run, its IQmath calls at TI's published C28x cycle
    count (IQmath read-me, call included; ASSUMED_CYCLES for those TI does
    not list) and its other C operations by OTHER_COST (/ and % by anything
    but a constant power of two: a call of the run-time library, from
    flash); the IQmath calls so
    attributed must cover every call the counted library saw (checked: more
    only where both arms of a ?: are costed); a line's executions are those
    of the basic block it is in (gcov -a), a statement over several lines is
    costed once, on its first; a line of the ISR path's FLASH set (the
    functions the flash image runs from flash: the `#ifdef
    ISR_FLASH_SET_IN_RAM` blocks of linker/F2812_isr_*.cmd) at FLASH_FACTOR
    times that, and FLASH_ENTRY per entry into such a function; plus
    the fixed part
    that the host build does not run: the interrupt entry and exit, and the
    firmware's own ISR code and HAL (firmware/isr.c, hal_*_f2812.c,
    datalog.c), costed statically with every line counted once (both arms of
    every branch) and every peripheral register access at its wait states.
 3. Per class, the WORST ISR is costed with every line at the largest count
    any sampled ISR of the class ran it: a sum of maxima, never below the
    largest single sample.  A class is a state and a slot; CALIBRATE's
    phases are classes apart (the offsets' calibration, the sensor test, the
    bridge's curve test: the sequence's outputs choose one for a whole
    control ISR, so their code never runs in one ISR together), each with its
    own samples of every block it runs; CALIBRATE's worst is its worst
    phase's.
    Per state: mean = the mean over the uniform samples of its classes (each
    slot is 1/S of the ISRs), worst = the worst of its classes.  Reported
    beside it, not the estimate: the same with each coverage sample's lines
    added to the schedule's samples on its own (one-off events not stacked in
    one ISR), and the costliest single sampled ISR.

A missing coverage build (no isr_cost, no .gcno, no gcov) is an error.
Usage: bench_isr.py [--build DIR] [--config INI ...] [--uniform K] [--hot N] [--json]
"""
import argparse
import concurrent.futures as cf
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BUDGET = 10000          # 150 MHz / 15 kHz
GOAL = 3000             # 30 % of the period: 70 % left for margin, background, compiler
# IDLE: the ISRs before the start command is taken (the first one enters CALIBRATE)
STATES = ("IDLE", "CALIBRATE", "MAGNETIZE", "ACCELERATE", "SETTLE", "RUN", "REFINE", "INJECT")
DEFAULT_CONFIGS = (("paper", "host_sim/config/paper_motor.ini"),
                   ("adaptive", "host_sim/config/paper_motor_wrong_nameplate.ini"),
                   ("standstill", "host_sim/config/paper_motor_standstill.ini"))

# TI IQmath V1.4c read-me, C28x cycles including the call
TI_CYCLES = {"_IQmpy": 5, "_IQrmpy": 22, "_IQrsmpy": 30, "_IQdiv": 73, "_IQsqrt": 70,
             "_IQisqrt": 74, "_IQsin": 49, "_IQcos": 47, "_IQsinPU": 43, "_IQcosPU": 41,
             "_IQatan2": 118, "_IQmag": 96, "_IQsat": 7, "_IQtoF": 23}
# not in that list: the "Benchmark" header of each function's source in TI's
# IQmath library (C2000Ware, libraries/math/IQmath/c28/source/coff/IQN<op>.asm:
# from 0-wait SARAM, LCR/LRETR included, the worst case it states); the
# table reads that the boot ROM's wait state adds are in ROM_TABLE_READS.
TI_ASM_CYCLES = {
    "_IQatan2PU": 121,      # IQNatan2PU.asm: 121 (16 <= Q <= 29, tables in SARAM), 127 in ROM
    "_IQmpyI32int": 28,     # IQNmpyI32int.asm: 28, worst case
    "_IQmpyI32frac": 34,    # IQNmpyI32frac.asm: 34, worst case
    "_IQint": 15,           # IQNint.asm
    "_IQfrac": 18,          # IQNfrac.asm
}
# neither: what TI's IQmathLib.h makes of them (our assumption)
ASSUMED_CYCLES = {
    "_IQmpyIQX": 5,      # the same __IQxmpy intrinsic as _IQmpy, another shift
    "_IQmpyI32": 4,      # (long) A * B: one IMPYL 32x32 plus moves
    "_IQatan": 118,      # IQmathLib.h: _IQatan2(A, _IQ(1.0)); IQNatan2.asm states 115 in ROM
    "_IQabs": 3,         # inline ABS on ACC: load, ABS, store
    "_IQdiv2": 2,        # TI's macro (A)>>1: an SFR ACC,1 on the loaded value, as op32
    "_IQtoIQN": 2, "_IQtoQN": 2,         # inline shift of ACC
    "iq_norm32": 3,      # the __norm32 intrinsic: CSB ACC (1) + moving the count out (2)
}
# the table look-ups of these read IQmathTables in the boot ROM (1 wait
# state, SPRS174): 2 reads each, +1 cycle per read; _IQatan2PU: its source's
# two benchmarks differ by 6 (127 with the tables in ROM, 121 in SARAM)
ROM_TABLE_READS = {"_IQsinPU": 2, "_IQcosPU": 2, "_IQsin": 2, "_IQcos": 2, "_IQatan2": 2,
                   "_IQatan2PU": 6, "_IQatan": 2, "_IQisqrt": 1, "_IQsqrt": 1, "_IQdiv": 1,
                   "_IQmag": 2}
ROM_WAIT = 1

# every other operation, per occurrence on an executed source line; each
# rounded up from the C28x instruction timing (SPRU430)
OTHER_COST = {
    "op32": 2,     # 32-bit add/sub/compare/logic/shift/assign: the ALU op + one MOVL
    "op64": 8,     # 64-bit: no 64-bit ALU, register-pair sequences
    "branch": 7,   # if/while/for/?:/&&/||/case: a conditional branch TAKEN (7; not taken: 4),
                   # every time: a loop test pays it per iteration (the loop-back branch)
    "call": 16,    # call of a non-inline function: LCR 4 + LRETR 4 + argument moves 2 +
                   # the callee's frame and register saves 6
    "field": 1,    # a struct member beyond the 3-bit *+XARn[0..7] offset: one more
                   # instruction for the address, per access path (d->cur.ia is one
                   # static offset from d; every path counted, small offsets too: errs high)
    "div_pow2": 6,  # / or % by a constant power of two: a shift, with the sign's
                    # correction for a signed operand (load, test, add, shift)
    "div_rts": None,    # any other / or %: a call of the run-time library, below
    "div_rts64": None,  # ... with a 64-bit operand
}
# The C28x has no divide instruction (the F2812's CPU has no FASTINTDIV): cl2000
# calls the run-time library (rts2800_ml.lib) for / and %.  TI measured the C
# operator on the C28x without that hardware (SPRACN6, "Fast Integer Division",
# section 4 "Cycle Count", Table 4): 52-56 cycles for 16-bit operands, 37-64 for
# 32-bit ones (i32/i16 Euclidean and modulo 64, the worst), 78-2 635 for 64-bit
# ones.  The library is in .text, i.e. in flash in the flash image
# (linker/F2812_flash.cmd), so each call costs the flash's price as the flash
# set's lines do: FLASH_FACTOR times, plus FLASH_ENTRY.
RTS_DIV_CYCLES = 64
RTS_DIV64_CYCLES = 2635
# fixed per ISR: PIE vector fetch and CPU interrupt latency with the automatic
# context save (14 cycles, SPRU430), the compiler's interrupt prologue and
# epilogue (the registers the hardware does not save: XAR2-XAR7, XT, RPC,
# AR1H:AR0H, ~2 x 12), IRET (8): 14 + 24 + 24 + 8 = 70, rounded up
ISR_ENTRY_EXIT = 80
# peripheral frame 1/2 registers (ADC, EV, PIE, SCI): 2 wait states on a
# read, 0 on a write (SPRS174, "Wait states"); every access charged as a read
PERIPH_WAIT = 2

# the ISR path's FLASH set runs from flash in the flash image (tools/bench_size.py
# FLASH_ROOTS: only in CALIBRATE, on a state change, after a fault, or the
# sequence's step once per slow period): the
# functions named in the `#ifdef ISR_FLASH_SET_IN_RAM` blocks of the generated
# linker includes.  Their lines cost FLASH_FACTOR times as much: TI measured
# code from the F28x flash (5 wait states, pipeline on, 150 MHz) at 62 % of
# the speed from SARAM (PID benchmark, TI's "Concerto control subsystem"
# training, F05 flash as the F2812's): 1 / 0.62 = 1.61, rounded up to 2.
# Each entry costs FLASH_ENTRY more: the prefetch starts cold, two random
# 64-bit reads of 1 + RANDWAIT 5 cycles (firmware/flash.c's wait states).
FLASH_FACTOR = 2.0
FLASH_ENTRY = 12
OTHER_COST["div_rts"] = RTS_DIV_CYCLES * FLASH_FACTOR + FLASH_ENTRY
OTHER_COST["div_rts64"] = RTS_DIV64_CYCLES * FLASH_FACTOR + FLASH_ENTRY
FLASH_SET_INCLUDES = ("linker/F2812_isr_path.cmd", "linker/F2812_isr_slow.cmd")
FLASH_SET_BLOCK = re.compile(r"^#ifdef ISR_FLASH_SET_IN_RAM$(.*?)^#endif$", re.S | re.M)

# the firmware's ISR path the host build does not run: (file, function)
FIRMWARE_ISR = (("firmware/isr.c", "isr_control"), ("firmware/isr.c", "isr_elapsed"),
                ("firmware/hal_adc_f2812.c", "hal_adc_read"),
                ("firmware/hal_pwm_f2812.c", "hal_pwm_write"),
                ("firmware/hal_pwm_f2812.c", "hal_pwm_enable"),
                ("firmware/hal_pwm_f2812.c", "hal_pwm_tripped"),
                ("firmware/hal_pwm_f2812.c", "hal_isr_overrun"),
                ("firmware/hal_pwm_f2812.c", "pwm_f2812_period"),
                ("firmware/hal_pwm_f2812.c", "hal_slow_isr_request"),
                ("firmware/hal_qep_f2812.c", "hal_qep_read_count"))
# the slow ISR's firmware (isr_slow: interrupts re-enabled with IER = INT1,
# the slow task, the log's test, DINT, its end time)
FIRMWARE_SLOW_ISR = (("firmware/isr.c", "isr_slow"), ("firmware/isr.c", "isr_elapsed"),
                     ("src/app/drive_slow.c", "drive_log_due"))
# the nesting's instructions that count_line sees as no operation: IER = M_INT1
# (MOV IER,#imm 2), EINT and DINT (CLRC/SETC INTM, 2 each), rounded up
NESTING = 8
# ... and what isr_slow runs only in the slow ISR of DRIVE_LOG_SLOT
FIRMWARE_LOG_SLOT = (("firmware/datalog.c", "datalog_step"),
                     ("src/app/drive_step.c", "drive_get_log_signals"))

# source file stem (.c and its .h, whose inline step functions run in the
# ISR) -> module of the report (others: GLUE)
STEM_MODULE = {
    "phase_current": "sensing", "dc_bus": "sensing", "qep_speed": "sensing",
    "protect": "protections", "encoder_check": "protections",
    "current_check": "protections", "isr_monitor": "protections",
    "volt_calc": "voltage model + dead-time feed-forward",
    "clarke": "Clarke/Park/inverse Park", "park": "Clarke/Park/inverse Park",
    "ipark": "Clarke/Park/inverse Park", "angle": "sin/cos",
    "ifo": "orientation (IFO)", "flux_obs": "orientation (observer)",
    "ident_regressor": "regression inputs + filters", "bw_filter": "regression inputs + filters",
    "rls": "RLS", "estim_bfp": "RLS", "theta_guard": "estimator guard",
    "id_sequence": "sequence", "ramp_gen": "speed ramp + PIs", "pi_ctrl": "speed ramp + PIs",
    "svgen": "SVPWM", "tr_track": "adaptation", "standstill_z": "adaptation",
    "drive_adapt": "adaptation", "iq_rmpy": "rounded products (iq_rmpy)",
    "drive_safety": "model-based protections", "current_model_check": "model-based protections",
    "sensor_test": "model-based protections", "stall_check": "model-based protections",
    "publish_guard": "model-based protections",
    "ident_conf": "confidence sums (ident_conf, rls_cov)",
    "rls_cov": "confidence sums (ident_conf, rls_cov)",
}
GLUE = "drive glue (drive_step, drive_slow)"
FIRMWARE = "firmware ISR + HAL, entry/exit"

OPS = sorted(["<<=", ">>=", "+=", "-=", "*=", "/=", "%=", "&=", "|=", "^=", "++", "--", "<<",
              ">>", "<=", ">=", "==", "!=", "&&", "||", "=", "+", "-", "*", "/", "%", "&",
              "|", "^", "~", "!", "<", ">", "?"], key=len, reverse=True)
TOKEN = re.compile(r"->|[A-Za-z_]\w*|\d[\w.]*|" + "|".join(re.escape(o) for o in OPS) +
                   r"|[()\[\]{};,.:]")
REG_ACCESS = re.compile(r"\b\w+Regs(?:\s*\.\s*\w+)+")
KEYWORDS = {"if", "for", "while", "switch", "return", "sizeof", "else", "do", "case"}
TYPES = {"int16_t", "uint16_t", "int32_t", "uint32_t", "int64_t", "uint64_t", "_iq", "_iq30",
         "_iq29", "_iq28", "_iq27", "_iq26", "_iq20", "void", "int", "unsigned", "const", "float",
         "double", "static", "inline", "Uint16", "Uint32"}


class BenchError(Exception):
    pass


def strip_comments(lines):
    """Source lines with comments and string literals blanked (line numbers kept)."""
    out, in_block = [], False
    for ln in lines:
        s, i, res = ln, 0, []
        while i < len(s):
            if in_block:
                j = s.find("*/", i)
                if j < 0:
                    i = len(s)
                else:
                    in_block, i = False, j + 2
            elif s.startswith("/*", i):
                in_block, i = True, i + 2
            elif s.startswith("//", i):
                break
            elif s[i] == '"':
                j = s.find('"', i + 1)
                i = len(s) if j < 0 else j + 1
            else:
                res.append(s[i])
                i += 1
        out.append("".join(res))
    return out


IQ_CALL = re.compile(r"\b(_IQ\d*[A-Za-z]\w*|_Q\d+toIQ|iq_norm32)\s*\(")


def iq_op_name(name):
    """The operation of an IQmath call as named in TI_CYCLES / ASSUMED_CYCLES
    (_IQ29rmpy -> _IQrmpy, _IQtoIQ27 and _IQ27toIQ -> _IQtoIQN, ...)."""
    if name == "iq_norm32":
        return name
    if name.startswith("_Q"):
        return "_IQtoQN"
    rest = re.match(r"_IQ\d*(.*)", name).group(1)
    if rest.startswith("toIQ"):
        return "_IQtoIQN"
    if rest.startswith("toQ"):
        return "_IQtoQN"
    return "_IQ" + rest


def count_iq(code):
    """{operation: calls} of the IQmath operations written on one line."""
    out = {}
    for m in IQ_CALL.finditer(code):
        op = iq_op_name(m.group(1))
        out[op] = out.get(op, 0) + 1
    return out


INT_LIT = re.compile(r"(0[xX][0-9a-fA-F]+|\d+)[uUlL]*$")
NUM_LIT = re.compile(r"(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?[fFlLuU]*$")
DIV_OPS = ("/", "%", "/=", "%=")
_INT_MACROS = {}


def int_macros():
    """{NAME: value} of the object-like #defines of src/ and include/ whose
    value is an integer constant expression (DRIVE_SLOTS -> 8), for the
    divisors the compiler knows."""
    if not _INT_MACROS:
        raw = {}
        for p in list((ROOT / "src").rglob("*.[ch]")) + list((ROOT / "include").glob("*.h")):
            text = "\n".join(strip_comments(p.read_text().splitlines()))
            for m in re.finditer(r"^[ \t]*#[ \t]*define[ \t]+([A-Za-z_]\w*)[ \t]+(.+)$", text, re.M):
                raw.setdefault(m.group(1), m.group(2).strip())
        for name in raw:
            v = const_int(TOKEN.findall(raw[name]), raw)
            if v is not None:
                _INT_MACROS[name] = v
        _INT_MACROS.setdefault("", None)   # computed once, even if empty
    return _INT_MACROS


def const_int(toks, raw=None, depth=0):
    """The value of an integer constant expression given as tokens (casts to
    integer types, integer suffixes and macros allowed: those of `raw`
    {NAME: text} while int_macros() reads them, else int_macros()), or None."""
    known = int_macros() if raw is None else {}
    out, i = [], 0
    while i < len(toks):
        t = toks[i]
        if t == "(" and i + 2 < len(toks) and toks[i + 2] == ")" and \
                (toks[i + 1] in TYPES or toks[i + 1].endswith("_t")):
            i += 3              # a cast
            continue
        if INT_LIT.match(t):
            out.append(str(int(re.match(r"(0[xX][0-9a-fA-F]+|\d+)", t).group(1), 0)))
        elif t in ("(", ")", "+", "-", "*", "<<", ">>", "&", "|", "^", "~"):
            out.append(t)
        elif t in ("/", "%"):
            out.append("//" if t == "/" else "%")
        elif re.match(r"[A-Za-z_]\w*$", t):
            if raw is not None:
                v = const_int(TOKEN.findall(raw[t]), raw, depth + 1) \
                    if t in raw and depth < 8 else None
            else:
                v = known.get(t)
            if v is None:
                return None
            out.append(f"({v})")
        else:
            return None
        i += 1
    try:
        v = eval(" ".join(out), {"__builtins__": {}}, {}) if out else None  # noqa: S307
    except Exception:   # noqa: BLE001 - not a constant expression
        return None
    return v if isinstance(v, int) else None


def operand(toks, j):
    """(tokens of the operand starting at toks[j] - casts skipped, a
    parenthesised group whole, else one token -, index after it)."""
    while j + 2 < len(toks) and toks[j] == "(" and toks[j + 2] == ")" and \
            (toks[j + 1] in TYPES or toks[j + 1].endswith("_t")):
        j += 3
    if j < len(toks) and toks[j] == "(":
        depth, k = 0, j
        while k < len(toks):
            depth += (toks[k] == "(") - (toks[k] == ")")
            if depth == 0:
                break
            k += 1
        return toks[j:k + 1], k + 1
    if j + 1 < len(toks) and toks[j + 1] in ("(", "->", ".", "["):
        return None, j + 1          # a call or a member: a run-time value
    return toks[j:j + 1], j + 1


def div_kind(toks, i, wide):
    """What the / or % at toks[i] costs: None (both operands constant: the
    compiler folds it, _IQ(1.0 / 6.0)), "div_pow2" (by a constant power of
    two), "div_rts64" / "div_rts" (a call of the run-time library)."""
    prev = toks[i - 1] if i > 0 else ""
    before = toks[i - 2] if i > 1 else ""
    divisor, _ = operand(toks, i + 1)
    d_const = divisor is not None and (
        (len(divisor) == 1 and NUM_LIT.match(divisor[0]) is not None) or
        const_int(divisor) is not None)
    if d_const and NUM_LIT.match(prev) and before not in ("*", "/", "%", ")", "]"):
        return None
    if wide:
        return "div_rts64"
    v = const_int(divisor) if divisor is not None else None
    if v is not None and v > 0 and (v & (v - 1)) == 0:
        return "div_pow2"
    return "div_rts"


def count_line(code, inline_funcs):
    """{op32, op64, branch, call, field, periph, div_pow2, div_rts, div_rts64,
    iq: {op: n}} on one line of C."""
    c = {"op32": 0, "op64": 0, "branch": 0, "call": 0, "field": 0, "periph": 0,
         "div_pow2": 0, "div_rts": 0, "div_rts64": 0, "iq": {}}
    if code.strip().startswith("#"):
        return c
    c["iq"] = count_iq(code)
    # a peripheral register access (AdcRegs.ADCTRL2.bit.RST_SEQ1): one
    # access with wait states, its dots are not struct fields
    code, c["periph"] = REG_ACCESS.subn(" __reg__ ", code)
    toks = TOKEN.findall(code)
    wide = "int64" in code
    for i, t in enumerate(toks):
        nxt = toks[i + 1] if i + 1 < len(toks) else ""
        prev = toks[i - 1] if i > 0 else ""
        if t in ("if", "while", "for", "case", "?", "&&", "||"):
            c["branch"] += 1
            if t in ("&&", "||"):
                c["op64" if wide else "op32"] += 1
        elif t in OPS and t != "?":
            # unary * and & after a type or '(' / ',' are declarations or
            # address-taking: no run-time operation
            if t in ("*", "&") and (prev in TYPES or prev.endswith("_t") or prev in ("(", ",", "")):
                continue
            if t in DIV_OPS:
                kind = div_kind(toks, i, wide)
                if kind is not None:
                    c[kind] += 1
                continue
            c["op64" if wide else "op32"] += 1
        elif t in ("->", "."):
            # one address computation per access path: d->cur.ia is one
            # static offset from d (count the first member operator of a chain)
            if toks[i - 2 if i > 1 else 0] not in ("->", ".") or i < 2:
                c["field"] += 1
        elif re.match(r"[A-Za-z_]\w*$", t) and nxt == "(":
            if t in KEYWORDS or t.startswith("_IQ") or t.startswith("iqm_") or \
                    t in inline_funcs or t in TYPES or t.endswith("_t"):
                continue
            if prev in TYPES or prev.endswith("_t") or prev == "*":
                continue    # a function's definition (its call is costed at the call site)
            c["call"] += 1
    return c


def iq_op_cycles(op):
    c = TI_CYCLES.get(op, TI_ASM_CYCLES.get(op, ASSUMED_CYCLES.get(op)))
    if c is None:
        raise BenchError(f"no cycle count for {op}: add it to TI_ASM_CYCLES or ASSUMED_CYCLES")
    return c + ROM_WAIT * ROM_TABLE_READS.get(op, 0)


# what a line's operations cost outside its own code: the run-time library's
# division, priced from flash already (a flash-set line's factor is not
# applied to it again)
RTS_OPS = ("div_rts", "div_rts64")


def line_cycles(ops, in_flash=False):
    """The cycles of one execution of a line's operations; in_flash: the line
    is in the flash set (its own code at FLASH_FACTOR)."""
    own = sum(OTHER_COST[k] * v for k, v in ops.items() if k in OTHER_COST and k not in RTS_OPS) + \
        PERIPH_WAIT * ops.get("periph", 0) + \
        sum(iq_op_cycles(op) * n for op, n in ops.get("iq", {}).items())
    rts = sum(OTHER_COST[k] * ops.get(k, 0) for k in RTS_OPS)
    return own * (FLASH_FACTOR if in_flash else 1.0) + rts


def inline_functions():
    names = set()
    for p in list((ROOT / "src").rglob("*.[ch]")) + list((ROOT / "include").glob("*.h")):
        for m in re.finditer(r"static\s+inline\s+[\w\s\*]+?\b(\w+)\s*\(", p.read_text()):
            names.add(m.group(1))
    return names


def function_body(path, name):
    """The lines of C function `name` in `path` (comments blanked), or error."""
    spans = body_span(ROOT / path, name)
    if not spans:
        raise BenchError(f"{path}: function {name} not found (update FIRMWARE_ISR)")
    first, last = spans[0]
    src = strip_comments((ROOT / path).read_text().splitlines())
    # the body between the braces: the rest of the header's line after `{`,
    # the lines between, the closing line before `}`
    text = "\n".join(src[first - 1:last])
    return text[text.index("{", text.index(name)) + 1:text.rindex("}")].splitlines()


def body_span(path, name):
    """[(first, last)] 1-based line numbers of every body of C function `name`
    in `path` (a static function of the same name may be defined in several
    files; the linker's input-section name matches them all)."""
    src = strip_comments(Path(path).read_text().splitlines())
    text = "\n".join(src)
    spans = []
    for m in re.finditer(r"^[^\n;{}]*\b" + re.escape(name) + r"\s*\([^;{]*\)\s*\{", text, re.M):
        depth, i = 0, m.end() - 1
        while i < len(text):
            if text[i] == "{":
                depth += 1
            elif text[i] == "}":
                depth -= 1
                if depth == 0:
                    break
            i += 1
        spans.append((text.count("\n", 0, m.start()) + 1, text.count("\n", 0, i) + 1))
    return spans


def flash_lines():
    """{path: [(first, last)]}: the bodies of the flash set's functions, which
    the flash image runs from flash (the linker includes name them)."""
    names = set()
    for inc in FLASH_SET_INCLUDES:
        for blk in FLASH_SET_BLOCK.findall((ROOT / inc).read_text()):
            names |= {n.lstrip("_") for n in re.findall(r"\(\.text:(\w+)\)", blk)}
    out, found = {}, set()
    for f in sorted(list((ROOT / "src").rglob("*.[ch]")) + list((ROOT / "include").glob("*.h"))):
        text = f.read_text()
        for n in names:
            if n in text:
                spans = body_span(f, n)
                if spans:
                    out.setdefault(str(f), []).extend(spans)
                    found.add(n)
    if names - found:
        raise BenchError(f"flash-set functions not found in src/ or include/: {sorted(names - found)}")
    return out, sorted(names)


def firmware_cost(inl):
    """Cycles of the firmware ISR path, every line once (static): per
    control ISR, per slow ISR, and in the log slot's slow ISR only."""
    per_fn, slow_fn, log_fn = {}, {}, {}
    for table, out in ((FIRMWARE_ISR, per_fn), (FIRMWARE_SLOW_ISR, slow_fn),
                       (FIRMWARE_LOG_SLOT, log_fn)):
        for path, fn in table:
            out[f"{Path(path).name}:{fn}"] = sum(line_cycles(count_line(ln, inl))
                                               for ln in function_body(path, fn))
    # the calls of these functions are costed where they are made: on the
    # lines of their callers (isr_control's here, drive_isr's in the host
    # build); isr_control and isr_slow are interrupts (ISR_ENTRY_EXIT each)
    return (ISR_ENTRY_EXIT + sum(per_fn.values()), per_fn,
            ISR_ENTRY_EXIT + NESTING + sum(slow_fn.values()), slow_fn,
            sum(log_fn.values()), log_fn)


# ---- running isr_cost and reading its gcov dumps ----------------------------

def isr_cost_paths(build):
    exe = build / "host_sim" / "api" / "isr_cost"
    objdir = build / "host_sim" / "api" / "CMakeFiles" / "isr_cost.dir"
    if not exe.exists():
        raise BenchError(f"{exe} not found: build the IQ_MATH preset (cmake --build --preset "
                         f"host-iq --target isr_cost)")
    gcno = list(objdir.rglob("*.gcno"))
    if not gcno:
        raise BenchError(f"no coverage notes (.gcno) under {objdir}: isr_cost was not built "
                         f"with --coverage; no estimate without line counts")
    if shutil.which("gcov") is None:
        raise BenchError("gcov not found")
    return exe, objdir


LINE_ROW = re.compile(r"^\s*([^:\s]+):\s*(\d+):")
BLOCK_ROW = re.compile(r"^\s*([^:\s]+):\s*(\d+)-block\s+\d+")


def gcov_count(field):
    """A gcov count column: '-' (no code), '#####'/'$$$$$'/'=====' (never
    run), or a number (maybe with a '*' mark)."""
    f = field.rstrip("*")
    return int(f) if f.isdigit() else 0


def parse_dump(args):
    """{path: {line: executions}} of one sample's gcov dump (src/ and
    include/ only).  gcov's line count is the number of times control
    ENTERED the line (a statement split over two lines is entered twice,
    from its own continuation), so the executions of a line are taken from
    its basic blocks instead (gcov -a: the largest count of a block that
    starts on the line); a line without a block of its own is a continuation
    of the statement above it (costed with it, LineCoster.ops)."""
    sdir, objdir = args
    gcdas = [p for p in Path(sdir).rglob("*.gcda")]
    if not gcdas:
        raise BenchError(f"{sdir}: no .gcda written (gcov dump failed)")
    for g in gcdas:
        # the dump mirrors the object directory's absolute path under sdir
        rel = str(g)[len(str(sdir)):]
        note = Path(rel).with_suffix(".gcno")
        link = g.with_suffix(".gcno")
        if not link.exists():
            os.symlink(note, link)
    # one gcov run per object: given several at once, gcov lists a header
    # they share with counts merged across them (a header's inline
    # functions are separate copies in each unit: their counts are summed
    # here, unit by unit)
    text = []
    for g in gcdas:
        r = subprocess.run(["gcov", "-a", "-t", str(g)], capture_output=True, text=True,
                           cwd=str(sdir))
        if r.returncode != 0:
            raise BenchError(f"gcov failed on {g}: {r.stderr.strip()[:200]}")
        text.append(r.stdout)
    out, cur, rows, blocks = {}, None, {}, {}

    def flush():
        # per line: its blocks' largest count where a block starts on it,
        # else gcov's count (a line inside a block is entered once per run)
        if cur is not None:
            d = out.setdefault(cur, {})
            for ln, n in rows.items():
                d[ln] = d.get(ln, 0) + blocks.get(ln, n)

    for row in "\n".join(text).splitlines():
        if ":Source:" in row:
            flush()
            path = Path(row.split(":Source:", 1)[1].strip())
            if not path.is_absolute():
                path = (objdir / path).resolve()
            keep = ROOT / "src" in path.parents or ROOT / "include" in path.parents
            cur, rows, blocks = (str(path) if keep else None), {}, {}
            continue
        if cur is None:
            continue
        m = BLOCK_ROW.match(row)
        if m:
            ln = int(m.group(2))
            blocks[ln] = max(blocks.get(ln, 0), gcov_count(m.group(1)))
            continue
        m = LINE_ROW.match(row)
        if m and m.group(1) != "-":
            rows[int(m.group(2))] = gcov_count(m.group(1))
    flush()
    return out


class LineCoster:
    def __init__(self):
        self.inl = inline_functions()
        self.flash, self.flash_names = flash_lines()
        self.src = {}
        self.cache = {}
        self.executable = {}   # path -> the lines gcov counts on their own

    def learn(self, lines):
        """Record which lines gcov counts on their own (from a dump)."""
        for path, d in lines.items():
            self.executable.setdefault(path, set()).update(d.keys())

    def ops(self, path, line):
        """The operations of the statement that starts at `line`: gcov counts
        a statement on its first line; its continuation lines (a statement
        not yet ended by ; { } or a label's :) are costed with it."""
        key = (path, line)
        if key not in self.cache:
            if path not in self.src:
                self.src[path] = strip_comments(Path(path).read_text().splitlines())
            src = self.src[path]
            if line > len(src):
                self.cache[key] = {}
                return self.cache[key]
            if self._continues(src, line):
                self.cache[key] = None      # costed with the statement's first line
                return None
            text, k = src[line - 1], line
            while k < len(src) and not self._ends(text):
                nxt = src[k]
                if nxt.strip().startswith("#"):
                    break
                text += " " + nxt
                k += 1
            self.cache[key] = count_line(text, self.inl)
        return self.cache[key]

    def _continues(self, src, line):
        """1 if `line` continues a statement begun on an earlier line."""
        k = line - 2
        while k >= 0 and not src[k].strip():
            k -= 1
        return k >= 0 and not self._ends(src[k]) and not src[line - 1].strip().startswith("#")

    @staticmethod
    def _ends(text):
        t = text.rstrip()
        return (not t) or t.endswith((";", "{", "}", ":")) or t.lstrip().startswith("#")

    def cost(self, lines, iq_calls=None):
        """(cycles, {module: cycles}, hot [(cycles, where, code)]); the IQmath
        calls the lines make are added to iq_calls {op: n} if given."""
        total, mods, hot = 0.0, {}, []
        for path, d in lines.items():
            mod = STEM_MODULE.get(Path(path).stem, GLUE)
            spans = self.flash.get(path, ())
            for a, b in spans:
                # entering a flash function: the count of its first executed line
                run = [(ln, n) for ln, n in d.items() if a <= ln <= b and n]
                if run:
                    c = FLASH_ENTRY * min(run)[1]
                    total += c
                    mods[mod] = mods.get(mod, 0.0) + c
                    hot.append((c, f"{Path(path).relative_to(ROOT)}:{a}", "(flash entry)"))
            for ln, n in d.items():
                if n == 0:
                    continue
                ops = self.ops(path, ln)
                if ops is None:
                    continue
                if iq_calls is not None:
                    for op, k in ops.get("iq", {}).items():
                        iq_calls[op] = iq_calls.get(op, 0) + k * n
                c = line_cycles(ops, any(a <= ln <= b for a, b in spans)) * n
                if c:
                    total += c
                    mods[mod] = mods.get(mod, 0.0) + c
                    hot.append((c, f"{Path(path).relative_to(ROOT)}:{ln}",
                                self.src[path][ln - 1].strip()))
        return total, mods, hot


def worst_lines(members, key):
    """Every line at the largest count any sampled ISR of the class ran it."""
    wl = {}
    for m in members:
        for path, d in m[key].items():
            t = wl.setdefault(path, {})
            for ln, n in d.items():
                t[ln] = max(t.get(ln, 0), n)
    return wl


def unsampled_lines(exe, blocks, coster):
    """The source lines of the basic blocks that ran in an ISR of a class but
    in none of its samples (isr_cost's "unsampled": offsets in the
    executable), each priced as the model prices a line run once (its flash
    price if it is in the flash set): [{"state", "slot", "isr", "where",
    "code", "cycles"}].  isr_cost samples the first ISR of every block of a
    class, so the list is empty unless the two passes differ."""
    if not blocks:
        return []
    if shutil.which("addr2line") is None:
        raise BenchError("addr2line not found (binutils): unsampled blocks cannot be priced")
    # the return address of the block's call of the callback: one byte back
    # is inside the call, on the block's line
    r = subprocess.run(["addr2line", "-e", str(exe)] + [hex(b["offset"] - 1) for b in blocks],
                       capture_output=True, text=True)
    if r.returncode != 0:
        raise BenchError(f"addr2line failed: {r.stderr.strip()[:200]}")
    out = []
    for b, row in zip(blocks, r.stdout.splitlines()):
        m = re.match(r"(.*):(\d+)", row.split(" (discriminator")[0])
        priced = price_line(coster, m.group(1), int(m.group(2))) if m else \
            {"where": row, "code": "", "cycles": 0.0}
        out.append(dict(priced, state=b["state"], slot=b["slot"], isr=b["isr"]))
    return out


def price_line(coster, path, line):
    """{"where", "code", "cycles"}: one line of `path` (or the first line of
    the statement it continues) priced as run once: its own operations
    (FLASH_FACTOR and FLASH_ENTRY if it is in the flash set), its calls of
    IQmath and of the run-time library.  A line outside the sources: 0."""
    cycles, code = 0.0, ""
    if line > 0 and Path(path).exists():
        ops = coster.ops(path, line)
        while ops is None and line > 1:     # a continuation: the statement's first line
            line -= 1
            ops = coster.ops(path, line)
        in_flash = any(a <= line <= e for a, e in coster.flash.get(path, ()))
        cycles = line_cycles(ops or {}, in_flash) + (FLASH_ENTRY if in_flash else 0)
        code = coster.src[path][line - 1].strip()
    p = Path(path).resolve()
    where = f"{p.relative_to(ROOT)}:{line}" if ROOT in p.parents else f"{path}:{line}"
    return {"where": where, "code": code[:80], "cycles": cycles}


def estimate(build, config, uniform, jobs):
    exe, objdir = isr_cost_paths(build)
    coster = LineCoster()
    fixed, fw_fns, fixed_slow, slow_fns, log_cost, log_fns = firmware_cost(coster.inl)
    with tempfile.TemporaryDirectory(prefix="bench_isr_") as tmp:
        r = subprocess.run([str(exe), str(config), "--out", tmp, "--uniform", str(uniform)],
                           capture_output=True, text=True)
        if r.returncode != 0:
            raise BenchError(f"isr_cost failed: {r.stderr.strip()}")
        data = json.loads(r.stdout)
        samples = data["samples"]
        if not samples:
            raise BenchError("isr_cost sampled no ISR")
        if data.get("pass_mismatch", 0) != 0:
            raise BenchError(f"isr_cost's two passes ran different blocks ({data['pass_mismatch']}):"
                             " the samples of pass 2 are not those pass 1 chose")
        dirs = [d for s in samples for d in (s["dir"], s["dir_slow"])]
        with cf.ThreadPoolExecutor(max_workers=jobs) as ex:
            dumps = list(ex.map(parse_dump, [(Path(tmp) / d, objdir) for d in dirs]))
    names = data["iqmath_names"]
    for lines in dumps:
        coster.learn(lines)
    missed = unsampled_lines(exe, data["unsampled"], coster)
    missed_cost = {}
    for u in missed:
        k = (u["state"], u["slot"], "fast" if u["isr"] == "control" else "slow")
        missed_cost[k] = missed_cost.get(k, 0.0) + u["cycles"]
    classes = {}
    mismatch = []
    for k, s in enumerate(samples):
        m = {"s": s, "fast": dumps[2 * k], "slow": dumps[2 * k + 1]}
        fw_slow = fixed_slow + (log_cost if s["slot"] == data["log_slot"] else 0)
        for key, iq, fw in (("fast", "iq", fixed), ("slow", "iq_slow", fw_slow)):
            calls = {}
            c_lines, _, _ = coster.cost(m[key], calls)
            s[key] = fw + c_lines
            # the IQmath calls attributed to lines must cover every call counted
            # (more is possible: both arms of a ?: are costed, errs high)
            for op, n in zip(names, s[iq]):
                if calls.get(op, 0) < n:
                    mismatch.append((s["index"], key, op, calls.get(op, 0), n))
        s["cycles"] = s["fast"] + s["slow"]
        classes.setdefault((s["state"], s["slot"]), []).append(m)
    if mismatch:
        raise BenchError("IQmath calls per line fewer than the counted ones "
                         f"(ISR, which, operation, by line, counted): {mismatch[:5]}")
    states = {}
    for (raw_state, slot), members in sorted(classes.items()):
        # a state's phases (isr_cost: "CALIBRATE.sensor_test") are classes
        # of the state: never in one ISR together, each a sum of maxima alone
        state, _, phase = raw_state.partition(".")
        one = {}
        for key, fw in (("fast", fixed),
                        ("slow", fixed_slow + (log_cost if slot == data["log_slot"] else 0))):
            c_lines, mods, hot = coster.cost(worst_lines(members, key))
            mods = dict(mods)
            mods[FIRMWARE] = fw
            # lines no sample of the class ran (none, unless the passes differ)
            extra = missed_cost.get((raw_state, slot, key), 0.0)
            if extra:
                mods["unsampled lines (priced once each)"] = extra
            # for comparison, not the estimate: the sum of maxima over the
            # schedule's samples (transitions, uniform) with each coverage
            # sample's lines added on its own, i.e. one-off events (a test's
            # verdict, a calibration's end) never stacked in one ISR
            regular = [m for m in members if not m["s"].get("coverage")]
            apart = max([coster.cost(worst_lines(regular + [c], key))[0]
                         for c in members if c["s"].get("coverage")] +
                        [coster.cost(worst_lines(regular, key))[0] if regular else 0.0])
            one[key] = {"worst": fw + c_lines + extra, "modules": mods, "hot": hot,
                        "apart": fw + apart + extra}
        uni = [m["s"] for m in members if m["s"]["uniform"]] or [m["s"] for m in members]
        st = states.setdefault(state, {"classes": {}})
        st["classes"][(phase, slot)] = {
            "slot": slot, "phase": phase,
            "worst": max(one["fast"]["worst"], one["slow"]["worst"]),
            "fast": one["fast"], "slow": one["slow"],
            # the period: both ISRs' worsts (a sum of maxima, errs high)
            "period": one["fast"]["worst"] + one["slow"]["worst"],
            "mean": sum(s["cycles"] for s in uni) / len(uni),
            "max_sample": max(max(m["s"]["fast"], m["s"]["slow"]) for m in members),
            # the costliest single sampled ISR of each kind (the same rules,
            # one real ISR's counts: below the sum of maxima)
            "sample_fast": max((m["s"]["fast"], m["s"]["index"]) for m in members),
            "sample_slow": max((m["s"]["slow"], m["s"]["index"]) for m in members),
            "samples": len(members)}
    out = {}
    for state, st in states.items():
        cl = st["classes"]
        wslot = max(cl, key=lambda k: cl[k]["worst"])
        # the mean: each phase's (its slots alike) weighted by its ISRs
        weights = {ph: data["state_isrs"].get(f"{state}.{ph}" if ph else state, 0)
                   for ph in {c["phase"] for c in cl.values()}}
        total = sum(weights.values()) or 1
        mean = sum(weights[ph] * sum(c["mean"] for c in cl.values() if c["phase"] == ph)
                   / data["slots"] for ph in weights) / total
        out[state] = {"mean": mean,
                      "worst": cl[wslot]["worst"], "worst_slot": wslot,
                      "worst_fast": max(c["fast"]["worst"] for c in cl.values()),
                      "worst_slow": max(c["slow"]["worst"] for c in cl.values()),
                      "worst_period": max(c["period"] for c in cl.values()),
                      "apart_fast": max(c["fast"]["apart"] for c in cl.values()),
                      "apart_slow": max(c["slow"]["apart"] for c in cl.values()),
                      "sample_fast": max(c["sample_fast"] for c in cl.values()),
                      "sample_slow": max(c["sample_slow"] for c in cl.values()),
                      "isrs": sum(n for s, n in data["state_isrs"].items()
                                  if s.partition(".")[0] == state),
                      "classes": cl}
    return {"states": out, "fixed": fixed, "firmware_functions": fw_fns,
            "unsampled_lines": missed, "coverage_samples": data["coverage_samples"],
            "blocks": data["blocks"], "samples": len(samples),
            "fixed_slow": fixed_slow, "slow_firmware_functions": slow_fns,
            "log_slot_cycles": log_cost, "log_slot_functions": log_fns,
            "slots": data["slots"], "log_slot": data["log_slot"], "isrs": data["isrs"]}


def class_name(key):
    """A class key (phase, slot) as text: "slot 3", "sensor_test slot 3"."""
    phase, slot = key
    return f"{phase} slot {slot}" if phase else f"slot {slot}"


def summary(res):
    st = {k: v for k, v in res["states"].items() if k in STATES}
    r = lambda x: int(round(x))   # noqa: E731
    return {"samples": res["samples"], "coverage_samples": res["coverage_samples"],
            "blocks": res["blocks"], "unsampled_lines": res["unsampled_lines"],
            "states": {k: {"mean": r(v["mean"]), "worst": r(v["worst"]),
                           "worst_control_isr": r(v["worst_fast"]),
                           "worst_slow_isr": r(v["worst_slow"]),
                           "worst_period": r(v["worst_period"]),
                           "control_isr_events_apart": r(v["apart_fast"]),
                           "slow_isr_events_apart": r(v["apart_slow"]),
                           "costliest_sampled_control_isr": r(v["sample_fast"][0]),
                           "costliest_sampled_slow_isr": r(v["sample_slow"][0])}
                       for k, v in st.items()},
            "worst_isr_cycles": r(max(v["worst"] for v in st.values())),
            "worst_control_isr_cycles": r(max(v["worst_fast"] for v in st.values())),
            "worst_slow_isr_cycles": r(max(v["worst_slow"] for v in st.values())),
            "worst_period_cycles": r(max(v["worst_period"] for v in st.values())),
            "total_cycles": r(max(v["mean"] for v in st.values()))}


def print_markdown(configs, results, sums):
    """The tables of the benchmarks document: per state the mean CPU per
    period, the worst control ISR, the worst slow ISR and the worst period
    of each sequence; the worst slow ISR of every slot."""
    names = [n for n, _ in configs]
    print("| state | " + " | ".join(f"{n}: mean/period | {n}: control ISR | {n}: slow ISR | "
                                   f"{n}: period" for n in names) + " |")
    print("|---|" + "---:|---:|---:|---:|" * len(names))
    for state in STATES:
        if not any(state in results[n]["states"] for n in names):
            continue
        cells = []
        for n in names:
            v = results[n]["states"].get(state)
            cells += ([f"{v['mean']:.0f}", f"{v['worst_fast']:.0f}", f"{v['worst_slow']:.0f}",
                       f"{v['worst_period']:.0f}"] if v else ["-"] * 4)
        print(f"| {state} | " + " | ".join(cells) + " |")
    print("| **worst** | " + " | ".join(
        f"{sums[n]['total_cycles']} | **{sums[n]['worst_control_isr_cycles']}** | "
        f"**{sums[n]['worst_slow_isr_cycles']}** | {sums[n]['worst_period_cycles']}"
        for n in names) + " |")
    print()
    slots = results[names[0]]["slots"]
    print("| worst slow ISR per slot | " + " | ".join(str(k) for k in range(slots)) + " |")
    print("|---|" + "---:|" * slots)
    for n in names:
        worst = [max(c["slow"]["worst"] for v in results[n]["states"].values()
                     for c in v["classes"].values() if c["slot"] == k) for k in range(slots)]
        print(f"| {n} | " + " | ".join(f"{w:.0f}" for w in worst) + " |")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default=str(ROOT / "build" / "host-iq"),
                    help="an IQ_MATH build directory with isr_cost (default build/host-iq)")
    ap.add_argument("--config", action="append",
                    help="INI file(s); default: the paper's sequence (paper_motor.ini) and the "
                         "adaptive one (paper_motor_wrong_nameplate.ini)")
    ap.add_argument("--uniform", type=int, default=8,
                    help="ISRs sampled evenly per (state, slot), besides the transitions")
    ap.add_argument("--hot", type=int, default=0, help="also list the N costliest lines of "
                                                       "the worst ISR")
    ap.add_argument("--hot-slot", type=int, default=None,
                    help="with --hot: this slot's worst ISR instead of the state's worst slot")
    ap.add_argument("--hot-state", default=None,
                    help="with --hot: of this state's worst ISR instead (e.g. CALIBRATE)")
    ap.add_argument("--hot-isr", choices=("worst", "control", "slow"), default="worst",
                    help="with --hot: the slot's control or slow ISR (default: the costlier)")
    ap.add_argument("--slots", action="store_true", help="also list the worst ISR of every slot")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 2)
    ap.add_argument("--markdown", action="store_true",
                    help="print the per-state (mean, worst) and per-slot tables in Markdown")
    ap.add_argument("--json", action="store_true",
                    help='print {"total_cycles", "budget_cycles", "worst_isr_cycles", '
                         '"states", "sequences", ...}')
    a = ap.parse_args(argv)
    configs = ([(Path(c).stem, c) for c in a.config] if a.config else list(DEFAULT_CONFIGS))
    try:
        results = {name: estimate(Path(a.build).resolve(), (ROOT / cfg).resolve()
                                  if not Path(cfg).is_absolute() else Path(cfg), a.uniform,
                                  a.jobs)
                   for name, cfg in configs}
    except BenchError as e:
        print(f"bench_isr: {e}", file=sys.stderr)
        return 1
    sums = {name: summary(r) for name, r in results.items()}
    first = sums[configs[0][0]]
    merged = {}
    for s in sums.values():
        for k, v in s["states"].items():
            m = merged.setdefault(k, {q: 0 for q in v})
            for q in v:
                m[q] = max(m[q], v[q])
    out = {"total_cycles": first["total_cycles"], "budget_cycles": BUDGET, "goal_cycles": GOAL,
           "worst_isr_cycles": max(s["worst_isr_cycles"] for s in sums.values()),
           "worst_control_isr_cycles": max(s["worst_control_isr_cycles"] for s in sums.values()),
           "worst_slow_isr_cycles": max(s["worst_slow_isr_cycles"] for s in sums.values()),
           "worst_period_cycles": max(s["worst_period_cycles"] for s in sums.values()),
           "states": merged, "sequences": sums,
           # every block an ISR ran is in a sample of its class (isr_cost), or
           # listed here with the price the worst ISR of that class carries
           "unsampled_lines": [dict(u, sequence=n) for n, s in sums.items()
                               for u in s["unsampled_lines"]],
           "fixed_cycles": int(round(next(iter(results.values()))["fixed"]))}
    if a.json:
        print(json.dumps(out, indent=1))
        return 0
    if a.markdown:
        print_markdown(configs, results, sums)
        return 0
    for (name, cfg), r in zip(configs, results.values()):
        print(f"{name} ({cfg}): cycles (C28x, 150 MHz) per period (mean: both ISRs), of the "
              f"control ISR, of the slow ISR, of the worst period; slots: {r['slots']}")
        print(f"  {'state':<11} {'periods':>7} {'mean':>7} {'control':>7} {'slow':>7} "
              f"{'period':>7}  worst slow ISR's slot: its modules")
        for state in STATES:
            if state not in r["states"]:
                continue
            v = r["states"][state]
            ws = max(v["classes"], key=lambda k: v["classes"][k]["slow"]["worst"])
            cl = v["classes"][ws]["slow"]
            mods = ", ".join(f"{k} {c:.0f}" for k, c in
                             sorted(cl["modules"].items(), key=lambda kv: -kv[1]) if c >= 1)
            print(f"  {state:<11} {v['isrs']:>7} {v['mean']:>7.0f} {v['worst_fast']:>7.0f} "
                  f"{v['worst_slow']:>7.0f} {v['worst_period']:>7.0f}  {class_name(ws)}: {mods}")
        s = sums[name]
        print("  for comparison: one-off events apart (not stacked in one ISR): control "
              + ", ".join(f"{k} {v['apart_fast']:.0f}" for k, v in r["states"].items()
                          if k in STATES)
              + "; slow " + ", ".join(f"{k} {v['apart_slow']:.0f}"
                                      for k, v in r["states"].items() if k in STATES))
        print("  costliest single sampled ISR (one ISR's own counts): control "
              + ", ".join(f"{k} {v['sample_fast'][0]:.0f}" for k, v in r["states"].items()
                          if k in STATES)
              + "; slow " + ", ".join(f"{k} {v['sample_slow'][0]:.0f}"
                                      for k, v in r["states"].items() if k in STATES))
        un = r["unsampled_lines"]
        print(f"  sampled ISRs {r['samples']} ({r['coverage_samples']} of them for a basic block "
              f"new to their class), {r['blocks']} blocks: unsampled lines "
              + ("none" if not un else ", ".join(f"{u['where']} ({u['state']} slot {u['slot']} "
                                                 f"{u['isr']}, +{u['cycles']:.0f})" for u in un)))
        if a.slots:
            for key, what in (("fast", "control"), ("slow", "slow")):
                print(f"  worst {what} ISR per slot (state: slot 0, 1, ...):")
                for state in STATES:
                    if state in r["states"]:
                        cl = r["states"][state]["classes"]
                        for ph in sorted({c["phase"] for c in cl.values()}):
                            name = f"{state}.{ph}" if ph else state
                            print(f"    {name:<22} " + " ".join(
                                f"{cl[k][key]['worst']:6.0f}" for k in sorted(cl) if k[0] == ph))
        print(f"  worst single ISR {s['worst_isr_cycles']} cycles = "
              f"{100 * s['worst_isr_cycles'] / BUDGET:.1f} % of {BUDGET}; goal {GOAL}: "
              f"{'met' if s['worst_isr_cycles'] <= GOAL else 'NOT met'} (control ISR "
              f"{s['worst_control_isr_cycles']}, slow ISR {s['worst_slow_isr_cycles']}); "
              f"worst period (both) {s['worst_period_cycles']} = "
              f"{100 * s['worst_period_cycles'] / BUDGET:.1f} %")
        if a.hot:
            worst_state = a.hot_state or max(r["states"], key=lambda k: r["states"][k]["worst"])
            v = r["states"][worst_state]
            if a.hot_slot is None:
                slot = v["worst_slot"]
            else:
                slot = max((k for k in v["classes"] if k[1] == a.hot_slot),
                           key=lambda k: v["classes"][k]["worst"])
            c2 = v["classes"][slot]
            if a.hot_isr == "worst":
                cl = c2["fast"] if c2["fast"]["worst"] >= c2["slow"]["worst"] else c2["slow"]
            else:
                cl = c2["fast"] if a.hot_isr == "control" else c2["slow"]
            which = "control" if cl is c2["fast"] else "slow"
            mods = ", ".join(f"{k} {c:.0f}" for k, c in
                             sorted(cl["modules"].items(), key=lambda kv: -kv[1]) if c >= 1)
            print(f"  costliest lines of the worst ISR ({worst_state}, {class_name(slot)}, {which} "
                  f"ISR, {cl['worst']:.0f} cycles: {mods}):")
            for c, where, code in sorted(cl["hot"], reverse=True)[:a.hot]:
                print(f"    {c:6.0f}  {where:34s} {code[:60]}")
    fw = next(iter(results.values()))
    print(f"fixed per ISR {fw['fixed']:.0f} cycles: entry/exit {ISR_ENTRY_EXIT}, firmware "
          + ", ".join(f"{k} {v:.0f}" for k, v in fw["firmware_functions"].items()))
    print(f"fixed per slow ISR {fw['fixed_slow']:.0f} cycles: entry/exit {ISR_ENTRY_EXIT}, "
          f"nesting {NESTING}, firmware "
          + ", ".join(f"{k} {v:.0f}" for k, v in fw["slow_firmware_functions"].items()))
    print(f"in the log slot's slow ISR (slot {fw['log_slot']}) {fw['log_slot_cycles']:.0f} more: "
          + ", ".join(f"{k} {v:.0f}" for k, v in fw["log_slot_functions"].items()))
    print("cycles per operation: " + ", ".join(f"{k} {v:g}" for k, v in OTHER_COST.items()) +
          f", peripheral register access +{PERIPH_WAIT}; assumed IQmath: " +
          ", ".join(f"{k} {v}" for k, v in ASSUMED_CYCLES.items()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
