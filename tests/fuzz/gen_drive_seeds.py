#!/usr/bin/env python3
"""Writes the seed corpus of fuzz_drive_step (tests/fuzz/corpus/drive_step).

Each seed is a byte 0 (configuration variant) and 8-byte records
[op][ia:2][ib:2][vdc:2][dq:1] (format in fuzz_drive_step.c).  The seeds take
the drive through every state of the identification sequence, so that the
fuzzer starts from deep states instead of finding the way there itself.
Run it again only when the format or the sequence changes:

    python3 tests/fuzz/gen_drive_seeds.py tests/fuzz/corpus/drive_step
"""
import os
import random
import struct
import sys

CMD_NONE, CMD_START, CMD_STOP, CMD_RESET = 0, 1, 2, 3
TRIP, ECHO = 4, 8
MID = 0x8000          # zero current: mid-scale of the Hall channel
VDC_60V = 0x9990      # 60 V of the 100 V full scale, 12 bits left-justified


def rec(cmd=CMD_NONE, log2n=0, ia=None, ib=None, vdc=VDC_60V, dq=0, flags=0):
    """One record; ia, ib default to zero current: the mid-scale word, or no
    perturbation in echo mode."""
    zero = 0 if flags & ECHO else MID
    ia = zero if ia is None else ia
    ib = zero if ib is None else ib
    return struct.pack("<BHHHb", cmd | flags | (log2n << 4), ia, ib, vdc, dq)


# start, then the 1050 calibration samples at zero current (echo from the end
# of the calibration on: the drive's references are zero until then)
CAL = rec(CMD_START, 0) + rec(log2n=10) + rec(log2n=5, flags=ECHO)


def identification(variant, perturb=0):
    """Calibrate (zero current), then with the currents following their
    references (echo): magnetise, accelerate to 6 counts/period, settle, run."""
    flags = ECHO
    p = perturb & 0xFFFF
    s = bytes([variant]) + CAL
    s += rec(log2n=11, ia=p, ib=p, flags=flags)       # 2048: the 0.1 s magnetisation
    for dq in range(1, 7):
        s += rec(log2n=8, ia=p, ib=p, dq=dq, flags=flags)   # 6 x 256: the 0.1 s ramp
    s += rec(log2n=13, ia=p, ib=p, dq=6, flags=flags)       # 8192: tail, settle, run, extraction
    s += rec(CMD_STOP, 10, ia=p, ib=p, dq=3, flags=flags)   # stop: ramp down, PWM off
    return s


def identification_adaptive(variant):
    """The adaptive sequence (variant bit 2): the 0.3 s magnetisation with
    the standstill test (4608 samples), the ramp, the first pass's settling,
    REFINE and the second pass, then RUN with the tracker."""
    flags = ECHO
    s = bytes([variant]) + CAL
    s += rec(log2n=12, flags=flags) + rec(log2n=9, flags=flags)
    for dq in range(1, 7):
        s += rec(log2n=8, dq=dq, flags=flags)
    s += rec(log2n=14, dq=6, flags=flags)
    s += rec(CMD_STOP, 10, dq=3, flags=flags)
    return s


LATCHED = 8           # byte 0 bit 3: commands wait for the 1 kHz background tick


def adaptive_stop_restart():
    """The adaptive sequence stopped in its first acceleration, restarted from
    IDLE (a new calibration, the standstill test again), then a phase-a
    overcurrent in the second run, a reset and a start."""
    flags = ECHO
    s = bytes([5]) + CAL
    s += rec(log2n=12, flags=flags) + rec(log2n=9, flags=flags)        # magnetise, standstill
    for dq in range(1, 4):
        s += rec(log2n=8, dq=dq, flags=flags)                          # half the ramp
    s += rec(CMD_STOP, 11, dq=2, flags=flags)                          # ramp down, IDLE
    s += rec(log2n=9)                                                  # bridge off, at rest
    s += CAL + rec(log2n=12, flags=flags) + rec(log2n=9, flags=flags)  # again
    s += rec(log2n=4, ia=0x7000, flags=flags)                          # overcurrent
    s += rec(CMD_RESET, 2) + rec(CMD_START, 10)
    return s


def latched(variant, body):
    """A seed whose commands wait for the background tick (byte 0 bit 3)."""
    return bytes([variant | LATCHED]) + body


def main(out):
    os.makedirs(out, exist_ok=True)
    seeds = {
        "ident_variant1": identification(1),
        "ident_variant2_offset": identification(2, perturb=-40),
        "ident_variant3": identification(3),
        "ident_adaptive": identification_adaptive(5),
        # board configuration: 0.3 s magnetisation, then an overcurrent in phase a
        "overcurrent_then_reset": bytes([0]) + CAL + rec(log2n=12, flags=ECHO)
        + rec(log2n=4, ia=0x7000, flags=ECHO) + rec(log2n=2) + rec(CMD_RESET, 4)
        + rec(CMD_START, 10),
        # PDPINTA while magnetising, then a reset with the line still active and released
        "hw_trip": bytes([1]) + CAL + rec(log2n=6, flags=TRIP | ECHO)
        + rec(CMD_RESET, 2, flags=TRIP) + rec(log2n=2) + rec(CMD_RESET, 2) + rec(CMD_START, 11),
        # bus collapse while running
        "undervoltage": identification(1)[:-8] + rec(log2n=5, vdc=0x1000, dq=6, flags=ECHO),
        # rails and a reversing encoder
        "rails_and_reversal": bytes([3]) + CAL + rec(log2n=11, flags=ECHO)
        + rec(log2n=9, dq=-6, flags=ECHO) + rec(log2n=3, ia=0, ib=0xFFFF, vdc=0xFFFF, dq=127),
    }
    # several commands in one background period (latched): single-period
    # records, so that consecutive commands meet before the next 1 kHz tick
    seeds["latched_trip_reset_start"] = latched(1, CAL + rec(log2n=6, flags=TRIP | ECHO)
                                                + rec(log2n=2) + rec(CMD_RESET, 0)
                                                + rec(CMD_START, 0) + rec(log2n=11, flags=ECHO))
    # (4 periods first: the background ran at period 0, the next tick is at 15,
    # so that the stop and the start of periods 4 and 5 meet there)
    seeds["latched_stop_start_idle"] = latched(1, rec(log2n=2) + rec(CMD_STOP, 0) + rec(CMD_START, 0)
                                               + rec(log2n=6) + rec(CMD_START, 0)
                                               + rec(log2n=10) + rec(log2n=11, flags=ECHO))
    seeds["latched_three_at_once"] = latched(5, CAL + rec(log2n=12, flags=ECHO)
                                             + rec(CMD_START, 0, flags=ECHO)
                                             + rec(CMD_RESET, 0, flags=ECHO)
                                             + rec(CMD_STOP, 0, flags=ECHO)
                                             + rec(log2n=10, flags=ECHO))
    seeds["adaptive_stop_restart"] = adaptive_stop_restart()
    rnd = random.Random(1)
    seeds["random"] = bytes(rnd.randrange(256) for _ in range(257))
    for name, data in seeds.items():
        with open(os.path.join(out, name + ".bin"), "wb") as f:
            f.write(data)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__),
                                                            "corpus", "drive_step"))
