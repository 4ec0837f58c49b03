#!/usr/bin/env python3
"""Healthy drives must never trip: the default sequence on motors nobody tuned
for, with every healthy disturbance a real drive meets at once.

For each motor (the family's CI subset on the buses their mains give, and the
shipped motor files), every combination of

  - the nameplate: true, or believed Tr, Lm, Rs off by -30 / +30 % (`axes`:
    one at a time and the 8 corners, 15 sets; `full`: the 27 of the cube),
  - the load at rated speed: 0, half, full rated torque (a quarter constant,
    three quarters fan, as tools/family_sweep.py's operating choices),
  - the bus: 0.85, 1.0, 1.1 x nominal (mains -15 % .. +10 %),

and, at the true nameplate, the same loads and buses with a bus ripple of
RIPPLE_OF_VDC of the bus at six times the rated frequency (a loaded diode
rectifier), runs motor_sim (start scenario, until the drive's verdict) and
counts:

  false_trips            runs in which a protection latched a fault (the
                         motor is healthy: every fault is false), or the
                         bridge's comparator fired, or the plant diverged
  published_above_3pct   runs whose published set is more than 3 % off on a
                         parameter (the drive's confidence must refuse those)
  refused                runs that published nothing, by the drive's reason
                         (a refusal with a reason is a correct answer)

    nuisance_sweep.py [--motors ci,shipped | --motor NAME]... [--grid axes|full]
                      [--loads 0,0.5,1] [--buses 0.85,1,1.1] [--no-ripple]
                      [--exe MOTOR_SIM | --build iq|float] [--jobs N]
                      [--out DIR] [--json] [--limit N] [--keep]

Writes OUT/nuisance.csv (one row per run: the case, the verdict, the faults,
the worst error, the model check's and the current check's largest
utilisation, the target the drive ran at); --json prints one line

    {"runs": N, "false_trips": 0, "published_above_3pct": 0, "published": n,
     "refused": {"low_confidence": n, ...}, "errors": 0, ...}

Exit status: 0 the sweep ran (a study: whatever it found), 1 bad options or a
missing simulator.  A family motor NAME is one of tools/family/motors.py's or
P_kW,poles,f_Hz,V,sigma; a shipped file is its path.
"""
from __future__ import annotations

import argparse
import csv
import itertools
import json
import math
import os
import subprocess
import sys
import tempfile
from collections import Counter
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tools"))
sys.path.insert(0, str(ROOT / "tools" / "family"))
import motors as fam  # noqa: E402
from sweep_start_errors import (ADAPTIVE, ini_merge, ini_value, rr_error_pct,  # noqa: E402
                                wrong_nameplate)

PARAMS = ("Rs_ohm", "Rr_ohm", "Lm_H", "Lr_H", "psi_r_Wb", "Tr_s")
BOUND_PCT = 3.0
RIPPLE_OF_VDC = 0.05     # peak, a loaded six-pulse rectifier's DC link
SHIPPED = ("paper_motor.ini", "paper_motor_adaptive.ini", "paper_motor_wrong_nameplate.ini",
           "motor_1kw.ini", "motor_15kw.ini", "motor_37kw.ini")
BUILDS = {"iq": "host-iq", "float": "host-float"}
RC_CONFIG = 1


def nameplate_sets(grid):
    """(tr, lm, rs) believed errors in %."""
    if grid == "full":
        return list(itertools.product((-30, 0, 30), repeat=3))
    axes = [(0, 0, 0)]
    for i in range(3):
        for e in (-30, 30):
            c = [0, 0, 0]
            c[i] = e
            axes.append(tuple(c))
    return axes + list(itertools.product((-30, 30), repeat=3))


def base_of(motor):
    """(label, INI text with the default sequence, truth dict, rated torque N m)."""
    if motor.endswith(".ini"):
        path = Path(motor)
        if not path.is_absolute() and not path.exists():
            path = ROOT / "host_sim" / "config" / motor
        text = path.read_text()
        truth = {k: float(ini_value(text, "plant", k) or ini_value(text, "nameplate", k))
                 for k in ("Rs_ohm", "Rr_ohm", "Lm_H", "Lls_H", "Llr_H")}
        p_w = float(ini_value(text, "nameplate", "rated_power_W") or 0.0)
        n = float(ini_value(text, "nameplate", "rated_speed_rpm"))
        t_n = p_w / (n * 2.0 * math.pi / 60.0) if p_w > 0 else 0.0
        return path.name, text, truth, t_n
    m = fam.by_name(motor)
    text = fam.to_ini(m, "split", extra={k: int(v) for k, v in ADAPTIVE.items()})
    truth = {"Rs_ohm": m.Rs, "Rr_ohm": m.Rr, "Lm_H": m.Lm, "Lls_H": m.Lls, "Llr_H": m.Llr}
    return m.name, text, truth, m.T_N


def cases(motors, grid, loads, buses, ripple):
    out = []
    for motor in motors:
        label = base_of(motor)[0]
        for (tr, lm, rs), load, bus in itertools.product(nameplate_sets(grid), loads, buses):
            out.append((label, motor, tr, lm, rs, load, bus, 0.0))
        if ripple:
            for load, bus in itertools.product(loads, buses):
                out.append((label, motor, 0, 0, 0, load, bus, RIPPLE_OF_VDC))
    return out


def run_one(job):
    (label, motor, tr, lm, rs, load, bus, ripple), exe, keep = job
    _, text, truth, t_n = base_of(motor)
    vdc = float(ini_value(text, "board", "vdc_nominal_V"))
    f_n = float(ini_value(text, "nameplate", "rated_freq_Hz"))
    over = {}
    if (tr, lm, rs) != (0, 0, 0):
        over.update(wrong_nameplate(truth, rs, lm,
                                    rr_error_pct(tr, lm, truth["Lm_H"], truth["Llr_H"])))
    if t_n > 0.0:
        over[("load", "const_Nm")] = repr(0.25 * load * t_n)
        over[("load", "fan_Nm")] = repr(0.75 * load * t_n)
    over[("inverter", "vdc_V")] = repr(bus * vdc)
    if ripple > 0.0:
        over[("inverter", "ripple_V")] = repr(ripple * bus * vdc)
        over[("inverter", "ripple_Hz")] = repr(6.0 * f_n)
    row = {"motor": label, "tr_pct": tr, "lm_pct": lm, "rs_pct": rs, "load": load, "bus": bus,
           "ripple": ripple, "status": "", "reason": "", "faults": "", "worst_pct": None,
           "worst_param": "", "target_of_rated": None, "max_cmc_util": None,
           "max_cur_check_pu": None, "hw_trips": 0, "message": ""}
    with tempfile.TemporaryDirectory(prefix="nuisance_") as tmp:
        d = Path(keep) / f"{label}_tr{tr:+d}_lm{lm:+d}_rs{rs:+d}_l{load:g}_b{bus:g}_r{ripple:g}" \
            if keep else Path(tmp)
        d.mkdir(parents=True, exist_ok=True)
        ini = d / "config.ini"
        ini.write_text(ini_merge(text, over))
        p = subprocess.run([str(exe), "--config", str(ini), "--quiet", "--out", str(d)],
                           capture_output=True, text=True)
        if p.returncode not in (0, 3):
            row["status"] = "config_error" if p.returncode == RC_CONFIG else f"error rc={p.returncode}"
            row["message"] = (p.stderr.strip().splitlines() or [""])[-1][-300:]
            return row
        rep = json.loads((d / "report.json").read_text())
        if not keep:
            (d / "trace.csv").unlink(missing_ok=True)
    row["faults"] = " ".join(f"{f['name']}@{f.get('state', '?')}{f.get('pass', '')}"
                             + (f"[{f['checks'].strip()}]" if f.get("checks") else "")
                             for f in rep.get("faults", []))
    row["hw_trips"] = rep.get("hw_comparator_trips") or 0
    row["reason"] = rep.get("publish_reason", "")
    row["max_cmc_util"] = max(v for v in (rep.get("max_cmc_util_r"), rep.get("max_cmc_util_neg"),
                                          rep.get("max_cmc_util_dc"), 0.0) if v is not None)
    row["max_cur_check_pu"] = rep.get("max_cur_check_pu")
    rated = float(ini_value(text, "nameplate", "rated_speed_rpm"))
    if rep.get("target_rpm"):
        row["target_of_rated"] = round(rep["target_rpm"] / rated, 4)
    if row["faults"] or row["hw_trips"] or rep.get("plant_diverged_at_s", -1) not in (None, -1, -1.0):
        row["status"] = "false_trip"
    elif rep.get("published"):
        e = rep.get("published_end_error_pct") or {}
        w = max(PARAMS, key=lambda k: abs(e.get(k) or 0.0))
        row["worst_pct"] = abs(e.get(w) or 0.0)
        row["worst_param"] = w
        row["status"] = "published" if row["worst_pct"] <= BOUND_PCT else "published_above_3pct"
    else:
        row["status"] = "refused"
    return row


def summary(rows):
    c = Counter(r["status"] for r in rows)
    refused = Counter(r["reason"] for r in rows if r["status"] == "refused")
    pub = [r["worst_pct"] for r in rows if r["status"] in ("published", "published_above_3pct")]
    return {"runs": len(rows), "false_trips": c["false_trip"],
            "published_above_3pct": c["published_above_3pct"],
            "published": c["published"] + c["published_above_3pct"],
            "published_worst_pct": round(max(pub), 3) if pub else None,
            "refused": dict(sorted(refused.items())),
            "errors": sum(v for k, v in c.items() if k.startswith(("error", "config_error"))),
            "max_cmc_util": max((r["max_cmc_util"] or 0.0) for r in rows) if rows else None}


def parse_args(argv):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--motors", default="ci,shipped",
                    help="ci (the family's CI subset), shipped (host_sim/config), or both")
    ap.add_argument("--motor", action="append", default=[],
                    help="a family motor's name (or P_kW,poles,f_Hz,V,sigma) or an INI path; "
                         "replaces --motors")
    ap.add_argument("--grid", choices=("axes", "full"), default="axes")
    ap.add_argument("--loads", default="0,0.5,1")
    ap.add_argument("--buses", default="0.85,1,1.1")
    ap.add_argument("--no-ripple", action="store_true")
    ap.add_argument("--build", choices=tuple(BUILDS), default="iq")
    ap.add_argument("--exe", type=Path)
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--out", type=Path, default=ROOT / "out" / "nuisance")
    ap.add_argument("--json", action="store_true", help="print the summary line only")
    ap.add_argument("--limit", type=int, default=0, help="run only the first N cases")
    ap.add_argument("--keep", action="store_true", help="keep every run's folder in OUT")
    return ap.parse_args(argv)


def main(argv=None):
    a = parse_args(argv)
    exe = a.exe or ROOT / "build" / BUILDS[a.build] / "host_sim" / "sim" / "motor_sim"
    if not exe.exists():
        print(f"nuisance_sweep: no simulator at {exe} (build it: cmake --build --preset "
              f"{BUILDS[a.build]})", file=sys.stderr)
        return 1
    try:
        loads = [float(x) for x in a.loads.split(",")]
        buses = [float(x) for x in a.buses.split(",")]
    except ValueError:
        print("nuisance_sweep: --loads and --buses take comma-separated numbers", file=sys.stderr)
        return 1
    motors = list(a.motor)
    if not motors:
        for part in a.motors.split(","):
            if part == "ci":
                motors += [m.name for m in fam.ci_subset()]
            elif part == "shipped":
                motors += list(SHIPPED)
            else:
                print(f"nuisance_sweep: --motors takes ci, shipped (not {part!r})",
                      file=sys.stderr)
                return 1
    try:
        todo = cases(motors, a.grid, loads, buses, not a.no_ripple)
    except KeyError as e:
        print(f"nuisance_sweep: no motor {e}", file=sys.stderr)
        return 1
    if a.limit > 0:
        todo = todo[:a.limit]
    a.out.mkdir(parents=True, exist_ok=True)
    if not a.json:
        print(f"nuisance_sweep: {len(todo)} runs ({len(motors)} motors), {a.jobs} at a time",
              file=sys.stderr)
    keep = str(a.out / "runs") if a.keep else None
    with ProcessPoolExecutor(max_workers=max(1, a.jobs)) as ex:
        rows = list(ex.map(run_one, [(c, str(exe), keep) for c in todo]))
    with open(a.out / "nuisance.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()) if rows else ["motor"])
        w.writeheader()
        w.writerows(rows)
    s = summary(rows)
    if a.json:
        print(json.dumps(s))
        return 0
    print(json.dumps(s, indent=1))
    bad = [r for r in rows if r["status"] not in ("published", "refused")]
    for r in bad[:40]:
        print(f"  {r['status']:22s} {r['motor']:34s} Tr{r['tr_pct']:+d} Lm{r['lm_pct']:+d} "
              f"Rs{r['rs_pct']:+d} load {r['load']:g} bus {r['bus']:g} ripple {r['ripple']:g}: "
              f"{r['faults'] or r['message'] or r['worst_param']}")
    print(f"wrote {a.out / 'nuisance.csv'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
