"""A firmware instance (include/imfoc_api.h) as a Python object."""
import configparser
import ctypes as C
import math
import os
import tempfile
from pathlib import Path

from . import _lib
from .protocol import STATES   # every id_state_t of include/id_sequence.h, REFINE included
from .protocol import REASONS  # every drive_pub_reason_t of include/drive.h

CMD_START_IDENT, CMD_STOP, CMD_RESET_FAULT = 1, 2, 3
# the sequence of the next starts (include/imfoc_api.h): the standstill one, the rotating one
CMD_SELECT_STANDSTILL, CMD_SELECT_ROTATING = 4, 5
PUB_PUBLISHED = REASONS.index("published")
CONFIG_DIR = _lib.REPO_ROOT / "host_sim" / "config"


class ImfocError(RuntimeError):
    pass


def read_ini(path):
    """The INI file as a ConfigParser (the simulator's syntax: `;` comments)."""
    cp = configparser.ConfigParser(inline_comment_prefixes=(";",), comment_prefixes=(";", "#"))
    cp.optionxform = str   # keys are case-sensitive
    with open(path) as f:
        cp.read_file(f)
    return cp


def write_config(base, overrides=None, path=None):
    """Write `base` (an INI path) with `overrides` {"section": {"key": value}}
    applied to `path` (a new temporary file if None); returns the path."""
    cp = read_ini(base)
    for sec, kv in (overrides or {}).items():
        if not cp.has_section(sec):
            cp.add_section(sec)
        for k, v in kv.items():
            cp.set(sec, k, repr(v) if isinstance(v, float) else str(v))
    if path is None:
        fd, path = tempfile.mkstemp(prefix="imfoc_", suffix=".ini")
        os.close(fd)
    with open(path, "w") as f:
        cp.write(f)
    return Path(path)


def _check(st):
    if st != 0:
        raise ImfocError(_lib.load().imfoc_status_str(st).decode())


class Drive:
    """One independent firmware instance.

    step_phys(ia, ib, vdc, theta_m) / step_raw(...) run one ISR with the inputs
    sampled at the start of a PWM period and return an Out whose duties the
    plant must apply over the NEXT period (the F2812's compare reload).  Each
    call returns a new Out, so the one a plant keeps for the next period is
    not overwritten by the next step.
    """

    def __init__(self, ini_path):
        self._lib = _lib.load()
        err = C.create_string_buffer(512)
        h = self._lib.imfoc_create_ini(str(ini_path).encode(), err, len(err))
        if not h:
            raise ImfocError(err.value.decode())
        self._h = C.c_void_p(h)
        self.info = _lib.Info()
        _check(self._lib.imfoc_get_info(self._h, C.byref(self.info)))
        self._phys = _lib.PhysIn()
        self._raw = _lib.RawIn()

    def close(self):
        if getattr(self, "_h", None):
            self._lib.imfoc_destroy(self._h)
            self._h = None

    def __del__(self):
        self.close()

    def __enter__(self):
        return self

    def __exit__(self, *a):
        self.close()

    # commands ---------------------------------------------------------------
    def command(self, cmd):
        _check(self._lib.imfoc_command(self._h, cmd))

    def start_identification(self):
        self.command(CMD_START_IDENT)

    def stop(self):
        self.command(CMD_STOP)

    def reset_fault(self):
        self.command(CMD_RESET_FAULT)

    def select_sequence(self, standstill):
        """The next starts run the standstill sequence (True) or the configured rotating
        one (False); a drive without the standstill test refuses a start after True
        (publication() reason "no_standstill")."""
        self.command(CMD_SELECT_STANDSTILL if standstill else CMD_SELECT_ROTATING)

    def set_speed_rpm(self, rpm):
        _check(self._lib.imfoc_set_speed_rpm(self._h, float(rpm)))

    def background(self):
        _check(self._lib.imfoc_background(self._h))

    def set_background_div(self, div):
        _check(self._lib.imfoc_set_background_div(self._h, int(div)))

    # one ISR ------------------------------------------------------------------
    def step_phys(self, ia_A, ib_A, vdc_V, theta_m_rad, trip=0):
        p = self._phys
        p.ia_A, p.ib_A, p.vdc_V, p.theta_m_rad, p.trip = ia_A, ib_A, vdc_V, theta_m_rad, trip
        out = _lib.Out()    # a new one each period: the plant may hold the last one
        _check(self._lib.imfoc_step_phys(self._h, C.byref(p), C.byref(out)))
        return out

    def step_raw(self, ia_raw, ib_raw, vdc_raw, qep_count, trip=0):
        r = self._raw
        r.ia_raw, r.ib_raw, r.vdc_raw, r.qep_count, r.trip = ia_raw, ib_raw, vdc_raw, qep_count, trip
        out = _lib.Out()
        _check(self._lib.imfoc_step_raw(self._h, C.byref(r), C.byref(out)))
        return out

    def phys_to_raw(self, ia_A, ib_A, vdc_V, theta_m_rad):
        p = _lib.PhysIn(ia_A, ib_A, vdc_V, theta_m_rad, 0)
        r = _lib.RawIn()
        _check(self._lib.imfoc_phys_to_raw(self._h, C.byref(p), C.byref(r)))
        return r

    def signals(self):
        """A fresh copy of the internal signals (imfoc_signals_t)."""
        s = _lib.Signals()
        _check(self._lib.imfoc_get_signals(self._h, C.byref(s)))
        return s

    def signals_dict(self):
        s = self.signals()
        d = {}
        for name, _t in s._fields_:
            v = getattr(s, name)
            d[name] = list(v) if name == "K" else v
        d["state_name"] = STATES[s.state] if s.state < len(STATES) else str(s.state)
        return d

    def parameters(self, live=False):
        """The published parameters (what the drive reports as identified, the
        telemetry's Rs..Tr; with [ident] track_rr = 1 the fused set), SI, as a dict;
        None while nothing is published (signals().params_valid 0: the telemetry's
        zeros are no estimate).  live=True: the running RLS's estimates instead
        (always a dict)."""
        s = self.signals()
        if not live and not s.params_valid:
            return None
        pre = "live_" if live else ""
        return {n: getattr(s, pre + n) for n in _lib.PARAM_NAMES}

    def last_extraction(self):
        """The RLS's last extraction (end of SETTLE, each pass) as extracted, SI, and
        whether it was plausible: ({name: value}, valid).  Not what the drive
        publishes: an implausible one is not published, and with tracking the
        published Rs, Rr, Tr come from elsewhere (parameters())."""
        s = self.signals()
        return {n: getattr(s, "extract_" + n) for n in _lib.PARAM_NAMES}, bool(s.extract_valid)

    def publication(self):
        """Why the last identification's set is or is not published, and how far each
        parameter can be trusted (ident_conf.h): {"reason": name ("pending",
        "published", "not_converged", "low_excitation", "high_residual",
        "low_confidence", "implausible", "fault", "timeout", "stopped", "bus_low",
        "rotor_turning", "torque_limit", "no_standstill"), "published":
        bool, "confidence_pct": {Rs_ohm: %, ...} (None where not available: the
        drive's negative figure, or 0, its "none yet": a figure is never exactly 0),
        "residual_rel", "amplification", "excitation"}."""
        s = self.signals()
        conf = {}
        for n, c in zip(_lib.PARAM_NAMES, _lib.CONF_NAMES):
            v = getattr(s, "conf_" + c)
            conf[n] = None if v <= 0 else 100.0 * v
        return {"reason": self._lib.imfoc_publish_reason_str(s.publish_reason).decode(),
                "published": s.publish_reason == PUB_PUBLISHED, "confidence_pct": conf,
                "residual_rel": s.conf_residual, "amplification": s.conf_amplification,
                "excitation": s.conf_excitation}


def rpm(w_m_rad_s):
    return w_m_rad_s * 60.0 / (2.0 * math.pi)
