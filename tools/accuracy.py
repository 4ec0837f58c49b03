#!/usr/bin/env python3
"""Identification accuracy on the three motors, IQ_MATH and FLOAT_MATH.

Runs motor_sim (default scenario) for each config in host_sim/config and
each build in build/host-iq and build/host-float, and prints the error of
every parameter of the RLS's extraction (the paper's method: what the drive
judged), the convergence time, the drive's verdict (published, or why not:
report.json's publish_reason) and the IQ-vs-FLOAT difference.
Usage: tools/accuracy.py [--markdown]   (after `cmake --build --preset host-iq` and host-float)
  --markdown  print the table of docs/accuracy.md instead (the same runs; the
              docs' table is this output, checked by tools/python/tests/test_docs.py)
The six runs go two at a time (the machine's two cores).
"""
import argparse
import json
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
KEYS = ["Rs_ohm", "Rr_ohm", "Lm_H", "Lr_H", "psi_r_Wb", "Tr_s"]
MOTORS = [("paper_motor", 2.0), ("motor_1kw", 3.0), ("motor_15kw", 3.0)]
LABELS = {"paper_motor": "paper, 250 W", "motor_1kw": "1.1 kW 400 V", "motor_15kw": "15 kW 400 V"}
BUILDS = ("host-iq", "host-float")
MATH = {"host-iq": "IQ_MATH", "host-float": "FLOAT_MATH"}


def run(build, config):
    exe = ROOT / "build" / build / "host_sim" / "sim" / "motor_sim"
    with tempfile.TemporaryDirectory() as d:
        p = subprocess.run([str(exe), "--config",
                            str(ROOT / "host_sim" / "config" / f"{config}.ini"), "--quiet",
                            "--out", d])
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


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--markdown", action="store_true", help="print the docs' markdown table")
    a = ap.parse_args()
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
