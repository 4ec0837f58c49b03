"""The drive's serial protocol (firmware/telemetry.h), decoded on the PC.

Drive -> PC, NMEA style, one frame per line, 20 $T/$A pairs a second:

    $T,<seq>,<state>,<fault>,<pwm_on>,<valid>,<load>,<speed>,<speed_ref>,<i_m>,<i_t>,<vdc>,
       <Rs>,<Rr>,<Lm>,<Lr>,<psi_r>,<Tr>*<CK>\\r\\n
    $A,<seq>,<pass>,<track_valid>,<tracked>,<Rs_dc>,<sigma_ls_dc>,<Rr_track>,<Tr_track>*<CK>\\r\\n
    $S,<seq>,<overruns>,<load>,<dropped>,<rx_errors>*<CK>\\r\\n
    $Q,<seq>,<reason>,<c_Rs>,<c_Rr>,<c_Lm>,<c_Lr>,<c_psi_r>,<c_Tr>,<residual>,<amp>*<CK>\\r\\n

$Q is the publication's verdict (REASONS) and the confidence of each parameter of the
set judged, a fraction (0.01 = 1 %; negative: not available), then the regression's
relative residual and its amplification (include/ident_conf.h).

The first fields of each type are 4 hex digits (uint16), the rest 8 hex digits: a per-unit
value in Q24 two's complement (value = int32 / 2^24), except Tr and Tr_track in Q20
(value = int32 / 2^20: a large motor's Tr exceeds 128 pu).  CK: XOR of the characters between
'$' and '*', 2 hex digits.  PC -> drive: $C,<c>*<CK>\\r\\n with c = S start, X stop, R reset
a fault, D arm the data-log trigger.

FrameDecoder takes bytes in any chunks and returns the frames it completes; everything
else is counted, never raised: checksum errors, framing errors (garbage between frames,
a frame cut off by the next '$', a frame longer than the firmware ever sends, a frame
whose fields do not match its type) and frames of a type this decoder does not know (a
later firmware may add some: they are counted by type and skipped).
"""
from dataclasses import dataclass, field

# include/id_sequence.h id_state_t, in enum order (test_protocol checks it against the header)
STATES = ("IDLE", "CALIBRATE", "MAGNETIZE", "ACCELERATE", "SETTLE", "RUN", "FAULT", "REFINE",
          "INJECT")
# include/protect.h fault_code_t, in enum order (likewise)
FAULTS = ("none", "overcurrent", "bus_overvoltage", "bus_undervoltage", "encoder",
          "current_offset", "adc_rail", "hw_trip", "config", "current_sensor", "isr_overrun",
          "sensor_test", "stall", "vi_curve")

# include/drive.h drive_pub_reason_t, in enum order (likewise)
REASONS = ("pending", "published", "not_converged", "low_excitation", "high_residual",
           "low_confidence", "implausible", "fault", "timeout", "stopped", "bus_low",
           "rotor_turning", "torque_limit", "no_standstill")
CONF_FIELDS = ("conf_Rs", "conf_Rr", "conf_Lm", "conf_Lr", "conf_psi_r", "conf_Tr")

# field layout of each frame type: (uint16 fields, Q24 fields)
LAYOUT = {
    "T": (("seq", "state", "fault", "pwm_on", "valid", "load"),
          ("speed", "speed_ref", "i_m", "i_t", "vdc", "Rs", "Rr", "Lm", "Lr", "psi_r", "Tr")),
    "A": (("seq", "pass", "track_valid", "tracked"),
          ("Rs_dc", "sigma_ls_dc", "Rr_track", "Tr_track")),
    "S": (("seq", "isr_overruns", "load", "tx_dropped", "rx_errors"), ()),
    "Q": (("seq", "reason"), CONF_FIELDS + ("residual", "amplification")),
}
# the 32-bit fields in Q20 (Tr, pu time, up to 2048), every other one Q24
Q20_FIELDS = frozenset(("Tr", "Tr_track"))
# select-*: the sequence of the next starts (include/drive.h DRIVE_CMD_SELECT_*)
COMMANDS = {"start": "S", "stop": "X", "reset": "R", "dlog-arm": "D",
            "select-standstill": "Z", "select-rotating": "M"}
FRAME_MAX = 160        # firmware/telemetry.c TLM_FRAME_MAX: no frame is longer
LOAD_PERIOD_TICKS = 10000   # $T load: T1 ticks of one PWM period (2 T1PR at 15 kHz)


def state_name(code):
    return STATES[code] if 0 <= code < len(STATES) else f"state {code}"


def fault_name(code):
    return FAULTS[code] if 0 <= code < len(FAULTS) else f"fault {code}"


def reason_name(code):
    return REASONS[code] if 0 <= code < len(REASONS) else f"reason {code}"


def checksum(body):
    """XOR of the characters of `body` (the text between '$' and '*')."""
    ck = 0
    for ch in body.encode("ascii"):
        ck ^= ch
    return ck


def q24(word):
    """An 8-hex-digit field (0..2^32-1) as its per-unit value: int32 / 2^24."""
    if word >= 1 << 31:
        word -= 1 << 32
    return word / 16777216.0


def q20(word):
    """A Q20 8-hex-digit field (Tr) as its per-unit value: int32 / 2^20."""
    return q24(word) * 16.0


_HEX = frozenset("0123456789ABCDEFabcdef")


def _hex(text, digits):
    """Exactly `digits` hex digits (no sign, space, 0x or _ that int() would take)."""
    if len(text) != digits or not set(text) <= _HEX:
        raise ValueError(text)
    return int(text, 16)


def command_frame(name):
    """The bytes of a command: command_frame("start") == b"$C,S*3C\\r\\n"."""
    body = "C," + COMMANDS[name]
    return f"${body}*{checksum(body):02X}\r\n".encode("ascii")


@dataclass
class Frame:
    """One decoded frame: its type letter, the raw integers of its fields (uint16 or the
    32-bit Q24 word), and `pu`, the Q24 fields as per-unit floats."""
    type: str
    raw: dict
    pu: dict
    text: str

    def __getitem__(self, name):
        return self.raw[name]


@dataclass
class Counters:
    frames: int = 0                # decoded frames of a known type
    checksum_errors: int = 0
    framing_errors: int = 0        # the sum of the four below
    garbage: int = 0               # runs of bytes outside any frame
    partial: int = 0               # a frame cut off by the next '$'
    overlong: int = 0              # no line end within FRAME_MAX characters
    malformed: int = 0             # checksum right, fields wrong for the type
    unknown_types: dict = field(default_factory=dict)   # type -> count

    @property
    def unknown(self):
        return sum(self.unknown_types.values())

    def as_dict(self):
        return {"frames": self.frames, "checksum_errors": self.checksum_errors,
                "framing_errors": self.framing_errors, "garbage": self.garbage,
                "partial": self.partial, "overlong": self.overlong,
                "malformed": self.malformed, "unknown_types": dict(self.unknown_types)}


class FrameDecoder:
    """Bytes in, Frame objects out; bad input is counted in `counters`."""

    def __init__(self):
        self.counters = Counters()
        self._buf = bytearray()
        self._in_frame = False
        self._in_garbage = False

    def feed(self, data):
        out = []
        for b in bytes(data):
            if b == 0x24:                            # '$'
                if self._in_frame and self._buf:
                    self._framing("partial")
                self._buf = bytearray(b"$")
                self._in_frame, self._in_garbage = True, False
            elif not self._in_frame:
                if b in (0x0D, 0x0A):                # line ends between frames are normal
                    self._in_garbage = False
                elif not self._in_garbage:
                    self._framing("garbage")
                    self._in_garbage = True
            elif b in (0x0D, 0x0A):
                f = self._finish(bytes(self._buf))
                if f is not None:
                    out.append(f)
                self._in_frame = False
                self._buf = bytearray()
            else:
                self._buf.append(b)
                if len(self._buf) > FRAME_MAX:
                    self._framing("overlong")
                    self._in_frame, self._in_garbage = False, True   # skip to the next '$'
                    self._buf = bytearray()
        return out

    def _framing(self, kind):
        c = self.counters
        setattr(c, kind, getattr(c, kind) + 1)
        c.framing_errors += 1

    def _finish(self, raw):
        try:
            text = raw.decode("ascii")
        except UnicodeDecodeError:
            self._framing("malformed")
            return None
        star = text.rfind("*")
        if star < 2 or len(text) != star + 3:
            self._framing("malformed")
            return None
        body, ck_text = text[1:star], text[star + 1:]
        try:
            ck = _hex(ck_text, 2)
        except ValueError:
            self._framing("malformed")
            return None
        if checksum(body) != ck:
            self.counters.checksum_errors += 1
            return None
        parts = body.split(",")
        kind = parts[0]
        if kind not in LAYOUT:
            u = self.counters.unknown_types
            u[kind] = u.get(kind, 0) + 1
            return None
        names16, names32 = LAYOUT[kind]
        vals = parts[1:]
        if len(vals) != len(names16) + len(names32):
            self._framing("malformed")
            return None
        rawf, pu = {}, {}
        try:
            for n, v in zip(names16, vals):
                rawf[n] = _hex(v, 4)
            for n, v in zip(names32, vals[len(names16):]):
                rawf[n] = _hex(v, 8)
                pu[n] = q20(rawf[n]) if n in Q20_FIELDS else q24(rawf[n])
        except ValueError:
            self._framing("malformed")
            return None
        self.counters.frames += 1
        return Frame(kind, rawf, pu, text)
