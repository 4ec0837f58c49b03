"""How long the drive's CALIBRATE lasts, from the INI the firmware was built from.

The telemetry says which state the drive is in, not how far into it: CALIBRATE (the
offsets with the bridge off, the sensors' pulse test, then the bridge's voltage-error test
at standstill) shows nothing moving for 1.7 s on the paper motor and 15-20 s on the 15 and
37 kW ones.  Its length is fixed by the configuration, so the PC works it out instead of
the drive sending a progress field:

    offsets       0.07 s                          (drive_init.c: cal_samples)
    sensor test   ~5 ms                           (sensor_test.h: 2.4-4.4 ms)
    bridge test   (4 ceil(6 n) + 7 ceil(3 n) + 11 2^k) Ts_slow      (vi_curve.c:
                  vi_curve_init, vi_curve_samples), n = Tr / Ts_slow, the believed
                  Tr = (Lm + Llr) / Rr, Ts_slow = 8 / f_pwm (DRIVE_SLOTS), 2^k the
                  smallest power of two >= max(128, n), at most 1024

The bridge test runs only with [controller] dead_time_comp = 1 and [ident] vi_test = 1
(both the default).  A test the drive repeats with a wider current (drive_vi.c: once,
when the bridge's band swallowed the first levels) takes twice as long: the estimate is
what a first test takes, and the progress line says when it is passed.
"""
import math

from .bases import read_ini, read_ini_values

# name -> (section, key, default or None if required), as host_sim/sim/sim_config.c names
# them (motor_sim --keys)
CALIBRATE_KEYS = {
    "Rr_ohm": ("nameplate", "Rr_ohm", None),
    "Lm_H": ("nameplate", "Lm_H", None),
    "Llr_H": ("nameplate", "Llr_H", None),
    "pwm_freq_Hz": ("board", "pwm_freq_Hz", 15000),
    "dead_time_comp": ("controller", "dead_time_comp", 1),
    "vi_test": ("ident", "vi_test", 1),
}

OFFSETS_S = 0.07          # drive_init.c: ~70 ms of offset averaging
SENSOR_TEST_S = 0.005     # sensor_test.h: 3 (2N + Z) periods, 2.4-4.4 ms on the three motors
DRIVE_SLOTS = 8           # include/drive_types.h: the slow task runs every 8 PWM periods
VI_LEVELS = 10            # include/vi_curve.h VI_CURVE_LEVELS (and one rest)
VI_AVG_MIN_SHIFT, VI_AVG_MAX_SHIFT = 7, 10   # vi_curve.c: a window of 128 .. 1024 samples


def bridge_test_s(tr_s, pwm_freq_Hz):
    """The bridge's voltage-error test (vi_curve_samples) in seconds."""
    ts_slow = DRIVE_SLOTS / pwm_freq_Hz
    n = tr_s / ts_slow
    k = VI_AVG_MIN_SHIFT
    while k < VI_AVG_MAX_SHIFT and 2 ** k < n:
        k += 1
    samples = 4 * math.ceil(6.0 * n) + 7 * math.ceil(3.0 * n) + (VI_LEVELS + 1) * 2 ** k
    return samples * ts_slow


def calibrate_s(path):
    """The expected length of CALIBRATE for the firmware built from the INI at `path`
    (ConfigError if a key it needs is missing or not a number)."""
    v = read_ini_values(path, CALIBRATE_KEYS)
    t = OFFSETS_S + SENSOR_TEST_S
    if v["dead_time_comp"] and v["vi_test"] and v["Rr_ohm"] > 0 and v["pwm_freq_Hz"] > 0:
        t += bridge_test_s((v["Lm_H"] + v["Llr_H"]) / v["Rr_ohm"], v["pwm_freq_Hz"])
    return t


# the standstill sequence (include/drive_static.h, include/standstill_lf.h)
STANDSTILL_KEYS = {
    "Rr_ohm": ("nameplate", "Rr_ohm", None),
    "Lm_H": ("nameplate", "Lm_H", None),
    "Llr_H": ("nameplate", "Llr_H", None),
    "pwm_freq_Hz": ("board", "pwm_freq_Hz", 15000),
}
LF_W1_TR = 0.5            # standstill_lf.h STANDSTILL_LF_W1_TR
LF_LEAD_TR = 5.0          # STANDSTILL_LF_LEAD_TR
STATIC_WINDOW_S = 4.0     # drive_static.h DRIVE_STATIC_WINDOW_S


def standstill_s(path):
    """The standstill sequence's injection (standstill_lf_samples) in seconds."""
    v = read_ini_values(path, STANDSTILL_KEYS)
    if not (v["Rr_ohm"] > 0 and v["pwm_freq_Hz"] > 0):
        return 0.0
    tr = (v["Lm_H"] + v["Llr_H"]) / v["Rr_ohm"]
    ts_slow = DRIVE_SLOTS / v["pwm_freq_Hz"]
    per = math.floor(2.0 * math.pi * tr / (LF_W1_TR * ts_slow) + 0.5)
    periods = max(1, math.ceil(0.5 * STATIC_WINDOW_S / (per * ts_slow)))
    lead = math.ceil(LF_LEAD_TR * tr / ts_slow)
    return (lead + 2 * periods * per) * ts_slow


def configured_standstill(path):
    """True if the INI selects the standstill sequence ([ident] sequence = standstill, or
    the key it implies, static_id = 1); ConfigError if the file cannot be read."""
    cp = read_ini(path)
    seq = cp.get("ident", "sequence", fallback="").strip()
    return seq == "standstill" or cp.get("ident", "static_id", fallback="0").strip() in ("1", "1.0")
