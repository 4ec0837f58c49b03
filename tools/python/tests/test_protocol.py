"""The PC side of the serial protocol (imfoc.protocol, imfoc.bases): frames decoded field
by field against values worked out by hand, and bad input counted, never raised."""
import math
import re
from pathlib import Path

import pytest

from imfoc import CONFIG_DIR, Drive, STATES, write_config
from imfoc.bases import Bases, ConfigError
from imfoc.protocol import FAULTS, REASONS, FrameDecoder, checksum, command_frame, q24
from imfoc.protocol import STATES as PROTO_STATES

ROOT = Path(__file__).resolve().parents[3]

# A $T frame as firmware/telemetry.c sent it (motor_sim --serial, paper motor, RUN with the
# published set) and the $A frame after it: checksums made by the firmware's C code.
# Tr (the last field) is Q20 on the wire: 0x00645A9A / 2^20 = 6.272 pu
T_FRAME = (b"$T,003A,0005,0000,0001,0001,0000,00EEEF7E,00EEEEEF,005335AB,0043765D,01BA3B61,"
           b"009880C3,00442375,012970D5,01AB5F75,00619942,00645A9A*07\r\n")
A_FRAME = b"$A,003B,0001,0000,0000,00000000,00000000,00000000,00000000*31\r\n"


def with_ck(body):
    """A frame with its checksum computed here by hand (XOR of the bytes of body)."""
    ck = 0
    for b in body.encode():
        ck ^= b
    return f"${body}*{ck:02X}\r\n".encode()


def test_command_frames():
    # 'C' ^ ',' = 0x43 ^ 0x2C = 0x6F; ^ 'S' (0x53) = 0x3C (README: $C,S*3C)
    assert command_frame("start") == b"$C,S*3C\r\n"
    assert command_frame("stop") == b"$C,X*37\r\n"       # 0x6F ^ 0x58
    assert command_frame("reset") == b"$C,R*3D\r\n"      # 0x6F ^ 0x52
    assert command_frame("dlog-arm") == b"$C,D*2B\r\n"   # 0x6F ^ 0x44
    assert checksum("C,S") == 0x3C


def test_q24_words():
    assert q24(0x01000000) == 1.0
    assert q24(0x00800000) == 0.5
    assert q24(0xFF800000) == -0.5               # two's complement
    assert q24(0x80000000) == -128.0             # the most negative word
    assert q24(0x7FFFFFFF) == 128.0 - 2.0 ** -24
    assert q24(0x00000001) == 2.0 ** -24


def test_firmware_frames_decode_field_by_field():
    d = FrameDecoder()
    t, a = d.feed(T_FRAME + A_FRAME)
    assert d.counters.frames == 2 and d.counters.checksum_errors == 0
    assert d.counters.framing_errors == 0
    assert t.type == "T" and a.type == "A"
    assert (t["seq"], t["state"], t["fault"], t["pwm_on"], t["valid"], t["load"]) == \
        (0x3A, 5, 0, 1, 1, 0)
    # 0x00EEEF7E = 15658878, 0x01BA3B61 = 28982113, 0x009880C3 = 9994435, 0x00645A9A = 6576794 (Q20)
    assert t.pu["speed"] == 15658878 / 2 ** 24
    assert t.pu["vdc"] == 28982113 / 2 ** 24
    assert t.pu["Rs"] == 9994435 / 2 ** 24
    assert t.pu["Tr"] == 6576794 / 2 ** 20
    assert (a["seq"], a["pass"], a["track_valid"], a["tracked"]) == (0x3B, 1, 0, 0)
    assert a.pu["Rs_dc"] == 0.0
    # SI with the paper motor's bases: Z = (60 V / sqrt 3) / 20 A, n = 60 * 50 / 2 r/min,
    # t_base = 1 / (2 pi 50 Hz)
    b = Bases.from_ini(CONFIG_DIR / "paper_motor.ini")
    assert b.si("Rs", t.pu["Rs"])[1] == pytest.approx(9994435 / 2 ** 24 * 60 / math.sqrt(3) / 20,
                                                      rel=1e-12)
    assert b.si("speed", t.pu["speed"]) == ("speed_rpm", pytest.approx(15658878 / 2 ** 24 * 1500))
    assert b.si("Tr", t.pu["Tr"])[1] == pytest.approx(6576794 / 2 ** 20 / (100 * math.pi))
    assert b.si("vdc", t.pu["vdc"])[1] == pytest.approx(28982113 / 2 ** 24 * 60 / math.sqrt(3))   # 59.84 V


def test_byte_by_byte_gives_the_same_frames():
    whole = FrameDecoder().feed(T_FRAME + A_FRAME)
    d = FrameDecoder()
    one = [f for b in T_FRAME + A_FRAME for f in d.feed(bytes([b]))]
    assert [f.raw for f in one] == [f.raw for f in whole]


def test_checksum_error_is_counted_and_the_stream_goes_on():
    bad = T_FRAME.replace(b"009880C3", b"009880C4")
    d = FrameDecoder()
    frames = d.feed(bad + A_FRAME)
    assert [f.type for f in frames] == ["A"]
    assert d.counters.checksum_errors == 1 and d.counters.framing_errors == 0


def test_garbage_between_frames():
    d = FrameDecoder()
    frames = d.feed(b"\x00\xff\x13noise" + T_FRAME + b"\r\n\r\n" + b"\x80\x81" + A_FRAME)
    assert [f.type for f in frames] == ["T", "A"]
    assert d.counters.garbage == 2               # two runs of garbage; the blank lines are fine
    assert d.counters.framing_errors == 2


def test_partial_frame_cut_by_the_next_one():
    d = FrameDecoder()
    frames = d.feed(T_FRAME[:50] + T_FRAME)
    assert len(frames) == 1 and frames[0]["seq"] == 0x3A
    assert d.counters.partial == 1 and d.counters.framing_errors == 1
    # a frame cut at the end of one read is completed by the next read, not an error
    d = FrameDecoder()
    assert d.feed(T_FRAME[:70]) == []
    assert len(d.feed(T_FRAME[70:])) == 1 and d.counters.framing_errors == 0


def test_overlong_frame_is_dropped():
    d = FrameDecoder()
    frames = d.feed(b"$T," + b"0" * 400 + b"\r\n" + A_FRAME)
    assert [f.type for f in frames] == ["A"]
    assert d.counters.overlong == 1 and d.counters.garbage == 0


def test_unknown_frame_types_are_counted_not_fatal():
    d = FrameDecoder()
    frames = d.feed(with_ck("Z,0001,DEADBEEF") + T_FRAME + with_ck("Z,0002") +
                    with_ck("XY,1") + A_FRAME)
    assert [f.type for f in frames] == ["T", "A"]
    assert d.counters.unknown_types == {"Z": 2, "XY": 1}
    assert d.counters.framing_errors == 0 and d.counters.checksum_errors == 0


def test_malformed_frames():
    d = FrameDecoder()
    for body in ("T,0001",                                    # too few fields
                 "A,0041,0001,0000,0000,0,0,0,0",             # Q24 fields not 8 digits
                 "A,0041,+001,0000,0000,00000000,00000000,00000000,00000000",   # a sign
                 "A,0x41,0001,0000,0000,00000000,00000000,00000000,00000000"):  # 0x
        assert d.feed(with_ck(body)) == []
    assert d.feed(b"$T,0001*Z1\r\n" + b"$T\r\n" + b"$\xe9\xe9*00\r\n") == []
    assert d.counters.malformed == 7 and d.counters.frames == 0
    assert d.counters.checksum_errors == 0


def _enum(header, prefix):
    text = (ROOT / "include" / header).read_text()
    body = re.search(r"typedef enum \{(.*?)\}", text, re.S).group(1)
    body = re.sub(r"/\*.*?\*/", "", body, flags=re.S)
    names = [n.strip().split("=")[0].strip() for n in body.split(",") if n.strip()]
    return [n[len(prefix):] for n in names]


def _enum_named(header, name, prefix):
    """The members of `typedef enum {...} name;` of the header, without the prefix."""
    text = (ROOT / "include" / header).read_text()
    body = re.search(r"typedef enum \{([^}]*)\}\s*" + name + r"\s*;", text, re.S).group(1)
    body = re.sub(r"/\*.*?\*/", "", body, flags=re.S)
    names = [n.strip().split("=")[0].strip() for n in body.split(",") if n.strip()]
    return [n[len(prefix):] for n in names]


def test_state_and_fault_names_follow_the_headers():
    assert list(PROTO_STATES) == _enum("id_sequence.h", "ID_")
    assert list(STATES) == _enum("id_sequence.h", "ID_")       # the co-simulation's too
    assert STATES[7] == "REFINE"
    assert list(FAULTS) == [n.lower() for n in _enum("protect.h", "FAULT_")]
    # the publication's reasons, up to the count DRIVE_PUB_N
    reasons = [n.lower() for n in _enum_named("drive.h", "drive_pub_reason_t", "DRIVE_PUB_")]
    assert reasons[-1] == "n" and list(REASONS) == reasons[:-1]


def test_quality_frame_decodes_field_by_field():
    """$Q (firmware/telemetry.h): the reason, six confidences (a negative one: not
    available), the residual and the amplification, Q24; values worked out by hand."""
    body = ("Q,0012,0005,FF000000,00080000,0000A3D7,00000000,0000A3D7,00400000,"
            "00004000,28000000")
    (q,) = FrameDecoder().feed(with_ck(body))
    assert q.type == "Q" and (q["seq"], q["reason"]) == (0x12, 5)
    assert REASONS[q["reason"]] == "low_confidence"
    assert q.pu["conf_Rs"] == -1.0                       # not available
    assert q.pu["conf_Rr"] == 0.03125                     # 0x80000 / 2^24
    assert q.pu["conf_Lm"] == 0xA3D7 / 2 ** 24            # 0.25 %: 41943 / 2^24 = 0.0025
    assert q.pu["conf_Tr"] == 0.25
    assert q.pu["residual"] == 2.0 ** -10
    assert q.pu["amplification"] == 40.0


def test_bases_agree_with_the_firmware():
    """The INI key table gives the bases drive_init computes (base_values.c, in float)."""
    for ini in ("paper_motor.ini", "motor_1kw.ini", "motor_15kw.ini"):
        b = Bases.from_ini(CONFIG_DIR / ini)
        with Drive(CONFIG_DIR / ini) as d:
            i = d.info
            for name in ("I_base_A", "V_base_V", "f_base_Hz", "Z_base_ohm", "L_base_H",
                         "psi_base_Wb", "t_base_s", "n_base_rpm"):
                assert getattr(b, name) == pytest.approx(getattr(i, name), rel=1e-6), (ini, name)


def test_bases_config_errors_name_the_key(tmp_path):
    bad = write_config(CONFIG_DIR / "paper_motor.ini", {"board": {"vdc_nominal_V": "sixty"}},
                       tmp_path / "bad.ini")
    with pytest.raises(ConfigError, match=r"\[board\] vdc_nominal_V is not a number"):
        Bases.from_ini(bad)
    text = (CONFIG_DIR / "paper_motor.ini").read_text().replace("current_full_scale_A", "x_A")
    (tmp_path / "missing.ini").write_text(text)
    with pytest.raises(ConfigError, match=r"missing \[board\] current_full_scale_A"):
        Bases.from_ini(tmp_path / "missing.ini")
    with pytest.raises(ConfigError, match="cannot read"):
        Bases.from_ini(tmp_path / "none.ini")
