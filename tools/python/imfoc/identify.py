"""imfoc identify: start the identification, follow it to the drive's verdict, print and
save what it published (or why it refused), with a trace and plots.

Times are the drive's, from the frame counter (telemetry_log.DriveClock): the same on a
board and on a simulator paced at any real-time factor.
"""
import json
import time
from pathlib import Path

from .bases import PARAM_FIELDS, SI_FIELDS, ConfigError
from .link import EXIT_DRIVE, EXIT_OK, EXIT_PORT, EXIT_USAGE, Failure, Link, reason_text
from .protocol import CONF_FIELDS, REASONS, fault_name, reason_name, state_name
from .sequence_time import calibrate_s, configured_standstill, standstill_s
from .telemetry_log import (DriveClock, TelemetryLog, counters_line, frame_values, params_si)
from .verdict import confidence_pct, summary

IDLE, CALIBRATE, ACCELERATE, FAULT = 0, 1, 3, 6
INJECT = 8
PROGRESS_EVERY_S = 1.0     # drive seconds between two progress lines within a state
START_WAIT_S = 1.0         # wall seconds before a start command is taken as lost
PENDING = REASONS.index("pending")


def print_table(out, params, label="identified"):
    """The set in the layout of the paper's Table 1 (and of motor_sim's table)."""
    out.write("\n%-12s %10s %10s %10s %10s %10s %10s\n" % ("", "Rs/ohm", "Rr/ohm", "Lm/H",
                                                          "Lr/H", "psi_r/Wb", "Tr/s"))
    p = [params[SI_FIELDS[n][0]] for n in PARAM_FIELDS]
    out.write("%-12s %10.4f %10.4f %10.5f %10.5f %10.5f %10.5f\n" % (label, *p))


def confidence_row(conf):
    """The confidences under the table's columns ("-": not available)."""
    return "%-12s" % "confidence" + "".join(
        " %10s" % ("-" if conf[SI_FIELDS[n][0]] is None else f"{conf[SI_FIELDS[n][0]]:.2f}%")
        for n in PARAM_FIELDS) + "\n"


class Identify:
    """Start the identification and follow it until the drive's verdict on this run."""

    def __init__(self, a, out, bases):
        self.a, self.out, self.bases = a, out, bases
        self.config = str(a.config)
        self.sequence = getattr(a, "sequence", "configured")
        try:
            self.standstill = (self.sequence == "standstill" or
                               (self.sequence == "configured" and configured_standstill(a.config)))
            self.t_calibrate = calibrate_s(a.config)
            # the standstill sequence's injection: 10 s on the paper motor, 30 s on a 37 kW one
            self.t_inject = standstill_s(a.config) if self.standstill else 0.0
        except ConfigError as e:
            raise Failure(str(e), EXIT_USAGE) from None
        # a 15 kW motor's CALIBRATE alone is 15 s: the default wait covers it
        self.timeout = (a.timeout if a.timeout is not None
                        else 30.0 + self.t_calibrate + self.t_inject)
        self.clock = DriveClock(bases.pwm_freq_Hz)
        self.log = None
        self.frames = []
        self.last_a = self.last_q = None
        self.t_start = None

    # --- the run ---------------------------------------------------------------------
    def run(self):
        out_dir = Path(self.a.out)
        if out_dir.exists() and not out_dir.is_dir():
            raise Failure(f"--out {out_dir} is not a directory", EXIT_USAGE)
        self.log = TelemetryLog(out_dir / "trace.csv", self.bases)
        link = failure = None
        try:
            link = Link(self.a.port, self.a.baud)
            result = self._follow(link)
        except Failure as e:
            failure = e
        finally:
            if link is not None:
                link.close()
            self.log.close()
        if failure is not None:
            if self.t_start is not None:
                self._plots(out_dir)      # the trace up to the failure: what to look at
            raise failure
        published = self._report(out_dir, result, link)
        self._plots(out_dir)
        if not published:
            q = result["verdict"]
            raise Failure("the drive refused its set: " + self._summary(q), EXIT_DRIVE)
        return EXIT_OK

    def _now(self):
        """Drive seconds since the start command (since the first frame before it)."""
        return self.clock.t(self._seq) - (self.t_start or 0.0)

    def _next(self, link, deadline, what):
        """The next frame (any type), logged; Failure(what) at the deadline."""
        while not self.frames:
            if time.monotonic() >= deadline:
                raise Failure(what, EXIT_DRIVE if self.clock.frames else EXIT_PORT)
            self.frames.extend(link.read())
        fr = self.frames.pop(0)
        self._seq = fr.raw["seq"]
        t = self.clock.t(self._seq)
        self.log.write(t, frame_values(fr, self.bases))   # trace time: since the first frame
        if fr.type == "A":
            self.last_a = fr
        elif fr.type == "Q":
            self.last_q = fr
        return fr

    def _next_t(self, link, deadline, what):
        while True:
            fr = self._next(link, deadline, what)
            if fr.type == "T":
                return fr

    def _follow(self, link):
        a, out = self.a, self.out
        deadline = time.monotonic() + self.timeout
        first = self._next_t(link, min(deadline, time.monotonic() + 5.0),
                             f"{a.port}: no telemetry within {min(self.timeout, 5.0):g} s "
                             "(wrong port or baud rate, or the drive is off?)")
        r = first.raw
        if r["fault"] != 0 or r["state"] == FAULT:
            raise Failure(f"the drive has fault {r['fault']} ({fault_name(r['fault'])}) "
                          f"latched: clear it first (imfoc reset {a.port})", EXIT_DRIVE)
        if r["state"] != IDLE:
            out.write(f"drive in {state_name(r['state'])}: stopping it first\n")
            link.send("stop")
            while first.raw["state"] != IDLE:
                first = self._next_t(link, deadline, "timeout: the drive did not stop "
                                     f"within {self.timeout:g} s")
                self._check_fault(first, first.raw["state"])
        if self.sequence != "configured":
            link.send("select-" + self.sequence)     # taken before the start (drive.h)
        link.send("start")
        self.t_start = self.clock.t(self._seq)
        t_sent, tries = time.monotonic(), 1
        out.write(f"identify on {a.port} ({self.config}): $C,S sent; CALIBRATE takes "
                  f"~{self.t_calibrate:.1f} s\n")
        out.write(f"{0.0:7.2f} s  IDLE\n")
        state, ran, started, pending_seen = IDLE, IDLE, False, False
        t_state = t_shown = 0.0
        verdict = t_verdict = None
        while True:
            fr = self._next(link, deadline, self._timeout_text(state))
            if (fr.type == "Q" and not started and self.standstill and
                    fr.raw["reason"] == REASONS.index("no_standstill")):
                raise Failure("the drive cannot run the standstill sequence: its INI has no "
                              "standstill test ([ident] sequence = adaptive or standstill); "
                              "nothing turned", EXIT_DRIVE)
            if fr.type == "Q" and started:
                if fr.raw["reason"] == PENDING:
                    pending_seen = True
                elif pending_seen and verdict is None:
                    verdict, t_verdict = fr, self._now()
                    if fr.raw["reason"] != REASONS.index("published"):
                        return {"verdict": fr, "frame": None, "adapt": None, "t_s": t_verdict,
                                "t_verdict_s": t_verdict}
                continue
            if fr.type != "T":
                continue
            r = fr.raw
            now = self._now()
            self._check_fault(fr, ran)
            if self.standstill and r["state"] == ACCELERATE:
                # never turn a shaft the user said cannot turn
                link.send("stop")
                raise Failure("the drive started to accelerate although the standstill "
                              "sequence was asked for: stopped", EXIT_DRIVE)
            if r["state"] != state:
                state, t_state = r["state"], now
                ran = state
                out.write(f"{now:7.2f} s  {state_name(state)}\n")
                t_shown = now
            elif now - t_shown >= PROGRESS_EVERY_S:
                out.write(self._progress(fr, now, now - t_state))
                t_shown = now
            out.flush()
            if state != IDLE:
                started = True
            elif not started and time.monotonic() - t_sent > START_WAIT_S:
                if tries >= 3:
                    raise Failure("the drive did not leave IDLE after 3 x $C,S", EXIT_DRIVE)
                link.send("start")      # a command the link lost
                t_sent, tries = time.monotonic(), tries + 1
            if verdict is not None and r["valid"]:
                # the first $T after a "published" verdict carries the set it published
                return {"verdict": verdict, "frame": fr, "adapt": self._adapt_of(link, fr),
                        "t_s": now, "t_verdict_s": t_verdict}

    def _adapt_of(self, link, t_frame):
        """The $A frame sent right after this $T (None if it was lost)."""
        want = (t_frame.raw["seq"] + 1) & 0xFFFF
        try:
            fr = self._next(link, time.monotonic() + 0.5, "")
        except Failure:
            return None
        return fr if fr.type == "A" and fr.raw["seq"] == want else None

    def _progress(self, fr, now, in_state):
        """A line of live values while a state lasts (CALIBRATE: against its expected
        length, from the INI)."""
        r, b = fr.raw, self.bases
        line = f"{now:7.2f} s    {state_name(r['state'])} {in_state:.1f} s"
        if r["state"] == INJECT:
            line += f" of ~{self.t_inject:.1f} s (the low-frequency test at standstill)"
        if r["state"] == CALIBRATE:
            phase = "sensor and bridge tests" if r["pwm_on"] else "current offsets, bridge off"
            line += f" of ~{self.t_calibrate:.1f} s ({phase})"
            if in_state > self.t_calibrate * 1.05:
                line += ", longer than expected: a second bridge test?"
        si = {n: b.si(n, fr.pu[n])[1] for n in ("speed", "speed_ref", "i_m", "i_t", "vdc")}
        return (line + f": speed {si['speed']:.0f} r/min (ref {si['speed_ref']:.0f}), "
                f"i_M {si['i_m']:.2f} A, i_T {si['i_t']:.2f} A, vdc {si['vdc']:.1f} V\n")

    def _check_fault(self, fr, ran):
        """A fault ends the run, named with the state it happened in (the frame says
        FAULT: the state before it is the one that was running)."""
        f = fr.raw["fault"]
        if f != 0 or fr.raw["state"] == FAULT:
            raise Failure(f"drive fault {f} ({fault_name(f)}) in {state_name(ran)}, "
                          f"{self._now():.2f} s after $C,S", EXIT_DRIVE)

    def _timeout_text(self, state):
        a = self.last_a
        p = f", pass {a.raw['pass']}" if a is not None and a.raw["pass"] else ""
        return (f"timeout: no verdict within {self.timeout:g} s (state {state_name(state)}{p}; "
                "--timeout S waits longer)")

    # --- the results -----------------------------------------------------------------
    def _plots(self, out_dir):
        try:
            from .plots import PlotError, plot_dir
        except ImportError:
            self.out.write("no plots: matplotlib is not installed (tools/install_deps.sh)\n")
            return
        try:
            outs = plot_dir(out_dir)
            self.out.write(f"wrote {outs[0]} and {outs[1]}\n")
        except (PlotError, ImportError) as e:
            self.out.write(f"no plots: {reason_text(e)}\n")

    def _report(self, out_dir, res, link):
        q, fr, ad, b = res["verdict"], res["frame"], res["adapt"], self.bases
        reason, conf = self._confidence(q)
        published = reason == "published"
        params = params_si(fr, b) if published else None
        if published:
            print_table(self.out, params)
            self.out.write(confidence_row(conf))
        extra = ""
        rs_dc = None
        if ad is not None:
            rs_dc = b.si("Rs_dc", ad.pu["Rs_dc"])[1] if ad.raw["Rs_dc"] else None
            extra = (f"; pass {ad.raw['pass']}"
                     f"{', fused set (standstill Rs, tracked Rr and Tr)' if ad.raw['tracked'] else ''}")
        self.out.write(f"\n{summary(reason, conf)}\n")
        if published:
            self.out.write(f"published {res['t_s']:.2f} s after $C,S (frame {fr.raw['seq']})"
                           f"{extra}\n")
        else:
            self.out.write(f"refused {res['t_s']:.2f} s after $C,S: the drive keeps the set it "
                           "held before (if any)\n")
        self.out.write(f"{link.port}: {counters_line(link.decoder.counters)}\n")
        rep = {
            "config": self.config,
            "port": link.port,
            "source": "telemetry",
            "published": published,
            "publish_reason": reason,
            "confidence_pct": conf,
            "t_decided_s": round(res["t_verdict_s"], 4),
            "trace_t_start_s": round(self.t_start, 4),   # trace.csv's t_s of the $C,S
            "t_published_s": round(res["t_s"], 4) if published else None,
            "identified": params,
            "published_end": params,
            "identified_q24": ({n: _signed(fr.raw[n]) for n in PARAM_FIELDS}
                               if published else None),
            "params_tracked": bool(ad.raw["tracked"]) if ad is not None else False,
            "pass": ad.raw["pass"] if ad is not None else (self.last_a.raw["pass"]
                                                           if self.last_a else None),
            "Rs_dc_ohm": rs_dc,
            "state": state_name(fr.raw["state"]) if fr is not None else None,
            "fault": fr.raw["fault"] if fr is not None else 0,
            "bases": {"I_base_A": b.I_base_A, "V_base_V": b.V_base_V, "f_base_Hz": b.f_base_Hz,
                      "Z_base_ohm": b.Z_base_ohm, "L_base_H": b.L_base_H,
                      "psi_base_Wb": b.psi_base_Wb, "t_base_s": b.t_base_s},
            "link": link.decoder.counters.as_dict(),
        }
        path = out_dir / "report.json"
        try:
            path.write_text(json.dumps(rep, indent=2) + "\n")
        except OSError as e:
            raise Failure(f"cannot write {path}: {reason_text(e)}", EXIT_USAGE) from None
        self.out.write(f"wrote {path}\n")
        return published

    @staticmethod
    def _confidence(q):
        reason = reason_name(q.raw["reason"])
        return reason, confidence_pct(reason, [q.pu[n] for n in CONF_FIELDS], q.pu["residual"],
                                      q.pu["amplification"])

    def _summary(self, q):
        return summary(*self._confidence(q))


def _signed(w):
    return w - (1 << 32) if w >= 1 << 31 else w
