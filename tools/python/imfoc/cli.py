"""imfoc: the PC side of the drive's serial link (SCI-A, 115200 8N1; or motor_sim --serial).

    imfoc monitor PORT [--config INI] [--csv FILE] [--plot] [--png FILE] [--duration S]
    imfoc start|stop|reset|dlog-arm PORT [--no-wait]
    imfoc select-standstill|select-rotating PORT
    imfoc identify PORT --config INI [--out DIR] [--sequence configured|standstill|rotating]

PORT is a serial device (/dev/ttyUSB0, COM3, the path motor_sim --serial made).  The
per-unit values of the telemetry are converted to SI with the bases of --config, the INI
file the firmware was built from (motor_sim's default: host_sim/config/paper_motor.ini);
without it `monitor` shows per-unit values, and `identify` needs it.

Exit status: 0 done; 1 the drive did not do it (fault, timeout, nothing published);
2 usage or configuration error; 3 port error (cannot open, vanished, no telemetry).
"""
import argparse
import math
import os
import sys
import time
from pathlib import Path

from .bases import Bases, ConfigError
from .link import EXIT_DRIVE, EXIT_OK, EXIT_PORT, EXIT_USAGE, Failure, Link, reason_text
from .protocol import COMMANDS, command_frame, fault_name, state_name
from .telemetry_log import TelemetryLog, counters_line, frame_values

IDLE = 0


def load_bases(path):
    """Bases from the INI file; None without one (the values stay per unit)."""
    if path is None:
        return None
    try:
        return Bases.from_ini(path)
    except ConfigError as e:
        raise Failure(str(e), EXIT_USAGE) from None


# --- monitor ----------------------------------------------------------------------------

def _fmt(v):
    if isinstance(v, float):
        return f"{v:.6g}"
    return str(v)


def has_display():
    return bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")
                or sys.platform in ("win32", "darwin"))


class LivePlot:
    """Speed, currents and the published parameters against time (matplotlib, with a
    display and an interactive backend; `ok` False otherwise)."""

    def __init__(self, bases, out):
        self.ok = False
        try:
            import matplotlib
            import matplotlib.pyplot as plt
        except ImportError:
            out.write("--plot: matplotlib is not installed; plotting off\n")
            return
        if matplotlib.get_backend().lower() in ("agg", "pdf", "ps", "svg", "cairo", "template"):
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
            sys.stderr.write(f"--plot: stopped ({reason_text(e)})\n")


class PngPlot:
    """The monitored frames kept, drawn into a PNG at the end (no display needed)."""

    def __init__(self, path):
        self.path = Path(path)
        self.rows = []

    def add(self, t, v):
        self.rows.append(dict(v, t_s=t))

    def write(self, out):
        try:
            from .plots import PlotError, Run, plot_run
        except ImportError:
            out.write("--png: matplotlib is not installed: no plot\n")
            return
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            plot_run(Run(self.rows, "the monitored frames"), self.path)
            out.write(f"wrote {self.path}\n")
        except (PlotError, OSError) as e:
            out.write(f"--png: no plot ({reason_text(e)})\n")


def _plots(a, bases, out):
    """The live plot and the PNG the options ask for; without a display --plot becomes
    a PNG (--png, or beside --csv, or ./monitor.png)."""
    live = png = None
    if a.plot:
        live = LivePlot(bases, out) if has_display() else None
        if live is None or not live.ok:
            live = None
            if not a.png:
                a.png = str(Path(a.csv).with_suffix(".png")) if a.csv else "monitor.png"
            out.write(f"--plot: no display here; the plot goes to {a.png} at the end\n")
    if a.png:
        png = PngPlot(a.png)
    return live, png


def cmd_monitor(a, out):
    bases = load_bases(a.config)
    log = TelemetryLog(a.csv, bases) if a.csv else None
    try:
        link = Link(a.port, a.baud)
    except Failure:
        if log is not None:
            log.close()
        raise
    tty = out.isatty()
    live, png = _plots(a, bases, out)
    out.write(f"monitor {a.port} at {a.baud} baud, "
              + (f"SI units ({a.config})" if bases else
                 "per unit (--config INI, the INI the firmware was built from, for SI)")
              + "; Ctrl-C ends\n")
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
                for sink in (log, live, png):
                    if sink is not None:
                        (sink.write if sink is log else sink.add)(t, v)
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
        if log is not None:
            log.close()
    if png is not None:
        png.write(out)
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
    "start": lambda r: r["state"] != IDLE,
    "stop": lambda r: r["state"] == IDLE,
    "reset": lambda r: r["fault"] == 0,
}


def _done_text(command, before, r):
    now = f"state {state_name(r['state'])}, fault {fault_name(r['fault'])}"
    if command == "start":
        return f"the drive left IDLE: {now}"
    if command == "stop":
        return f"the drive is IDLE: {now}"
    if before is not None and before["fault"] != 0:
        return f"fault {before['fault']} ({fault_name(before['fault'])}) cleared: {now}"
    return f"reset sent; no fault was latched: {now}"


def _first_t(link, timeout):
    """The drive's state before the command: the first $T within `timeout`."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        for fr in link.read():
            if fr.type == "T":
                return fr.raw
    raise Failure(f"{link.port}: no telemetry within {timeout:g} s", EXIT_PORT)


def cmd_command(a, out):
    link = Link(a.port, a.baud)
    try:
        wait = not a.no_wait and a.command in _DONE
        before = _first_t(link, a.timeout) if wait else None
        link.send(a.command)
        out.write(f"sent {command_frame(a.command).decode().strip()} to {a.port}\n")
        if not wait:
            if a.command == "dlog-arm":
                out.write("(the data log has no telemetry field: read it with CCS)\n")
            elif a.command.startswith("select-"):
                out.write("(for the next starts; a drive without the standstill test refuses "
                          "a start after select-standstill: no_standstill)\n")
            return EXIT_OK
        done = _DONE[a.command]
        deadline = time.monotonic() + a.timeout
        last = before
        while time.monotonic() < deadline:
            for fr in link.read():
                if fr.type != "T":
                    continue
                last = fr.raw
                if done(last):
                    out.write(_done_text(a.command, before, last) + "\n")
                    return EXIT_OK
        why = ""
        if a.command == "start" and last["fault"] != 0:
            why = f": fault {last['fault']} ({fault_name(last['fault'])}) latched, reset first"
        elif a.command == "reset":
            why = ": its cause is still there (the fault latched again)"
        raise Failure(f"{a.command}: not done within {a.timeout:g} s (state "
                      f"{state_name(last['state'])}, fault {fault_name(last['fault'])}){why}",
                      EXIT_DRIVE)
    finally:
        link.close()


# --- identify ---------------------------------------------------------------------------

def cmd_identify(a, out):
    if a.config is None:
        raise Failure("--config INI is needed: the INI the firmware was built from (its bases "
                      "turn the telemetry into SI; motor_sim's default is "
                      "host_sim/config/paper_motor.ini)", EXIT_USAGE)
    from .identify import Identify
    return Identify(a, out, load_bases(a.config)).run()


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
                       help=f"{what} (default {timeout:g} s)" if timeout else what)

    m = sub.add_parser("monitor", help="decode $T, $A, $S and $Q frames: live table, CSV, plot")
    common(m, 5.0, "seconds without a frame before giving up")
    m.add_argument("--config", help="INI the firmware was built from, for SI units "
                                    "(default: per unit)")
    m.add_argument("--csv", help="log every decoded field with a time stamp to FILE (its "
                                 "folder is created)")
    m.add_argument("--plot", action="store_true", help="live plot (matplotlib) with a display; "
                                                       "without one, a PNG at the end")
    m.add_argument("--png", help="write speed, currents, state and the verdict to FILE (PNG) "
                                 "at the end")
    m.add_argument("--duration", type=_positive, help="stop after S seconds (default: Ctrl-C)")
    for name in COMMANDS:
        c = sub.add_parser(name, help=f"send $C,{COMMANDS[name]}"
                           + ("" if name == "dlog-arm" else " and wait until the drive acts"))
        common(c, 3.0, "seconds to wait for the drive to act")
        c.add_argument("--no-wait", action="store_true", help="send only")
        c.set_defaults(command=name)
    i = sub.add_parser("identify", help="run the identification to the drive's verdict: print "
                                        "and save the published set, its confidences, a trace "
                                        "and plots")
    common(i, None, "seconds to wait for the verdict (default 30 s plus CALIBRATE's expected "
                    "length)")
    i.add_argument("--config", help="INI the firmware was built from (required)")
    i.add_argument("--out", default=".", help="directory for report.json, trace.csv, run.png, "
                                              "parameters.png (default: .; created)")
    i.add_argument("--sequence", choices=("configured", "standstill", "rotating"),
                   default="configured",
                   help="standstill: every parameter with the rotor at rest (a load that "
                        "cannot be uncoupled; the drive needs [ident] sequence = adaptive or "
                        "standstill in its INI); rotating: the INI's rotating sequence; "
                        "configured (default): whatever the INI says")
    return ap


def _quiet_stdout():
    """The reader of our output has gone (imfoc monitor | head): send the rest nowhere, so
    that neither this command nor the interpreter's exit writes a traceback."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError):
        pass


def main(argv=None, out=None):
    out = out or sys.stdout
    a = parser().parse_args(argv)
    try:
        if a.cmd == "monitor":
            return cmd_monitor(a, out)
        if a.cmd == "identify":
            return cmd_identify(a, out)
        return cmd_command(a, out)
    except Failure as e:
        sys.stderr.write(f"imfoc {a.cmd}: {e}\n")
        return e.status
    except BrokenPipeError:
        _quiet_stdout()
        return EXIT_OK
    except KeyboardInterrupt:
        sys.stderr.write(f"imfoc {a.cmd}: interrupted\n")
        return EXIT_DRIVE


if __name__ == "__main__":
    sys.exit(main())
