#!/usr/bin/env python3
"""PNG plots of a motor_sim run, from DIR/trace.csv (and DIR/report.json).

  run.png         speed reference and speed, M/T currents, rotor-flux q/d
                  (field orientation), identification state
  parameters.png  each identified parameter against time with its true value
                  as a line, like the paper's figures 2-6

Usage: plot_run.py DIR
"""
import json
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

PARAMS = [
    ("Rs_ohm", "$R_s$ / $\\Omega$"),
    ("Rr_ohm", "$R_r$ / $\\Omega$"),
    ("Lm_H", "$L_m$ / H"),
    ("Lr_H", "$L_r$ / H"),
    ("psi_r_Wb", "$\\psi_r$ / Wb"),
    ("Tr_s", "$T_r$ / s"),
]


def load_trace(path):
    data = np.genfromtxt(path, delimiter=",", names=True)
    if data.size == 0:
        raise SystemExit(f"plot_run: {path} has no rows")
    return data


def plot_run(d, out):
    t = d["t_s"]
    fig, ax = plt.subplots(4, 1, figsize=(9, 10), sharex=True)
    ax[0].plot(t, d["speed_ref_rpm"], label="reference")
    ax[0].plot(t, d["speed_rpm"], label="true")
    ax[0].plot(t, d["speed_meas_rpm"], label="measured (QEP)", lw=0.8)
    ax[0].set_ylabel("speed / (r/min)")
    ax[0].legend(loc="lower right")
    ax[1].plot(t, d["i_m_A"], label="$i_M$")
    ax[1].plot(t, d["i_t_A"], label="$i_T$")
    ax[1].set_ylabel("current / A")
    ax[1].legend(loc="upper right")
    ax[2].plot(t, 100 * d["psi_rq_over_d"])
    ax[2].set_ylabel("$\\psi_{rq}/\\psi_{rd}$ / %")
    ax[2].set_ylim(-5, 5)
    ax[3].plot(t, d["state"], drawstyle="steps-post")
    ax[3].set_yticks(range(8))
    ax[3].set_yticklabels(["idle", "calibrate", "magnetize", "accelerate", "settle", "run", "fault",
                           "refine"])
    ax[3].set_xlabel("time / s")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)


def plot_parameters(d, truth, out):
    t = d["t_s"]
    valid = d["est_valid"] > 0
    fig, axes = plt.subplots(3, 2, figsize=(10, 9), sharex=True)
    for ax, (key, label) in zip(axes.flat, PARAMS):
        y = np.where(valid, d[key], np.nan)
        ax.plot(t, y, label="identified (RLS)")
        # the adaptive sequence: the tracked Rr, Tr and the standstill Rs, where the run has them
        names = d.dtype.names
        if key in ("Rr_ohm", "Tr_s") and "track_valid" in names and np.any(d["track_valid"] > 0):
            col = "Rr_track_ohm" if key == "Rr_ohm" else "Tr_track_s"
            if col in names:
                ax.plot(t, np.where(d["track_valid"] > 0, d[col], np.nan), label="tracked")
        if key == "Rs_ohm" and "Rs_dc_ohm" in names and np.any(d["Rs_dc_ohm"] > 0):
            ax.plot(t, np.where(d["Rs_dc_ohm"] > 0, d["Rs_dc_ohm"], np.nan), label="standstill")
        if truth and key in truth:
            ax.axhline(truth[key], color="k", ls="--", lw=1, label="true")
            lo, hi = 0.8 * truth[key], 1.2 * truth[key]
            ax.set_ylim(min(lo, hi), max(lo, hi))
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    for ax in axes.flat:
        if len(ax.get_lines()) > 2:
            ax.legend(loc="lower right", fontsize=8)
    axes[0, 0].legend(loc="upper right", fontsize=8)
    for ax in axes[-1]:
        ax.set_xlabel("time / s")
    fig.suptitle("Online RLS identification (true value dashed, y-range +-20 %)")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)


def main(argv):
    if len(argv) != 2:
        print(__doc__, file=sys.stderr)
        return 1
    run_dir = Path(argv[1])
    d = load_trace(run_dir / "trace.csv")
    truth = None
    rep = run_dir / "report.json"
    if rep.exists():
        truth = json.loads(rep.read_text())["true"]
    plot_run(d, run_dir / "run.png")
    plot_parameters(d, truth, run_dir / "parameters.png")
    print(f"wrote {run_dir / 'run.png'} and {run_dir / 'parameters.png'}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
