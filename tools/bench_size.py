#!/usr/bin/env python3
"""Code and RAM size of the F2812 firmware, estimated with a stand-in compiler,
and the placement of the control ISR's call graph in RAM (`ramfuncs`, `ramfuncs_slow`).

TI's cl2000 cannot be installed here, so the code is compiled for Thumb-2
(Debian's gcc-arm-none-eabi, -mthumb -mcpu=cortex-m3) and its bytes are
converted to C28x 16-bit words by an assumed factor (below).  An estimate,
not a measurement: the cl2000 link's .map file is the measurement.

What is compiled: every file of src/ and the firmware's portable and HAL files
(firmware/*.c; the register-level ones against the TI-register shim of
tests/target/ti_shim, as the target_fw_syntax_* tests compile them), with
MATH_TYPE=IQ_MATH, GLOBAL_Q=24 and the host IQmath header standing in for TI's
IQmathLib.h in its IQMATH_TI_CALLS mode: every operation that TI's
IQmathLib.h makes a library call is a call to TI's entry of that Q
(ti_IQ24div ...), so the call sites are sized as on the target and the call
graph names the IQmath functions reached, each counted at the size of its
code in TI's own IQmath_coff.lib (TI_IQMATH_WORDS: a measurement of TI's
library, tools/target/iqmath_lib_sizes.py, not a stand-in);
with board_config.c when given (--board-config).  code_start.asm and TI's
DSP281x_GlobalVariableDefs.c (register frames only, no code) are not counted.

Two compiles, both -ffunction-sections -fdata-sections -fcallgraph-info=su:
  * the SIZE compile, -Os: the stand-in of the firmware build's cl2000
    `-O2 --opt_for_speed=2` (full optimisation, code size favoured at a low
    risk to speed, SPRU514 "Controlling code size versus speed"; chosen so
    that the ISR path fits the on-chip SARAM: with gcc -O2 the ISR path is
    about 24 % larger, 11 087 words instead of 8 900), with gcc's automatic inlining
    of functions not declared `inline` turned off (-fno-inline-functions,
    -fno-inline-small-functions, -fno-inline-functions-called-once) and no
    IPA cloning: cl2000 inlines automatically only from -O3 (SPRU514,
    "Automatic inline expansion"), so every C function stays a function, as
    on the target.  Sizes (symbol sizes) and stack frames come from it.
  * the GRAPH compile, -O1 -fno-inline: not even `static inline` functions
    are inlined, so its call graph has every function of the source that the
    ISR can reach whatever the compiler inlines.  The linker include
    (--write-isr-cmd) lists those: a superset of what cl2000 emits as
    functions (a name that cl2000 inlined matches no input section, which
    the linker accepts).

The ISR path: every function reachable in the call graph (gcc
-fcallgraph-info) from the two interrupt entries of firmware/isr.c: the
control ISR `isr_control` (ADCINT, which calls drive_isr) and the slow ISR
`isr_slow` (INT14, which calls drive_slow_isr and the data log), nothing else: init,
background and float code are not on it unless the ISR calls them (checked:
no soft-float helper may be reachable).  The call graph has no function
pointers to miss: the core has none, and every interrupt entry is a root.
It is split in two sets: FAST, every function the control ISR reaches, placed
in `ramfuncs` (linker/F2812_isr_path.cmd), and SLOW, reached only from the
slow ISR (the slot tasks), placed in `ramfuncs_slow`
(linker/F2812_isr_slow.cmd); a function reached from both is fast.  Out of
both, the FLASH set (FLASH_ROOTS and what only they reach: CALIBRATE-only
code, state changes, faults, the sequence's step) runs from flash in the
flash image (an `#ifdef ISR_FLASH_SET_IN_RAM` block of each include, which
the RAM image defines); tools/bench_isr.py costs its wait states.  The TI
IQmath functions the ISR reaches count in the output section that #includes
F2812_isr_slow.cmd (whose last lines name their library members).

Conversion Thumb-2 bytes -> C28x words: WORDS_PER_HALFWORD (1.2) words per
Thumb-2 halfword, i.e. 0.6 words per byte.  Why: both instruction sets mix 16-
and 32-bit instructions (SPRU430: C28x instructions are one or two 16-bit
words; Thumb-2: one or two halfwords), so one halfword = one word is the first
guess.  The C28x needs more instructions where it has fewer registers: one
32-bit accumulator (ACC) with P and XT for 32-bit data and XAR0-XAR7 for
addresses (SPRU430, SPRAC71 "C28x architecture overview"), against Thumb-2's
13 general registers, so intermediate results of a long fixed-point
expression are stored and reloaded; the large memory model loads 22-bit
addresses with two-word MOVL XARn,#imm (SPRAC71 "C28x memory models");
64-bit intermediate values (the core's rounding and block floating point
helpers) have no 64-bit ALU on either, but Thumb-2 has 4 registers to hold
two of them.  Against that, the C28x does IQ products in a few one-word
instructions (IMPYL/QMPYL, TI IQmath _IQmpy: about 5 cycles) and operates
directly on memory (loc32 operands), so factor 1 is possible; 1.2 errs high
and is stated in every output.

RAM capacities come from the linker command file the firmware build uses
(--linker-cmd, default linker/F2812_flash.cmd): every RAM range is counted
with what it holds (the RUN ranges of `ramfuncs` and `ramfuncs_slow`, the
ranges of `.ebss`, `dlog`), the stack against --stack_size; in the RAM image
(linker/F2812_ram.cmd) the rest of the program against its external RAM.  .ebss is computed in C28x words from the declared
types of every global variable (tools/bench_ram.py's C28x layout of the
structures, drive_t included), not from the Thumb-2 sizes.

Usage:
  bench_size.py [--json] [--build DIR] [--linker-cmd F] [--board-config F]
                [--factor X] [--check] [--write-isr-cmd F | --check-isr-cmd F]
                [--slow-cmd S]
--check [ramfuncs|data|all]: exit 1 when (ramfuncs) a RAM range that runs
ramfuncs or ramfuncs_slow holds > 70 % of its size, or a soft-float helper is
reachable from the ISR, or (RAM image) the rest of the program > 70 % of its
external RAM; (data) a range holding .ebss or dlog > 70 %, or the estimated
stack > 70 % of --stack_size (firmware/CMakeLists.txt).
--write-isr-cmd F: write the fast set to F and the slow set to --slow-cmd
(default next to F: F2812_isr_path.cmd -> F2812_isr_slow.cmd).
--check-isr-cmd F [--slow-cmd S]: exit 1 when a committed include differs
from what the call graph gives now (naming a function in the wrong set), or
when the firmware's `#pragma CODE_SECTION(f, "ramfuncs")` and the ISR path
disagree.
"""
import argparse
import concurrent.futures as cf
import difflib
import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tools"))
sys.path.insert(0, str(ROOT / "tools" / "target"))
import bench_ram            # noqa: E402  (C28x layout of the structures)
import check_linker_cmd     # noqa: E402  (the linker command file parser)

CC = "arm-none-eabi-gcc"
NM = "arm-none-eabi-nm"
ARCH = ["-mthumb", "-mcpu=cortex-m3"]
WORDS_PER_HALFWORD = 1.2           # see the module docstring
FAST_ROOTS = ("isr_control",)      # firmware/isr.c: the control ISR, ADCINT (PIE 1.6)
SLOW_ROOTS = ("isr_slow",)         # firmware/isr.c: the slow ISR, INT14 forced by it
ISR_ROOTS = FAST_ROOTS + SLOW_ROOTS
# the slow ISR (firmware/isr.c): what only it reaches is in `ramfuncs_slow`
SLOW_DISPATCH = "isr_slow"
SLOW_TASK = "drive_slow_task"      # src/app/drive_slow.c: must be on the slow side
LIMIT = 0.70                       # the goal: 30 % of every RAM block kept spare
# (the flash image's CTests check it; the RAM image, which keeps the flash set
# on chip too, is checked at --limit 0.90)
SIZE_FLAGS = ["-Os", "-fno-inline-functions", "-fno-inline-small-functions",
              "-fno-inline-functions-called-once", "-fno-ipa-cp", "-fno-ipa-sra",
              "-fno-partial-inlining", "-fno-ipa-icf"]
GRAPH_FLAGS = ["-O1", "-fno-inline"]
# firmware functions in `ramfuncs` that are not on the ISR path, and why
RAMFUNCS_NOT_ISR = {
    "flash_init": "reprograms the flash wait states: must not run from flash (SPRU078)",
}
# ISR-path functions that run from FLASH on purpose in the flash image (the
# FLASH SET), each with why flash's wait states are affordable there: it runs
# only in CALIBRATE, on a state change or after a fault, or (the sequence's
# step) once per slow period in a slot that has the cycles.  tools/bench_isr.py
# costs every line of them at FLASH_FACTOR, so the worst ISRs include the
# price.  What only these reach goes with them (flash_set()).  Why not more:
# the 30 % spare of every RAM block needs about this much out of the SARAM
# (docs/board.md), and the rest of the slow ISR from flash would take its
# worst ISR past the 3 000-cycle goal.  Generated into an
# `#ifdef ISR_FLASH_SET_IN_RAM` block at the end of each ISR include: the
# flash image leaves them in .text (flash); the RAM image defines
# ISR_FLASH_SET_IN_RAM and keeps them on chip (its .text is in external RAM
# at the XINTF's reset timing, far slower than flash).
FLASH_ROOTS = {
    "drive_safety_test_verdict": "slot SAFETY, CALIBRATE only (and once after it): the sensor "
                                 "test's verdicts (sensor_test_judge)",
    "phase_current_cal_start": "control ISR, CALIBRATE only (calibrate(): seq.calibrating): "
                               "the current offsets, the bridge off",
    "phase_current_cal_step": "control ISR, CALIBRATE only (as phase_current_cal_start)",
    "drive_vi_slow": "slot SEQUENCE, CALIBRATE with the bridge's voltage-error test "
                     "(seq.vi_test)",
    "id_sequence_step": "slot SEQUENCE, once per slow period (1.875 kHz): the identification's "
                        "state machine, whose outputs act from the next control ISR on",
    "state_change": "slot SEQUENCE, once per state change (the adaptation's resets)",
    "standstill": "slot SEQUENCE, the adaptive sequence's MAGNETIZE (the standstill test)",
    "take_set": "slot SEQUENCE, once per adapted set (adapt.box.ready)",
    "drive_static_slow": "slot SEQUENCE, the standstill sequence's INJECT only (its multisine "
                         "and lock-in: standstill_lf_step)",
    "stall_check_decide": "slot FILTERS_C, only after the encoder's frozen test tripped",
    "excite": "slot SEQUENCE, the adaptive sequence's RUN while its verdict is owed (a free "
              "shaft's excitation, drive_adapt.c)",
    "tr_track_step": "slot OBSERVER_B, the adaptive sequence's RUN only (the Rr/Tr tracker), in "
                     "a slot with room in every state",
    "clear_state": "slot SAFETY, when the model check re-arms (the bridge off, a window with "
                   "the bridge off in it)",
    "period_mean_window": "slot FILTERS_A, only with [ident] period_mean = 1 (an option of "
                          "the paper's sequence, off by default): the period-mean rows' window",
    "flux_obs_step_a": "slot OBSERVER_A only (orientation 1): the slot with the most room in "
                       "every state (1 385 cycles in RAM; from flash it stays the lightest "
                       "but two), which frees H0 for the sensor test (FAST_IN_SLOW_RAM)",
}
FLASH_SET_DEFINE = "ISR_FLASH_SET_IN_RAM"
FLASH_TEXT = ".text"                # where the flash image leaves the flash set
# C28x interrupt context on the stack, 16-bit words: the automatic save
# (T, ST0, AH, AL, PH, PL, AR1, AR0, DP, ST1, DBGSTAT, IER, PC: 14 words,
# SPRU430 "Interrupt context save") and the compiler's interrupt prologue
# (the registers the hardware does not save: XAR2-XAR7, XT, RPC, AR1H:AR0H,
# about 24 words), as tools/bench_isr.py counts them
ISR_CONTEXT_WORDS = 14 + 24
SOFT_FLOAT = re.compile(r"^__aeabi_[fd]|^__(add|sub|mul|div)[sd]f3$|^__float|^__fix")
# TI's IQmath library functions (the host IQmathLib.h's IQMATH_TI_CALLS mode
# names each call ti_IQ<N><op>), in C28x words: the size of the `IQmath`
# code section of each object of TI's IQmath_coff.lib (C2000Ware core SDK,
# libraries/math/IQmath/c28/lib; read from the COFF section headers by
# tools/target/iqmath_lib_sizes.py), the largest over N = 1..30 (they differ
# by at most 5 words).  A measurement of TI's code, not a stand-in; the
# seed tables they read (IQmathTables) are in the F2812's boot ROM.
TI_IQMATH_CALL = re.compile(r"^ti_IQ(\d+)(\w+)$")
TI_IQMATH_WORDS = {
    "rmpy": 14, "rsmpy": 22, "mpyI32int": 17, "mpyI32frac": 20, "int": 9, "frac": 11,
    "div": 71, "sqrt": 66, "isqrt": 71, "mag": 96, "sin": 50, "cos": 48, "sinPU": 42,
    "cosPU": 40, "atan2": 127, "atan2PU": 140, "toF": 20,
}
# stack of one IQmath call below its caller's frame: the return address
# (LCR pushes RPC, 2 words, SPRU430) and at most 2 saved words (TI's
# routines keep their work in ACC, P, XT and XAR4-7, which the caller saves)
TI_IQMATH_STACK_WORDS = 4


def sources(board_config=None):
    src = sorted((ROOT / "src").rglob("*.c"))
    fw = sorted((ROOT / "firmware").glob("*.c"))
    extra = [Path(board_config).resolve()] if board_config else []
    return src + fw + extra


def cflags():
    return ARCH + ["-std=c99", "-ffunction-sections", "-fdata-sections",
                   "-fcallgraph-info=su", "-DMATH_TYPE=IQ_MATH", "-DGLOBAL_Q=24",
                   # TI's IQmath library calls as calls (host IQmathLib.h)
                   "-DIQMATH_TI_CALLS",
                   "-Wno-unknown-pragmas",
                   # C28x inline assembly (flash.c's RPT || NOP) means nothing here
                   "-D__asm(x)=",
                   "-I", str(ROOT / "include"), "-I", str(ROOT / "firmware"),
                   "-I", str(ROOT / "tests/target/ti_shim"),
                   "-I", str(ROOT / "host_sim/iqmath")]


def compile_all(srcs, outdir, flags):
    outdir = Path(outdir).resolve()
    outdir.mkdir(parents=True, exist_ok=True)
    stems = [s.stem for s in srcs]
    dup = {s for s in stems if stems.count(s) > 1}
    if dup:
        raise SystemExit(f"bench_size: two sources named {sorted(dup)}: object names collide")

    def one(s):
        obj = outdir / (s.stem + ".o")
        r = subprocess.run([CC] + cflags() + flags + ["-c", str(s), "-o", str(obj)],
                           cwd=outdir, capture_output=True, text=True)
        if r.returncode != 0:
            raise SystemExit(f"bench_size: {CC} failed on {s}:\n{r.stderr}")
        return obj

    with cf.ThreadPoolExecutor(max_workers=2) as ex:
        return list(ex.map(one, srcs))


class Graph:
    """The call graph of one compile: functions defined (per translation unit,
    static ones qualified by their file), their size, stack frame and where
    they are defined, the edges, and the data of every object."""

    def __init__(self, objs):
        self.func = {}      # title -> dict(name, tu, file, stack, bytes)
        self.edges = {}     # title -> set of titles or external names
        self.byname = {}    # name -> [titles of non-static definitions]
        self.sizes = {}     # (tu, name) -> bytes
        self.data = []      # (tu, name, kind, bytes): kind b/d (RAM) or r (const)
        self.sections = {}  # tu -> {section: bytes}
        node = re.compile(r'node: \{ title: "([^"]+)" label: "([^"\\]+)\\n([^"\\]+):\d+:\d+'
                          r'(?:\\n(\d+) bytes \(([a-z, ]+)\))?"( shape : ellipse)?')
        edge = re.compile(r'edge: \{ sourcename: "([^"]+)" targetname: "([^"]+)"')
        for obj in objs:
            tu = obj.stem
            ci = obj.with_suffix(".ci")
            text = ci.read_text()
            for m in node.finditer(text):
                title, name, deffile, stack, qual, ext = m.groups()
                if ext:
                    continue
                self.func[title] = {"name": name, "tu": tu, "file": os.path.normpath(deffile),
                                    "stack": int(stack or 0), "dynamic": "dynamic" in (qual or "")}
                if ":" not in title.replace(str(ROOT), ""):
                    self.byname.setdefault(name, []).append(title)
            for m in edge.finditer(text):
                self.edges.setdefault(m.group(1), set()).add(m.group(2))
            out = subprocess.run([NM, "-S", "--defined-only", str(obj)], capture_output=True,
                                 text=True, check=True).stdout
            for line in out.splitlines():
                p = line.split()
                if len(p) == 4 and p[2] in "tT":
                    self.sizes[(tu, p[3])] = int(p[1], 16)
                elif len(p) == 4 and p[2] in "bBdDrRC":
                    self.data.append((tu, p[3], p[2].lower(), int(p[1], 16)))
            out = subprocess.run(["arm-none-eabi-size", "-A", str(obj)], capture_output=True,
                                 text=True, check=True).stdout
            secs = {}
            for line in out.splitlines()[2:]:
                p = line.split()
                if len(p) >= 2 and p[1].isdigit():
                    secs[p[0]] = int(p[1])
            self.sections[tu] = secs
        for t, f in self.func.items():
            f["bytes"] = self.sizes.get((f["tu"], f["name"]), 0)

    def resolve(self, target):
        """A call target: a title defined here, or an external name."""
        if target in self.func:
            return target
        titles = self.byname.get(target, [])
        if len(titles) > 1:
            raise SystemExit(f"bench_size: {target} defined twice: {titles}")
        return titles[0] if titles else None

    def roots(self, names):
        out = []
        for n in names:
            ts = [t for t, f in self.func.items() if f["name"] == n]
            if not ts:
                raise SystemExit(f"bench_size: root {n} not found in the call graph")
            out += ts
        return out

    def reach(self, roots, stop=lambda f: False):
        """(functions reached, external names reached).  Below a function for
        which stop() holds, the walk does not descend (the host IQmathLib.h's
        inline helpers call nothing the target has)."""
        seen, ext, todo = set(), set(), list(roots)
        while todo:
            t = todo.pop()
            if t in seen:
                continue
            seen.add(t)
            if stop(self.func[t]):
                continue
            for tgt in self.edges.get(t, ()):
                r = self.resolve(tgt)
                if r is None:
                    ext.add(tgt)
                elif r not in seen:
                    todo.append(r)
        return seen, ext

    def deepest(self, root, stop=lambda f: False):
        """The largest sum of stack frames (bytes) along a call chain from root."""
        memo, active = {}, set()

        def depth(t):
            if t in memo:
                return memo[t]
            if t in active:
                raise SystemExit(f"bench_size: recursion through {self.func[t]['name']}")
            active.add(t)
            sub = 0
            if not stop(self.func[t]):
                for tgt in self.edges.get(t, ()):
                    r = self.resolve(tgt)
                    if r is not None:
                        sub = max(sub, depth(r))
            active.discard(t)
            memo[t] = self.func[t]["stack"] + sub
            return memo[t]
        return depth(root)


def rel(path):
    try:
        return str(Path(path).resolve().relative_to(ROOT))
    except ValueError:
        return str(path)


def is_iqmath(f):
    return rel(f["file"]).startswith("host_sim/iqmath/")


def ti_iqmath(ext):
    """{TI name (_IQ24div): C28x words} of the IQmath library calls among the
    external names `ext` (ti_IQ<N><op> in the compile, IQMATH_TI_CALLS)."""
    out = {}
    for e in sorted(ext):
        m = TI_IQMATH_CALL.match(e)
        if m:
            if m.group(2) not in TI_IQMATH_WORDS:
                raise SystemExit(f"bench_size: no size for TI's IQmath {e[3:]} (TI_IQMATH_WORDS)")
            out[e[2:]] = TI_IQMATH_WORDS[m.group(2)]
    return out


def words(nbytes, factor):
    """Thumb-2 code bytes -> C28x words (nbytes / 2 halfwords x factor), rounded up."""
    return int(-(-nbytes * factor // 2))


# --- the linker command file -------------------------------------------------
def linker_plan(path):
    """{'ranges': {name: length}, 'ramfuncs_run': [names], 'place': {section: [names]}}"""
    text = Path(path).read_text()
    ranges, sections = check_linker_cmd.parse(text)
    lengths = {r[0]: r[3] for r in ranges}
    place, contents = {}, {}
    body = check_linker_cmd.strip_comments(sections)
    # one output section per entry: NAME [: {..}] (> | >> | RUN =) R1 [| R2 ...]
    for m in re.finditer(r"^\s*([.\w]+)\s*:(.*?)(?=^\s*[.\w]+\s*:|\Z)", body, re.S | re.M):
        name, spec = m.group(1), m.group(2)
        contents[name] = spec
        run = re.search(r"RUN\s*=\s*(\w+(?:\s*\|\s*\w+)*)", spec)
        tgt = run or re.search(r">>?\s*(\w+(?:\s*\|\s*\w+)*)", spec)
        if tgt:
            place[name] = re.split(r"\s*\|\s*", tgt.group(1).strip())
    for need in ("ramfuncs", "ramfuncs_slow"):
        if need not in place:
            raise SystemExit(f"bench_size: {path} places no {need}")
    # TI's IQmath functions the ISR reaches come with the slow set's include
    # (IQMATH_MEMBERS); the rest of the IQmath section goes to an output
    # section of its own (flash, or external RAM in the RAM image)
    iq = [n for n, c in contents.items() if SLOW_INCLUDE_NAME in c]
    if len(iq) != 1:
        raise SystemExit(f"bench_size: {path}: one output section must #include "
                         f"{SLOW_INCLUDE_NAME}, not {iq}")
    if "IQmath" not in place:
        raise SystemExit(f"bench_size: {path} places no IQmath output section (the IQmath "
                         "functions off the ISR path)")
    # the ISR path's flash set: on chip only where the file defines FLASH_SET_DEFINE
    flash_set_in_ram = bool(re.search(rf"(?m)^\s*#define\s+{FLASH_SET_DEFINE}\b", text))
    return {"ranges": lengths, "place": place, "file": rel(path), "iqmath_in": iq[0],
            "text_in": place.get(".text", []), "flash_set_in_ram": flash_set_in_ram}


def stack_size():
    """The --stack_size of the firmware's link (firmware/CMakeLists.txt)."""
    m = re.search(r"--stack_size=(0x[0-9A-Fa-f]+|\d+)",
                  (ROOT / "firmware" / "CMakeLists.txt").read_text())
    if not m:
        raise SystemExit("bench_size: no --stack_size in firmware/CMakeLists.txt")
    return int(m.group(1), 0)


def runtime_sizes(names):
    """Thumb-2 bytes of the run-time library functions the image calls
    (libgcc's soft float, newlib's libm/libc), standing in for TI's
    rts2800_ml.lib (float emulation, 64-bit division, memcpy)."""
    out = {}
    libs = []
    for lib in ("libgcc.a", "libc.a", "libm.a"):
        r = subprocess.run([CC] + ARCH + [f"-print-file-name={lib}"], capture_output=True,
                           text=True)
        if r.returncode == 0 and os.path.isabs(r.stdout.strip()):
            libs.append(r.stdout.strip())
    for lib in libs:
        nm = subprocess.run([NM, "-S", "--defined-only", lib], capture_output=True, text=True)
        for line in nm.stdout.splitlines():
            p = line.split()
            if len(p) == 4 and p[2] in "tTW" and p[3] in names and p[3] not in out:
                out[p[3]] = int(p[1], 16)
    return out


# --- .ebss in C28x words -----------------------------------------------------
def c28x_layout():
    hdrs = (sorted((ROOT / "include").glob("*.h")) + sorted((ROOT / "firmware").glob("*.h"))
            + [ROOT / "host_sim/iqmath/IQmathLib.h"])
    structs, enums, consts = bench_ram.parse_headers(hdrs)
    for h in hdrs:   # typedef struct tag name;  ->  name is "struct tag"
        t = bench_ram.strip_comments(h.read_text())
        for m in re.finditer(r"typedef\s+struct\s+(\w+)\s+(\w+)\s*;", t):
            if "struct " + m.group(1) in structs:
                structs[m.group(2)] = structs["struct " + m.group(1)]
    return bench_ram.Layout(structs, enums, consts)


def global_words(layout, tu_file, name):
    """C28x words of the file-scope variable `name` from its declaration."""
    text = bench_ram.strip_comments(Path(tu_file).read_text())
    m = re.search(r"^\s*(?:static\s+)?(?:volatile\s+)?(?:const\s+)?(\w+)\s*(\*?)\s*(?:volatile\s+)?"
                  + re.escape(name) + r"\s*((?:\[[^\]]+\])*)\s*[;=]", text, re.M)
    if not m:
        raise SystemExit(f"bench_size: no declaration of {name} in {rel(tu_file)}")
    typ, ptr, dims = m.groups()
    w, _al = layout.type_size(typ, bool(ptr))
    for d in re.findall(r"\[([^\]]+)\]", dims):
        d = d.strip().rstrip("uU")
        w *= int(d, 0) if re.fullmatch(r"0x[0-9a-fA-F]+|\d+", d) else layout.consts[d]
    return w


def ebss(graph, srcs, layout):
    """[(tu, name, words, section)] of every RAM variable; section 'dlog' for
    the variables the firmware puts there with #pragma DATA_SECTION."""
    by_tu = {s.stem: s for s in srcs}
    rows = []
    for tu, name, kind, _b in graph.data:
        if kind == "r":
            continue
        src = by_tu[tu]
        w = global_words(layout, src, name)
        sec = ".ebss"
        m = re.search(r"#pragma\s+DATA_SECTION\s*\(\s*" + re.escape(name) + r'\s*,\s*"(\w+)"',
                      src.read_text())
        if m:
            sec = m.group(1)
        rows.append((tu, name, w, sec))
    return rows


# --- the linker includes of the ISR path -------------------------------------
PRAGMA = re.compile(r'#pragma\s+CODE_SECTION\s*\(\s*(\w+)\s*,\s*"(\w+)"\s*\)')
FAST_SECTION, SLOW_SECTION = "ramfuncs", "ramfuncs_slow"
SLOW_INCLUDE_NAME = "F2812_isr_slow.cmd"
# the library whose members hold TI's IQmath functions (C2000Ware's; the
# firmware build links it by that name, firmware/CMakeLists.txt)
IQMATH_LIB = "IQmath_coff.lib"


def pragma_sections():
    """{function: (section, file)} of the firmware's #pragma CODE_SECTION
    into ramfuncs or ramfuncs_slow."""
    out = {}
    for f in sorted((ROOT / "firmware").glob("*.c")):
        for m in PRAGMA.finditer(f.read_text()):
            if m.group(2) in (FAST_SECTION, SLOW_SECTION):
                out[m.group(1)] = (m.group(2), rel(f))
    return out


def pragma_ramfuncs():
    """{function: file} of the firmware's #pragma CODE_SECTION(f, "ramfuncs")."""
    return {f: p for f, (s, p) in pragma_sections().items() if s == FAST_SECTION}


def isr_sets(graph):
    """(fast, slow) titles of the ISR path, the host IQmathLib.h's inline
    helpers included where they are reached: fast = reachable from the control
    ISR, slow = reachable from the slow ISR only (the slot tasks)."""
    fast, _ = graph.reach(graph.roots(FAST_ROOTS), stop=is_iqmath)
    every, _ = graph.reach(graph.roots(ISR_ROOTS), stop=is_iqmath)
    if not any(graph.func[t]["name"] == SLOW_TASK for t in every - fast):
        raise SystemExit(f"bench_size: {SLOW_TASK} is not reachable from {SLOW_ROOTS} alone")
    return fast, every - fast


def flash_set(graph):
    """Titles of the ISR path that run from flash in the flash image: the
    FLASH_ROOTS and what only they reach (not the host IQmath helpers)."""
    fast, slow = isr_sets(graph)
    isr = fast | slow
    roots = [t for t in isr if graph.func[t]["name"] in FLASH_ROOTS]
    missing = set(FLASH_ROOTS) - {graph.func[t]["name"] for t in roots}
    if missing:
        raise SystemExit(f"bench_size: FLASH_ROOTS {sorted(missing)} are not on the ISR path")
    below, _ = graph.reach(roots, stop=is_iqmath)
    # everything the ISRs reach without entering a root
    keep, _ = graph.reach(graph.roots(ISR_ROOTS),
                          stop=lambda f: is_iqmath(f) or f["name"] in FLASH_ROOTS)
    keep -= set(roots)
    return {t for t in below - keep if not is_iqmath(graph.func[t])
            and not rel(graph.func[t]["file"]).startswith("firmware/")}


# Flash-set roots of the slow ISR whose flash set the RAM image keeps in the
# fast include's block (L0+L1, `ramfuncs`) instead of H0: the RAM image's H0
# holds the slow ISR's RAM set and the rest of its flash set at 90 %, L0+L1
# has room.  Where a function runs changes nothing but its speed.
FLASH_SET_IN_FAST = ("drive_static_slow",)


def flash_set_in_fast(graph):
    """The flash-set titles that only FLASH_SET_IN_FAST's roots reach."""
    flash = flash_set(graph)
    roots = [t for t in flash if graph.func[t]["name"] in FLASH_SET_IN_FAST]
    below, _ = graph.reach(roots, stop=is_iqmath)
    others = [t for t in flash if graph.func[t]["name"] in FLASH_ROOTS
              and graph.func[t]["name"] not in FLASH_SET_IN_FAST]
    rest, _ = graph.reach(others, stop=is_iqmath)
    return (below & flash) - rest


# Control-ISR roots whose code runs from H0 (`ramfuncs_slow`'s range) instead
# of L0+L1: the sensor test's pulses and the bridge test's voltage, CALIBRATE
# only, whose per-ISR cost from flash made CALIBRATE the worst control ISR;
# L0+L1 has no room for them within the 70 % rule, H0 has once
# flux_obs_step_a runs from flash.  Both ranges are zero-wait SARAM: where a
# function runs changes nothing but the block it fills.
FAST_IN_SLOW_RAM = ("drive_safety_test_period",)
# The RAM image (linker/F2812_ram.cmd defines it) keeps them in L0+L1: its H0
# holds the slow ISR's flash set too.
RAM_IMAGE_DEFINE = "ISR_RAM_IMAGE"


def fast_in_slow_ram(graph):
    """The fast-set titles that only FAST_IN_SLOW_RAM's roots reach (the
    control ISR reaches nothing else of them), firmware and IQmath aside."""
    fast, _slow = isr_sets(graph)
    roots = [t for t in fast if graph.func[t]["name"] in FAST_IN_SLOW_RAM]
    missing = set(FAST_IN_SLOW_RAM) - {graph.func[t]["name"] for t in roots}
    if missing:
        raise SystemExit(f"bench_size: FAST_IN_SLOW_RAM {sorted(missing)} are not on the "
                         "control ISR's path")
    below, _ = graph.reach(roots, stop=is_iqmath)
    keep, _ = graph.reach(graph.roots(FAST_ROOTS),
                          stop=lambda f: is_iqmath(f) or f["name"] in FAST_IN_SLOW_RAM)
    return {t for t in (below & fast) - (keep - set(roots)) if not is_iqmath(graph.func[t])
            and not rel(graph.func[t]["file"]).startswith("firmware/")}


def slow_cmd_path(fast_path):
    """The slow set's include next to the fast one: F2812_isr_path.cmd ->
    F2812_isr_slow.cmd (other names: <stem>_slow.cmd)."""
    p = Path(fast_path)
    if p.name.endswith("_isr_path.cmd"):
        return p.with_name(p.name[:-len("_isr_path.cmd")] + "_isr_slow.cmd")
    return p.with_name(p.stem + "_slow" + p.suffix)


def src_names(graph, titles):
    return {graph.func[t]["name"] for t in titles
            if not is_iqmath(graph.func[t])
            and not rel(graph.func[t]["file"]).startswith("firmware/")}


def isr_cmd_texts(graph, abi="coffabi"):
    """(fast include, slow include): the input sections of every source
    function the control ISR reaches, except the firmware's own (placed by
    #pragma) and the host IQmath's inline helpers; the slow include ends
    with the members of TI's IQmath library that hold the IQmath functions
    the ISR reaches (IQMATH_MEMBERS).  A name reached both ways is in the
    fast file only."""
    fast, slow = isr_sets(graph)
    flash = flash_set(graph)
    _seen, ext = graph.reach(graph.roots(ISR_ROOTS), stop=is_iqmath)
    prefix = "_" if abi == "coffabi" else ""
    to_slow = fast_in_slow_ram(graph) - flash
    fast_names = sorted(src_names(graph, fast - flash - to_slow))
    slow_names = sorted(src_names(graph, slow - flash) - set(fast_names))
    moved = sorted(src_names(graph, to_slow) - set(fast_names) - set(slow_names))
    # a name of the flash set that another (static) function on the path
    # shares is in RAM anyway (the input section name matches both)
    ram = set(fast_names) | set(slow_names)
    to_fast = flash_set_in_fast(graph)
    flash_fast = sorted(src_names(graph, (fast & flash) | to_fast) - ram)
    flash_slow = sorted(src_names(graph, slow & flash) - ram - set(flash_fast))

    def flash_block(names, which):
        return [
            "/*",
            f" * The {which}'s FLASH set: functions that run only in CALIBRATE, on a state",
            " * change, after a fault, or once per slow period (tools/bench_size.py",
            " * FLASH_ROOTS says why, each).",
            " * The flash image runs them from flash (.text, not named here; their wait",
            " * states costed by tools/bench_isr.py); the RAM image defines",
            f" * {FLASH_SET_DEFINE} and keeps them on chip with the rest of this set.",
            f" * {len(names)} functions.",
            " */",
            f"#ifdef {FLASH_SET_DEFINE}",
        ] + [f"*(.text:{prefix}{n})" for n in names] + ["#endif"]
    def moved_block(which):
        return [
            "/*",
            f" * FAST_IN_SLOW_RAM (tools/bench_size.py): what only {', '.join(FAST_IN_SLOW_RAM)}",
            " * reaches, the control ISR's CALIBRATE-only code: in H0 (F2812_isr_slow.cmd)",
            f" * in the flash image, in L0+L1 (F2812_isr_path.cmd) in the RAM image, which",
            f" * defines {RAM_IMAGE_DEFINE} (its H0 holds the slow ISR's flash set too).",
            f" * {len(moved)} functions.",
            " */",
            f"#{which} {RAM_IMAGE_DEFINE}",
        ] + [f"*(.text:{prefix}{n})" for n in moved] + ["#endif"]
    common = [
        " *",
        " * cl2000 --gen_func_subsections=on puts each function in its own subsection",
        " * `.text:<symbol>` (SPRU514 \"--gen_func_subsections\"; SPRU513 \"Subsections\": the",
        " * linker gathers .text and its subsections into .text unless one is placed by",
        " * name).  Symbol names: COFF ABI prefixes C names with '_', EABI does not",
        f" * (SPRU514 \"COFF ABI vs EABI\").  This file: --abi={abi}.  A static function of",
        " * the same name in two .c files would be matched in both: --check-isr-cmd refuses it.",
    ]
    fast_lines = [
        "/*",
        " * F2812_isr_path.cmd: GENERATED by tools/bench_size.py --write-isr-cmd, do not edit.",
        " * CTest target_isr_path_cmd_current fails when it differs from the call graph.",
        " *",
        " * The FAST set of the ISR path: the input sections of every function of src/",
        " * (and of the inline functions of include/ that cl2000 may emit as functions)",
        " * that the control ISR (isr_control -> drive_isr ...) can call, found in the",
        " * call graph of gcc -O1 -fno-inline (every source-level",
        " * function kept).  Included inside the `ramfuncs` output section of",
        " * F2812_flash.cmd / F2812_ram.cmd (RUN in L0+L1, copied at boot by",
        " * flash_copy_ramfuncs).  What only the slow ISR (isr_slow) reaches is in",
        " * F2812_isr_slow.cmd (`ramfuncs_slow`, RUN in H0).",
    ] + common + [
        " * The firmware's own ISR functions are in `ramfuncs` by #pragma CODE_SECTION",
        " * (checked by the same test); TI's IQmath functions by the IQmath section.",
        f" * {len(fast_names)} functions.",
        " */",
    ] + ([f"*(.text:{prefix}{n})" for n in fast_names] + moved_block("ifdef")
         + flash_block(flash_fast, "control ISR"))
    slow_lines = [
        "/*",
        " * F2812_isr_slow.cmd: GENERATED by tools/bench_size.py --write-isr-cmd, do not edit.",
        " * CTest target_isr_path_cmd_current fails when it differs from the call graph.",
        " *",
        " * The SLOW set of the ISR path: the input sections of every function of src/",
        f" * that ONLY the slow ISR {SLOW_DISPATCH} reaches (INT14, below the control ISR)",
        " * (the slot tasks: filters, observer, sequence, adaptation, tracker), found in",
        " * the call graph of gcc -O1 -fno-inline.  A function also reached on the",
        " * every-period path is in F2812_isr_path.cmd instead (but for the",
        " * FAST_IN_SLOW_RAM block below).  Included inside the",
        " * `ramfuncs_slow` output section of F2812_flash.cmd / F2812_ram.cmd (RUN in",
        " * H0 SARAM, zero wait states as L0/L1; copied at boot by flash_copy_ramfuncs).",
    ] + common + [
        f" * {len(slow_names)} functions.",
        " */",
    ] + ([f"*(.text:{prefix}{n})" for n in slow_names] + moved_block("ifndef")
         + flash_block(flash_slow, "slow ISR")
         + iqmath_members_text(ti_iqmath(ext)))
    return "\n".join(fast_lines) + "\n", "\n".join(slow_lines) + "\n"


def iqmath_members_text(ti_iq):
    """The lines of the slow include that take TI's IQmath functions of the
    ISR path into ramfuncs_slow: members of IQMATH_LIB (SPRU513 "Specifying
    library or archive members as input to output sections")."""
    members = " ".join(f"{n[1:]}.obj" for n in sorted(ti_iq))
    return [
        "/*",
        " * TI's IQmath functions the ISR reaches: the members of C2000Ware's",
        f" * {IQMATH_LIB} that hold them (one function per member, IQ<N><op>.obj).",
        " * Every other IQmath function the image calls stays out of RAM (output",
        " * section IQmath).  Linked against the stand-alone IQmath.lib (SPRC087)",
        " * instead, the firmware build defines IQMATH_WHOLE_IN_RAM and the whole",
        " * IQmath section comes here.",
        " */",
        "#ifndef IQMATH_WHOLE_IN_RAM",
        f"-l {IQMATH_LIB}<{members}> (IQmath)",
        "#else",
        "*(IQmath)",
        "#endif",
    ]


def pragma_problems(graph):
    """Firmware ISR-path functions without the pragma of their set, and
    pragma'd functions that are not in that set nor in RAMFUNCS_NOT_ISR."""
    fast, slow = isr_sets(graph)
    want = {}
    for titles, sec in ((slow, SLOW_SECTION), (fast, FAST_SECTION)):   # fast wins
        for t in titles:
            if rel(graph.func[t]["file"]).startswith("firmware/"):
                want[graph.func[t]["name"]] = (sec, rel(graph.func[t]["file"]))
    pr = pragma_sections()
    errs = []
    for f, (sec, p) in sorted(want.items()):
        have = pr.get(f, (None,))[0]
        if have != sec:
            errs.append(f"{f} ({p}) is on the ISR path ({sec}) but has "
                        + (f"#pragma CODE_SECTION({f}, \"{have}\")" if have else "no #pragma")
                        + f": want #pragma CODE_SECTION({f}, \"{sec}\")")
    errs += [f"{f} ({p}) is in {sec} by #pragma but not on the ISR path "
             f"(add it to RAMFUNCS_NOT_ISR with a reason, or drop the pragma)"
             for f, (sec, p) in sorted(pr.items()) if f not in want and f not in RAMFUNCS_NOT_ISR]
    return errs


def name_clash_problems(graph):
    """Functions of a .c file off the ISR path that share their name with an
    ISR-path function of another .c file (two statics): the includes place
    sections by name, `*(.text:_name)`, so both would land in RAM and the
    off-path one is not counted in its block.  Each must be renamed.  (A
    header's static inline emitted out of line in a background file is the
    same code, a few words: not an error.)"""
    fast, slow = isr_sets(graph)
    on = {graph.func[t]["name"] for t in fast | slow
          if rel(graph.func[t]["file"]).endswith(".c")} & src_names(graph, fast | slow)
    errs = []
    for t, f in sorted(graph.func.items()):
        if (t in fast or t in slow or f["name"] not in on or is_iqmath(f)
                or not rel(f["file"]).endswith(".c")):
            continue
        errs.append(f"{f['name']} ({rel(f['file'])}) is off the ISR path but shares its name "
                    f"with an ISR-path function: its section would be placed in RAM too; "
                    f"rename one of them")
    return errs


def cmd_problems(old_fast, old_slow, new_fast, new_slow, fast_file, slow_file):
    """Errors of the committed includes against the call graph's."""
    def names(t):
        # FAST_IN_SLOW_RAM's block is in both includes, each for one image
        t = re.sub(rf"(?ms)^#ifn?def {RAM_IMAGE_DEFINE}$.*?^#endif$", "", t)
        return set(re.findall(r"\(\.text:(\w+)\)", t))
    errs = []
    was_f, was_s, now_f, now_s = names(old_fast), names(old_slow), names(new_fast), names(new_slow)
    for n in sorted(was_f & now_s):
        errs.append(f"{n} is in {fast_file} but only the slow ISR {SLOW_DISPATCH} reaches it: "
                    f"it belongs in {slow_file}")
    for n in sorted(was_s & now_f):
        errs.append(f"{n} is in {slow_file} but the control ISR reaches it: "
                    f"it belongs in {fast_file}")
    for n in sorted(was_f & was_s):
        errs.append(f"{n} is in both {fast_file} and {slow_file}")
    for old, new, path in ((old_fast, new_fast, fast_file), (old_slow, new_slow, slow_file)):
        if old != new:
            sys.stdout.writelines(difflib.unified_diff(
                old.splitlines(True), new.splitlines(True), str(path), "call graph now"))
            was, now = names(old), names(new)
            errs.append(f"{path} is stale: missing {sorted(now - was)}, "
                        f"not in this set any more {sorted(was - now)}; run "
                        f"tools/bench_size.py --write-isr-cmd {fast_file}")
    return errs


# --- the report ----------------------------------------------------------------
def measure(args, kind):
    """Compile for `kind`: "size" (the report) or "graph" (the linker include)."""
    if not shutil.which(CC):
        raise SystemExit(f"bench_size: {CC} not found (Debian: gcc-arm-none-eabi, "
                         "libnewlib-arm-none-eabi; tools/install_deps.sh installs them)")
    srcs = sources(args.board_config if kind == "size" else None)
    # IQMATH_TI_CALLS names every _IQNmag ti_IQ24mag (iqm_mag has no Q): right
    # only while the core calls no other N's mag, which live in other members
    other_mag = sorted({m for f in srcs for m in re.findall(r"_IQ(\d+)mag\s*\(", f.read_text())
                        if m != "24"})
    if other_mag:
        raise SystemExit(f"bench_size: _IQ{other_mag[0]}mag is used: IQMATH_TI_CALLS would name "
                         "it _IQ24mag (host_sim/iqmath/IQmathLib.h)")
    flags = SIZE_FLAGS if kind == "size" else GRAPH_FLAGS
    return srcs, Graph(compile_all(srcs, Path(args.build) / kind, flags))


def report(args, srcs, g):
    factor = args.factor
    plan = linker_plan(args.linker_cmd)
    fast, slow = isr_sets(g)
    isr = fast | slow
    # the flash set runs from .text (flash) unless the linker file keeps it on chip
    flash_run = set() if plan["flash_set_in_ram"] else flash_set(g)
    to_fast = flash_set_in_fast(g) if plan["flash_set_in_ram"] else set()
    to_slow = fast_in_slow_ram(g)
    _all, isr_ext = g.reach(g.roots(ISR_ROOTS), stop=is_iqmath)
    # the host IQmathLib.h's inline helpers (TI's intrinsics: _IQmpy, _IQsat,
    # _IQabs ...) that the compiler left as functions count where IQmath goes
    iq = g.reach([t for t in isr if is_iqmath(g.func[t])])[0]
    if not any(g.func[t]["name"] == "drive_isr" for t in isr):
        raise SystemExit("bench_size: drive_isr is not reachable from isr_control")
    soft_float = sorted(e for e in isr_ext if SOFT_FLOAT.search(e))
    # whole image: every function reachable from main and the interrupt entries
    fw_text = "".join(s.read_text() for s in srcs if "firmware" in s.parts)
    entries = ["main"] + sorted(set(re.findall(r"interrupt\s+void\s+(\w+)", fw_text)))
    image, image_ext = g.reach(g.roots(entries))
    # TI's IQmath functions: those the ISR reaches run from RAM (members of
    # the library named in the slow include), the others from flash
    ti_iq = ti_iqmath(isr_ext)
    ti_all = ti_iqmath(image_ext)
    pr = pragma_ramfuncs()
    rows = []
    for t in isr | iq:
        f = g.func[t]
        kind = "IQmath inline (host)" if is_iqmath(f) else rel(f["file"]).split("/")[0]
        if is_iqmath(f):
            sec = plan["iqmath_in"]
        elif t in flash_run:
            sec = FLASH_TEXT
        elif t in to_fast:
            sec = FAST_SECTION   # the RAM image: FLASH_SET_IN_FAST's in L0+L1
        elif t in to_slow:
            # FAST_IN_SLOW_RAM's: control-ISR code in H0 (the RAM image: L0+L1)
            sec = FAST_SECTION if plan["flash_set_in_ram"] else SLOW_SECTION
        else:
            sec = FAST_SECTION if t in fast else SLOW_SECTION
        rows.append({"function": f["name"], "file": rel(f["file"]), "kind": kind,
                     "section": sec, "thumb_bytes": f["bytes"], "words": words(f["bytes"], factor)})
    for name, w in ti_iq.items():
        rows.append({"function": name, "file": f"{IQMATH_LIB} (TI)", "kind": "TI IQmath",
                     "section": plan["iqmath_in"], "thumb_bytes": 0, "words": w})
    rows.sort(key=lambda r: (-r["words"], r["function"]))
    # ramfuncs: the fast set + the other firmware functions placed there by pragma
    extra = [t for t, f in g.func.items() if f["name"] in RAMFUNCS_NOT_ISR
             and rel(f["file"]) == pr.get(f["name"])]
    isr_bytes = sum(r["thumb_bytes"] for r in rows)
    extra_bytes = sum(g.func[t]["bytes"] for t in extra)
    sec_bytes = {s: sum(r["thumb_bytes"] for r in rows if r["section"] == s)
                 for s in (FAST_SECTION, SLOW_SECTION)}
    sec_ti = {s: sum(w for w in ti_iq.values()) if plan["iqmath_in"] == s else 0
              for s in (FAST_SECTION, SLOW_SECTION)}
    ramfuncs_words = words(sec_bytes[FAST_SECTION] + extra_bytes, factor) + sec_ti[FAST_SECTION]
    slow_words = words(sec_bytes[SLOW_SECTION], factor) + sec_ti[SLOW_SECTION]
    run = plan["place"][FAST_SECTION]
    run_slow = plan["place"][SLOW_SECTION]
    # with RUN = A | B the linker puts the section in ONE of the ranges
    cap = max(plan["ranges"][r] for r in run)
    cap_slow = max(plan["ranges"][r] for r in run_slow)

    rts = runtime_sizes(image_ext)
    code_bytes = sum(g.func[t]["bytes"] for t in image) + sum(rts.values())
    ti_words = sum(ti_all.values())
    const_words = 0
    for tu, secs in g.sections.items():
        for s, b in secs.items():
            if s.startswith(".rodata.str"):
                const_words += b              # a char is a 16-bit word on the C28x
            elif s.startswith(".rodata"):
                const_words += (b + 1) // 2   # 16/32-bit data: bytes / 2, exact
    lay = c28x_layout()
    data = ebss(g, srcs, lay)
    ebss_words = sum(w for *_x, w, s in data if s == ".ebss")
    other_ram = {}
    for tu, name, w, s in data:
        if s != ".ebss":
            other_ram[s] = other_ram.get(s, 0) + w
    drive_words = lay.struct_size("struct drive")[0]

    # what each RAM range holds (a section with RUN = A | B counts in A)
    blocks = {}

    def put(sec, w):
        rng = plan["place"].get(sec, [None])[0]
        if rng is None:
            raise SystemExit(f"bench_size: {plan['file']} does not place {sec}")
        blocks.setdefault(rng, {})[sec] = w
    put(FAST_SECTION, ramfuncs_words)
    put(SLOW_SECTION, slow_words)
    put(".ebss", ebss_words)
    for s, w in other_ram.items():
        put(s, w)
    # the stack's reservation (--stack_size) occupies its range whatever it uses
    blocks.setdefault(plan["place"][".stack"][0], {})[".stack"] = stack_size()
    block_rows = {k: {"contents": v, "used_words": sum(v.values()),
                      "capacity_words": plan["ranges"][k],
                      "fraction": round(sum(v.values()) / plan["ranges"][k], 3)}
                  for k, v in sorted(blocks.items())}
    ebss_block = plan["place"][".ebss"][0]
    in_block = {s: w for s, w in blocks[ebss_block].items() if s != ".ebss"}

    # the rest of the image (code outside the ISR path, constants) where .text
    # goes: flash in the flash image, external RAM in the RAM image
    rest_words = (words(code_bytes - sum(g.func[t]["bytes"] for t in (isr | iq) - flash_run
                                         if t in image), factor) + const_words)
    text_in = plan["text_in"]
    text_offchip = bool(text_in) and not any(re.fullmatch(r"FLASH[A-J]", r) for r in text_in)

    # stack: the background's deepest chain, the slow ISR's on it (INT14
    # interrupts the background), the deepest other ISR's on that (the
    # control ISR or PDPINTA preempt the slow ISR: nesting; they do not nest
    # in each other), and two interrupt contexts
    bg_bytes = g.deepest(g.roots(["main"])[0])
    slow_roots = g.roots(SLOW_ROOTS)
    slow_bytes_stack = max(g.deepest(t, stop=is_iqmath) for t in slow_roots)
    isr_bytes_stack = max(g.deepest(t, stop=is_iqmath) for t in g.roots(entries[1:])
                          if t not in slow_roots)
    # (an IQmath call below each chain: TI_IQMATH_STACK_WORDS each, errs high)
    stack_words = (words(bg_bytes, factor) + words(slow_bytes_stack, factor)
                   + words(isr_bytes_stack, factor) + 2 * ISR_CONTEXT_WORDS
                   + (3 * TI_IQMATH_STACK_WORDS if ti_iq else 0))
    stack_block = plan["place"][".stack"][0]
    stack_cap = min(plan["ranges"][stack_block], stack_size())

    return {
        "linker_cmd": plan["file"],
        "words_per_thumb_halfword": factor,
        "ramfuncs_words": ramfuncs_words,
        "ramfuncs_capacity_words": cap,
        "ramfuncs_run": run,
        "ramfuncs_fraction": round(ramfuncs_words / cap, 3),
        "ramfuncs_slow_words": slow_words,
        "ramfuncs_slow_capacity_words": cap_slow,
        "ramfuncs_slow_run": run_slow,
        "ramfuncs_slow_fraction": round(slow_words / cap_slow, 3),
        "goal_fraction": 0.70,
        "goal_met": bool(ramfuncs_words <= 0.70 * cap and slow_words <= 0.70 * cap_slow and
                         all(b["used_words"] <= 0.70 * b["capacity_words"]
                             for b in block_rows.values())),
        "iqmath_section_in": plan["iqmath_in"],
        "isr_path_functions": len(rows),
        "isr_path_words": words(isr_bytes, factor) + sum(
            r["words"] for r in rows if r["kind"] == "TI IQmath"),
        "isr_path_fast_functions": sum(1 for r in rows if r["section"] == FAST_SECTION),
        "isr_path_slow_functions": sum(1 for r in rows if r["section"] == SLOW_SECTION),
        "isr_path_iqmath_words": sum(r["words"] for r in rows if r["kind"] == "TI IQmath"),
        "isr_path_flash_functions": sorted(r["function"] for r in rows
                                           if r["section"] == FLASH_TEXT),
        "isr_path_flash_words": words(sum(r["thumb_bytes"] for r in rows
                                          if r["section"] == FLASH_TEXT), factor),
        "iqmath_image_words": ti_words,
        "ramfuncs_not_isr": sorted(g.func[t]["name"] for t in extra),
        "isr_path_external_calls": sorted(isr_ext),
        "isr_path_soft_float": soft_float,
        "flash_words": words(code_bytes, factor) + ti_words + const_words,
        "flash_code_words": words(code_bytes, factor) + ti_words,
        "flash_const_words": const_words,
        "flash_capacity_words": sum(v for k, v in plan["ranges"].items()
                                    if re.fullmatch(r"FLASH[A-J]", k)),
        "image_functions": len(image),
        "image_external_calls": sorted(image_ext),
        "image_runtime_words": words(sum(rts.values()), factor),
        "image_rest_words": rest_words,
        "image_rest_in": text_in,
        "image_rest_offchip": text_offchip,
        "image_rest_capacity_words": (max(plan["ranges"][r] for r in text_in)
                                      if text_offchip else None),
        "blocks": block_rows,
        "drive_t_words": drive_words,
        "ebss_words": ebss_words,
        "ebss_block": ebss_block,
        "ebss_block_other": in_block,
        "ebss_block_used_words": block_rows[ebss_block]["used_words"],
        "ebss_block_capacity_words": plan["ranges"][ebss_block],
        "ebss_variables": {f"{tu}:{n}": w for tu, n, w, _s in sorted(data, key=lambda r: -r[2])},
        "stack_words": stack_words,
        "stack_background_thumb_bytes": bg_bytes,
        "stack_isr_thumb_bytes": isr_bytes_stack,
        "stack_slow_isr_thumb_bytes": slow_bytes_stack,
        "stack_block": stack_block,
        "stack_capacity_words": stack_cap,
        "board_config": rel(args.board_config) if args.board_config else None,
        "isr_path": rows,
    }


CODE_SECTIONS = (FAST_SECTION, SLOW_SECTION)


def problems(r, what=("ramfuncs", "data")):
    """--check ramfuncs: every RAM range that holds ramfuncs or ramfuncs_slow
    (with whatever data shares it) within LIMIT, no soft float on the ISR
    path, and in the RAM image the rest of the program within LIMIT of its
    external RAM; --check data: every range that holds .ebss or another data
    section (dlog) within LIMIT, and the estimated stack within LIMIT of
    --stack_size."""
    out = []
    for rng, b in r["blocks"].items():
        code = any(s in CODE_SECTIONS for s in b["contents"])
        dat = any(s not in CODE_SECTIONS for s in b["contents"])
        if not (("ramfuncs" in what and code) or ("data" in what and dat)):
            continue
        if b["used_words"] > LIMIT * b["capacity_words"]:
            parts = " + ".join(f"{s} {w}" for s, w in b["contents"].items())
            out.append(f"{rng}: {parts} = {b['used_words']} words > {LIMIT:.0%} of "
                       f"{rng} ({b['capacity_words']} words)")
    if ("ramfuncs" in what and r["image_rest_offchip"]
            and r["image_rest_words"] > LIMIT * r["image_rest_capacity_words"]):
        out.append(f"the rest of the image {r['image_rest_words']} words > {LIMIT:.0%} of "
                   f"{r['image_rest_in']} ({r['image_rest_capacity_words']} words)")
    if "data" in what and r["stack_words"] > LIMIT * r["stack_capacity_words"]:
        out.append(f"stack {r['stack_words']} words > {LIMIT:.0%} of {r['stack_block']} "
                   f"({r['stack_capacity_words']} words)")
    if "ramfuncs" in what and r["isr_path_soft_float"]:
        out.append(f"the ISR reaches soft-float helpers {r['isr_path_soft_float']}")
    return out


def print_table(r):
    f = r["words_per_thumb_halfword"]
    print(f"F2812 size estimate (Thumb-2 stand-in, {f} C28x words per Thumb-2 halfword; "
          f"linker file {r['linker_cmd']})")
    iq = f", IQmath in {r['iqmath_section_in']}"
    print(f"  ramfuncs (fast ISR path + {', '.join(r['ramfuncs_not_isr']) or 'nothing else'}"
          f"{iq if r['iqmath_section_in'] == FAST_SECTION else ''}): "
          f"{r['ramfuncs_words']} words of {r['ramfuncs_capacity_words']} "
          f"({100 * r['ramfuncs_fraction']:.0f} %), RUN {r['ramfuncs_run']}")
    print(f"  ramfuncs_slow (only from the slow ISR {SLOW_DISPATCH}"
          f"{iq if r['iqmath_section_in'] == SLOW_SECTION else ''}): "
          f"{r['ramfuncs_slow_words']} words of {r['ramfuncs_slow_capacity_words']} "
          f"({100 * r['ramfuncs_slow_fraction']:.0f} %), RUN {r['ramfuncs_slow_run']}")
    print(f"  ISR path: {r['isr_path_functions']} functions ({r['isr_path_fast_functions']} fast, "
          f"{r['isr_path_slow_functions']} slow), {r['isr_path_words']} words "
          f"(TI IQmath {r['isr_path_iqmath_words']} of the {r['iqmath_image_words']} "
          f"the image calls); "
          f"run-time calls {r['isr_path_external_calls']}")
    if r["isr_path_flash_functions"]:
        print(f"  of it from flash (the flash set, FLASH_ROOTS): "
              f"{len(r['isr_path_flash_functions'])} functions, {r['isr_path_flash_words']} words")
    print(f"  flash image: {r['flash_words']} words (code {r['flash_code_words']}, "
          f"constants {r['flash_const_words']}; run-time library stand-in "
          f"{r['image_runtime_words']}) of {r['flash_capacity_words']}")
    if r["image_rest_offchip"]:
        print(f"  the rest of the image (code off the ISR path + constants): "
              f"{r['image_rest_words']} words in {r['image_rest_in']} "
              f"({r['image_rest_capacity_words']} words, off-chip)")
    print(f"  .ebss: {r['ebss_words']} words (drive_t {r['drive_t_words']}) in {r['ebss_block']}")
    print(f"  RAM ranges (limit {LIMIT:.0%} each):")
    for rng, b in r["blocks"].items():
        parts = " + ".join(f"{s} {w}" for s, w in b["contents"].items())
        print(f"    {rng:14s} {parts} = {b['used_words']} of {b['capacity_words']} "
              f"({100 * b['fraction']:.0f} %)")
    print(f"  stack: {r['stack_words']} words (background {r['stack_background_thumb_bytes']} + "
          f"slow ISR {r['stack_slow_isr_thumb_bytes']} + control ISR "
          f"{r['stack_isr_thumb_bytes']} Thumb bytes nested, + 2 x {ISR_CONTEXT_WORDS} words of "
          f"interrupt context) of {r['stack_capacity_words']} (--stack_size, in "
          f"{r['stack_block']})")
    print(f"\n  {'ISR-path function':32s} {'file':34s} {'section':14s} {'Thumb B':>8s} {'words':>6s}")
    for row in r["isr_path"]:
        print(f"  {row['function']:32s} {row['file']:34s} {row['section']:14s} "
              f"{row['thumb_bytes']:8d} {row['words']:6d}")


RANGE_ROLE = {"RAML0L1": "L0+L1 code", "RAML0L1_DATA": "L0+L1 data", "RAMH0": "H0 code",
              "RAMH0_DATA": "H0 data", "RAMM0M1": "M0+M1"}


def print_markdown(r):
    """The RAM ranges of the linker file as a markdown table (docs/board.md)."""
    print(f"| RAM range ({r['linker_cmd']}) | holds | words | of | % |")
    print("|---|---|---:|---:|---:|")
    for rng, b in r["blocks"].items():
        parts = ", ".join(f"`{s}` {w}" for s, w in b["contents"].items())
        print(f"| {RANGE_ROLE.get(rng, rng)} `{rng}` | {parts} | {b['used_words']} | "
              f"{b['capacity_words']} | {100 * b['fraction']:.0f} |")
    on_chip = sum(b["capacity_words"] for k, b in r["blocks"].items() if k in RANGE_ROLE)
    used = sum(b["used_words"] for k, b in r["blocks"].items() if k in RANGE_ROLE)
    flash = (f"; its flash set {r['isr_path_flash_words']} runs from flash"
             if r["isr_path_flash_words"] else "")
    print(f"| **on chip** | ISR path {r['isr_path_words']} (TI IQmath {r['isr_path_iqmath_words']}"
          f"{flash}), stack used {r['stack_words']} of its {r['stack_capacity_words']} | **{used}** | "
          f"{on_chip} | **{100 * used / on_chip:.0f}** |")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--markdown", action="store_true", help="the RAM ranges as a markdown table")
    ap.add_argument("--build", default=str(ROOT / "build" / "bench_size"),
                    help="folder for the stand-in objects (default build/bench_size)")
    ap.add_argument("--linker-cmd", default=str(ROOT / "linker" / "F2812_flash.cmd"))
    ap.add_argument("--board-config", help="the generated board_config.c to count")
    ap.add_argument("--factor", type=float, default=WORDS_PER_HALFWORD,
                    help="C28x words per Thumb-2 halfword (default %(default)s)")
    ap.add_argument("--limit", type=float, default=None,
                    help="the fraction of each RAM block --check allows (default 0.70, the goal)")
    ap.add_argument("--check", nargs="?", const="all", choices=("all", "ramfuncs", "data"),
                    help="exit 1 if a RAM limit is exceeded: ramfuncs (the RAM ranges that "
                         "run ramfuncs/ramfuncs_slow, no soft float), data (the ranges of "
                         ".ebss and dlog, the stack), all")
    ap.add_argument("--abi", choices=("coffabi", "eabi"), default="coffabi")
    g = ap.add_mutually_exclusive_group()
    g.add_argument("--write-isr-cmd", metavar="FILE",
                   help="write the fast set to FILE and the slow set to --slow-cmd")
    g.add_argument("--check-isr-cmd", metavar="FILE",
                   help="check FILE (fast set) and --slow-cmd (slow set)")
    ap.add_argument("--slow-cmd", metavar="FILE",
                    help="the slow set's include (default: next to FILE, "
                         "F2812_isr_path.cmd -> F2812_isr_slow.cmd)")
    a = ap.parse_args(argv)
    global LIMIT
    if a.limit is not None:
        if not 0.0 < a.limit <= 1.0:
            ap.error("--limit must be in (0, 1]")
        LIMIT = a.limit

    if a.write_isr_cmd or a.check_isr_cmd:
        _srcs, graph_g = measure(a, "graph")
        fast_text, slow_text = isr_cmd_texts(graph_g, a.abi)
        errs = pragma_problems(graph_g) + name_clash_problems(graph_g)
        fast_file = a.write_isr_cmd or a.check_isr_cmd
        slow_file = a.slow_cmd or slow_cmd_path(fast_file)
        if a.write_isr_cmd:
            Path(fast_file).write_text(fast_text)
            Path(slow_file).write_text(slow_text)
            print(f"wrote {fast_file} and {slow_file}")
        else:
            if not Path(slow_file).exists():
                errs.append(f"{slow_file}: no such file (the slow set's include; --slow-cmd)")
                old_slow = ""
            else:
                old_slow = Path(slow_file).read_text()
            errs += cmd_problems(Path(fast_file).read_text(), old_slow, fast_text, slow_text,
                                 fast_file, slow_file)
            if not errs:
                print(f"{fast_file}: current ({fast_text.count('*(.text:')} functions); "
                      f"{slow_file}: current ({slow_text.count('*(.text:')} functions)")
        for e in errs:
            print("ERROR", e)
        return 1 if errs else 0

    srcs, size_g = measure(a, "size")
    r = report(a, srcs, size_g)
    if a.json:
        print(json.dumps(r, indent=1))
    elif a.markdown:
        print_markdown(r)
    else:
        print_table(r)
    if a.check:
        what = ("ramfuncs", "data") if a.check == "all" else (a.check,)
        errs = problems(r, what)
        for e in errs:
            print("FAIL", e)
        if not errs:
            print(f"OK ({', '.join(what)}): within {LIMIT:.0%} of each RAM block")
        return 1 if errs else 0
    return 0


if __name__ == "__main__":
    sys.exit(main())
