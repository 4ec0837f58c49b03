#!/usr/bin/env python3
"""Estimated cost of the control ISR on the F2812 (C28x, 150 MHz), per
identification state, the mean and the WORST SINGLE ISR, against the budget
of 10 000 cycles per 15 kHz period.  A cost model that errs high.

Method (an estimate from an instrumented host build, not a measurement on a
board; BENCHMARKS.md section b states every assumption):
 1. isr_cost (host_sim/api/isr_cost.c, IQ_MATH build with gcov) runs the
    configured motor's identification closed loop through every state; for
    each class (state, slot of the multi-rate schedule) it samples single
    ISRs - the first two and last two of the class and K spread evenly -
    and dumps that ISR's gcov line counts alone, with its IQmath calls.
 2. Each sampled ISR is costed: every IQmath call at TI's published C28x
    cycle count (IQmath read-me, call included; ASSUMED_CYCLES for those TI
    does not list), every other C operation on every executed line of src/
    and include/ by OTHER_COST (per run of the line), plus the fixed part
    that the host build does not run: the interrupt entry and exit, and the
    firmware's own ISR code and HAL (firmware/isr.c, hal_*_f2812.c,
    datalog.c), costed statically with every line counted once (both arms of
    every branch) and every peripheral register access at its wait states.
 3. Per class, the WORST ISR is costed with every line at the largest count
    any sampled ISR of the class ran it, and every IQmath operation at its
    largest count: a sum of maxima, never below the largest single sample.
    Per state: mean = the mean over the uniform samples of its classes (each
    slot is 1/S of the ISRs), worst = the worst of its classes.

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
STATES = ("CALIBRATE", "MAGNETIZE", "ACCELERATE", "SETTLE", "RUN", "REFINE")
DEFAULT_CONFIGS = (("paper", "host_sim/config/paper_motor.ini"),
                   ("adaptive", "host_sim/config/paper_motor_wrong_nameplate.ini"))

# TI IQmath V1.4c read-me, C28x cycles including the call
TI_CYCLES = {"_IQmpy": 5, "_IQrmpy": 22, "_IQrsmpy": 30, "_IQdiv": 73, "_IQsqrt": 70,
             "_IQisqrt": 74, "_IQsin": 49, "_IQcos": 47, "_IQsinPU": 43, "_IQcosPU": 41,
             "_IQatan2": 118, "_IQmag": 96, "_IQsat": 7, "_IQtoF": 23}
# not in that list: what TI's IQmathLib.h makes of them (our assumption)
ASSUMED_CYCLES = {
    "_IQmpyIQX": 5,      # the same __IQxmpy intrinsic as _IQmpy, another shift
    "_IQmpyI32": 4,      # (long) A * B: one IMPYL 32x32 plus moves
    "_IQmpyI32int": 22,  # library call, as _IQrmpy
    "_IQmpyI32frac": 24,
    "_IQatan2PU": 118, "_IQatan": 118,   # as _IQatan2
    "_IQint": 14, "_IQfrac": 17,         # library calls
    "_IQabs": 3,         # inline ABS on ACC: load, ABS, store
    "_IQtoIQN": 2, "_IQtoQN": 2,         # inline shift of ACC
    "iq_norm32": 3,      # the __norm32 intrinsic: CSB ACC (1) + moving the count out (2)
}
# the table look-ups of these read IQmathTables in the boot ROM (1 wait
# state, SPRS174): 2 reads each, +1 cycle per read
ROM_TABLE_READS = {"_IQsinPU": 2, "_IQcosPU": 2, "_IQsin": 2, "_IQcos": 2, "_IQatan2": 2,
                   "_IQatan2PU": 2, "_IQatan": 2, "_IQisqrt": 1, "_IQsqrt": 1, "_IQdiv": 1,
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
                   # instruction for the address (every -> and . counted: errs high)
}
# fixed per ISR: PIE vector fetch and CPU interrupt latency with the automatic
# context save (14 cycles, SPRU430), the compiler's interrupt prologue and
# epilogue (the registers the hardware does not save: XAR2-XAR7, XT, RPC,
# AR1H:AR0H, ~2 x 12), IRET (8): 14 + 24 + 24 + 8 = 70, rounded up
ISR_ENTRY_EXIT = 80
# peripheral frame 1/2 registers (ADC, EV, PIE, SCI): 2 wait states on a
# read, 0 on a write (SPRS174, "Wait states"); every access charged as a read
PERIPH_WAIT = 2

# the firmware's ISR path the host build does not run: (file, function)
FIRMWARE_ISR = (("firmware/isr.c", "isr_control"), ("firmware/isr.c", "isr_elapsed"),
                ("firmware/hal_adc_f2812.c", "hal_adc_read"),
                ("firmware/hal_pwm_f2812.c", "hal_pwm_write"),
                ("firmware/hal_pwm_f2812.c", "hal_pwm_enable"),
                ("firmware/hal_pwm_f2812.c", "hal_pwm_tripped"),
                ("firmware/hal_pwm_f2812.c", "hal_isr_overrun"),
                ("firmware/hal_pwm_f2812.c", "pwm_f2812_period"),
                ("firmware/hal_qep_f2812.c", "hal_qep_read_count"),
                ("firmware/datalog.c", "datalog_step"),
                ("src/app/drive_step.c", "drive_get_log_signals"))

# source file -> module of the report (others: GLUE)
FILE_MODULE = {
    "phase_current.c": "sensing", "dc_bus.c": "sensing", "qep_speed.c": "sensing",
    "protect.c": "protections", "encoder_check.c": "protections",
    "current_check.c": "protections", "isr_monitor.c": "protections",
    "volt_calc.c": "voltage model + dead-time feed-forward",
    "clarke.c": "Clarke/Park/inverse Park", "park.c": "Clarke/Park/inverse Park",
    "ipark.c": "Clarke/Park/inverse Park", "angle.c": "sin/cos",
    "ifo.c": "orientation (IFO)", "flux_obs.c": "orientation (observer)",
    "ident_regressor.c": "regression inputs + filters", "bw_filter.c": "regression inputs + filters",
    "rls.c": "RLS", "estim_bfp.h": "RLS", "theta_guard.c": "estimator guard",
    "id_sequence.c": "sequence", "ramp_gen.c": "speed ramp + PIs", "pi_ctrl.c": "speed ramp + PIs",
    "svgen.c": "SVPWM", "tr_track.c": "adaptation", "standstill_z.c": "adaptation",
    "drive_adapt.c": "adaptation", "iq_rmpy.h": "rounded products (iq_rmpy)",
}
FN_MODULE = {
    "phase_current_step": "sensing", "dc_bus_step": "sensing", "qep_speed_step": "sensing",
    "protect_step": "protections", "encoder_check_step": "protections",
    "current_check_step": "protections", "volt_calc_step": "voltage model + dead-time feed-forward",
    "volt_calc_feedforward": "voltage model + dead-time feed-forward",
    "clarke_step": "Clarke/Park/inverse Park", "park_step": "Clarke/Park/inverse Park",
    "ipark_step": "Clarke/Park/inverse Park", "ifo_frame_from_rotor": "orientation (IFO)",
    "ifo_step_slip_fast": "orientation (IFO)", "ifo_update_slip_gain": "orientation (IFO)",
    "angle_sincos": "sin/cos", "angle_sincos_step": "sin/cos",
    "ident_regressor_accumulate": "regression inputs + filters",
    "ident_regressor_filter": "regression inputs + filters", "rls_step_row1": "RLS",
    "rls_step_row2": "RLS", "theta_guard_step": "estimator guard", "id_sequence_step": "sequence",
    "ramp_gen_step": "speed ramp + PIs", "pi_step": "speed ramp + PIs",
    "pi_reset": "speed ramp + PIs", "svgen_step": "SVPWM",
    "flux_obs_step": "orientation (observer)", "drive_adapt_fast": "adaptation",
    "drive_adapt_slow": "adaptation",
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


def count_line(code, inline_funcs):
    """{op32, op64, branch, call, field, periph} on one line of C."""
    c = {"op32": 0, "op64": 0, "branch": 0, "call": 0, "field": 0, "periph": 0}
    if code.strip().startswith("#"):
        return c
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
            c["op64" if wide else "op32"] += 1
        elif t in ("->", "."):
            c["field"] += 1
        elif re.match(r"[A-Za-z_]\w*$", t) and nxt == "(":
            if t in KEYWORDS or t.startswith("_IQ") or t.startswith("iqm_") or \
                    t in inline_funcs or t in TYPES or t.endswith("_t"):
                continue
            c["call"] += 1
    return c


def line_cycles(ops):
    return sum(OTHER_COST[k] * v for k, v in ops.items() if k in OTHER_COST) + \
        PERIPH_WAIT * ops.get("periph", 0)


def inline_functions():
    names = set()
    for p in list((ROOT / "src").rglob("*.[ch]")) + list((ROOT / "include").glob("*.h")):
        for m in re.finditer(r"static\s+inline\s+[\w\s\*]+?\b(\w+)\s*\(", p.read_text()):
            names.add(m.group(1))
    return names


def function_body(path, name):
    """The lines of C function `name` in `path` (comments blanked), or error."""
    src = strip_comments((ROOT / path).read_text().splitlines())
    text = "\n".join(src)
    m = re.search(r"^[^\n;{}]*\b" + re.escape(name) + r"\s*\([^;{]*\)\s*\{", text, re.M)
    if m is None:
        raise BenchError(f"{path}: function {name} not found (update FIRMWARE_ISR)")
    depth, i = 0, m.end() - 1
    while i < len(text):
        if text[i] == "{":
            depth += 1
        elif text[i] == "}":
            depth -= 1
            if depth == 0:
                break
        i += 1
    return text[m.end():i].splitlines()


def firmware_cost(inl):
    """Cycles per ISR of the firmware ISR path, every line once (static)."""
    per_fn = {}
    for path, fn in FIRMWARE_ISR:
        per_fn[f"{Path(path).name}:{fn}"] = sum(line_cycles(count_line(ln, inl))
                                              for ln in function_body(path, fn))
    # each firmware function is one call from its caller (isr_control is the
    # interrupt itself: its entry and exit are ISR_ENTRY_EXIT)
    calls = (len(FIRMWARE_ISR) - 1) * OTHER_COST["call"]
    return ISR_ENTRY_EXIT + calls + sum(per_fn.values()), per_fn


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


def parse_dump(args):
    """{path: {line: count}} of one sample's gcov dump (src/ and include/ only)."""
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
    r = subprocess.run(["gcov", "-t", "-j"] + [str(g) for g in gcdas], capture_output=True,
                       text=True, cwd=str(sdir))
    if r.returncode != 0:
        raise BenchError(f"gcov failed in {sdir}: {r.stderr.strip()[:200]}")
    out = {}
    for doc in r.stdout.splitlines():
        if not doc.strip():
            continue
        for f in json.loads(doc)["files"]:
            path = Path(f["file"])
            if not path.is_absolute():
                path = (objdir / path).resolve()
            if ROOT / "src" not in path.parents and ROOT / "include" not in path.parents:
                continue
            d = out.setdefault(str(path), {})
            for ln in f["lines"]:
                if ln["count"]:
                    d[ln["line_number"]] = d.get(ln["line_number"], 0) + ln["count"]
    return out


class LineCoster:
    def __init__(self):
        self.inl = inline_functions()
        self.src = {}
        self.cache = {}

    def ops(self, path, line):
        key = (path, line)
        if key not in self.cache:
            if path not in self.src:
                self.src[path] = strip_comments(Path(path).read_text().splitlines())
            src = self.src[path]
            self.cache[key] = count_line(src[line - 1], self.inl) if line <= len(src) else {}
        return self.cache[key]

    def cost(self, lines):
        """(cycles, {module: cycles}, hot [(cycles, where, code)])"""
        total, mods, hot = 0.0, {}, []
        for path, d in lines.items():
            mod = FILE_MODULE.get(Path(path).name, GLUE)
            for ln, n in d.items():
                c = line_cycles(self.ops(path, ln)) * n
                if c:
                    total += c
                    mods[mod] = mods.get(mod, 0.0) + c
                    hot.append((c, f"{Path(path).relative_to(ROOT)}:{ln}",
                                self.src[path][ln - 1].strip()))
        return total, mods, hot


def iq_cost(counts, names, fn_rows=None, fn_names=None):
    """(cycles, {module: cycles}) of per-operation counts."""
    w = [TI_CYCLES.get(n, ASSUMED_CYCLES.get(n)) for n in names]
    if None in w:
        missing = [n for n, x in zip(names, w) if x is None]
        raise BenchError(f"no cycle count for {missing}: add them to ASSUMED_CYCLES")
    w = [x + ROM_WAIT * ROM_TABLE_READS.get(n, 0) for n, x in zip(names, w)]
    total = sum(a * b for a, b in zip(w, counts))
    mods = {}
    if fn_rows is not None:
        attributed = [0] * len(names)
        for fn, row in zip(fn_names, fn_rows):
            m = FN_MODULE.get(fn, GLUE)
            c = sum(a * b for a, b in zip(w, row))
            if c:
                mods[m] = mods.get(m, 0.0) + c
            attributed = [a + b for a, b in zip(attributed, row)]
        rest = sum(a * max(0, b - c) for a, b, c in zip(w, counts, attributed))
        if rest:
            mods[GLUE] = mods.get(GLUE, 0.0) + rest
    return total, mods


def estimate(build, config, uniform, jobs):
    exe, objdir = isr_cost_paths(build)
    coster = LineCoster()
    fixed, fw_fns = firmware_cost(coster.inl)
    with tempfile.TemporaryDirectory(prefix="bench_isr_") as tmp:
        r = subprocess.run([str(exe), str(config), "--out", tmp, "--uniform", str(uniform)],
                           capture_output=True, text=True)
        if r.returncode != 0:
            raise BenchError(f"isr_cost failed: {r.stderr.strip()}")
        data = json.loads(r.stdout)
        samples = data["samples"]
        if not samples:
            raise BenchError("isr_cost sampled no ISR")
        with cf.ThreadPoolExecutor(max_workers=jobs) as ex:
            dumps = list(ex.map(parse_dump, [(Path(tmp) / s["dir"], objdir) for s in samples]))
    names, fn_names = data["iqmath_names"], data["functions"]
    classes = {}
    for s, lines in zip(samples, dumps):
        c_other, m_other, _ = coster.cost(lines)
        c_iq, m_iq = iq_cost(s["iq"], names, s["fn_iq"], fn_names)
        s["cycles"] = fixed + c_other + c_iq
        classes.setdefault((s["state"], s["slot"]), []).append((s, lines))
    states = {}
    for (state, slot), members in sorted(classes.items()):
        # worst: every line at its largest count, every IQmath op at its largest count
        wl, wiq, wfn = {}, [0] * len(names), [[0] * len(names) for _ in fn_names]
        for s, lines in members:
            for path, d in lines.items():
                t = wl.setdefault(path, {})
                for ln, n in d.items():
                    t[ln] = max(t.get(ln, 0), n)
            wiq = [max(a, b) for a, b in zip(wiq, s["iq"])]
            wfn = [[max(a, b) for a, b in zip(x, y)] for x, y in zip(wfn, s["fn_iq"])]
        c_other, m_other, hot = coster.cost(wl)
        c_iq, m_iq = iq_cost(wiq, names, wfn, fn_names)
        worst = fixed + c_other + c_iq
        mods = dict(m_other)
        for k, v in m_iq.items():
            mods[k] = mods.get(k, 0.0) + v
        mods[FIRMWARE] = fixed
        uni = [s["cycles"] for s, _ in members if s["uniform"]] or \
              [s["cycles"] for s, _ in members]
        st = states.setdefault(state, {"classes": {}})
        st["classes"][slot] = {"worst": worst, "mean": sum(uni) / len(uni),
                               "max_sample": max(s["cycles"] for s, _ in members),
                               "samples": len(members), "modules": mods, "hot": hot}
    out = {}
    for state, st in states.items():
        cl = st["classes"]
        wslot = max(cl, key=lambda k: cl[k]["worst"])
        out[state] = {"mean": sum(c["mean"] for c in cl.values()) / data["slots"],
                      "worst": cl[wslot]["worst"], "worst_slot": wslot,
                      "isrs": data["state_isrs"].get(state, 0), "classes": cl}
    return {"states": out, "fixed": fixed, "firmware_functions": fw_fns,
            "slots": data["slots"], "isrs": data["isrs"]}


def summary(res):
    st = {k: v for k, v in res["states"].items() if k in STATES}
    return {"states": {k: {"mean": int(round(v["mean"])), "worst": int(round(v["worst"]))}
                       for k, v in st.items()},
            "worst_isr_cycles": int(round(max(v["worst"] for v in st.values()))),
            "total_cycles": int(round(max(v["mean"] for v in st.values())))}


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
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 2)
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
            m = merged.setdefault(k, {"mean": 0, "worst": 0})
            m["mean"] = max(m["mean"], v["mean"])
            m["worst"] = max(m["worst"], v["worst"])
    out = {"total_cycles": first["total_cycles"], "budget_cycles": BUDGET, "goal_cycles": GOAL,
           "worst_isr_cycles": max(s["worst_isr_cycles"] for s in sums.values()),
           "states": merged, "sequences": sums,
           "fixed_cycles": int(round(next(iter(results.values()))["fixed"]))}
    if a.json:
        print(json.dumps(out, indent=1))
        return 0
    for (name, cfg), r in zip(configs, results.values()):
        print(f"{name} ({cfg}): cycles per ISR (C28x, 150 MHz), slots of the schedule: "
              f"{r['slots']}")
        print(f"  {'state':<11} {'ISRs':>7} {'mean':>7} {'worst':>7}  worst slot: its modules")
        for state in STATES:
            if state not in r["states"]:
                continue
            v = r["states"][state]
            cl = v["classes"][v["worst_slot"]]
            mods = ", ".join(f"{k} {c:.0f}" for k, c in
                             sorted(cl["modules"].items(), key=lambda kv: -kv[1]) if c >= 1)
            print(f"  {state:<11} {v['isrs']:>7} {v['mean']:>7.0f} {v['worst']:>7.0f}  "
                  f"slot {v['worst_slot']}: {mods}")
        s = sums[name]
        print(f"  worst single ISR {s['worst_isr_cycles']} cycles = "
              f"{100 * s['worst_isr_cycles'] / BUDGET:.1f} % of {BUDGET}; goal {GOAL}: "
              f"{'met' if s['worst_isr_cycles'] <= GOAL else 'NOT met'}")
        if a.hot:
            worst_state = max(r["states"], key=lambda k: r["states"][k]["worst"])
            v = r["states"][worst_state]
            print(f"  costliest lines of the worst ISR ({worst_state}, slot {v['worst_slot']}):")
            for c, where, code in sorted(v["classes"][v["worst_slot"]]["hot"],
                                         reverse=True)[:a.hot]:
                print(f"    {c:6.0f}  {where:34s} {code[:60]}")
    fw = next(iter(results.values()))
    print(f"fixed per ISR {fw['fixed']:.0f} cycles: entry/exit {ISR_ENTRY_EXIT}, firmware "
          + ", ".join(f"{k} {v:.0f}" for k, v in fw["firmware_functions"].items()))
    print("cycles per operation: " + ", ".join(f"{k} {v}" for k, v in OTHER_COST.items()) +
          f", peripheral register access +{PERIPH_WAIT}; assumed IQmath: " +
          ", ".join(f"{k} {v}" for k, v in ASSUMED_CYCLES.items()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
