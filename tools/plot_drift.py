#!/usr/bin/env python3
"""Rotor-resistance tracking under thermal drift, from a
`motor_sim --scenario drift --out DIR` run.

Reads DIR/trace.csv and DIR/report.json, prints the report's drift figures
and draws DIR/drift.png:
  1. true Rr with a +-3 % band, and the drive's tracked Rr (where track_valid)
  2. tracking error (Rr_track - Rr_true) / Rr_true
  3. load torque and electromagnetic torque; speed reference and speed
  4. rotor-flux q/d in the drive's frame, as traced and as a 20 ms mean

Usage: plot_drift.py DIR
"""
import json
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

BAND_PCT = 3.0
NEEDED = ("t_s", "speed_ref_rpm", "speed_rpm", "Te_Nm", "TL_Nm", "psi_rq_over_d",
          "Rr_true_ohm", "Rr_track_ohm", "track_valid")


def load_trace(path):
    """Columns by name (the header of trace.csv)."""
    with path.open() as f:
        names = f.readline().strip().split(",")
    missing = [c for c in NEEDED if c not in names]
    if missing:
        raise SystemExit(f"plot_drift: {path} lacks {', '.join(missing)} (an older motor_sim?)")
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    if data.shape[0] == 0:
        raise SystemExit(f"plot_drift: {path} has no rows")
    return {n: data[:, i] for i, n in enumerate(names)}


def fmt(v, spec, unit=""):
    return "none" if v is None else f"{v:{spec}}{unit}"


def print_figures(r):
    print(f"scenario {r.get('scenario')}, {r.get('duration_s', 0):.1f} s; published "
          f"{r.get('published')}; pass {r.get('pass')}; standstill Rs "
          f"{fmt(r.get('Rs_dc_ohm'), '.4f', ' ohm')}")
    if r.get("drift_t_start_s") is None:
        print("no drift window (the identification never completed, or not a drift run)")
        return
    print(f"drift from {r['drift_t_start_s']:.2f} s: true Rr {r['true']['Rr_ohm']:.4f} -> "
          f"{fmt(r.get('drift_rr_true_end_ohm'), '.4f', ' ohm')}")
    print(f"  tracked samples (100 Hz, valid)   {r.get('track_samples', 0)}")
    print(f"  worst tracking error, lag 0       {fmt(r.get('track_err_lag0_pct'), '.2f', ' %')}")
    print(f"  at the best lag                   {fmt(r.get('track_err_best_lag_pct'), '.2f', ' %')}"
          f" (lag {fmt(r.get('track_best_lag_s'), '.1f', ' s')})")
    print(f"  max |psi_q/psi_d|                 {fmt(r.get('drift_max_q_over_d'), '.4f')}"
          f"  (20 ms mean {fmt(r.get('drift_max_q_over_d_20ms'), '.4f')})")
    print(f"  max |speed ref - speed|           "
          f"{fmt(r.get('drift_speed_ripple_rpm'), '.1f', ' r/min')}")


def running_mean(x, n):
    if n <= 1 or len(x) < n:
        return x
    c = np.cumsum(np.insert(x, 0, 0.0))
    out = np.full(len(x), np.nan)
    out[n - 1:] = (c[n:] - c[:-n]) / n
    return out


def plot(d, r, out):
    t = d["t_s"]
    t0 = r.get("drift_t_start_s")
    valid = d["track_valid"] > 0
    rr, trk = d["Rr_true_ohm"], np.where(valid, d["Rr_track_ohm"], np.nan)
    fig, ax = plt.subplots(4, 1, figsize=(10, 11), sharex=True)

    ax[0].fill_between(t, rr * (1 - BAND_PCT / 100), rr * (1 + BAND_PCT / 100), color="0.85",
                       label=f"true $\\pm${BAND_PCT:g} %")
    ax[0].plot(t, rr, "k", lw=1, label="true $R_r$")
    ax[0].plot(t, trk, "C0", lw=1, label="tracked $R_r$ (track_valid)")
    if not valid.any():
        ax[0].text(0.5, 0.5, "no valid tracked Rr (track_valid never set)",
                   transform=ax[0].transAxes, ha="center", color="C3")
    ax[0].set_ylabel("$R_r$ / $\\Omega$")
    ax[0].legend(loc="upper left")

    ax[1].axhspan(-BAND_PCT, BAND_PCT, color="0.9")
    ax[1].plot(t, 100 * (trk - rr) / rr, "C0", lw=0.8)
    ax[1].set_ylabel("tracking error / %")
    lo = np.nanmin(100 * (trk - rr) / rr) if valid.any() else -BAND_PCT
    hi = np.nanmax(100 * (trk - rr) / rr) if valid.any() else BAND_PCT
    ax[1].set_ylim(min(lo, -2 * BAND_PCT), max(hi, 2 * BAND_PCT))

    ax[2].plot(t, d["TL_Nm"], "C1", label="load $T_L$")
    ax[2].plot(t, d["Te_Nm"], "C2", lw=0.5, alpha=0.6, label="$T_e$")
    ax[2].set_ylabel("torque / N m")
    ax[2].legend(loc="center left")
    sp = ax[2].twinx()
    sp.plot(t, d["speed_ref_rpm"], "k--", lw=0.8, label="reference")
    sp.plot(t, d["speed_rpm"], "C4", lw=0.8, label="speed")
    sp.set_ylabel("speed / (r/min)")
    sp.legend(loc="center right")

    dt = float(np.median(np.diff(t))) if len(t) > 1 else 1e-3
    qd = d["psi_rq_over_d"]
    ax[3].plot(t, 100 * qd, "0.6", lw=0.5, label="traced")
    ax[3].plot(t, 100 * running_mean(qd, int(round(0.020 / dt))), "C3", lw=1,
               label="20 ms mean")
    ax[3].set_ylabel("$\\psi_{rq}/\\psi_{rd}$ / %")
    ax[3].set_ylim(-10, 10)
    ax[3].legend(loc="upper left")
    ax[3].set_xlabel("time / s")
    for a in ax:
        a.grid(alpha=0.3)
        if t0 is not None:
            a.axvline(t0, color="k", ls=":", lw=1)
    lag0 = r.get("track_err_lag0_pct")
    fig.suptitle(f"Rr drift +{100 * (r['drift_rr_true_end_ohm'] / r['true']['Rr_ohm'] - 1):.0f} %"
                 if r.get("drift_rr_true_end_ohm") else "Rr drift", fontsize=11)
    ax[0].set_title("worst tracking error " + (f"{lag0:.2f} % (lag 0), "
                    f"{r['track_err_best_lag_pct']:.2f} % at lag {r['track_best_lag_s']:.1f} s"
                    if lag0 is not None else "none (no valid sample)") +
                    ("; dotted: drift start" if t0 is not None else ""), fontsize=9)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)


def main(argv):
    if len(argv) != 2:
        print(__doc__, file=sys.stderr)
        return 1
    run = Path(argv[1])
    r = json.loads((run / "report.json").read_text())
    print_figures(r)
    plot(load_trace(run / "trace.csv"), r, run / "drift.png")
    print(f"wrote {run / 'drift.png'}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
