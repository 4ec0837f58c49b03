#!/usr/bin/env python3
"""Estimated cost of the 15 kHz control ISR on the F2812 (C28x, 150 MHz), per
module and in total, against the budget of 10 000 cycles per period.

Method (an estimate from an instrumented host build, not a measurement on a
board; BENCHMARKS.md states the assumptions):
 1. IQmath calls.  `isr_cost` (host_sim/api/isr_cost.c, IQ_MATH build) runs the
    paper motor's identification closed loop with the whole core compiled
    against the counted IQmath; in ACCELERATE (every block active: PWM on,
    speed and current loops, RLS updating) it counts every IQmath call over
    N ISRs, per step function that drive_step() calls (link-time wrappers).
    Each call costs TI's published C28x cycle count (IQmath V1.4c read-me,
    call included) or, for the few operations that list does not give, the
    cost of the C28x instructions TI's header expands them to (ASSUMED below).
 2. The other C operations.  The same build has gcov line counts: every
    executed line of src/ is tokenised and each operator, branch and call on it
    costs the cycles in OTHER_COST, times how often the line ran per ISR.
    (IQmath macros on a line are costed by step 1, not here.)
Usage: bench_isr.py [--build DIR] [--config INI] [--isrs N] [--json]
"""
import argparse
import json
import re
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BUDGET = 10000          # 150 MHz / 15 kHz
GOAL = 3000

# TI IQmath V1.4c read-me, C28x cycles including the call (given in the issue)
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
}
# every other operation, per occurrence on an executed source line
OTHER_COST = {
    "op32": 2,     # 32-bit add/sub/compare/logic/shift/assign: ALU op + one MOVL
    "op64": 8,     # 64-bit: no 64-bit ALU, register-pair sequences
    "branch": 5,   # if/while/for/?:/&&/||/case: conditional branch (4 not taken, 7 taken)
    "call": 10,    # call of a non-inline function: LCR 4 + LRETR 4 + argument moves
}

# step function (wrapped in isr_cost) -> module of the report
FUNC_MODULE = {
    "phase_current_step": "sensing", "dc_bus_step": "sensing", "qep_speed_step": "sensing",
    "protect_step": "protection", "volt_calc_step": "voltage model",
    "clarke_step": "Clarke/Park/inverse Park", "park_step": "Clarke/Park/inverse Park",
    "ipark_step": "Clarke/Park/inverse Park",
    "angle_sincos": "sin/cos", "angle_wrap_pu": "sin/cos",
    "ifo_frame_from_rotor": "orientation (IFO)", "ifo_theta_mid": "orientation (IFO)",
    "ifo_step_slip": "orientation (IFO)",
    "ident_regressor_step": "regression + Butterworth", "rls_step": "RLS", "rls_step_row": "RLS",
    "id_sequence_step": "sequence", "ramp_gen_step": "speed ramp + PIs",
    "pi_step": "speed ramp + PIs", "pi_reset": "speed ramp + PIs", "svgen_step": "SVPWM",
    "flux_obs_step": "orientation (observer)", "angle_sincos_step": "sin/cos",
    "tr_track_step": "adaptation (issue 8)", "standstill_z_step": "adaptation (issue 8)",
}
# source file of src/ -> module (others: "drive_step glue + other")
FILE_MODULE = {
    "phase_current.c": "sensing", "dc_bus.c": "sensing", "qep_speed.c": "sensing",
    "protect.c": "protection", "volt_calc.c": "voltage model",
    "clarke.c": "Clarke/Park/inverse Park", "park.c": "Clarke/Park/inverse Park",
    "ipark.c": "Clarke/Park/inverse Park", "angle.c": "sin/cos",
    "ifo.c": "orientation (IFO)", "ident_regressor.c": "regression + Butterworth",
    "bw_filter.c": "regression + Butterworth", "rls.c": "RLS", "estim_bfp.h": "RLS",
    "id_sequence.c": "sequence", "ramp_gen.c": "speed ramp + PIs",
    "pi_ctrl.c": "speed ramp + PIs", "svgen.c": "SVPWM",
    "flux_obs.c": "orientation (observer)", "tr_track.c": "adaptation (issue 8)",
    "standstill_z.c": "adaptation (issue 8)", "drive_adapt.c": "adaptation (issue 8)",
    "iq_rmpy.h": "rounded products (iq_rmpy)",
}
GLUE = "drive_step glue + other"

OPS = sorted(["<<=", ">>=", "+=", "-=", "*=", "/=", "%=", "&=", "|=", "^=", "++", "--", "<<",
              ">>", "<=", ">=", "==", "!=", "&&", "||", "=", "+", "-", "*", "/", "%", "&",
              "|", "^", "~", "!", "<", ">", "?"], key=len, reverse=True)
TOKEN = re.compile(r"->|[A-Za-z_]\w*|\d[\w.]*|" + "|".join(re.escape(o) for o in OPS) +
                   r"|[()\[\]{};,.:]")
KEYWORDS = {"if", "for", "while", "switch", "return", "sizeof", "else", "do", "case"}
TYPES = {"int16_t", "uint16_t", "int32_t", "uint32_t", "int64_t", "uint64_t", "_iq", "_iq30",
         "_iq29", "_iq28", "_iq20", "void", "int", "unsigned", "const", "float", "double"}


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
    """{op32, op64, branch, call} on one line of C."""
    c = {"op32": 0, "op64": 0, "branch": 0, "call": 0}
    if code.strip().startswith("#"):
        return c
    toks = TOKEN.findall(code)
    wide = "int64" in code
    # a declaration line without an initialiser costs nothing
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
        elif re.match(r"[A-Za-z_]\w*$", t) and nxt == "(":
            if t in KEYWORDS or t.startswith("_IQ") or t.startswith("iqm_") or \
                    t in inline_funcs or t in TYPES or t.endswith("_t"):
                continue
            c["call"] += 1
    return c


def inline_functions():
    names = set()
    for p in list((ROOT / "src").rglob("*.[ch]")) + list((ROOT / "include").glob("*.h")):
        for m in re.finditer(r"static\s+inline\s+[\w\s\*]+?\b(\w+)\s*\(", p.read_text()):
            names.add(m.group(1))
    return names


def run_isr_cost(build, config, isrs):
    exe = build / "host_sim" / "api" / "isr_cost"
    if not exe.exists():
        raise SystemExit(f"bench_isr: {exe} not found: build the IQ_MATH preset (target isr_cost)")
    objdir = build / "host_sim" / "api" / "CMakeFiles" / "isr_cost.dir"
    for f in objdir.rglob("*.gcda"):      # libgcov merges into old files: start clean
        f.unlink()
    names = json.loads(subprocess.run([str(exe), str(config), "--isrs", "1"], check=True,
                                      capture_output=True, text=True).stdout)["iqmath_names"]
    for f in objdir.rglob("*.gcda"):
        f.unlink()
    w = ",".join(str(TI_CYCLES.get(n, ASSUMED_CYCLES.get(n, 0))) for n in names)
    r = subprocess.run([str(exe), str(config), "--isrs", str(isrs), "--weights", w],
                       check=True, capture_output=True, text=True)
    return json.loads(r.stdout), objdir


def gcov_lines(objdir):
    """{source path: {line: count}} of the measured window, src/ and the core's
    headers (include/: their inline functions).  A header's inline functions
    are compiled into every unit that includes it: its counts are summed over
    the units (each .c file is in one unit only)."""
    gcov = shutil.which("gcov")
    if gcov is None:
        raise SystemExit("bench_isr: gcov not found")
    out = {}
    for gcda in objdir.rglob("*.gcda"):
        r = subprocess.run([gcov, "-t", "-j", "-o", str(gcda.parent), str(gcda)],
                           capture_output=True, text=True, check=True, cwd=str(gcda.parent))
        for doc in r.stdout.splitlines():
            if not doc.strip():
                continue
            for f in json.loads(doc)["files"]:
                path = Path(f["file"])
                if not path.is_absolute():
                    path = (gcda.parent / path).resolve()
                if ROOT / "src" not in path.parents and ROOT / "include" not in path.parents:
                    continue
                d = out.setdefault(path, {})
                for ln in f["lines"]:
                    d[ln["line_number"]] = d.get(ln["line_number"], 0) + ln["count"]
    return out


def estimate(build, config, isrs):
    data, objdir = run_isr_cost(build, config, isrs)
    n = data["isrs"]
    names = data["iqmath_names"]
    cyc = [TI_CYCLES.get(nm, ASSUMED_CYCLES.get(nm)) for nm in names]
    mods = {}

    def mod(name):
        return mods.setdefault(name, {"iqmath_calls": {}, "iqmath_cycles": 0.0,
                                      "other_ops": {k: 0.0 for k in OTHER_COST},
                                      "other_cycles": 0.0})

    wrapped = [0] * len(names)
    for fn, row in data["functions"].items():
        m = mod(FUNC_MODULE.get(fn, GLUE))
        for i, c in enumerate(row["iq"]):
            wrapped[i] += c
            if c:
                m["iqmath_calls"][names[i]] = m["iqmath_calls"].get(names[i], 0) + c / n
                m["iqmath_cycles"] += cyc[i] * c / n
    g = mod(GLUE)
    for i, c in enumerate(data["total"]):
        rest = c - wrapped[i]
        if rest:
            g["iqmath_calls"][names[i]] = g["iqmath_calls"].get(names[i], 0) + rest / n
            g["iqmath_cycles"] += cyc[i] * rest / n

    inl = inline_functions()
    hot, by_file = [], {}
    for path, lines in gcov_lines(objdir).items():
        src = strip_comments(path.read_text().splitlines())
        m = mod(FILE_MODULE.get(path.name, GLUE))
        for ln, count in lines.items():
            if count == 0 or ln > len(src):
                continue
            ops = count_line(src[ln - 1], inl)
            for k, v in ops.items():
                m["other_ops"][k] += v * count / n
            c = sum(OTHER_COST[k] * v for k, v in ops.items()) * count / n
            by_file[path.name] = by_file.get(path.name, 0.0) + c
            if c > 0:
                hot.append((c, f"{path.relative_to(ROOT)}:{ln}", src[ln - 1].strip()))
    for m in mods.values():
        m["other_cycles"] = sum(OTHER_COST[k] * v for k, v in m["other_ops"].items())
        m["cycles"] = m["iqmath_cycles"] + m["other_cycles"]
    total = sum(m["cycles"] for m in mods.values())
    iq_total = sum(m["iqmath_cycles"] for m in mods.values())
    return {"total_cycles": int(round(total)), "budget_cycles": BUDGET,
            "goal_cycles": GOAL,
            "iqmath_cycles": int(round(iq_total)),
            "other_cycles": int(round(total - iq_total)),
            "max_isr_iqmath_cycles": data["max_isr_weighted"],
            "isrs_measured": n, "state": "ACCELERATE (RLS on, PWM on, all loops)",
            "modules": {k: int(round(v["cycles"])) for k, v in
                        sorted(mods.items(), key=lambda kv: -kv[1]["cycles"])},
            "other_cycles_by_file": {k: int(round(v)) for k, v in
                                     sorted(by_file.items(), key=lambda kv: -kv[1])},
            "detail": mods, "hot_lines": sorted(hot, reverse=True)}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default=str(ROOT / "build" / "host-iq"),
                    help="an IQ_MATH build directory with isr_cost (default build/host-iq)")
    ap.add_argument("--config", default=str(ROOT / "host_sim" / "config" / "paper_motor.ini"))
    ap.add_argument("--isrs", type=int, default=3000, help="ISRs measured (default 3000 = 0.2 s)")
    ap.add_argument("--hot", type=int, default=0, help="also list the N costliest source lines")
    ap.add_argument("--json", action="store_true",
                    help='print {"total_cycles", "budget_cycles", "modules", ...}')
    a = ap.parse_args(argv)
    r = estimate(Path(a.build).resolve(), Path(a.config).resolve(), a.isrs)
    if a.json:
        out = {k: v for k, v in r.items() if k not in ("detail", "hot_lines")}
        print(json.dumps(out, indent=1))
        return 0
    print(f"ISR cost estimate, {r['isrs_measured']} ISRs in {r['state']}, cycles per ISR "
          f"(C28x, 150 MHz):")
    print(f"  {'module':28s} {'IQmath':>7s} {'other':>7s} {'total':>7s}   IQmath calls per ISR")
    for name in r["modules"]:
        m = r["detail"][name]
        calls = ", ".join(f"{k} {v:.3g}" for k, v in
                          sorted(m["iqmath_calls"].items(), key=lambda kv: -kv[1]))
        print(f"  {name:28s} {m['iqmath_cycles']:7.0f} {m['other_cycles']:7.0f} "
              f"{m['cycles']:7.0f}   {calls}")
    t = r["total_cycles"]
    print(f"  {'total':28s} {r['iqmath_cycles']:7d} {r['other_cycles']:7d} {t:7d}")
    print(f"budget {BUDGET} cycles (150 MHz / 15 kHz): {100 * t / BUDGET:.1f} % used; "
          f"goal {GOAL}: {'met' if t <= GOAL else 'NOT met'}")
    print(f"largest single ISR, IQmath part: {r['max_isr_iqmath_cycles']:.0f} cycles")
    print("assumed cycles (not in TI's list): " +
          ", ".join(f"{k} {v}" for k, v in ASSUMED_CYCLES.items()))
    print("other operations, cycles per ISR by file: " +
          ", ".join(f"{k} {v}" for k, v in r["other_cycles_by_file"].items()))
    for c, where, code in r["hot_lines"][:a.hot]:
        print(f"  {c:6.0f}  {where:32s} {code[:70]}")
    print("other operations, cycles each: " + ", ".join(f"{k} {v}" for k, v in OTHER_COST.items()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
