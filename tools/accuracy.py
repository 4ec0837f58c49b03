#!/usr/bin/env python3
"""Identification accuracy on the three motors, IQ_MATH and FLOAT_MATH.

Runs motor_sim (default scenario) for each config in host_sim/config, with
the paper's sequence (the motor files' own is the adaptive one), and each build
in build/host-iq and build/host-float, and prints the error of every parameter
of the RLS's extraction (the paper's method: what the drive judged), the convergence time, the drive's verdict (published, or why not:
report.json's publish_reason) and the IQ-vs-FLOAT difference.
Usage: tools/accuracy.py [--markdown] [--seeds N]   (after `cmake --build --preset host-iq` and host-float)
  --markdown  print the table of docs/accuracy.md instead (the same runs; the
              docs' table is this output, checked by tools/python/tests/test_docs.py)
  --seeds N   the same runs over noise seeds 1..N (`[sensors] seed`): per motor
              and build the mean error and the seed-to-seed spread of each
              parameter, and the IQ-FLOAT difference of the means.  One seed's
              difference between the builds is mostly the realisation: the ADC
              and the PWM quantise signals that differ in the last bits, so the
              two builds see different quantisation noise; the means show what
              the arithmetic itself moves.  With --markdown, the docs' table.
The runs go two at a time (the machine's two cores).
"""
import argparse
import json
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tools"))
from sweep_start_errors import PAPER, ini_merge  # noqa: E402
KEYS = ["Rs_ohm", "Rr_ohm", "Lm_H", "Lr_H", "psi_r_Wb", "Tr_s"]
MOTORS = [("paper_motor", 1.0), ("motor_1kw", 3.0), ("motor_15kw", 3.0)]
LABELS = {"paper_motor": "paper, 250 W", "motor_1kw": "1.1 kW 400 V", "motor_15kw": "15 kW 400 V"}
BUILDS = ("host-iq", "host-float")
MATH = {"host-iq": "IQ_MATH", "host-float": "FLOAT_MATH"}


def with_seed(text, seed):
    """The INI text with `[sensors] seed = seed` (the section added if missing,
    a seed key already there replaced)."""
    lines = [ln for ln in text.splitlines()
             if not ln.replace(" ", "").startswith("seed=")]
    if "[sensors]" not in (ln.strip() for ln in lines):
        lines += ["", "[sensors]"]
    i = [ln.strip() for ln in lines].index("[sensors]")
    lines.insert(i + 1, f"seed = {seed}")
    return "\n".join(lines) + "\n"


def run(build, config, seed=None):
    exe = ROOT / "build" / build / "host_sim" / "sim" / "motor_sim"
    text = ini_merge((ROOT / "host_sim" / "config" / f"{config}.ini").read_text(), PAPER)
    with tempfile.TemporaryDirectory() as d:
        ini = Path(d) / f"{config}.ini"
        ini.write_text(with_seed(text, seed) if seed is not None else text)
        p = subprocess.run([str(exe), "--config", str(ini), "--quiet", "--out", d])
        if p.returncode not in (0, 3):   # 3: the run completed, nothing published
            raise SystemExit(f"accuracy: motor_sim failed ({p.returncode}) on {config}")
        return json.loads((Path(d) / "report.json").read_text())


def markdown(reports):
    """The docs' table: one row per motor and build."""
    print("| motor | build | " + " | ".join(k.rsplit("_", 1)[0] for k in KEYS) +
          " | converged | bound | verdict |")
    print("|---" * (len(KEYS) + 5) + "|")
    ok = True
    for motor, bound in MOTORS:
        for build in BUILDS:
            r = reports[(build, motor)]
            e = r["last_extraction_error_pct"]
            worst = max(abs(e[k]) for k in KEYS) if e else float("inf")
            ok &= worst < bound
            print(f"| {LABELS[motor]} | {MATH[build]} | " +
                  " | ".join(f"{e[k]:+.2f} %" for k in KEYS) +
                  f" | {r['converge_s']:.2f} s | {bound:g} % | {r['publish_reason']} |")
    return 0 if ok else 1


def over_seeds(n, md):
    """Mean and spread over seeds 1..n, both builds; the IQ-FLOAT difference
    of the means.  Returns 1 if a mean is beyond its motor's bound."""
    import statistics
    seeds = range(1, n + 1)
    with ThreadPoolExecutor(2) as pool:
        futures = {(b, m, sd): pool.submit(run, b, m, sd)
                   for m, _ in MOTORS for b in BUILDS for sd in seeds}
        reports = {k: f.result() for k, f in futures.items()}
    names = [k.rsplit("_", 1)[0] for k in KEYS]
    if md:
        print(f"| motor ({n} seeds) | build | " +
              " | ".join(f"{k} mean (sd)" for k in names) + " | worst seed |")
        print("|---" * (len(KEYS) + 3) + "|")
    else:
        print(f"{'motor':<12} {'build':<6} " + " ".join(f"{k:>15}" for k in names) +
              "  worst seed (mean and sd over seeds 1-" + f"{n}, %)")
    ok = True
    for motor, bound in MOTORS:
        means = {}
        for build in BUILDS:
            errs = {k: [reports[(build, motor, sd)]["last_extraction_error_pct"][k]
                        for sd in seeds] for k in KEYS}
            means[build] = {k: statistics.fmean(v) for k, v in errs.items()}
            sd_ = {k: statistics.pstdev(v) for k, v in errs.items()}
            worst = max(abs(x) for v in errs.values() for x in v)
            ok &= max(abs(x) for x in means[build].values()) < bound
            row(md, (LABELS[motor], MATH[build]) if md else (motor, build[5:]),
                [f"{means[build][k]:+.2f} ({sd_[k]:.2f})" for k in KEYS], "%",
                f"{worst:.2f}" + (" %" if md else ""))
        gap = {k: means["host-iq"][k] - means["host-float"][k] for k in KEYS}
        big = max(abs(x) for x in gap.values())
        row(md, (LABELS[motor], "IQ - FLOAT") if md else ("", "IQ-FL"),
            [f"{gap[k]:+.2f}" for k in KEYS], "pt",
            f"max {big:.2f} pt" + ("" if md else " (means)"))
    return 0 if ok else 1


def row(md, names, cells, unit, tail):
    """One line of over_seeds' table: markdown, or aligned text."""
    if md:
        print(f"| {names[0]} | {names[1]} | " + " | ".join(f"{c} {unit}" for c in cells) +
              f" | {tail} |")
    else:
        print(f"{names[0]:<12} {names[1]:<6} " + " ".join(f"{c:>15}" for c in cells) +
              f"  {tail}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--markdown", action="store_true", help="print the docs' markdown table")
    ap.add_argument("--seeds", type=int, metavar="N",
                    help="over noise seeds 1..N: means, spreads, IQ-FLOAT of the means")
    a = ap.parse_args()
    if a.seeds is not None:
        if not 1 <= a.seeds <= 100:
            ap.error("--seeds: a whole number in [1, 100]")
        return over_seeds(a.seeds, a.markdown)
    with ThreadPoolExecutor(2) as pool:
        futures = {(b, m): pool.submit(run, b, m) for m, _ in MOTORS for b in BUILDS}
        reports = {k: f.result() for k, f in futures.items()}
    if a.markdown:
        return markdown(reports)
    print(f"{'motor':<12} {'build':<6} " + " ".join(f"{k:>9}" for k in KEYS) +
          f" {'conv/s':>7} {'bound':>6}  verdict")
    ok = True
    for motor, bound in MOTORS:
        reps = {}
        for build in BUILDS:
            r = reports[(build, motor)]
            reps[build] = r
            e = r["last_extraction_error_pct"]
            worst = max(abs(e[k]) for k in KEYS) if e else float("inf")
            flag = "" if worst < bound else "  <- above bound"
            ok &= worst < bound
            print(f"{motor:<12} {build[5:]:<6} " + " ".join(f"{e[k]:>+8.2f}%" for k in KEYS) +
                  f" {r['converge_s']:>7.2f} {bound:>5.1f}%  {r['publish_reason']}{flag}")
        d = max(abs(reps['host-iq']['last_extraction_error_pct'][k] -
                    reps['host-float']['last_extraction_error_pct'][k]) for k in KEYS)
        print(f"{'':<12} {'IQ-FL':<6} max difference {d:.3f} percentage points")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
