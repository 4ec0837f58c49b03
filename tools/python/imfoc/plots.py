"""PNG plots of an identification run (matplotlib's Agg backend: no display needed).

Two kinds of log give the same plots:
  * motor_sim's trace.csv (one row a trace step; the live RLS's estimates, the true speed
    and flux) with its report.json (the verdict, when, the true values);
  * the telemetry log of `imfoc monitor --csv` and `imfoc identify` (one row a frame:
    $T rows the published set, $A rows the tracker, $Q rows the verdict), with identify's
    report.json when there is one.

  run.png         speed, M/T currents, (motor_sim) rotor-flux q/d, the sequence's state
  parameters.png  each parameter against time (true value dashed, where known)
Both mark when the drive gave its verdict: published, or refused with the reason.
"""
import csv
import json
import math
from pathlib import Path

import numpy as np

from .protocol import STATES
from .verdict import SHORT   # Rs_ohm -> Rs: the telemetry's field names

PARAMS = [("Rs_ohm", "$R_s$ / $\\Omega$"), ("Rr_ohm", "$R_r$ / $\\Omega$"),
          ("Lm_H", "$L_m$ / H"), ("Lr_H", "$L_r$ / H"), ("psi_r_Wb", "$\\psi_r$ / Wb"),
          ("Tr_s", "$T_r$ / s")]
# the state axis in the order the sequence passes them (REFINE, 7, sits between SETTLE and
# the next ACCELERATE; the standstill sequence's INJECT, 8, after MAGNETIZE), FAULT apart on top
STATE_AXIS = ("IDLE", "CALIBRATE", "MAGNETIZE", "INJECT", "ACCELERATE", "SETTLE", "REFINE", "RUN",
              "FAULT")


class PlotError(ValueError):
    """A log the plots cannot be made from (said in one line)."""


def _float(x):
    try:
        return float(x)
    except (TypeError, ValueError):
        return math.nan


def _column(rows, *names):
    """The first of `names` the rows have, as floats (NaN where empty); None if none."""
    for n in names:
        if rows and n in rows[0]:
            return np.array([_float(r.get(n)) for r in rows]), n
    return None, None


class Run:
    """One run's series (numpy arrays, None when the log has no such column) and its
    verdict: reason ("published", "low_confidence", ...; None if the log has none), the
    time it was given, the confidences (percent, None where not available), the true
    values (motor_sim only)."""

    def __init__(self, rows, source):
        if not rows:
            raise PlotError(f"{source} has no rows")
        self.source = source
        self.telemetry = "frame" in rows[0]
        self.reason = self.t_verdict = self.confidence = self.truth = None
        self.unit = {}
        if self.telemetry:
            self._from_frames(rows)
        else:
            self._from_trace(rows)
        if self.t is None or self.state is None:
            raise PlotError(f"{source}: no t_s or state column: not a motor_sim trace or an "
                            "imfoc telemetry log")

    def _series(self, rows, key, *names):
        x, n = _column(rows, *names)
        setattr(self, key, x)
        self.unit[key] = "pu" if n is not None and n.endswith("_pu") else "SI"

    def _from_trace(self, rows):
        self.t, _ = _column(rows, "t_s")
        self.state, _ = _column(rows, "state")
        for key, names in (("speed_ref", ("speed_ref_rpm",)), ("speed_true", ("speed_rpm",)),
                           ("speed_meas", ("speed_meas_rpm",)), ("i_m", ("i_m_A",)),
                           ("i_t", ("i_t_A",)), ("flux_q", ("psi_rq_over_d",))):
            self._series(rows, key, *names)
        valid, _ = _column(rows, "est_valid")
        self.params_label = "identified (RLS)"
        self.params = {k: self._masked(rows, valid, k) for k, _ in PARAMS}
        self.t_params = self.t
        self._tracker(rows, self.t)

    def _from_frames(self, rows):
        t_rows = [r for r in rows if r.get("frame") == "T"]
        a_rows = [r for r in rows if r.get("frame") == "A"]
        q_rows = [r for r in rows if r.get("frame") == "Q"]
        if not t_rows:
            raise PlotError(f"{self.source}: no $T frame")
        self.t, _ = _column(t_rows, "t_s")
        self.state, _ = _column(t_rows, "state")
        self.speed_true = self.flux_q = None
        for key, names in (("speed_ref", ("speed_ref_rpm", "speed_ref_pu")),
                           ("speed_meas", ("speed_rpm", "speed_pu")),
                           ("i_m", ("i_m_A", "i_m_pu")), ("i_t", ("i_t_A", "i_t_pu"))):
            self._series(t_rows, key, *names)
        valid, _ = _column(t_rows, "valid")
        self.params_label = "published"
        self.params = {k: self._masked(t_rows, valid, k, SHORT[k] + "_pu") for k, _ in PARAMS}
        self.t_params = self.t
        t_a, _ = _column(a_rows, "t_s")
        self._tracker(a_rows, t_a)
        self._verdict_from_frames(q_rows)

    def _masked(self, rows, valid, *names):
        x, _ = _column(rows, *names)
        if x is None:
            return None
        return x if valid is None else np.where(valid > 0, x, np.nan)

    def _tracker(self, rows, t):
        """The adaptive sequence: the tracked Rr, Tr and the standstill Rs, where valid."""
        self.t_track = t
        tv, _ = _column(rows, "track_valid")
        self.track = {}
        for key, col in (("Rr_ohm", "Rr_track_ohm"), ("Tr_s", "Tr_track_s")):
            x, _ = _column(rows, col)
            if x is not None and tv is not None and np.any(tv > 0):
                self.track[key] = np.where(tv > 0, x, np.nan)
        rs_dc, _ = _column(rows, "Rs_dc_ohm")
        self.rs_dc = (np.where(rs_dc > 0, rs_dc, np.nan)
                      if rs_dc is not None and np.any(rs_dc > 0) else None)

    def _verdict_from_frames(self, q_rows):
        """The last verdict after a pending one: the run's (an earlier run's verdict is
        on the link until the start is taken)."""
        pending = False
        for r in q_rows:
            name = r.get("reason_name")
            if name == "pending":
                pending, self.reason = True, None
            elif pending and self.reason is None and name:
                self.reason, self.t_verdict = name, _float(r.get("t_s"))
                conf = {k: _float(r.get(f"conf_{SHORT[k]}_pct")) for k, _ in PARAMS}
                self.confidence = {k: (None if math.isnan(v) else v) for k, v in conf.items()}

    def add_report(self, rep):
        """A report.json (motor_sim's or imfoc identify's): its verdict and true values."""
        reason = rep.get("publish_reason")
        if reason and reason != "pending":
            self.reason = reason
            t = rep.get("t_decided_s", rep.get("t_published_s"))
            # imfoc identify's times count from its $C,S, its trace from the first frame
            t0 = rep.get("trace_t_start_s") or 0.0
            self.t_verdict = self.t_verdict if t is None else float(t) + t0
            self.confidence = rep.get("confidence_pct") or self.confidence
        self.truth = rep.get("true")


def load_run(path):
    """A Run from a CSV log (trace.csv or a telemetry log) or a folder holding trace.csv
    and, if there, report.json.  PlotError if it cannot be read."""
    path = Path(path)
    csv_path = path / "trace.csv" if path.is_dir() else path
    try:
        with open(csv_path, newline="") as f:
            rows = list(csv.DictReader(f))
    except (OSError, UnicodeDecodeError, csv.Error) as e:
        raise PlotError(f"cannot read {csv_path}: {e}") from None
    run = Run(rows, str(csv_path))
    rep = csv_path.parent / "report.json"
    if rep.is_file():
        try:
            run.add_report(json.loads(rep.read_text()))
        except (OSError, ValueError, AttributeError) as e:
            raise PlotError(f"cannot read {rep}: {e}") from None
    return run


def _pyplot():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def _verdict_text(run):
    if run.reason is None:
        return None
    return "published" if run.reason == "published" else f"refused ({run.reason})"


def _mark_verdict(ax, run, label=True):
    """A vertical line where the drive gave its verdict: green published, red refused."""
    if run.reason is None or run.t_verdict is None or math.isnan(run.t_verdict):
        return
    ok = run.reason == "published"
    ax.axvline(run.t_verdict, color="tab:green" if ok else "tab:red", ls=":", lw=1.5,
               label=_verdict_text(run) if label else None)


def _legend(ax):
    """Outside the axes, on the right: it never covers a trace."""
    if ax.get_legend_handles_labels()[0]:
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, borderaxespad=0)


def plot_run(run, out):
    plt = _pyplot()
    panels = 4 if run.flux_q is not None else 3
    fig, ax = plt.subplots(panels, 1, figsize=(10, 2.5 * panels + 0.5), sharex=True)
    u = "r/min" if run.unit.get("speed_meas") == "SI" else "pu"
    for key, label, lw in (("speed_ref", "reference", 1.5), ("speed_true", "true", 1.5),
                           ("speed_meas", "measured (QEP)", 0.8)):
        if getattr(run, key) is not None:
            ax[0].plot(run.t, getattr(run, key), label=label, lw=lw)
    ax[0].set_ylabel(f"speed / ({u})")
    ax[1].plot(run.t, run.i_m, label="$i_M$")
    ax[1].plot(run.t, run.i_t, label="$i_T$")
    ax[1].set_ylabel("current / " + ("A" if run.unit.get("i_m") == "SI" else "pu"))
    if run.flux_q is not None:
        ax[2].plot(run.t, 100 * run.flux_q)
        ax[2].set_ylabel("$\\psi_{rq}/\\psi_{rd}$ / %")
        ax[2].set_ylim(-5, 5)
    level = {STATES.index(s): i for i, s in enumerate(STATE_AXIS)}
    y = np.array([level.get(int(s), np.nan) if not math.isnan(s) else np.nan
                  for s in run.state])
    ax[-1].plot(run.t, y, drawstyle="steps-post")
    fault = np.where(y == STATE_AXIS.index("FAULT"), y, np.nan)
    if np.any(~np.isnan(fault)):
        ax[-1].plot(run.t, fault, drawstyle="steps-post", color="tab:red", lw=3, label="fault")
    ax[-1].set_yticks(range(len(STATE_AXIS)))
    ax[-1].set_yticklabels([s.lower() for s in STATE_AXIS])
    ax[-1].set_ylim(-0.5, len(STATE_AXIS) - 0.5)
    ax[-1].set_xlabel("time / s")
    for i, a in enumerate(ax):
        _mark_verdict(a, run, label=(i == 0))
        a.grid(alpha=0.3)
        _legend(a)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)


def plot_parameters(run, out):
    plt = _pyplot()
    fig, axes = plt.subplots(3, 2, figsize=(11, 9), sharex=True)
    for ax, (key, label) in zip(axes.flat, PARAMS):
        y = run.params.get(key)
        if y is not None:
            ax.plot(run.t_params, y, label=run.params_label)
        if key in run.track:
            ax.plot(run.t_track, run.track[key], label="tracked")
        if key == "Rs_ohm" and run.rs_dc is not None:
            ax.plot(run.t_track, run.rs_dc, label="standstill")
        if run.truth and key in run.truth:
            tv = run.truth[key]
            ax.axhline(tv, color="k", ls="--", lw=1, label="true")
            ax.set_ylim(min(0.8 * tv, 1.2 * tv), max(0.8 * tv, 1.2 * tv))
        _mark_verdict(ax, run)
        conf = (run.confidence or {}).get(key)
        if run.reason is not None:
            ax.set_title(f"{_verdict_text(run)}" +
                         (f", confidence {conf:.2f} %" if conf is not None else ""), fontsize=9,
                         color="k" if run.reason == "published" else "tab:red")
        ax.set_ylabel(label if run.unit.get("i_m") != "pu" else label.split(" /")[0] + " / pu")
        ax.grid(alpha=0.3)
    for ax in axes[-1]:
        ax.set_xlabel("time / s")
    _legend(axes[0, 1])
    if run.reason is None:
        head = "no verdict in this log"
    elif run.reason == "published":
        head = f"published at {run.t_verdict:.2f} s"
    else:
        head = (f"REFUSED ({run.reason}) at {run.t_verdict:.2f} s: the drive did not publish "
                "this set")
    what = "the RLS's live estimates" if not run.telemetry else "the published set"
    fig.suptitle(f"Identification: {head}\n({what}" +
                 ("; true value dashed, y-range +-20 %)" if run.truth else ")"),
                 color="k" if run.reason in (None, "published") else "tab:red")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)


def plot_dir(path, out_dir=None):
    """run.png and parameters.png of the log at `path` (a folder with trace.csv, or a CSV
    file) into `out_dir` (default: the log's folder); returns their paths."""
    run = load_run(path)
    path = Path(path)
    out_dir = Path(out_dir) if out_dir else (path if path.is_dir() else path.parent)
    outs = (out_dir / "run.png", out_dir / "parameters.png")
    try:
        out_dir.mkdir(parents=True, exist_ok=True)
        plot_run(run, outs[0])
        plot_parameters(run, outs[1])
    except OSError as e:
        raise PlotError(f"cannot write the plots into {out_dir}: {e}") from None
    return outs
