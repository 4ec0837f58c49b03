"""imfoc: the PC side of the drive's serial link (SCI-A, 115200 8N1; or motor_sim --serial).

    imfoc monitor PORT [--config INI] [--csv FILE] [--plot] [--duration S]
    imfoc start|stop|reset|dlog-arm PORT [--no-wait]
    imfoc identify PORT [--config INI] [--out DIR]

PORT is a serial device (/dev/ttyUSB0, COM3, the path motor_sim --serial made).  The
per-unit values of the telemetry are converted to SI with the bases of --config, the INI
file the firmware was built from (default: host_sim/config/paper_motor.ini, the numbers
of firmware/board_config.c).

Exit status: 0 done; 1 the drive did not do it (fault, timeout, nothing published);
2 usage or configuration error; 3 port error (cannot open, vanished, no telemetry).
"""
import argparse
import csv
import json
import math
import os
import sys
import time
from pathlib import Path

from .bases import PARAM_FIELDS, SI_FIELDS, Bases, ConfigError
from .protocol import (COMMANDS, CONF_FIELDS, LAYOUT, LOAD_PERIOD_TICKS, REASONS, FrameDecoder,
                       command_frame, fault_name, reason_name, state_name)

# tools/python/imfoc/cli.py -> the repository root (for the default configuration)
DEFAULT_CONFIG = Path(__file__).resolve().parents[3] / "host_sim" / "config" / "paper_motor.ini"
EXIT_OK, EXIT_DRIVE, EXIT_USAGE, EXIT_PORT = 0, 1, 2, 3
IDLE, RUN, FAULT = 0, 5, 6


class Failure(Exception):
    """Ends the command with a one-line reason and an exit status."""

    def __init__(self, reason, status):
        super().__init__(reason)
        self.status = status


class Link:
    """The serial port with the frame decoder on its input."""

    def __init__(self, port, baud):
        try:
            import serial
        except ImportError:
            raise Failure("pyserial is not installed (pip install pyserial, or "
                          "tools/install_deps.sh)", EXIT_USAGE) from None
        self._serial = serial
        self.port = port
        try:
            self.ser = serial.Serial(port, baudrate=baud, bytesize=8, parity="N", stopbits=1,
                                     timeout=0.05, write_timeout=2.0)
            self.ser.reset_input_buffer()
        except (serial.SerialException, OSError, ValueError) as e:
            raise Failure(f"cannot open {port}: {_reason(e)}", EXIT_PORT) from None
        self.decoder = FrameDecoder()
        self.t_last_frame = None

    def read(self):
        """The frames completed by what arrived within ~50 ms ([] if none)."""
        try:
            data = self.ser.read(max(1, self.ser.in_waiting))
        except (self._serial.SerialException, OSError) as e:
            raise Failure(f"{self.port}: the port vanished ({_reason(e)})", EXIT_PORT) from None
        frames = self.decoder.feed(data)
        if frames:
            self.t_last_frame = time.monotonic()
        return frames

    def send(self, name):
        try:
            self.ser.write(command_frame(name))
            self.ser.flush()
        except (self._serial.SerialException, OSError) as e:
            raise Failure(f"{self.port}: cannot send ({_reason(e)})", EXIT_PORT) from None

    def close(self):
        try:
            self.ser.close()
        except (self._serial.SerialException, OSError):
            pass


def _reason(e):
    text = str(e).strip() or e.__class__.__name__
    return text.splitlines()[0]


def load_bases(path, required):
    """Bases from the INI file; None if not required and no file is given or found."""
    if path is None:
        if not DEFAULT_CONFIG.is_file():
            if required:
                raise Failure("--config INI is needed for the per-unit bases", EXIT_USAGE)
            return None
        path = DEFAULT_CONFIG
    try:
        return Bases.from_ini(path)
    except ConfigError as e:
        raise Failure(str(e), EXIT_USAGE) from None


# --- decoded values ---------------------------------------------------------------------

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
    q = list(LAYOUT["T"][1])
    cols_a = ["pass", "track_valid", "tracked"]
    qa = list(LAYOUT["A"][1])
    name = (lambda n: n + "_pu") if bases is None else (lambda n: SI_FIELDS[n][0])
    cols_s = ["isr_overruns", "tx_dropped", "rx_errors"]
    cols_q = (["reason", "reason_name"] + [n + "_pct" for n in CONF_FIELDS] +
              ["residual_rel", "amplification"])
    return cols + [name(n) for n in q] + cols_a + [name(n) for n in qa] + cols_s + cols_q


def params_si(frame, bases):
    return {SI_FIELDS[n][0]: bases.si(n, frame.pu[n])[1] for n in PARAM_FIELDS}


def print_table(out, params, label="identified"):
    """The published set in the layout of the paper's Table 1 (and of motor_sim's table)."""
    out.write("\n%-12s %10s %10s %10s %10s %10s %10s\n" % ("", "Rs/ohm", "Rr/ohm", "Lm/H",
                                                          "Lr/H", "psi_r/Wb", "Tr/s"))
    p = [params[SI_FIELDS[n][0]] for n in PARAM_FIELDS]
    out.write("%-12s %10.4f %10.4f %10.5f %10.5f %10.5f %10.5f\n" % (label, *p))


def counters_line(c):
    unknown = ", ".join(f"${k}: {n}" for k, n in sorted(c.unknown_types.items())) or "none"
    return (f"{c.frames} frames, {c.checksum_errors} checksum errors, {c.framing_errors} "
            f"framing errors (garbage {c.garbage}, partial {c.partial}, over-long {c.overlong}, "
            f"malformed {c.malformed}), unknown frame types: {unknown}")


# --- monitor ----------------------------------------------------------------------------

def _fmt(v):
    if isinstance(v, float):
        return f"{v:.6g}"
    return str(v)


class LivePlot:
    """Speed, currents and the published parameters against time (matplotlib, if a
    display is there)."""

    def __init__(self, bases, out):
        self.ok = False
        if not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")
                or sys.platform in ("win32", "darwin")):
            out.write("--plot: no display here; plotting off\n")
            return
        try:
            import matplotlib
            import matplotlib.pyplot as plt
        except ImportError:
            out.write("--plot: matplotlib is not installed; plotting off\n")
            return
        if matplotlib.get_backend().lower() in ("agg", "pdf", "ps", "svg", "cairo", "template"):
            out.write("--plot: no interactive matplotlib backend; plotting off\n")
            return
        self.plt = plt
        self.suffix = "" if bases is not None else "_pu"
        self.t, self.rows = [], []
        plt.ion()
        self.fig, self.ax = plt.subplots(3, 1, sharex=True, figsize=(8, 7))
        self.t_draw = 0.0
        self.ok = True

    def add(self, t, v):
        if not self.ok or v.get("frame") != "T":
            return
        self.t.append(t)
        self.rows.append(v)
        if t - self.t_draw < 0.5:
            return
        self.t_draw = t
        try:
            s = self.suffix
            keys = [("speed_rpm", "speed_ref_rpm") if not s else ("speed_pu", "speed_ref_pu"),
                    ("i_m_A", "i_t_A") if not s else ("i_m_pu", "i_t_pu"),
                    ("Rs_ohm", "Rr_ohm") if not s else ("Rs_pu", "Rr_pu")]
            for ax, ks in zip(self.ax, keys):
                ax.clear()
                for k in ks:
                    ax.plot(self.t, [r[k] for r in self.rows], label=k)
                ax.legend(loc="upper left", fontsize="small")
            self.ax[-1].set_xlabel("t / s")
            self.plt.pause(0.001)
        except Exception as e:   # a closed window or a backend error ends the plot only
            self.ok = False
            sys.stderr.write(f"--plot: stopped ({_reason(e)})\n")


def cmd_monitor(a, out):
    bases = load_bases(a.config, required=False)
    link = Link(a.port, a.baud)
    tty = out.isatty()
    f_csv = writer = None
    if a.csv:
        try:
            f_csv = open(a.csv, "w", newline="")
        except OSError as e:
            link.close()
            raise Failure(f"cannot write {a.csv}: {_reason(e)}", EXIT_USAGE) from None
        writer = csv.DictWriter(f_csv, fieldnames=csv_columns(bases), extrasaction="ignore")
        writer.writeheader()
    plot = LivePlot(bases, out) if a.plot else None
    out.write(f"monitor {a.port} at {a.baud} baud, "
              f"{'SI units (' + str(a.config or DEFAULT_CONFIG) + ')' if bases else 'per unit'}"
              f"; Ctrl-C ends\n")
    t0 = time.monotonic()
    last = {"T": None, "A": None, "S": None, "Q": None}
    t_draw = 0.0
    status = EXIT_OK
    try:
        while True:
            now = time.monotonic()
            if a.duration is not None and now - t0 >= a.duration:
                break
            seen = link.t_last_frame if link.t_last_frame is not None else t0
            if now - seen > a.timeout:
                raise Failure(f"{a.port}: no telemetry for {a.timeout:g} s (wrong port or baud "
                              "rate, or the drive is off?)", EXIT_PORT)
            for fr in link.read():
                t = time.monotonic() - t0
                v = frame_values(fr, bases)
                last[fr.type] = v
                if writer is not None:
                    writer.writerow(dict(v, t_s=f"{t:.4f}"))
                if plot is not None:
                    plot.add(t, v)
                if not tty and fr.type == "T":
                    out.write(f"{t:8.3f} " + " ".join(f"{k}={_fmt(x)}" for k, x in v.items()
                                                      if k not in ("frame",)) + "\n")
            if tty and time.monotonic() - t_draw > 0.25:
                t_draw = time.monotonic()
                _draw(out, a.port, last, link.decoder.counters, t_draw - t0)
    except KeyboardInterrupt:
        pass
    except Failure as e:
        out.write("\n")
        sys.stderr.write(f"imfoc monitor: {e}\n")
        status = e.status
    finally:
        link.close()
        if f_csv is not None:
            f_csv.close()
    out.write(f"\n{a.port}: {counters_line(link.decoder.counters)}\n")
    return status


def _draw(out, port, last, counters, t):
    lines = [f"\x1b[H\x1b[J{port}  {t:7.1f} s   {counters_line(counters)}", ""]
    for kind in ("T", "A", "S", "Q"):
        v = last.get(kind)
        if v is None:
            lines.append(f"${kind}: (none yet)")
            continue
        items = [(k, x) for k, x in v.items() if k != "frame"]
        lines.append(f"${kind}")
        for i in range(0, len(items), 4):
            lines.append("  " + "".join(f"{k:>14s} {_fmt(x):<12s}" for k, x in items[i:i + 4]))
    out.write("\n".join(lines) + "\n")
    out.flush()


# --- commands ---------------------------------------------------------------------------

# what a $T frame shows once the drive has acted on the command
_DONE = {
    "start": (lambda r: r["state"] != IDLE, "the drive left IDLE"),
    "stop": (lambda r: r["state"] == IDLE, "the drive is IDLE"),
    "reset": (lambda r: r["fault"] == 0, "no fault latched"),
}


def cmd_command(a, out):
    link = Link(a.port, a.baud)
    try:
        link.send(a.command)
        out.write(f"sent {command_frame(a.command).decode().strip()} to {a.port}\n")
        if a.no_wait or a.command not in _DONE:
            if a.command == "dlog-arm":
                out.write("(the data log has no telemetry field: read it with CCS)\n")
            return EXIT_OK
        done, what = _DONE[a.command]
        deadline = time.monotonic() + a.timeout
        last = None
        while time.monotonic() < deadline:
            for fr in link.read():
                if fr.type != "T":
                    continue
                last = fr.raw
                if done(last):
                    out.write(f"{what}: state {state_name(last['state'])}, "
                              f"fault {fault_name(last['fault'])}\n")
                    return EXIT_OK
        if last is None:
            raise Failure(f"{a.port}: no telemetry within {a.timeout:g} s", EXIT_PORT)
        why = ""
        if a.command == "start" and last["fault"] != 0:
            why = f": fault {last['fault']} ({fault_name(last['fault'])}) latched, reset first"
        raise Failure(f"{a.command}: not done within {a.timeout:g} s (state "
                      f"{state_name(last['state'])}, fault {fault_name(last['fault'])}){why}",
                      EXIT_DRIVE)
    finally:
        link.close()


# --- identify ---------------------------------------------------------------------------

class Identify:
    """Start the identification and follow it until the drive publishes this run's set."""

    def __init__(self, a, out):
        self.a, self.out = a, out
        self.bases = load_bases(a.config, required=True)
        self.config = str(a.config or DEFAULT_CONFIG)

    def run(self):
        a, out = self.a, self.out
        out_dir = Path(a.out)
        if out_dir.exists() and not out_dir.is_dir():
            raise Failure(f"--out {out_dir} is not a directory", EXIT_USAGE)
        link = Link(a.port, a.baud)
        try:
            result = self._follow(link)
        finally:
            link.close()
        self._report(out_dir, result, link)
        return EXIT_OK

    def _next_t(self, link, deadline, what):
        while time.monotonic() < deadline:
            for fr in link.read():
                self._frames.append(fr)
            while self._frames:
                fr = self._frames.pop(0)
                if fr.type == "A":
                    self.last_a = fr
                elif fr.type == "S":
                    self.last_s = fr      # the ISR's overruns and load: shown, not followed
                elif fr.type == "Q":
                    self.last_q = fr      # the publication's verdict and confidences
                elif fr.type == "T":
                    return fr
        raise Failure(what, EXIT_DRIVE if self.seen_t else EXIT_PORT)

    def _follow(self, link):
        a, out = self.a, self.out
        self._frames, self.last_a, self.last_s, self.last_q, self.seen_t = [], None, None, None, False
        t0 = time.monotonic()
        deadline = t0 + a.timeout
        first = self._next_t(link, min(deadline, t0 + 5.0),
                             f"{a.port}: no telemetry within {min(a.timeout, 5.0):g} s (wrong "
                             "port or baud rate, or the drive is off?)")
        self.seen_t = True
        r = first.raw
        if r["fault"] != 0 or r["state"] == FAULT:
            raise Failure(f"the drive has fault {r['fault']} ({fault_name(r['fault'])}) "
                          f"latched: clear it first (imfoc reset {a.port})", EXIT_DRIVE)
        before = tuple(r[n] for n in PARAM_FIELDS) if r["valid"] else None
        if r["state"] != IDLE:
            out.write(f"drive in {state_name(r['state'])}: stopping it first\n")
            link.send("stop")
            while first.raw["state"] != IDLE:
                first = self._next_t(link, deadline, "timeout: the drive did not stop "
                                     f"within {a.timeout:g} s")
                self._check_fault(first)
        link.send("start")
        t_start = time.monotonic()
        t_sent, tries = t_start, 1
        out.write(f"identify on {a.port} ({self.config}): $C,S sent\n")
        out.write(f"{0.0:7.2f} s  IDLE\n")
        state, started, pass_no = IDLE, False, 0
        while True:
            fr = self._next_t(link, deadline, self._timeout_text(state, pass_no))
            r = fr.raw
            self._check_fault(fr)
            if r["state"] != state:
                state = r["state"]
                out.write(f"{time.monotonic() - t_start:7.2f} s  {state_name(state)}\n")
            if state != IDLE:
                started = True
                self._check_refused()
            elif not started and time.monotonic() - t_sent > 1.0:
                if tries >= 3:
                    raise Failure("the drive did not leave IDLE after 3 x $C,S", EXIT_DRIVE)
                link.send("start")      # a command the link lost
                t_sent, tries = time.monotonic(), tries + 1
            if not (started and state == RUN and r["valid"]):
                continue
            adapt = self._adapt_of(link, fr, deadline)
            pass_no = adapt.raw["pass"] if adapt is not None else pass_no
            if self.bases.passes > 1 and (adapt is None or adapt.raw["pass"] < self.bases.passes):
                continue
            if self.bases.track_rr and (adapt is None or not adapt.raw["tracked"]
                                        or not adapt.raw["track_valid"]):
                continue
            if before is not None and tuple(r[n] for n in PARAM_FIELDS) == before:
                raise Failure("the published set is the one from before the start: this run's "
                              "extraction was implausible and not published", EXIT_DRIVE)
            return {"frame": fr, "adapt": adapt, "t_s": time.monotonic() - t_start}

    def _adapt_of(self, link, t_frame, deadline):
        """The $A frame sent right after this $T (None if it was lost)."""
        want = (t_frame.raw["seq"] + 1) & 0xFFFF
        end = min(deadline, time.monotonic() + 0.5)
        while time.monotonic() < end:
            for fr in link.read():
                self._frames.append(fr)
            for i, fr in enumerate(self._frames):
                if fr.type == "A" and fr.raw["seq"] == want:
                    del self._frames[:i + 1]
                    self.last_a = fr
                    return fr
                if fr.type == "T":
                    return None
        return None

    def _check_refused(self):
        """The drive's verdict on this run's set, once it has one and it is not
        "published" (a $Q frame sent after this run's start: its reason left
        "pending" when the start was taken)."""
        q = self.last_q
        if q is None:
            return
        if q.raw["reason"] == REASONS.index("pending"):
            self.pending_seen = True
            return
        if getattr(self, "pending_seen", False) and q.raw["reason"] != REASONS.index("published"):
            conf = ", ".join(f"{n[5:]} {100.0 * q.pu[n]:.2f} %" for n in CONF_FIELDS
                             if q.pu[n] >= 0)
            raise Failure(f"the drive refused its set: {reason_name(q.raw['reason'])}"
                          f"{' (confidence ' + conf + ')' if conf else ''}", EXIT_DRIVE)

    def _check_fault(self, fr):
        f = fr.raw["fault"]
        if f != 0 or fr.raw["state"] == FAULT:
            raise Failure(f"drive fault {f} ({fault_name(f)}) in "
                          f"{state_name(fr.raw['state'])}", EXIT_DRIVE)

    def _timeout_text(self, state, pass_no):
        p = f", pass {pass_no}" if pass_no else ""
        return (f"timeout: no published set within {self.a.timeout:g} s "
                f"(state {state_name(state)}{p})")

    def _report(self, out_dir, res, link):
        fr, ad, b = res["frame"], res["adapt"], self.bases
        params = params_si(fr, b)
        print_table(self.out, params)
        extra = ""
        rs_dc = None
        if ad is not None:
            rs_dc = b.si("Rs_dc", ad.pu["Rs_dc"])[1] if ad.raw["Rs_dc"] else None
            extra = (f"; pass {ad.raw['pass']}"
                     f"{', fused set (standstill Rs, tracked Rr and Tr)' if ad.raw['tracked'] else ''}")
        q = self.last_q
        conf = None
        if q is not None and q.raw["reason"] == REASONS.index("published"):
            conf = {SI_FIELDS[n][0]: (None if q.pu["conf_" + n] < 0 else
                                      100.0 * q.pu["conf_" + n]) for n in PARAM_FIELDS}
            self.out.write("%-12s" % "confidence" + "".join(
                "%10s" % ("-" if conf[SI_FIELDS[n][0]] is None else
                          f"{conf[SI_FIELDS[n][0]]:.2f}%") for n in PARAM_FIELDS) + "\n")
        self.out.write(f"\npublished {res['t_s']:.2f} s after $C,S (frame {fr.raw['seq']}){extra}\n"
                       f"{link.port}: {counters_line(link.decoder.counters)}\n")
        rep = {
            "config": self.config,
            "port": link.port,
            "source": "telemetry",
            "published": True,
            "publish_reason": "published",
            "confidence_pct": conf,
            "t_published_s": round(res["t_s"], 4),
            "identified": params,
            "published_end": params,
            "identified_q24": {n: _signed(fr.raw[n]) for n in PARAM_FIELDS},
            "params_tracked": bool(ad.raw["tracked"]) if ad is not None else False,
            "pass": ad.raw["pass"] if ad is not None else None,
            "Rs_dc_ohm": rs_dc,
            "state": state_name(fr.raw["state"]),
            "fault": fr.raw["fault"],
            "bases": {"I_base_A": b.I_base_A, "V_base_V": b.V_base_V, "f_base_Hz": b.f_base_Hz,
                      "Z_base_ohm": b.Z_base_ohm, "L_base_H": b.L_base_H,
                      "psi_base_Wb": b.psi_base_Wb, "t_base_s": b.t_base_s},
            "link": link.decoder.counters.as_dict(),
        }
        path = out_dir / "report.json"
        try:
            out_dir.mkdir(parents=True, exist_ok=True)
            path.write_text(json.dumps(rep, indent=2) + "\n")
        except OSError as e:
            raise Failure(f"cannot write {path}: {_reason(e)}", EXIT_USAGE) from None
        self.out.write(f"wrote {path}\n")


def _signed(w):
    return w - (1 << 32) if w >= 1 << 31 else w


# --- the command line -------------------------------------------------------------------

def _positive(text):
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a number") from None
    if not (v > 0 and math.isfinite(v)):
        raise argparse.ArgumentTypeError(f"'{text}' must be a positive number")
    return v


def _baud(text):
    try:
        v = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a whole number") from None
    if v <= 0:
        raise argparse.ArgumentTypeError("the baud rate must be positive")
    return v


def parser():
    ap = argparse.ArgumentParser(prog="imfoc", description=__doc__.split("\n\n")[0],
                                 epilog="Exit status: 0 done; 1 the drive did not do it; 2 "
                                 "usage or configuration error; 3 port error.")
    sub = ap.add_subparsers(dest="cmd", metavar="COMMAND", required=True)

    def common(p, timeout, what):
        p.add_argument("port", metavar="PORT", help="serial device or motor_sim --serial path")
        p.add_argument("--baud", type=_baud, default=115200, help="default 115200 (8N1)")
        p.add_argument("--timeout", type=_positive, default=timeout,
                       help=f"{what} (default {timeout:g} s)")

    m = sub.add_parser("monitor", help="decode $T, $A, $S and $Q frames: live table, CSV, plot")
    common(m, 5.0, "seconds without a frame before giving up")
    m.add_argument("--config", help="INI of the firmware, for SI units (default: the board's)")
    m.add_argument("--csv", help="log every decoded field with a time stamp to FILE")
    m.add_argument("--plot", action="store_true", help="live plot (matplotlib, needs a display)")
    m.add_argument("--duration", type=_positive, help="stop after S seconds (default: Ctrl-C)")
    for name in COMMANDS:
        c = sub.add_parser(name, help=f"send $C,{COMMANDS[name]}"
                           + ("" if name == "dlog-arm" else " and wait until the drive acts"))
        common(c, 3.0, "seconds to wait for the drive to act")
        c.add_argument("--no-wait", action="store_true", help="send only")
        c.set_defaults(command=name)
    i = sub.add_parser("identify", help="run the identification, print and save the "
                                        "published parameters")
    common(i, 30.0, "seconds to wait for the published set")
    i.add_argument("--config", help="INI the firmware was built from (default: the board's, "
                                    "host_sim/config/paper_motor.ini)")
    i.add_argument("--out", default=".", help="directory for report.json (default: .)")
    return ap


def main(argv=None, out=None):
    out = out or sys.stdout
    a = parser().parse_args(argv)
    try:
        if a.cmd == "monitor":
            return cmd_monitor(a, out)
        if a.cmd == "identify":
            return Identify(a, out).run()
        return cmd_command(a, out)
    except Failure as e:
        sys.stderr.write(f"imfoc {a.cmd}: {e}\n")
        return e.status
    except KeyboardInterrupt:
        sys.stderr.write(f"imfoc {a.cmd}: interrupted\n")
        return EXIT_DRIVE


if __name__ == "__main__":
    sys.exit(main())
