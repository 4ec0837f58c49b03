#!/usr/bin/env python3
"""Identification from a wrong nameplate: every combination of believed errors
in Tr, Lm and Rs (identification from wrong starting values).

For each (tr, lm, rs) of the grid (default -30, 0, +30 %: 27 runs) motor_sim
runs the start scenario on the base config with a wrong nameplate: [plant]
holds the true motor (the base file's [plant], each parameter its
[nameplate]'s unless given) and [nameplate] what the drive believes,

    Rs (1 + rs), Lm (1 + lm), Rr (1 + rr), the leakages as the true ones,

where rr gives the wanted Tr error.  The drive's Lr is Lm(1 + lm) + Llr and
its Tr = Lr_believed / Rr_believed; for a believed Tr = Tr (1 + tr):

    rr = (Lm (1 + lm) + Llr) / (Lr (1 + tr)) - 1       (Lm_H, Llr_H of [plant])

(rs and lm are written %g and rr %.6f as percentages, and each believed
value exactly, so that a case gives the numbers the former
[controller] *_error_pct keys gave.)

Prints a table (published?, worst |error| and which parameter, each error,
max |psi_q/psi_d|, faults) and a summary (how many within 3 %, the worst
case); writes OUT/sweep.csv and OUT/sweep.png (one panel per Rs error, the
Tr x Lm grid coloured by the worst parameter error, 3 % at the middle of the
colour scale, runs that published nothing in grey).

The INI of each run is the base file with the sweep's keys and the --set
options merged in: a key the base file already has is replaced on its own
line (the simulator refuses a key given twice), the others are appended in a
repeated [section] at the end (the simulator reads a repeated section as a
continuation of the first).

Usage: sweep_start_errors.py [--exe MOTOR_SIM] [--config INI] [--grid=-30,0,30]
                             [--adaptive] [--compare] [--duration S]
                             [--set SECTION.KEY=VALUE]... [--jobs N] [--out DIR]
e.g.   .venv/bin/python tools/sweep_start_errors.py --adaptive --compare
       (the adaptive sequence and, on the same cases, the paper's; one table
       and one row of panels each)

Exit status 0 when the sweep ran (whatever the runs found: this is a study,
not a test), 1 for bad options or a missing simulator or config.
"""
import argparse
import concurrent.futures
import csv
import json
import re
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PARAMS = ("Rs_ohm", "Rr_ohm", "Lm_H", "Lr_H", "psi_r_Wb", "Tr_s")
SHORT = {"Rs_ohm": "Rs", "Rr_ohm": "Rr", "Lm_H": "Lm", "Lr_H": "Lr", "psi_r_Wb": "psi_r",
         "Tr_s": "Tr"}
MOTOR = ("Rs_ohm", "Rr_ohm", "Lm_H", "Lls_H", "Llr_H")   # [plant] and [nameplate], set by the sweep
BOUND_PCT = 3.0
# the adaptive sequence (README): observer, standstill Rs and sigma Ls, two
# passes, Rr/Tr tracking with the fused published set
ADAPTIVE = {("controller", "orientation"): "1", ("ident", "standstill"): "1",
            ("ident", "passes"): "2", ("ident", "track_rr"): "1"}
# the paper's sequence: indirect orientation on the nameplate, one pass
PAPER = {("controller", "orientation"): "0", ("ident", "standstill"): "0",
         ("ident", "passes"): "1", ("ident", "track_rr"): "0"}

SECTION_RE = re.compile(r"^\s*\[([^\]]*)\]")
KEY_RE = re.compile(r"^([^\s=;#][^=]*?)\s*[=:]\s*(.*)$")


# ---------------------------------------------------------------- INI merge
def ini_entries(lines):
    """(line index, section, key, value) of every key line, as inih reads
    them: comments start a line with ; or #, an inline comment is ; after
    whitespace."""
    out, section = [], ""
    for i, line in enumerate(lines):
        m = SECTION_RE.match(line)
        if m:
            section = m.group(1).strip()
            continue
        m = KEY_RE.match(line)
        if m:
            value = re.split(r"\s;", m.group(2), maxsplit=1)[0].strip()
            out.append((i, section, m.group(1).strip(), value))
    return out


def ini_merge(text, overrides):
    """The base text with overrides {(section, key): value} merged: replaced
    in place where the key exists, appended in repeated sections otherwise."""
    lines = text.splitlines()
    pending = dict(overrides)
    for i, sec, key, old in ini_entries(lines):
        if (sec, key) in pending:
            lines[i] = f"{key} = {pending.pop((sec, key))}    ; set by the sweep (was {old})"
    by_section = {}
    for (sec, key), value in pending.items():
        by_section.setdefault(sec, []).append((key, value))
    if by_section:
        lines += ["", "; appended by tools/sweep_start_errors.py"]
    for sec, kv in by_section.items():
        lines.append(f"[{sec}]")
        lines += [f"{key} = {value}" for key, value in kv]
    return "\n".join(lines) + "\n"


def ini_value(text, section, key):
    """The last value of section.key in text (None if absent)."""
    vals = [v for _, s, k, v in ini_entries(text.splitlines()) if s == section and k == key]
    return vals[-1] if vals else None


# ---------------------------------------------------------------- the sweep
def rr_error_pct(tr_pct, lm_pct, lm_h, llr_h):
    """Believed Rr error that, with the believed Lm, gives the wanted Tr error."""
    lr = lm_h + llr_h
    return 100.0 * ((lm_h * (1.0 + lm_pct / 100.0) + llr_h) / (lr * (1.0 + tr_pct / 100.0)) - 1.0)


def adaptive_duration_s(cfg):
    """Simulated time of an adaptive run: two passes (motor_sim's own
    default per pass: calibration, magnetisation, ramp, 3.2 s) and 6 s of
    tracking for the fused set to be published (the tracker is valid 3 Tr +
    2 memories into RUN, tr_track_settle_s: 2.1-2.8 s on the three motors,
    and starts from the RLS's Tr)."""
    text = cfg.read_text()
    mag = float(ini_value(text, "ident", "magnetize_s") or 0.3)
    rated = float(ini_value(text, "nameplate", "rated_speed_rpm"))
    target = float(ini_value(text, "ident", "target_speed_rpm") or rated)
    ramp = float(ini_value(text, "controller", "speed_ramp_rpm_s"))
    return 2.0 * (0.1 + mag + target / ramp + 3.2) + 6.0


def wrong_nameplate(truth, rs, lm, rr):
    """[plant] = the truth, [nameplate] = the believed motor; each percentage
    as the sweep prints it (%g, %g, %.6f), the products in double as the
    simulator computed them from the former *_error_pct keys."""
    pct = lambda text: 1.0 + float(text) / 100.0
    over = {("plant", k): repr(v) for k, v in truth.items()}
    over[("nameplate", "Rs_ohm")] = repr(truth["Rs_ohm"] * pct(f"{rs:g}"))
    over[("nameplate", "Lm_H")] = repr(truth["Lm_H"] * pct(f"{lm:g}"))
    over[("nameplate", "Rr_ohm")] = repr(truth["Rr_ohm"] * pct(f"{rr:.6f}"))
    over[("nameplate", "Lls_H")] = repr(truth["Lls_H"])
    over[("nameplate", "Llr_H")] = repr(truth["Llr_H"])
    return over


def run_case(exe, base_text, extra, case, truth, tmp, duration_s=0.0):
    """One motor_sim run; returns a row dict."""
    tr, lm, rs = case
    rr = rr_error_pct(tr, lm, truth["Lm_H"], truth["Llr_H"])
    over = dict(extra)
    over.update(wrong_nameplate(truth, rs, lm, rr))
    d = Path(tmp) / f"tr{tr:+g}_lm{lm:+g}_rs{rs:+g}"
    d.mkdir(parents=True)
    ini = d / "config.ini"
    ini.write_text(ini_merge(base_text, over))
    row = {"tr_err_pct": tr, "lm_err_pct": lm, "rs_err_pct": rs, "rr_err_pct": round(rr, 4),
           "status": "", "published": False, "worst_param": "", "worst_abs_pct": float("nan"),
           "max_flux_q_over_d": float("nan"), "converge_s": float("nan"), "faults": "",
           "message": ""}
    for k in PARAMS:
        row["err_" + k] = float("nan")
    cmd = [str(exe), "--config", str(ini), "--quiet", "--out", str(d)]
    if duration_s > 0:
        cmd += ["--duration", f"{duration_s:g}"]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode not in (0, 3):   # 3: the run completed and published nothing
        row["status"] = "config_error" if p.returncode == 1 else f"failed rc={p.returncode}"
        msg = p.stderr.strip().splitlines()[-1] if p.stderr.strip() else ""
        # the temporary file's name says nothing: keep the reason
        row["message"] = re.sub(r"^motor_sim: .*?config\.ini(:\d+)?: ", "", msg)
        return row
    rep = json.loads((d / "report.json").read_text())
    (d / "trace.csv").unlink(missing_ok=True)   # 1.5 MB a run, not needed
    row["max_flux_q_over_d"] = rep["max_flux_q_over_d"]
    row["faults"] = " ".join(f["name"] for f in rep["faults"])
    row["published"] = bool(rep["published"])
    if not row["published"]:
        row["status"] = "not_published"
        row["message"] = rep.get("publish_reason", "")   # the drive's reason
        return row
    # what the drive publishes at the end of the run: the RLS set, or with
    # [ident] track_rr = 1 the standstill Rs and the tracked Rr, Tr
    e = rep.get("published_end_error_pct") or rep["error_pct"]
    row["tracked"] = bool(rep.get("params_tracked"))
    for k in PARAMS:
        row["err_" + k] = e[k]
    worst = max(PARAMS, key=lambda k: abs(e[k]))
    row["worst_param"] = SHORT[worst]
    row["worst_abs_pct"] = abs(e[worst])
    row["converge_s"] = rep["converge_s"]
    row["status"] = "ok" if row["worst_abs_pct"] <= BOUND_PCT else "above_bound"
    return row


def print_table(rows):
    print("believed errors / % (Rr: as set, for the Tr error) -> identified errors")
    print(f"{'Tr':>5} {'Lm':>5} {'Rs':>5} {'Rr':>7} | {'pub':>3} {'worst':>12} | " +
          " ".join(f"{SHORT[k]:>7}" for k in PARAMS) + f" | {'q/d':>8} | faults")
    for r in rows:
        head = (f"{r['tr_err_pct']:>+5g} {r['lm_err_pct']:>+5g} {r['rs_err_pct']:>+5g} "
                f"{r['rr_err_pct']:>+7.1f} | ")
        if r["status"] in ("config_error",) or r["status"].startswith("failed"):
            print(head + f"{r['status']}: {r['message']}")
            continue
        if r["published"]:
            worst = f"{r['worst_abs_pct']:>6.2f}% {r['worst_param']:<5}"
            errs = " ".join(f"{r['err_' + k]:>+6.2f}%" for k in PARAMS)
        else:
            worst = f"{'-':>12}"
            errs = " ".join(f"{'-':>7}" for _ in PARAMS)
        flag = " <" if r["status"] == "above_bound" else ""
        print(head + f"{'yes' if r['published'] else 'no':>3} {worst} | {errs} | "
              f"{r['max_flux_q_over_d']:>8.3g} | {r['faults'] or '-'}{flag}")


def print_summary(rows):
    n = len(rows)
    ok = [r for r in rows if r["status"] == "ok"]
    pub = [r for r in rows if r["published"]]
    none = [r for r in rows if not r["published"]]
    print(f"\n{len(ok)} of {n} runs converged within {BOUND_PCT:g} % (all six parameters); "
          f"{len(pub)} published, {len(none)} published nothing"
          f"{' (marked grey in the plot)' if none else ''}.")
    if pub:
        w = max(pub, key=lambda r: r["worst_abs_pct"])
        print(f"worst published: believed Tr {w['tr_err_pct']:+g} %, Lm {w['lm_err_pct']:+g} %, "
              f"Rs {w['rs_err_pct']:+g} %: {w['worst_param']} off by {w['worst_abs_pct']:.2f} %")
    if none:
        why = {}
        for r in none:
            k = r["faults"] or r["message"] or r["status"]
            why[k] = why.get(k, 0) + 1
        print("nothing published (the drive's own reason: fault, or the config refused): " +
              ", ".join(f"{n} x {k}" for k, n in sorted(why.items(), key=lambda x: -x[1])))


def write_csv(rows, path):
    cols = ["sequence", "tr_err_pct", "lm_err_pct", "rs_err_pct", "rr_err_pct", "status", "published",
            "worst_param", "worst_abs_pct"] + ["err_" + k for k in PARAMS] + \
           ["max_flux_q_over_d", "converge_s", "faults", "message"]
    with path.open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=cols)
        w.writeheader()
        for r in rows:
            w.writerow({c: r[c] for c in cols})


def plot(rowsets, grid, title, path):
    """rowsets: [(label, rows)], one row of panels each (one panel per Rs
    error)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    from matplotlib.colors import TwoSlopeNorm

    pub = [r["worst_abs_pct"] for _, rows in rowsets for r in rows if r["published"]]
    vmax = min(max([2.0 * BOUND_PCT] + pub), 10.0 * BOUND_PCT)
    norm = TwoSlopeNorm(vmin=0.0, vcenter=BOUND_PCT, vmax=vmax)
    cmap = plt.get_cmap("RdYlGn_r").copy()
    cmap.set_bad("0.8")
    n = len(grid)
    fig, axes = plt.subplots(len(rowsets), n, figsize=(3.6 * n + 1.2, 4.2 * len(rowsets)),
                             squeeze=False)
    fig.subplots_adjust(hspace=0.45)
    im = None
    for row_axes, (label, rows) in zip(axes, rowsets):
        im = plot_row(row_axes, label, rows, grid, cmap, norm, plt, np) or im
    cb = fig.colorbar(im, ax=axes.ravel().tolist(),
                      extend="max" if max(pub, default=0) > vmax else "neither")
    cb.set_label("worst parameter error / %  (number: worst %, parameter)")
    cb.ax.axhline(BOUND_PCT, color="k", lw=2)
    # the norm gives 0..3 % half the bar: ticks by the percent below, by a
    # round step above
    step = max(1.0, float(np.ceil((vmax - BOUND_PCT) / 4.0)))
    ticks = [0.0, 1.0, 2.0, BOUND_PCT] + list(np.arange(BOUND_PCT + step, vmax + 1e-9, step))
    cb.set_ticks(ticks, labels=[f"{BOUND_PCT:g} % bound" if t == BOUND_PCT else f"{t:g}"
                                for t in ticks])
    fig.suptitle(title, fontsize=10)
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)


def plot_row(row_axes, label, rows, grid, cmap, norm, plt, np):
    """One row of panels (one per Rs error); returns the last image."""
    by = {(r["tr_err_pct"], r["lm_err_pct"], r["rs_err_pct"]): r for r in rows}
    n = len(grid)
    im = None
    for ax, rs in zip(row_axes, grid):
        z = np.full((n, n), np.nan)
        for i, lm in enumerate(grid):
            for j, tr in enumerate(grid):
                r = by[(tr, lm, rs)]
                if r["published"]:
                    z[i, j] = r["worst_abs_pct"]
        im = ax.imshow(np.ma.masked_invalid(z), origin="lower", cmap=cmap, norm=norm,
                       aspect="auto")
        for i, lm in enumerate(grid):
            for j, tr in enumerate(grid):
                r = by[(tr, lm, rs)]
                if r["published"]:
                    txt = f"{r['worst_abs_pct']:.1f}\n{r['worst_param']}"
                    bold = "bold" if r["worst_abs_pct"] > BOUND_PCT else "normal"
                else:
                    why = (r["faults"] or r["status"]).split()[0]
                    txt, bold = "X\n" + why.replace("_", "\n"), "bold"
                ax.text(j, i, txt, ha="center", va="center", fontsize=8, weight=bold)
        ax.set_xticks(range(n), [f"{g:+g}" for g in grid])
        ax.set_yticks(range(n), [f"{g:+g}" for g in grid])
        ax.set_xlabel("believed Tr error / %")
        ax.set_title(f"{label}\nbelieved Rs error {rs:+g} %", fontsize=9)
    row_axes[0].set_ylabel("believed Lm error / %")
    return im


# ---------------------------------------------------------------- main
def parse_args(argv):
    # "--grid -30,0,30" would be taken for an option: join it to "--grid=..."
    fixed, i = [], 0
    while i < len(argv):
        if argv[i] == "--grid" and i + 1 < len(argv):
            fixed.append("--grid=" + argv[i + 1])
            i += 2
        else:
            fixed.append(argv[i])
            i += 1
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--exe", default=str(ROOT / "build" / "host-iq" / "host_sim" / "sim" /
                                         "motor_sim"), help="motor_sim to run")
    ap.add_argument("--config", default=str(ROOT / "host_sim" / "config" / "paper_motor.ini"))
    ap.add_argument("--grid", default="-30,0,30", help="errors in %%, for Tr, Lm and Rs alike")
    ap.add_argument("--set", action="append", default=[], metavar="SECTION.KEY=VALUE",
                    help="extra key for every run (repeatable)")
    ap.add_argument("--adaptive", action="store_true",
                    help="the adaptive sequence: " + ", ".join(f"{k[0]}.{k[1]}={v}"
                                                              for k, v in ADAPTIVE.items()))
    ap.add_argument("--compare", action="store_true",
                    help="also run the paper's sequence on every case (its keys unchanged): "
                         "a second table and a second row of panels")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--duration", type=float, default=0.0,
                    help="simulated seconds per run (default: motor_sim's; with tracking "
                         "give the tracker time to converge after the last pass)")
    ap.add_argument("--out", default=str(ROOT / "out" / "sweep"))
    return ap.parse_args(fixed)


def parse_sets(sets):
    over = {}
    for s in sets:
        m = re.fullmatch(r"\s*([^.=\s]+)\.([^=\s]+)\s*=\s*(\S.*?)\s*", s)
        if not m:
            raise SystemExit(f"sweep: --set '{s}' is not SECTION.KEY=VALUE")
        if m.group(1) in ("plant", "nameplate") and m.group(2) in MOTOR:
            raise SystemExit(f"sweep: --set {m.group(1)}.{m.group(2)}: the sweep sets that key")
        over[(m.group(1), m.group(2))] = m.group(3)
    return over


def main(argv):
    a = parse_args(argv)
    try:
        grid = sorted({float(x) for x in a.grid.split(",") if x.strip()})
    except ValueError:
        raise SystemExit(f"sweep: --grid '{a.grid}' is not a comma-separated list of numbers")
    if not grid or a.jobs < 1:
        raise SystemExit("sweep: an empty --grid or --jobs < 1")
    exe, cfg = Path(a.exe), Path(a.config)
    if not exe.is_file():
        raise SystemExit(f"sweep: no simulator at {exe} (build it, or give --exe)")
    if not cfg.is_file():
        raise SystemExit(f"sweep: no config {cfg}")
    extra = dict(ADAPTIVE) if a.adaptive else {}
    extra.update(parse_sets(a.set))
    if a.adaptive and a.duration <= 0:
        a.duration = adaptive_duration_s(cfg)
    base = cfg.read_text()
    merged = ini_merge(base, extra)
    try:
        # the true motor: [plant], each parameter the [nameplate]'s unless given
        truth = {k: float(ini_value(merged, "plant", k) or ini_value(merged, "nameplate", k))
                 for k in MOTOR}
    except (TypeError, ValueError):
        raise SystemExit(f"sweep: {cfg} has no numeric [nameplate] {', '.join(MOTOR)}")
    orient = ini_value(merged, "controller", "orientation") or "0"
    cases = [(tr, lm, rs) for rs in grid for lm in grid for tr in grid]
    label = ("adaptive sequence" if a.adaptive else f"orientation {orient}") + \
        (" (" + ", ".join(a.set) + ")" if a.set else "")
    runs = [(label, extra)]
    if a.compare:
        paper = dict(extra)
        paper.update(PAPER)
        runs.append(("paper's sequence", paper))
    rowsets = []
    for name, over in runs:
        print(f"sweep: {len(cases)} runs of {exe} on {cfg}, {name}, {a.jobs} at a time")
        with tempfile.TemporaryDirectory(prefix="sweep_") as tmp:
            with concurrent.futures.ThreadPoolExecutor(max_workers=a.jobs) as pool:
                rows = list(pool.map(lambda c, o=over: run_case(exe, base, o, c, truth,
                                                                tmp, a.duration), cases))
        for r in rows:
            r["sequence"] = name
        print_table(rows)
        print_summary(rows)
        rowsets.append((name, rows))
    rows = [r for _, rs in rowsets for r in rs]
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    write_csv(rows, out / "sweep.csv")
    title = f"{cfg.name}: " + ";  ".join(
        f"{name}: {sum(r['status'] == 'ok' for r in rs)} of {len(rs)} within {BOUND_PCT:g} %"
        for name, rs in rowsets) + "  (grey X: nothing published)"
    plot(rowsets, grid, title, out / "sweep.png")
    print(f"wrote {out / 'sweep.csv'} and {out / 'sweep.png'}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
