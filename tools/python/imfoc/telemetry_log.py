"""Decoded frames as named values, and the CSV log of them (imfoc monitor --csv, imfoc
identify's trace.csv: the same columns, which tools/plot_run.py and imfoc.plots read)."""
import csv
from pathlib import Path

from .bases import PARAM_FIELDS, SI_FIELDS
from .link import EXIT_USAGE, Failure, reason_text
from .protocol import CONF_FIELDS, LAYOUT, LOAD_PERIOD_TICKS, fault_name, reason_name, state_name

BG_TLM_PERIOD_TICKS = 750   # firmware/bg_loop.h: one burst of four frames every 750 ISRs
FRAMES_PER_BURST = 4        # $T, $A, $S, $Q (firmware/bg_loop.c)


def frame_values(frame, bases):
    """The fields of a frame as named values: SI (or *_pu without bases), names and flags."""
    r = frame.raw
    v = {"frame": frame.type, "seq": r["seq"]}
    if frame.type == "T":
        v.update(state=r["state"], state_name=state_name(r["state"]), fault=r["fault"],
                 fault_name=fault_name(r["fault"]), pwm_on=r["pwm_on"], valid=r["valid"],
                 load_pct=100.0 * r["load"] / LOAD_PERIOD_TICKS)
    elif frame.type == "S":
        v.update(isr_overruns=r["isr_overruns"], load_pct=100.0 * r["load"] / LOAD_PERIOD_TICKS,
                 tx_dropped=r["tx_dropped"], rx_errors=r["rx_errors"])
    elif frame.type == "Q":
        # the publication: not per-unit values but fractions (percent here)
        v.update(reason=r["reason"], reason_name=reason_name(r["reason"]))
        for n in CONF_FIELDS:
            x = frame.pu[n]
            v[n + "_pct"] = None if x < 0 else 100.0 * x
        v.update(residual_rel=frame.pu["residual"], amplification=frame.pu["amplification"])
        return v
    else:
        v.update({"pass": r["pass"], "track_valid": r["track_valid"], "tracked": r["tracked"]})
    for name, pu in frame.pu.items():
        if bases is None:
            v[name + "_pu"] = pu
        else:
            col, x = bases.si(name, pu)
            v[col] = x
    return v


def csv_columns(bases):
    cols = ["t_s", "frame", "seq", "state", "state_name", "fault", "fault_name", "pwm_on",
            "valid", "load_pct"]
    name = (lambda n: n + "_pu") if bases is None else (lambda n: SI_FIELDS[n][0])
    cols_a = ["pass", "track_valid", "tracked"]
    cols_s = ["isr_overruns", "tx_dropped", "rx_errors"]
    cols_q = (["reason", "reason_name"] + [n + "_pct" for n in CONF_FIELDS] +
              ["residual_rel", "amplification"])
    return (cols + [name(n) for n in LAYOUT["T"][1]] + cols_a +
            [name(n) for n in LAYOUT["A"][1]] + cols_s + cols_q)


def params_si(frame, bases):
    return {SI_FIELDS[n][0]: bases.si(n, frame.pu[n])[1] for n in PARAM_FIELDS}


def counters_line(c):
    unknown = ", ".join(f"${k}: {n}" for k, n in sorted(c.unknown_types.items())) or "none"
    return (f"{c.frames} frames, {c.checksum_errors} checksum errors, {c.framing_errors} "
            f"framing errors (garbage {c.garbage}, partial {c.partial}, over-long {c.overlong}, "
            f"malformed {c.malformed}), unknown frame types: {unknown}")


def open_for_writing(path, what):
    """`path` opened for writing, its folder created if missing; Failure if it cannot be."""
    path = Path(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        return open(path, "w", newline="")
    except OSError as e:
        raise Failure(f"cannot write {what} {path}: {reason_text(e)}", EXIT_USAGE) from None


class TelemetryLog:
    """Every decoded field with a time stamp, one CSV row per frame."""

    def __init__(self, path, bases):
        self.path = Path(path)
        self._f = open_for_writing(self.path, "the CSV log")
        self._w = csv.DictWriter(self._f, fieldnames=csv_columns(bases), extrasaction="ignore")
        self._w.writeheader()

    def write(self, t_s, values):
        self._w.writerow(dict(values, t_s=f"{t_s:.4f}"))

    def close(self):
        self._f.close()


class DriveClock:
    """The drive's time from the frame counter: `seq` rises by one per frame sent, four
    frames every 750 ISRs (80 a second at 15 kHz), so the times are the drive's whatever
    the link's delays or the simulator's pacing (a frame the drive dropped, counted in
    $S tx_dropped, makes it run slow by 12.5 ms)."""

    def __init__(self, pwm_freq_Hz):
        self.s_per_frame = BG_TLM_PERIOD_TICKS / (FRAMES_PER_BURST * pwm_freq_Hz)
        self._last = None
        self.frames = 0         # since the first frame seen, across the 16-bit wrap

    def t(self, seq):
        """Seconds since the first frame seen, at the frame numbered `seq`."""
        if self._last is not None:
            self.frames += (seq - self._last) & 0xFFFF
        self._last = seq
        return self.frames * self.s_per_frame
