#!/usr/bin/env python3
"""The identification over the motor family: every motor of
tools/family/motors.py (the CI subset of 8, the grid of 56) under a grid of
operating choices, in both builds and both identification sequences.

    family_sweep.py [--subset ci|grid|all] [--motors NAME,...] [--ops nominal|all|OP,...]
                    [--seq paper,adaptive,paper_pm,standstill]
                    [--plant realistic|ideal|ideal_bridge]
                    [--builds iq,float | --exe MOTOR_SIM] [--jobs N]
                    [--out DIR] [--json] [--markdown [--summary-only]] [--no-plot]
                    [--check-bounds FILE] [--keep]

Sequences (`[controller]`/`[ident]` keys merged into each motor's file):

    paper      orientation 0, standstill 0, passes 1, track_rr 0: the paper's
               (indirect orientation on the nameplate, one RLS pass)
    adaptive   orientation 1, standstill 1, passes 2, track_rr 1: the drive's
               default (docs/method.md "Beyond the paper"; host_sim/config/paper_motor.ini)
    paper_pm   the paper's on the period-mean regression (period_mean 1,
               include/ident_regressor.h; tools/study/regression_bias.md §5)
    standstill `[ident] sequence = standstill` with the rotor held (`[load]
               locked = 1`): every parameter at standstill (include/drive_static.h);
               judged against 3 % on Rs, Lm, Lr, psi_r and 5 % on Rr and Tr
               (STANDSTILL_BOUNDS_PCT); its time to the verdict (t_decided_s)

Plants: `realistic` (default: the generator's bridge and sensors), `ideal`
(motors.py IDEAL_PLANT: no dead time, drop, ripple, sensor errors or noise) or
`ideal_bridge` (the same with the sensors' noise, IDEAL_BRIDGE).

Operating choices (one at a time from the generator's nominal point; the same
as tools/study/regression_bias.py's, scaled to each motor): `nominal`, `load0`
and `load100` (0 % and 100 % of rated torque at rated speed, a quarter constant
and three quarters fan), `ramp0.5` and `ramp2` (the speed ramp x0.5, x2),
`target0.5` (half the rated speed), `im0.8` and `im1.2` (the magnetising
current x0.8, x1.2, on the motor's own bus).

Each run is `motor_sim --config <file> --out <tmp>` of build/host-iq or
build/host-float, in parallel on --jobs processes (default: the machine's
cores).  A motor the firmware refuses (the INI check and drive_init share one
table of limits, e.g. Tr beyond the Q24 time base) is listed as `refused` with
motor_sim's message, never dropped.  A run that publishes nothing is listed
with the drive's reason (report.json's publish_reason).

Writes OUT/family.csv (one row per run), OUT/family.md (the per-motor table
and the family summary) and OUT/family.png (the worst parameter error against
motor size and against w_r Tr, published runs filled, refused sets hollow at
the error they would have had).  --markdown prints the tables (as in the
README); --json prints one line

    {"motors": n, "adaptive_worst_pct": x, "paper_published_worst_pct": y,
     "paper_unpublished": n, ...}

where the worsts are over the six parameters (Rs Rr Lm Lr psi_r Tr), every
operating choice run and both builds; paper_published_worst_pct over the
paper's runs that published (null if none did).

--check-bounds FILE (the CTest `family_subset`): the runs must match the
expectations of FILE (JSON: per motor and sequence, "published" true/false,
the bound on the worst published error, the reasons accepted, and
"refused_bound_pct": a refusal must carry report.json's refused_set, within
that bound); exit 1 with
the failures listed otherwise.

Exit status: 0 the sweep ran (a study: whatever the runs found), 1 bad
options, a missing simulator, or (with --check-bounds) an expectation not met.
"""
from __future__ import annotations

import argparse
import csv
import json
import math
import os
import re
import statistics
import subprocess
import sys
import tempfile
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tools" / "family"))
import motors as fam  # noqa: E402

PARAMS = ("Rs_ohm", "Rr_ohm", "Lm_H", "Lr_H", "psi_r_Wb", "Tr_s")
SHORT = {"Rs_ohm": "Rs", "Rr_ohm": "Rr", "Lm_H": "Lm", "Lr_H": "Lr", "psi_r_Wb": "psi_r",
         "Tr_s": "Tr"}
BOUND_PCT = 3.0
SEQUENCES = {
    "paper": {("controller", "orientation"): 0, ("ident", "standstill"): 0,
              ("ident", "passes"): 1, ("ident", "track_rr"): 0},
    "adaptive": {("controller", "orientation"): 1, ("ident", "standstill"): 1,
                 ("ident", "passes"): 2, ("ident", "track_rr"): 1},
    # the paper's sequence on the period-mean regression (ident_regressor.h)
    "paper_pm": {("controller", "orientation"): 0, ("ident", "standstill"): 0,
                 ("ident", "passes"): 1, ("ident", "track_rr"): 0, ("ident", "period_mean"): 1},
    # every parameter at standstill, the rotor held (a load that cannot turn)
    "standstill": {("ident", "sequence"): "standstill", ("load", "locked"): 1},
}
# the standstill sequence's goals per parameter (its Rr and Tr rest on the
# rotor branch's small share of the impedance at standstill)
STANDSTILL_BOUNDS_PCT = {"Rs_ohm": 3.0, "Rr_ohm": 5.0, "Lm_H": 3.0, "Lr_H": 3.0,
                         "psi_r_Wb": 3.0, "Tr_s": 5.0}
PLANTS = {"realistic": {}, "ideal": fam.IDEAL_PLANT, "ideal_bridge": fam.IDEAL_BRIDGE}
BUILDS = {"iq": "host-iq", "float": "host-float"}
# motor_sim's exit status (motor_sim --help)
RC_PUBLISHED, RC_CONFIG, RC_RUN_FAILED, RC_NOT_PUBLISHED = 0, 1, 2, 3


EXE = {}   # build name -> motor_sim path given with --exe (the CTest's own build)


def motor_sim(build):
    if build in EXE:
        return Path(EXE[build])
    return ROOT / "build" / BUILDS[build] / "host_sim" / "sim" / "motor_sim"


# ------------------------------------------------------------ operating choices
def _load(m, frac):
    return {("load", "const_Nm"): 0.25 * frac * m.T_N, ("load", "fan_Nm"): 0.75 * frac * m.T_N}


def _im(m, k):
    """i_M x k on the motor's own bus (motors.py note 7: the rectified mains,
    no boost; the drive's target speed follows the voltage it has)."""
    return {("controller", "magnetizing_current_A"): k * m.i_m}


OPS = {
    "nominal": lambda m: {},
    "load0": lambda m: _load(m, 0.0),
    "load100": lambda m: _load(m, 1.0),
    "ramp0.5": lambda m: {("controller", "speed_ramp_rpm_s"): 0.5 * m.ramp_rpm_s},
    "ramp2": lambda m: {("controller", "speed_ramp_rpm_s"): 2.0 * m.ramp_rpm_s},
    "target0.5": lambda m: {("ident", "target_speed_rpm"): 0.5 * m.n_N},
    "im0.8": lambda m: _im(m, 0.8),
    "im1.2": lambda m: _im(m, 1.2),
}


# ------------------------------------------------------------ one run
def run_one(job):
    """job: (motor name, op, sequence, build, keep dir or None, --exe map,
    plant).  Returns a row dict (plain types: it crosses the process boundary)."""
    name, op, seq, build, keep, exe, plant = job
    EXE.update(exe)
    m = fam.by_name(name)
    extra = dict(OPS[op](m))
    extra.update(SEQUENCES[seq])
    extra.update(PLANTS[plant])
    row = {"motor": name, "P_kW": m.P_kW, "poles": m.poles, "f_Hz": m.f_Hz, "V": m.V,
           "sigma": m.sigma, "Tr_s": round(m.Tr, 5), "wrTr": round(m.wrTr, 2),
           "dead_time_us": m.dead_time_s * 1e6, "op": op, "seq": seq, "build": build,
           "status": "", "reason": "", "message": "", "worst_pct": None, "worst_param": "",
           "worst_of": "", "cmc_r": None, "cmc_neg": None, "cmc_dc": None,
           "t_published_s": None, "settle_timeout": None, "target_rpm": None,
           "target_of_rated": None}
    for k in PARAMS:
        row["err_" + SHORT[k]] = None
        row["rls_" + SHORT[k]] = None
        row["ref_" + SHORT[k]] = None
        row["conf_" + SHORT[k]] = None
    with tempfile.TemporaryDirectory(prefix="family_") as tmp:
        d = Path(keep) / f"{name}__{op}__{seq}__{build}" if keep else Path(tmp)
        d.mkdir(parents=True, exist_ok=True)
        ini = d / "motor.ini"
        ini.write_text(fam.to_ini(m, "split", extra=extra))
        p = subprocess.run([str(motor_sim(build)), "--config", str(ini), "--quiet", "--out",
                            str(d)], capture_output=True, text=True)
        if p.returncode == RC_CONFIG:
            row["status"] = "refused"
            msg = p.stderr.strip().splitlines()[-1] if p.stderr.strip() else ""
            row["message"] = re.sub(r"^motor_sim: \S*motor\.ini(:\d+)?: ", "", msg)
            return row
        if p.returncode not in (RC_PUBLISHED, RC_NOT_PUBLISHED):
            row["status"] = f"error rc={p.returncode}"
            row["message"] = p.stderr.strip()[-300:]
            return row
        rep = json.loads((d / "report.json").read_text())
        if not keep:
            (d / "trace.csv").unlink(missing_ok=True)
    row["status"] = "published" if rep["published"] else "not_published"
    if row["status"] == "published" and p.returncode != RC_PUBLISHED:
        row["status"] = f"error rc={p.returncode} with a published set"
    row["reason"] = rep.get("publish_reason", "")
    row["settle_timeout"] = rep.get("settle_timeout")
    row["t_published_s"] = rep.get("t_published_s")
    row["t_decided_s"] = rep.get("t_decided_s")
    row["rotor_counts"] = rep.get("rotor_turn_counts")
    # the identification's target as the drive ran it (drive_target.h: lowered
    # where the voltage ran out), and per unit of the rated speed
    row["target_rpm"] = rep.get("target_rpm")
    if row["target_rpm"]:
        row["target_of_rated"] = round(row["target_rpm"] / m.n_N, 4)
    row["faults"] = " ".join(f["name"] for f in rep.get("faults", []))
    pub = rep.get("published_end_error_pct") if rep["published"] else None
    rls = rep.get("last_extraction_error_pct")
    # the adaptive sequence's refused fused set (standstill Rs, tracked Rr
    # and Tr, the RLS's Lm, Lr, psi_r): what a refusal concerned
    ref = None if rep["published"] else rep.get("refused_set_error_pct")
    conf = rep.get("confidence_pct") or {}
    for k in PARAMS:
        if pub:
            row["err_" + SHORT[k]] = pub[k]
        if rls:
            row["rls_" + SHORT[k]] = rls[k]
        if ref:
            row["ref_" + SHORT[k]] = ref[k]
        if conf.get(k) is not None:
            row["conf_" + SHORT[k]] = conf[k]
    # the worst error of what was published, or of what the drive refused to
    # publish (the fused set, else the RLS's extraction), so that a refusal
    # can be judged
    src = pub or ref or rls
    row["worst_of"] = ("published" if pub else "refused_set" if ref else
                       "extraction" if rls else "")
    if src:
        w = max(PARAMS, key=lambda k: abs(src[k]))
        row["worst_pct"] = abs(src[w])
        row["worst_param"] = SHORT[w]
    # the model check's healthy margins (fractions of its levels)
    row["cmc_r"] = rep.get("max_cmc_util_r")
    row["cmc_neg"] = rep.get("max_cmc_util_neg")
    row["cmc_dc"] = rep.get("max_cmc_util_dc")
    c = rep.get("confidence") or {}
    row["residual_rel"] = c.get("residual_rel")
    row["amplification"] = c.get("amplification")
    row["excitation"] = c.get("excitation")
    row["pd_repairs"] = c.get("rls_pd_repairs")
    for k in PARAMS:
        row["bound_" + SHORT[k]] = (c.get("bound_pct") or {}).get(k)
        row["drift_" + SHORT[k]] = (c.get("drift_pct") or {}).get(k)
    return row


# ------------------------------------------------------------ summaries
def published(rows):
    return [r for r in rows if r["status"] == "published"]


def summary(rows, n_motors):
    """The --json line."""
    out = {"motors": n_motors}
    for seq in SEQUENCES:
        rs = [r for r in rows if r["seq"] == seq]
        pub = published(rs)
        worst = max((r["worst_pct"] for r in pub), default=None)
        unpub = [r for r in rs if r["status"] == "not_published"]
        out[f"{seq}_runs"] = len(rs)
        out[f"{seq}_published"] = len(pub)
        out[f"{seq}_unpublished"] = len(unpub)
        out[f"{seq}_refused"] = sum(r["status"] == "refused" for r in rs)
        out[f"{seq}_published_worst_pct"] = None if worst is None else round(worst, 3)
        out[f"{seq}_published_above_{BOUND_PCT:g}pct"] = sum(r["worst_pct"] > BOUND_PCT
                                                              for r in pub)
    # the adaptive sequence is judged on every run the firmware accepted: its
    # worst is over the published ones, and adaptive_unpublished says how many
    # published nothing (null if none published)
    out["adaptive_worst_pct"] = out.pop("adaptive_published_worst_pct")
    out["paper_published_worst_pct"] = out.pop("paper_published_worst_pct")
    out["paper_unpublished"] = out.pop("paper_unpublished")
    return out


def fmt_pct(v, signed=False):
    if v is None:
        return "-"
    return f"{v:+.2f}" if signed else f"{v:.2f}"


def motor_rows_md(rows, motors, builds):
    """One line per motor, sequence and build: published? why not, worst
    error (parameter), each parameter's error (of the published set; in
    brackets of the refused set: the fused one, else the RLS's extraction)."""
    head = ("| motor | kW | poles | sigma | w_r Tr | sequence | build | published | worst % | " +
            " | ".join(SHORT[k] for k in PARAMS) + " |")
    out = [head, "|" + "---|" * (8 + len(PARAMS))]
    for name in motors:
        for seq in SEQUENCES:
            for b in builds:
                rs = [r for r in rows if r["motor"] == name and r["seq"] == seq and
                      r["build"] == b and r["op"] == "nominal"]
                if not rs:
                    continue
                r = rs[0]
                if r["status"] == "refused":
                    pubtxt = f"refused: {r['message']}"
                elif r["status"] == "published":
                    pubtxt = "yes"
                else:
                    pubtxt = f"no: {r['reason'] or r['status']}"
                errs = []
                for k in PARAMS:
                    v = (r["err_" + SHORT[k]] if r["status"] == "published" else
                         r["ref_" + SHORT[k]] if r["ref_" + SHORT[k]] is not None else
                         r["rls_" + SHORT[k]])
                    errs.append(fmt_pct(v, True) if r["status"] == "published"
                                else (f"({fmt_pct(v, True)})" if v is not None else "-"))
                worst = ("-" if r["worst_pct"] is None else
                         (f"{r['worst_pct']:.2f} ({r['worst_param']})" if r["status"] == "published"
                          else f"({r['worst_pct']:.2f} {r['worst_param']})"))
                out.append(f"| {name} | {r['P_kW']:g} | {r['poles']} | {r['sigma']:.3f} | "
                           f"{r['wrTr']:.1f} | {seq} | {b} | {pubtxt} | {worst} | " +
                           " | ".join(errs) + " |")
    return "\n".join(out)


def family_md(rows, builds, label):
    """Per sequence and build: runs, published (worst, median), not
    published (by reason), refused."""
    out = [f"| {label} | build | runs | published | within {BOUND_PCT:g} % | worst % | "
           f"median % | not published (reason) | refused |", "|---|---|---|---|---|---|---|---|---|"]
    for seq in SEQUENCES:
        for b in builds:
            rs = [r for r in rows if r["seq"] == seq and r["build"] == b]
            if not rs:
                continue
            pub = published(rs)
            w = [r["worst_pct"] for r in pub]
            reasons = {}
            for r in rs:
                if r["status"] == "not_published" or r["status"].startswith("error"):
                    k = r["reason"] or r["status"]
                    reasons[k] = reasons.get(k, 0) + 1
            out.append(f"| {seq} | {b} | {len(rs)} | {len(pub)} | "
                       f"{sum(x <= BOUND_PCT for x in w)} | "
                       f"{fmt_pct(max(w) if w else None)} | "
                       f"{fmt_pct(statistics.median(w) if w else None)} | "
                       f"{', '.join(f'{n} {k}' for k, n in sorted(reasons.items())) or '-'} | "
                       f"{sum(r['status'] == 'refused' for r in rs)} |")
    return "\n".join(out)


def write_csv(rows, path):
    cols = list(rows[0].keys()) if rows else []
    for r in rows:
        for k in r:
            if k not in cols:
                cols.append(k)
    with path.open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=cols)
        w.writeheader()
        for r in rows:
            w.writerow(r)


def plot(rows, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(13, 5), sharey=True)
    style = {"paper": ("o", "tab:red"), "adaptive": ("s", "tab:blue")}
    ymax = BOUND_PCT * 3
    for ax, xk, xl in ((axes[0], "P_kW", "rated power / kW"),
                       (axes[1], "wrTr", "w_r Tr at the target speed")):
        for seq, (mk, col) in style.items():
            for b, dx in (("iq", 1.0), ("float", 1.04)):
                rs = [r for r in rows if r["seq"] == seq and r["build"] == b and
                      r["worst_pct"] is not None]
                pub = [r for r in rs if r["status"] == "published"]
                ref = [r for r in rs if r["status"] != "published"]
                lab = f"{seq}, {b}"
                ax.scatter([r[xk] * dx for r in pub], [min(r["worst_pct"], ymax) for r in pub],
                           marker=mk, color=col, alpha=0.7 if b == "iq" else 0.4, s=22,
                           label=f"{lab}: published")
                if ref:
                    ax.scatter([r[xk] * dx for r in ref], [min(r["worst_pct"], ymax) for r in ref],
                               marker=mk, facecolors="none", edgecolors=col, s=30,
                               label=f"{lab}: refused by the drive (its extraction)")
        ax.axhline(BOUND_PCT, color="k", lw=1, ls="--")
        ax.set_xscale("log")
        ax.set_xlabel(xl)
        ax.grid(alpha=0.3)
    axes[0].set_ylabel(f"worst parameter error / % (clipped at {ymax:g})")
    axes[0].set_ylim(0, ymax * 1.05)
    axes[1].legend(fontsize=7, loc="upper left")
    n = len({r["motor"] for r in rows})
    fig.suptitle(f"identification over {n} motors: worst of Rs Rr Lm Lr psi_r Tr "
                 f"(dashed: {BOUND_PCT:g} %)", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


# ------------------------------------------------------------ expectations
def check_bounds(rows, spec):
    """spec: {"bound_pct": x, "motors": {name: {seq: {"published": bool,
    "bound_pct": x, "reasons": [...]}}}}; returns a list of failures.
    "published": null accepts either verdict (a motor at the verdict's edge):
    published within bound_pct, or refused for one of the reasons."""
    fails = []
    for r in rows:
        e = spec["motors"].get(r["motor"], {}).get(r["seq"])
        if e is None:
            continue
        tag = f"{r['motor']} {r['seq']} {r['build']} {r['op']}"
        want = e["published"]
        if r["status"] not in ("published", "not_published"):
            fails.append(f"{tag}: {r['status']} {r['message']}")
        elif want is None:
            if r["status"] == "published" and r["worst_pct"] > e.get("bound_pct",
                                                                      spec["bound_pct"]):
                fails.append(f"{tag}: worst {r['worst_pct']:.3f} % ({r['worst_param']}) above "
                             f"{e.get('bound_pct', spec['bound_pct'])} %")
            elif r["status"] != "published" and r["reason"] not in e.get("reasons", []):
                fails.append(f"{tag}: reason {r['reason']!r}, expected one of "
                             f"{e.get('reasons', [])}")
        elif (r["status"] == "published") != want:
            fails.append(f"{tag}: published {r['status'] == 'published'} (reason "
                         f"{r['reason']!r}), expected {want}; worst {r['worst_pct']}")
        elif want and r["worst_pct"] > e.get("bound_pct", spec["bound_pct"]):
            fails.append(f"{tag}: worst {r['worst_pct']:.3f} % ({r['worst_param']}) above "
                         f"{e.get('bound_pct', spec['bound_pct'])} %")
        elif not want and r["reason"] not in e.get("reasons", [r["reason"]]):
            fails.append(f"{tag}: reason {r['reason']!r}, expected one of {e['reasons']}")
        if r["status"] == "not_published" and "refused_bound_pct" in e:
            # the set the refusal concerned (report.json's refused_set)
            if r["worst_of"] != "refused_set":
                fails.append(f"{tag}: refused without a refused_set in report.json")
            elif r["worst_pct"] > e["refused_bound_pct"]:
                fails.append(f"{tag}: the refused set's worst {r['worst_pct']:.3f} % "
                             f"({r['worst_param']}) above {e['refused_bound_pct']} %")
        if r["status"] == "published" and r["worst_pct"] > spec["bound_pct"]:
            fails.append(f"{tag}: a published error of {r['worst_pct']:.3f} % "
                         f"({r['worst_param']}) above {spec['bound_pct']} %")
    return fails


# ------------------------------------------------------------ main
def select_motors(a):
    if a.motors:
        names = [x.strip() for x in a.motors.split(",") if x.strip()]
        for n in names:
            try:
                fam.by_name(n)
            except KeyError:
                raise SystemExit(f"family_sweep: no motor {n!r} (motors.py list --ci | --grid)")
        return names
    ms = {"ci": fam.ci_subset, "grid": fam.grid,
          "all": lambda: fam.ci_subset() + fam.grid()}[a.subset]()
    return list(dict.fromkeys(m.name for m in ms))   # a CI motor may be in the grid too


def split_list(text, allowed, what):
    if text == "all":
        return list(allowed)
    out = [x.strip() for x in text.split(",") if x.strip()]
    bad = [x for x in out if x not in allowed]
    if bad or not out:
        raise SystemExit(f"family_sweep: {what} {bad or text!r} not in {', '.join(allowed)}")
    return out


def parse_args(argv):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--subset", choices=("ci", "grid", "all"), default="ci")
    ap.add_argument("--motors", help="comma-separated motor names (motors.py list)")
    ap.add_argument("--ops", default="nominal", help="operating choices: nominal (default), "
                    "all, or a list of " + ", ".join(OPS))
    ap.add_argument("--seq", default="paper,adaptive,standstill",
                    help="sequences: paper, adaptive, standstill (the rotor held), paper_pm "
                    "(the paper's on the period-mean regression, ident.period_mean 1)")
    ap.add_argument("--plant", choices=tuple(PLANTS), default="realistic",
                    help="ideal: no dead time, drop, ripple, sensor errors or noise "
                    "(motors.py IDEAL_PLANT); ideal_bridge: the same with the sensors' noise")
    ap.add_argument("--builds", default="iq,float")
    ap.add_argument("--exe", metavar="MOTOR_SIM", help="run this motor_sim as the only build "
                    "(named after its report's math_type: the CTest runs its own build)")
    ap.add_argument("--no-plot", action="store_true", help="no family.png (no matplotlib)")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--out", type=Path, default=ROOT / "out" / "family")
    ap.add_argument("--json", action="store_true", help="print the summary line only")
    ap.add_argument("--markdown", action="store_true", help="print the markdown tables")
    ap.add_argument("--summary-only", action="store_true",
                    help="with --markdown: the family table only, not one line per motor")
    ap.add_argument("--check-bounds", type=Path, metavar="FILE")
    ap.add_argument("--keep", action="store_true", help="keep every run's folder "
                    "(trace.csv, report.json, motor.ini) under OUT/runs")
    return ap.parse_args(argv)


def main(argv=None):
    a = parse_args(sys.argv[1:] if argv is None else argv)
    motors = select_motors(a)
    ops = split_list(a.ops, OPS, "operating choice")
    seqs = split_list(a.seq, SEQUENCES, "sequence")
    builds = split_list(a.builds, BUILDS, "build")
    if a.exe:
        if not Path(a.exe).is_file():
            raise SystemExit(f"family_sweep: no {a.exe}")
        builds = ["exe"]
        EXE["exe"] = str(Path(a.exe).resolve())
    if a.jobs < 1:
        raise SystemExit("family_sweep: --jobs must be at least 1")
    for b in builds:
        if not motor_sim(b).is_file():
            raise SystemExit(f"family_sweep: no {motor_sim(b)} (cmake --build --preset "
                             f"{BUILDS[b]})")
    a.out.mkdir(parents=True, exist_ok=True)
    keep = str(a.out / "runs") if a.keep else None
    jobs = [(m, op, s, b, keep, dict(EXE), a.plant) for m in motors for op in ops for s in seqs
            for b in builds]
    if not a.json:
        print(f"family_sweep: {len(jobs)} runs ({len(motors)} motors x {len(ops)} operating "
              f"choices x {len(seqs)} sequences x {len(builds)} builds), {a.jobs} at a time",
              file=sys.stderr)
    with ProcessPoolExecutor(max_workers=a.jobs) as pool:
        rows = list(pool.map(run_one, jobs, chunksize=1))
    write_csv(rows, a.out / "family.csv")
    fam_md = family_md(rows, builds, f"{len(motors)} motors, {len(ops)} operating choice(s)")
    md = ["### The motors (nominal operating point)", "", motor_rows_md(rows, motors, builds), "",
          "### The family", "", fam_md, ""]
    (a.out / "family.md").write_text("\n".join(md))
    if a.summary_only:
        md = [fam_md]
    if not a.no_plot:
        plot(rows, a.out / "family.png")
    s = summary(rows, len(motors))
    if a.json:
        print(json.dumps(s))
    elif a.markdown:
        print("\n".join(md))
    else:
        print("\n".join(md))
        print(json.dumps(s))
        print(f"wrote {a.out / 'family.csv'}, {a.out / 'family.md'}"
              f"{'' if a.no_plot else ', ' + str(a.out / 'family.png')}")
    if a.check_bounds:
        fails = check_bounds(rows, json.loads(a.check_bounds.read_text()))
        for f in fails:
            print("FAIL " + f, file=sys.stderr)
        return 1 if fails else 0
    return 0


if __name__ == "__main__":
    sys.exit(main())
