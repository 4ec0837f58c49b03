#!/usr/bin/env python3
"""A family of realistic three-phase squirrel-cage induction motors, each with
an inverter, DC bus, sensors, load and controller keys scaled to its ratings,
written as motor_sim INI files.

    motors.py list [--ci | --grid] [--csv]          table of the family
    motors.py show NAME [--set SECTION.KEY=VALUE]... one motor, every key
    motors.py write DIR [--ci | --grid] [--layout split|current] [--set ...]
                                                     one INI per motor + index.csv
NAME: a motor of the family, or P_kW,poles,f_Hz,V,sigma for any other design()
(e.g. 37,8,50,690,0.08).  --set replaces or adds a key (e.g. board.dead_time_s=3e-6).

Importable: `design(P_kW, poles, f_Hz, V, sigma)`, `ci_subset()`, `grid()`,
`to_ini(motor, layout)`.

How a motor is made (every assumption is stated here; the sources are cited
where a published figure is used):

1. Rated efficiency: the minimum of its IE class, from the interpolation
   formula eta = A x^3 + B x^2 + C x + D, x = log10(P_N / 1 kW), of Commission
   Regulation (EU) 2019/1781, Annex I (the same coefficients as the UK's SI
   2021/745, Schedule 16, Tables 27 (0.12-0.55 kW) and 28 (0.75-200 kW),
   legislation.gov.uk).  The class is the regulation's minimum: IE2 below
   0.75 kW, IE3 from 0.75 kW (55 kW is the top of the family; IE4 applies
   from 75 kW).  The 50 Hz coefficients are used for 60 Hz motors too (the
   60 Hz NEMA-premium values are within about one point).
2. Loss split: the total loss P_N (1/eta - 1) is split as stator I^2R 37 %,
   rotor I^2R 22 %, core 17 %, friction and windage 10 %, stray load 14 %,
   the middle of the ranges usually quoted for standard motors (stator
   25-40 %, rotor 15-25 %, core 15-25 %, F&W 5-15 %, stray 10-20 %; e.g. the
   U.S. DOE's motor tip sheets).  The equivalent circuit carries only the
   copper losses; the rated slip follows from the rotor's share,
   s_N = P_Cu,r / P_airgap, P_airgap = P_N + P_F&W + P_stray + P_Cu,r (this
   gives 1443 r/min for 1.1 kW and 1472 r/min for 15 kW, 4-pole IE3: what
   IE3 catalogues list).
3. No-load current (= the magnetising current the drive uses, the brief's
   choice): I_0 / I_N = a(poles) - 0.14 log10(P_N / 1 kW), a = 0.50, 0.58,
   0.64, 0.70 for 2, 4, 6, 8 poles, limited to [0.22, 0.80].  This is an
   assumption shaped after the repair-shop rules of thumb (EASA, "No-load
   current basics", C. Yung, 2005: about one third of rated current, more
   for small motors and more poles) and checked against the project's two
   catalogue motors (1.1 kW 4-pole: 0.54, the law 0.57; 15 kW 4-pole: 0.37,
   the law 0.42) and against the power factors it implies (0.70..0.96 over
   the grid, `pf`; the 2-pole sigma = 0.05 corners, up to 0.96, are
   optimistic: kept as the hardest case for the identification).
4. Leakage: sigma is a family axis (0.05..0.15, the range users have), with
   Ls = Lr (Lls = Llr), so Lm = Ls sqrt(1 - sigma).
5. The circuit is solved at rated frequency so that (a) at no load and rated
   voltage the current is I_0: V = |Rs + j w Ls| I_0; (b) at the rated point
   (rotor-flux frame, flux Lm I_0) the torque is the air-gap torque
   1.5 p (1 - sigma) Ls I_0 i_T = P_airgap / w_sync; (c) I_0 / I_N is the
   ratio of 3.; (d) the stator copper loss at I_N is its share of 2.  These
   give I_0, i_T, Ls and Rs in closed form; Tr = (i_T / I_0) / (s_N w_e),
   Rr = Lr / Tr.  The power factor and the rated current follow (reported).
6. Inertia: J_motor = 2.0e-4 T_N^1.3 kg m^2 (T_N in N m), a fit by eye to
   catalogue ranges of 4-pole IE3 motors (90L 1.5 kW: ~0.003; 160L 15 kW:
   0.07-0.1; 250M 55 kW: 0.5-0.6 kg m^2); the load inertia equals the
   motor's (J = 2 J_motor).  Load: 10 % of T_N constant + 30 % of T_N at
   rated speed, quadratic (fan).
7. Inverter by voltage class (typical datasheet values, reasoned, not one
   source): up to 240 V: 600 V IGBTs, dead time 1.0 us, device drop 1.0 V;
   up to 480 V: 1200 V IGBTs, 2.0 us, 1.5 V; up to 690 V: 1700 V IGBTs,
   3.5 us, 2.0 V.  PWM 15 kHz (the F2812 firmware's ISR rate).  DC bus: the
   one a drive on the motor's own mains has, the peak of the line voltage
   behind a diode rectifier, sqrt(2) x V_line (230 V: 325 V, 400 V: 566 V,
   460 V: 651 V, 575 V: 813 V, 690 V: 976 V); no boost.  A motor wound for
   its line voltage then needs about all of the linear modulation's
   vdc / sqrt(3) at rated speed, more at rated load once the bridge's dead
   time and drops are paid (`vdc_need`, the bus the rated point would need
   in linear modulation, is reported): the drive identifies below the
   voltage limit (its target speed within the measured bus) and runs beyond
   it by over-modulation and field weakening, as real drives do.  Bus sensor
   full scale ~1.67 x vdc (rounded up to 50 V), trips at 1.25 x vdc
   (mains +10 % and regeneration) and 0.70 x vdc (mains -15 % with the
   ripple under load).
8. Current sensors: full scale = the smallest standard Hall size of at least
   2.5 x the rated peak current; noise 0.1 % of full scale rms; offsets
   +0.25 % and -0.15 % of full scale; gain residual 0.1 %; trip at 0.8 x full
   scale; the dead-time compensation's linear zone 3 ADC codes.  Encoder:
   2048 lines (1024 below 0.75 kW).
9. Controller keys as the project's INI files derive them: current loop
   400 - 100 log10(P/1 kW) Hz in [250, 500], speed loop 8 - 2 log10(P/1 kW)
   Hz in [4, 8], max torque current 1.2 x the rated torque current,
   magnetising current I_0 (peak), ramp rated speed per second (faster where
   that accelerates with less than 10 % of T_N: ACCEL_TORQUE_OF_T_N), magnetise
   max(0.3 s, 6 Tr), the RLS filter at 10 Hz with 10 Euler passes.

The firmware holds Tr in Q20 per unit (< 2048): drive_init refuses
Tr > 1000 / w_base (3.2 s at 50 Hz, 2.7 s at 60 Hz; IFO_TR_MAX_PU).  `fw_ok`
says whether the motor fits; every motor of the grid does (the largest, 55 kW
2-pole, Tr 0.93 s = 292 pu).  Before, Tr was Q24 (limit 120 pu, 0.38 s at
50 Hz), which refused 14 motors of the grid: the CI subset keeps below that.
"""
from __future__ import annotations

import argparse
import csv
import math
import sys
from dataclasses import asdict, dataclass, field
from pathlib import Path

SQRT2 = math.sqrt(2.0)
SQRT3 = math.sqrt(3.0)

# Commission Regulation (EU) 2019/1781, Annex I, interpolation coefficients
# (A, B, C, D) by IE class, power range and poles.
IE_COEF = {
    ("IE2", "small"): {2: (22.4864, 27.7603, 37.8091, 82.458), 4: (17.2751, 23.978, 35.5822, 84.9935),
                       6: (-15.9218, -30.258, 16.6861, 79.1838), 8: (6.4855, 9.4748, 36.852, 70.762)},
    ("IE3", "small"): {2: (6.8532, 6.2006, 25.1317, 84.0392), 4: (7.6356, 4.8236, 21.0903, 86.0998),
                       6: (-17.361, -44.538, -3.0554, 79.1318), 8: (-0.5896, -25.526, 4.2884, 75.831)},
    ("IE2", "large"): {2: (0.2972, -3.3454, 13.0651, 79.077), 4: (0.0278, -1.9247, 10.4395, 80.9761),
                       6: (0.0148, -2.4978, 13.247, 77.5603), 8: (2.1311, -12.029, 26.719, 69.735)},
    ("IE3", "large"): {2: (0.3569, -3.3076, 11.6108, 82.2503), 4: (0.0773, -1.8951, 9.2984, 83.7025),
                       6: (0.1252, -2.613, 11.9963, 80.4769), 8: (0.7189, -5.1678, 15.705, 77.074)},
}
LOSS_SPLIT = {"stator_cu": 0.37, "rotor_cu": 0.22, "core": 0.17, "fw": 0.10, "stray": 0.14}
I0_A = {2: 0.50, 4: 0.58, 6: 0.64, 8: 0.70}
HALL_SIZES = (5, 6, 10, 15, 20, 25, 32, 40, 50, 75, 100, 150, 200, 250, 300, 400, 500, 600)
PWM_HZ = 15000.0
# the bus trips per unit of the nominal bus (note 7)
VDC_MAX_OF_NOMINAL = 1.25
VDC_MIN_OF_NOMINAL = 0.70
SYSCLK_HZ = 150e6
# The bridge's dead-time linear zone is set by nobody: the simulated bridge's
# stays at motor_sim's default ([inverter] dead_time_band_A) and the drive
# measures the curve at standstill ([ident] vi_test, motor_sim's default 1).


# The identification ramp's accelerating torque, at least this fraction of T_N.
# Rated speed per second alone gives J alpha = 4e-4 T_N^1.3 (J = 2 J_motor,
# note 6) x alpha: 4-6 % of T_N on the 0.2 kW 4- to 8-pole motors, whose
# torque current in the ramp (0.1-0.2 A against i_M 0.6-0.9 A) then left the
# RLS's Lm, Lr still converging at the ramp's end (confidence 2.7-6.1 %,
# refused); with 10 %: published within 0.39 %, confidence <= 1.6 % (grid run, both builds).
ACCEL_TORQUE_OF_T_N = 0.1


def ramp_rpm_s(n_N, T_N, J):
    """The speed ramp: rated speed per second, or faster where that
    accelerates the rotor with less than ACCEL_TORQUE_OF_T_N of T_N."""
    return round(max(n_N, ACCEL_TORQUE_OF_T_N * T_N / J * 60.0 / (2.0 * math.pi)))


def ie_class(P_kW):
    return "IE2" if P_kW < 0.75 else "IE3"


def efficiency(P_kW, poles, cls=None):
    cls = cls or ie_class(P_kW)
    rng = "small" if P_kW < 0.75 else "large"
    A, B, C, D = IE_COEF[(cls, rng)][poles]
    x = math.log10(P_kW)
    return (A * x ** 3 + B * x ** 2 + C * x + D) / 100.0


def no_load_ratio(P_kW, poles):
    return min(0.80, max(0.22, I0_A[poles] - 0.14 * math.log10(P_kW)))


def voltage_class(V):
    """(dead time s, device drop V, device class)"""
    if V <= 240:
        return 1.0e-6, 1.0, "600 V IGBT"
    if V <= 480:
        return 2.0e-6, 1.5, "1200 V IGBT"
    return 3.5e-6, 2.0, "1700 V IGBT"


@dataclass
class Motor:
    name: str
    P_kW: float
    poles: int
    f_Hz: float
    V: float
    sigma: float
    ie: str
    eta: float
    # equivalent circuit (Ls = Lr)
    Rs: float
    Rr: float
    Lm: float
    Lls: float
    Llr: float
    # ratings
    I_N: float                   # A rms
    n_N: float                   # r/min
    slip: float
    pf: float
    T_N: float                   # shaft, N m
    i_m: float                   # magnetising current, A peak (= no-load)
    i_t_rated: float             # A peak
    # mechanics and load
    J: float
    B: float
    load_const: float
    load_fan: float
    # board and inverter
    vdc: float
    front_end: str
    vdc_need: float
    dead_time_s: float
    device_drop_V: float
    device: str
    vdc_fs: float
    hall_fs: float
    encoder_lines: int
    # controller and identification
    current_bw_Hz: float
    speed_bw_Hz: float
    max_torque_current: float
    overcurrent: float
    ramp_rpm_s: float
    magnetize_s: float
    target_rpm: float
    target_given: bool = False   # False: the INI says -1 (rated, lowered to what the bus gives)
    extra: dict = field(default_factory=dict)

    @property
    def p(self):
        return self.poles // 2

    @property
    def Ls(self):
        return self.Lm + self.Lls

    @property
    def Lr(self):
        return self.Lm + self.Llr

    @property
    def Tr(self):
        return self.Lr / self.Rr

    @property
    def wrTr(self):
        """rotor electrical speed x Tr at the target speed"""
        return self.target_rpm / 60.0 * 2.0 * math.pi * self.p * self.Tr

    @property
    def fw_ok(self):
        """within the firmware's design limit Tr <= 1000 / w_base (Tr in Q20)"""
        return self.Tr * 2.0 * math.pi * self.f_Hz <= 1000.0


def _name(P_kW, poles, f_Hz, V, sigma):
    p = f"{P_kW:g}".replace(".", "p")
    return f"m{p}kW_{poles}p_{f_Hz:g}Hz_{V:g}V_s{round(sigma * 1000):03d}"


def design(P_kW, poles, f_Hz, V, sigma, cls=None, name=None, Tr=None, target_rpm=None,
           i_m=None):
    """One motor and its drive.  Tr, i_m: override the derived rotor time
    constant (Rr) or magnetising current (for reconstructions of a named
    motor); target_rpm: the identification's target speed (default rated)."""
    if poles not in I0_A:
        raise ValueError("poles must be 2, 4, 6 or 8")
    p = poles // 2
    P = P_kW * 1e3
    cls = cls or ie_class(P_kW)
    eta = efficiency(P_kW, poles, cls)
    P_loss = P * (1.0 / eta - 1.0)
    P_cur = LOSS_SPLIT["rotor_cu"] * P_loss
    P_ag = P + (LOSS_SPLIT["fw"] + LOSS_SPLIT["stray"]) * P_loss + P_cur
    s = P_cur / P_ag
    w_e = 2.0 * math.pi * f_Hz
    w_sync_m = w_e / p
    T_e = P_ag / w_sync_m
    k0 = no_load_ratio(P_kW, poles)
    kt = math.sqrt(1.0 - k0 * k0)
    # (b),(c): Ls I0^2 = Cc; (d): Rs I_pk^2 = cs, I_pk = I0 / k0
    Cc = T_e * k0 / (1.5 * p * (1.0 - sigma) * kt)
    cs = LOSS_SPLIT["stator_cu"] * P_loss / 1.5
    V_ph = V * SQRT2 / SQRT3
    # (a): V_ph = |Rs + j w Ls| I0 = sqrt((cs k0^2)^2 + (w Cc)^2) / I0
    I0 = math.hypot(cs * k0 * k0, w_e * Cc) / V_ph
    if i_m is not None:
        I0 = i_m
    Ls = Cc / (I0 * I0)
    i_t = I0 * kt / k0
    I_pk = math.hypot(I0, i_t)
    Rs = cs / (I_pk * I_pk)
    Lm = Ls * math.sqrt(1.0 - sigma)
    Ll = Ls - Lm
    Tr_d = (i_t / I0) / (s * w_e)
    if Tr is not None:
        Tr_d = Tr
    Rr = Ls / Tr_d
    n_N = (1.0 - s) * 60.0 * f_Hz / p
    T_N = P / (n_N * 2.0 * math.pi / 60.0)
    I_N = I_pk / SQRT2
    pf = (P / eta) / (SQRT3 * V * I_N)
    tgt = n_N if target_rpm is None else target_rpm

    # the rated point's phase voltage (as motor_sim's cross-check computes it)
    w_r = 2.0 * math.pi * n_N / 60.0 * p
    ud = Rs * I0 - w_r * sigma * Ls * i_t
    uq = Rs * i_t + w_r * Ls * I0
    need = math.hypot(ud, uq)
    td, vd, dev = voltage_class(V)
    vdc_req = (need + 2.0 * vd) / (0.95 / SQRT3 - td * PWM_HZ)
    vdc, fe = round(SQRT2 * V, 1), "diode rectifier, sqrt(2) x V_line"
    vdc_fs = 50.0 * math.ceil(vdc * 5.0 / 3.0 / 50.0)
    hall = next(h for h in HALL_SIZES if h >= 2.5 * I_pk) if 2.5 * I_pk <= HALL_SIZES[-1] \
        else 100.0 * math.ceil(2.5 * I_pk / 100.0)

    J_m = 2.0e-4 * T_N ** 1.3
    lg = math.log10(P_kW)
    m = Motor(
        name=name or _name(P_kW, poles, f_Hz, V, sigma), P_kW=P_kW, poles=poles, f_Hz=f_Hz,
        V=V, sigma=sigma, ie=cls, eta=eta, Rs=Rs, Rr=Rr, Lm=Lm, Lls=Ll, Llr=Ll, I_N=I_N,
        n_N=n_N, slip=s, pf=pf, T_N=T_N, i_m=I0, i_t_rated=i_t,
        J=2.0 * J_m, B=0.002 * T_N / (n_N * 2.0 * math.pi / 60.0),
        load_const=0.1 * T_N, load_fan=0.3 * T_N,
        vdc=vdc, front_end=fe, vdc_need=vdc_req, dead_time_s=td, device_drop_V=vd, device=dev,
        vdc_fs=vdc_fs, hall_fs=float(hall), encoder_lines=2048 if P_kW >= 0.75 else 1024,
        current_bw_Hz=round(min(500.0, max(250.0, 400.0 - 100.0 * lg))),
        speed_bw_Hz=round(min(8.0, max(4.0, 8.0 - 2.0 * lg)), 1),
        max_torque_current=min(1.2 * i_t, 0.8 * hall * 0.95),
        overcurrent=0.8 * hall, ramp_rpm_s=ramp_rpm_s(n_N, T_N, 2.0 * J_m), magnetize_s=round(max(0.3, 6.0 * Tr_d), 2),
        target_rpm=tgt, target_given=target_rpm is not None)
    return m


# --------------------------------------------------------------------------
# the family
# --------------------------------------------------------------------------
# (f, V) pairs users have: 50 Hz 230/400/690 V (IEC), 60 Hz 230/460/575 V (NEMA)
SUPPLIES = ((50.0, 400.0), (60.0, 460.0), (50.0, 230.0), (60.0, 575.0), (50.0, 690.0),
            (60.0, 230.0))
GRID_POWERS = (0.2, 0.55, 1.5, 4.0, 11.0, 30.0, 55.0)
GRID_POLES = (2, 4, 6, 8)
GRID_SIGMAS = (0.05, 0.15)


def grid():
    """7 powers x 4 pole numbers x 2 leakage factors = 56 motors; the supply
    (f, V) cycles through SUPPLIES so that every size meets several."""
    out = []
    k = 0
    for P in GRID_POWERS:
        for poles in GRID_POLES:
            for sg in GRID_SIGMAS:
                f, V = SUPPLIES[k % len(SUPPLIES)]
                k += 1
                # small motors are not built for 690 V
                if P < 1.0 and V > 600:
                    V = 400.0
                out.append(design(P, poles, f, V, sg))
    return out


CI_SPEC = (
    # P kW, poles, f, V, sigma: spans size, poles, frequency, voltage, sigma and w_r Tr
    (0.25, 2, 50.0, 230.0, 0.12),
    (0.75, 4, 60.0, 230.0, 0.10),
    (2.2, 6, 50.0, 400.0, 0.08),
    (4.0, 2, 60.0, 460.0, 0.05),
    (7.5, 8, 50.0, 400.0, 0.15),
    (11.0, 4, 60.0, 575.0, 0.06),
    (11.0, 4, 50.0, 690.0, 0.05),
    (15.0, 6, 50.0, 400.0, 0.07),
)


def ci_subset():
    """8 motors that today's firmware accepts (fw_ok), from 0.25 to 15 kW,
    2..8 poles, 50/60 Hz, 230..690 V, sigma 0.05..0.15, w_r Tr ~15..110."""
    return [design(*s) for s in CI_SPEC]


def by_name(name):
    """A motor of the family by its name, or design(*spec) for "P_kW,poles,f_Hz,V,sigma"."""
    for m in ci_subset() + grid():
        if m.name == name:
            return m
    parts = name.split(",")
    if len(parts) == 5:
        try:
            P, poles, f, V, sg = (float(x) for x in parts)
        except ValueError:
            raise KeyError(name) from None
        return design(P, int(poles), f, V, sg)
    raise KeyError(name)


def parse_sets(items):
    """['section.key=value', ...] -> {(section, key): float or text}."""
    out = {}
    for it in items or ():
        left, sep, value = it.partition("=")
        sec, dot, key = left.strip().partition(".")
        if not sep or not dot or not sec or not key:
            raise SystemExit(f"motors.py: --set {it!r} is not SECTION.KEY=VALUE")
        try:
            out[(sec, key)] = float(value)
        except ValueError:
            out[(sec, key)] = value.strip()
    return out


# --------------------------------------------------------------------------
# INI writer
# --------------------------------------------------------------------------
def ini_values(m: Motor):
    """The logical keys and values of one motor's file (layout-neutral)."""
    noise = 0.001 * m.hall_fs
    return {
        # the motor (today: [motor]; split: [nameplate], the plant defaults to it)
        "Rs_ohm": m.Rs, "Rr_ohm": m.Rr, "Lm_H": m.Lm, "Lls_H": m.Lls, "Llr_H": m.Llr,
        "pole_pairs": m.p, "rated_power_W": m.P_kW * 1e3, "rated_voltage_V": m.V,
        "rated_current_A": m.I_N, "rated_speed_rpm": m.n_N, "rated_freq_Hz": m.f_Hz,
        "J_kgm2": m.J, "B_Nm_s": m.B,
        # load
        "const_Nm": m.load_const, "fan_Nm": m.load_fan,
        # inverter (the simulated bridge)
        # 0.5 % of the bus at rated power, within motor_sim's [0, 10] ohm
        "vdc_V": m.vdc, "source_resistance_ohm": min(0.005 * m.vdc ** 2 / (m.P_kW * 1e3), 10.0),
        "ripple_V": 0.005 * m.vdc, "ripple_Hz": 6.0 * m.f_Hz,
        "dead_time_s": m.dead_time_s, "device_drop_V": m.device_drop_V,
        # sensors (relative to their range)
        "hall_full_scale_A": m.hall_fs, "hall_gain_error_pct": 0.1,
        "hall_offset_a_A": 0.0025 * m.hall_fs, "hall_offset_b_A": -0.0015 * m.hall_fs,
        "hall_noise_A_rms": noise, "adc_noise_lsb": 0.5,
        "vdc_full_scale_V": m.vdc_fs, "encoder_lines": m.encoder_lines,
        # controller
        "current_bw_Hz": m.current_bw_Hz, "speed_bw_Hz": m.speed_bw_Hz, "inertia_kgm2": m.J,
        "max_torque_current_A": m.max_torque_current, "speed_ramp_rpm_s": m.ramp_rpm_s,
        "magnetizing_current_A": m.i_m, "overcurrent_A": m.overcurrent,
        "vdc_max_V": VDC_MAX_OF_NOMINAL * m.vdc, "vdc_min_V": VDC_MIN_OF_NOMINAL * m.vdc,
        # identification
        # the default: the rated speed, which the drive lowers to what its bus
        # carries (drive_target.h); a target given to design() is written
        "magnetize_s": m.magnetize_s,
        "target_speed_rpm": m.target_rpm if m.target_given else -1,
        # simulation
        "pwm_freq_Hz": PWM_HZ, "sysclk_Hz": SYSCLK_HZ,
    }


def key_map(layout="split"):
    """Where each logical key goes: {key: (section, name)}.  THE one place to
    change when the INI layout changes.

    'split': motor_sim's layout (drive side [nameplate] [board] [controller]
    [ident]; simulated world [plant] [inverter] [sensors] [load] [drift]
    [simulation]; `motor_sim --keys`, checked by test_key_map_matches_motor_sim).
    'current': the former single-consumer layout ([motor] [load] [inverter]
    [sensors] [controller] [ident] [simulation]); motor_sim refuses it, but
    tools/study/ideal_drive.py (case_from_ini) still reads it."""
    if layout == "current":
        sec = {}
        for k in ("Rs_ohm", "Rr_ohm", "Lm_H", "Lls_H", "Llr_H", "pole_pairs", "rated_power_W",
                  "rated_voltage_V", "rated_current_A", "rated_speed_rpm", "rated_freq_Hz",
                  "J_kgm2", "B_Nm_s"):
            sec[k] = "motor"
        for k in ("const_Nm", "fan_Nm"):
            sec[k] = "load"
        for k in ("vdc_V", "source_resistance_ohm", "ripple_V", "ripple_Hz", "dead_time_s",
                  "device_drop_V"):
            sec[k] = "inverter"
        for k in ("hall_full_scale_A", "hall_gain_error_pct", "hall_offset_a_A",
                  "hall_offset_b_A", "hall_noise_A_rms", "adc_noise_lsb", "vdc_full_scale_V",
                  "encoder_lines"):
            sec[k] = "sensors"
        for k in ("current_bw_Hz", "speed_bw_Hz", "inertia_kgm2", "max_torque_current_A",
                  "speed_ramp_rpm_s", "magnetizing_current_A", "overcurrent_A", "vdc_max_V",
                  "vdc_min_V"):
            sec[k] = "controller"
        for k in ("magnetize_s", "target_speed_rpm"):
            sec[k] = "ident"
        for k in ("pwm_freq_Hz", "sysclk_Hz"):
            sec[k] = "simulation"
        return {k: (s, k) for k, s in sec.items()}
    if layout == "split":
        m = {}
        for k in ("Rs_ohm", "Rr_ohm", "Lm_H", "Lls_H", "Llr_H", "pole_pairs", "rated_current_A",
                  "rated_speed_rpm", "rated_freq_Hz", "rated_voltage_V", "rated_power_W"):
            m[k] = ("nameplate", k)
        m.update({"J_kgm2": ("plant", "J_kgm2"), "B_Nm_s": ("plant", "B_Nm_s"),
                  "pwm_freq_Hz": ("board", "pwm_freq_Hz"), "sysclk_Hz": ("board", "sysclk_Hz"),
                  "dead_time_s": ("board", "dead_time_s"),
                  "device_drop_V": ("board", "device_drop_V"),
                  "vdc_V": ("board", "vdc_nominal_V"),
                  "vdc_full_scale_V": ("board", "vdc_full_scale_V"),
                  "hall_full_scale_A": ("board", "current_full_scale_A"),
                  "encoder_lines": ("board", "encoder_lines")})
        for k in ("source_resistance_ohm", "ripple_V", "ripple_Hz"):
            m[k] = ("inverter", k)
        for k in ("hall_gain_error_pct", "hall_offset_a_A", "hall_offset_b_A",
                  "hall_noise_A_rms", "adc_noise_lsb"):
            m[k] = ("sensors", k)
        for k in ("const_Nm", "fan_Nm"):
            m[k] = ("load", k)
        for k in ("current_bw_Hz", "speed_bw_Hz", "inertia_kgm2", "max_torque_current_A",
                  "speed_ramp_rpm_s", "magnetizing_current_A", "overcurrent_A", "vdc_max_V",
                  "vdc_min_V"):
            m[k] = ("controller", k)
        for k in ("magnetize_s", "target_speed_rpm"):
            m[k] = ("ident", k)
        return m
    raise ValueError(f"unknown layout {layout!r}")


SECTION_ORDER = {
    "current": ("motor", "load", "inverter", "sensors", "controller", "ident", "simulation"),
    "split": ("nameplate", "board", "controller", "ident", "plant", "inverter", "sensors", "load",
              "drift", "simulation"),
}


def _fmt(v):
    if isinstance(v, str):
        return v   # a name ([ident] sequence = standstill)
    if isinstance(v, int) or (isinstance(v, float) and v.is_integer() and abs(v) < 1e9):
        return str(int(v))
    return f"{v:.6g}"


# The ideal plant for motor_sim: no dead time, device drop, bus ripple or
# source resistance in the bridge, no sensor gain error, offset or noise
# (the 12-bit ADC's quantisation and the encoder's remain), and a drive that
# knows it (no dead-time feed-forward, no bridge test).  The overrides for
# to_ini's `extra`.
IDEAL_PLANT = {("inverter", "dead_time_s"): 0, ("inverter", "device_drop_V"): 0,
               ("inverter", "ripple_V"): 0, ("inverter", "source_resistance_ohm"): 0,
               ("sensors", "hall_gain_error_pct"): 0, ("sensors", "hall_offset_a_A"): 0,
               ("sensors", "hall_offset_b_A"): 0, ("sensors", "hall_noise_A_rms"): 0,
               ("sensors", "adc_noise_lsb"): 0, ("ident", "vi_test"): 0,
               ("board", "dead_time_s"): 0, ("board", "device_drop_V"): 0}
# The ideal bridge with the sensors' noise kept (no offsets or gain errors):
# the noise dithers the ADC's and the encoder's quantisation, so that what a
# regression's rows leave is seen as a mean over noise seeds, not as one
# deterministic realisation of the quantisation.
IDEAL_BRIDGE = {k: v for k, v in IDEAL_PLANT.items()
                if k not in (("sensors", "hall_noise_A_rms"), ("sensors", "adc_noise_lsb"))}


def to_ini(m: Motor, layout="split", extra=None):
    """The INI text of one motor.  extra: {(section, key): value} appended
    (e.g. an ideal plant for a study)."""
    vals = ini_values(m)
    km = key_map(layout)
    secs = {}
    for k, v in vals.items():
        s, name = km[k]
        secs.setdefault(s, []).append((name, v))
    for (s, name), v in (extra or {}).items():
        lst = secs.setdefault(s, [])
        lst[:] = [(n, x) for n, x in lst if n != name]
        lst.append((name, v))
    head = (f"; {m.name}: {m.P_kW:g} kW, {m.poles} poles, {m.f_Hz:g} Hz, {m.V:g} V, {m.ie} "
            f"(eta {100 * m.eta:.1f} %, pf {m.pf:.2f}), sigma {m.sigma:.3f}, Tr {m.Tr:.4f} s,\n"
            f"; w_r Tr {m.wrTr:.1f} at {m.target_rpm:.0f} r/min; bus {m.vdc:g} V ({m.front_end}), "
            f"{m.device}.\n; Generated by tools/family/motors.py (see its docstring for the "
            f"sources and assumptions).\n")
    order = SECTION_ORDER[layout]
    out = [head]
    for s in order + tuple(x for x in secs if x not in order):
        if s in secs:
            out.append(f"\n[{s}]\n")
            for name, v in secs[s]:
                out.append(f"{name} = {_fmt(v)}\n")
    return "".join(out)


COLUMNS = ("name", "P_kW", "poles", "f_Hz", "V", "sigma", "ie", "eta", "pf", "I_N", "n_N", "slip",
           "i_m", "Rs", "Rr", "Lm", "Lls", "Tr", "wrTr", "vdc", "hall_fs", "J", "fw_ok")


def row(m):
    d = asdict(m)
    d.update({"Tr": m.Tr, "wrTr": m.wrTr, "fw_ok": int(m.fw_ok)})
    return [d[c] for c in COLUMNS]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    for c in ("list", "write"):
        sp = sub.add_parser(c)
        if c == "write":
            sp.add_argument("dir")
            sp.add_argument("--layout", choices=("split", "current"), default="split")
            sp.add_argument("--set", action="append", metavar="SECTION.KEY=VALUE")
        g = sp.add_mutually_exclusive_group()
        g.add_argument("--ci", action="store_true", help="the CI subset (default)")
        g.add_argument("--grid", action="store_true", help="the whole family grid")
        if c == "list":
            sp.add_argument("--csv", action="store_true")
    sp = sub.add_parser("show")
    sp.add_argument("name")
    sp.add_argument("--layout", choices=("split", "current"), default="split")
    sp.add_argument("--set", action="append", metavar="SECTION.KEY=VALUE")
    a = ap.parse_args(argv)
    if a.cmd == "show":
        try:
            m = by_name(a.name)
        except KeyError:
            raise SystemExit(f"motors.py: no motor {a.name!r} (motors.py list, or "
                             "P_kW,poles,f_Hz,V,sigma)") from None
        print(to_ini(m, a.layout, extra=parse_sets(a.set)), end="")
        return 0
    motors = grid() if a.grid else ci_subset()
    if a.cmd == "list":
        if a.csv:
            w = csv.writer(sys.stdout)
            w.writerow(COLUMNS)
            for m in motors:
                w.writerow(row(m))
        else:
            print(f"{'name':34s} {'kW':>5s} {'p':>2s} {'Hz':>3s} {'V':>4s} {'sigma':>5s} {'IE':3s} "
                  f"{'eta':>5s} {'pf':>4s} {'I_N':>6s} {'n_N':>6s} {'i_M':>6s} {'Tr s':>6s} "
                  f"{'wrTr':>6s} {'vdc':>5s} {'Hall':>4s} fw")
            for m in motors:
                print(f"{m.name:34s} {m.P_kW:5g} {m.poles:2d} {m.f_Hz:3.0f} {m.V:4.0f} "
                      f"{m.sigma:5.3f} {m.ie:3s} {100 * m.eta:5.1f} {m.pf:4.2f} {m.I_N:6.2f} "
                      f"{m.n_N:6.0f} {m.i_m:6.2f} {m.Tr:6.3f} {m.wrTr:6.1f} {m.vdc:5.0f} "
                      f"{m.hall_fs:4.0f} {'ok' if m.fw_ok else 'Tr>max'}")
        return 0
    out = Path(a.dir)
    out.mkdir(parents=True, exist_ok=True)
    with open(out / "index.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(COLUMNS)
        for m in motors:
            (out / f"{m.name}.ini").write_text(to_ini(m, a.layout, extra=parse_sets(a.set)))
            w.writerow(row(m))
    print(f"wrote {len(motors)} INI files and index.csv to {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
