#!/usr/bin/env python3
"""Double-precision model of the drive on an ideal plant, for the regression-bias
study (tools/study/regression_bias.py).  Nothing here runs in the firmware.

What it simulates, vectorised over many cases at once (numpy arrays of shape (C,)):

* the plant: the fifth-order induction-motor model (stator and rotor flux
  vectors in the stationary frame, mechanical speed, angle) integrated by RK4
  with `substeps` steps per PWM period; load = const + fan (quadratic in speed);
* an ideal averaged inverter: the stator-frame voltage the controller asked
  for is applied exactly, constant over the whole PWM period;
* ideal sensors: the phase currents sampled at the period start (the F2812's
  T1 underflow), the exact rotor angle;
* the firmware's control path (src/app/drive_step.c), in double precision:
  speed = 16-sample window of the angle + 100 Hz low-pass (qep_speed.c), the
  one-period speed speed_1 for the regression; ramp + speed PI (drive_init.c:
  Kp = w_sc/gain, Ti = 4/w_sc); d/q current PIs with the zero on the stator pole
  and decoupling feed-forward with ifo's w_s; indirect field orientation with
  the TRUE Tr (ifo.c: i_mr by exact ZOH, slip = i_T/(Tr i_mr), frame angle =
  rotor angle + integrated slip); the voltage of ISR k applied over period
  k+1, rotated at the middle of that period (theta_k + 1.5 w_s Ts); the
  identification sequence (id_sequence.c: magnetise, accelerate with the RLS
  on, rls_tail_s beyond the end of the ramp);
* the regression signals exactly as ident_regressor.c and identify() form
  them: current at the period start (Park at theta_k), the voltage of the
  period that just ended rotated at the frame angle of its middle, w_s from the
  frame's actual angle step, w_r over the period, the products w_s i_T and
  w_s i_M filtered as signals, every signal through the same 2nd-order
  Butterworth solved by improved Euler with N corrector passes (bw_filter.c,
  the exact 2x2 map);
* oracle quantities from the plant for the diagnosis: the period means (in the
  rotating frame) of the stator current and of the rotor flux, from moments
  integral x(t) tau^n dt (n = 0..3) integrated with the plant, and the exact
  period-mean voltage in the frame (sinc).

Instead of storing the rows, each named "group" of filtered regression columns
is accumulated as a Gram matrix G = sum over the RLS rows (both rows of every
sample) of x x^T, so that any least-squares fit over those columns (and the
projection of any residual column on the regressors) is solved afterwards
(regression_bias.py).  Units: SI throughout (A, V, rad/s, s).
"""
from __future__ import annotations

import configparser
import math
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

SQRT2 = math.sqrt(2.0)
TWO_PI = 2.0 * math.pi


# --------------------------------------------------------------------------
# cases
# --------------------------------------------------------------------------
@dataclass
class Case:
    """One motor with its drive settings and one set of operating choices."""
    name: str
    Rs: float
    Rr: float
    Lm: float
    Lls: float
    Llr: float
    p: int                       # pole pairs
    J: float                     # plant inertia, kg m^2
    B: float
    rated_speed_rpm: float
    rated_freq_Hz: float
    rated_current_A: float       # rms
    vdc: float
    hall_fs_A: float
    current_bw_Hz: float
    speed_bw_Hz: float
    inertia_ctl: float
    max_torque_current_A: float
    ramp_rpm_s: float
    i_m: float                   # magnetising current reference, A peak
    magnetize_s: float
    target_rpm: float
    rls_tail_s: float = 0.3
    rated_power_W: float = 0.0
    load_const: float = 0.0
    load_fan: float = 0.0        # N m at rated speed
    filter_Hz: float = 10.0
    euler_passes: int = 10
    speed_filter_Hz: float = 100.0
    # learning window (proposal): RLS rows only while the speed reference is
    # inside [learn_lo, learn_hi] electrical rad/s (0, inf: the paper's)
    learn_lo: float = 0.0
    learn_hi: float = float("inf")
    # speed profile: 'ramp' (the paper's), or 'ramp2' (two ramp rates: the
    # first half of the speed range at ramp_rpm_s, the second at ramp2_rpm_s)
    profile: str = "ramp"
    ramp2_rpm_s: float = 0.0
    extra: dict = field(default_factory=dict)

    # derived
    @property
    def Ls(self):
        return self.Lm + self.Lls

    @property
    def Lr(self):
        return self.Lm + self.Llr

    @property
    def sigma(self):
        return 1.0 - self.Lm ** 2 / (self.Ls * self.Lr)

    @property
    def Tr(self):
        return self.Lr / self.Rr

    @property
    def T_N(self):
        """rated shaft torque, N m"""
        return self.rated_power_W / (self.rated_speed_rpm * TWO_PI / 60.0)

    @property
    def w_target(self):
        """electrical rad/s at the target speed"""
        return self.target_rpm * TWO_PI / 60.0 * self.p

    def true_params(self, i_m=None):
        i_m = self.i_m if i_m is None else i_m
        return {"Rs": self.Rs, "Rr": self.Rr, "Lm": self.Lm, "Lr": self.Lr,
                "psi_r": self.Lm * i_m, "Tr": self.Tr}

    def true_K(self, psi0):
        """method §2 (constant third regressor, eq. 7) with psi_r = psi0."""
        sls = self.sigma * self.Ls
        K1 = -(self.Rs / sls + self.Rr * self.Lm ** 2 / (sls * self.Lr ** 2))
        K2 = 1.0 / sls
        K3 = self.Lm * self.Rr * psi0 / (sls * self.Lr ** 2)
        K4 = -self.Lm * psi0 / (sls * self.Lr)
        return np.array([K1, K2, K3, K4])


def _ini_float(cp, sec, key, default=None):
    if cp.has_option(sec, key):
        return float(cp.get(sec, key).split(";")[0])
    if default is None:
        raise KeyError(f"{sec}.{key}")
    return default


def _from_split_layout(cp):
    """The drive/plant split of today's files ([nameplate], [board], [plant])
    read as the layout below: the nameplate's motor with the plant's J and B,
    the board's bus and current range."""
    if not cp.has_section("nameplate"):
        return
    cp.add_section("motor")
    for k, v in cp.items("nameplate"):
        cp.set("motor", k, v)
    for k in ("J_kgm2", "B_Nm_s"):
        if cp.has_option("plant", k):
            cp.set("motor", k, cp.get("plant", k))
    for sec, key, src in (("inverter", "vdc_V", "vdc_nominal_V"),
                          ("sensors", "hall_full_scale_A", "current_full_scale_A")):
        if not cp.has_section(sec):
            cp.add_section(sec)
        if not cp.has_option(sec, key):
            cp.set(sec, key, cp.get("board", src))


def case_from_ini(path, name=None, text=None, **over):
    """A Case from a motor_sim INI file ([motor], [load], [inverter], [sensors],
    [controller], [ident]; or the split layout, [nameplate] [board] [plant]),
    or from its text."""
    cp = configparser.ConfigParser(inline_comment_prefixes=(";",))
    if text is not None:
        cp.read_string(text)
    else:
        cp.read(path)
    _from_split_layout(cp)
    m = "motor"
    rated_rpm = _ini_float(cp, m, "rated_speed_rpm")
    tgt = _ini_float(cp, "ident", "target_speed_rpm", -1.0)
    c = Case(
        name=name or Path(path).stem,
        rated_power_W=_ini_float(cp, m, "rated_power_W"),
        Rs=_ini_float(cp, m, "Rs_ohm"), Rr=_ini_float(cp, m, "Rr_ohm"),
        Lm=_ini_float(cp, m, "Lm_H"), Lls=_ini_float(cp, m, "Lls_H"),
        Llr=_ini_float(cp, m, "Llr_H"), p=int(_ini_float(cp, m, "pole_pairs")),
        J=_ini_float(cp, m, "J_kgm2"), B=_ini_float(cp, m, "B_Nm_s", 0.0),
        rated_speed_rpm=rated_rpm, rated_freq_Hz=_ini_float(cp, m, "rated_freq_Hz"),
        rated_current_A=_ini_float(cp, m, "rated_current_A"),
        vdc=_ini_float(cp, "inverter", "vdc_V"),
        hall_fs_A=_ini_float(cp, "sensors", "hall_full_scale_A"),
        current_bw_Hz=_ini_float(cp, "controller", "current_bw_Hz"),
        speed_bw_Hz=_ini_float(cp, "controller", "speed_bw_Hz"),
        inertia_ctl=_ini_float(cp, "controller", "inertia_kgm2"),
        max_torque_current_A=_ini_float(cp, "controller", "max_torque_current_A"),
        ramp_rpm_s=_ini_float(cp, "controller", "speed_ramp_rpm_s"),
        i_m=_ini_float(cp, "controller", "magnetizing_current_A"),
        magnetize_s=_ini_float(cp, "ident", "magnetize_s", 0.3),
        target_rpm=rated_rpm if tgt < 0 else tgt,
        rls_tail_s=_ini_float(cp, "ident", "rls_tail_s", 0.3),
        load_const=_ini_float(cp, "load", "const_Nm", 0.0),
        load_fan=_ini_float(cp, "load", "fan_Nm", 0.0),
        filter_Hz=_ini_float(cp, "ident", "filter_cutoff_Hz", 10.0),
        euler_passes=int(_ini_float(cp, "ident", "euler_passes", 10)),
        speed_filter_Hz=_ini_float(cp, "controller", "speed_filter_Hz", 100.0),
    )
    return replace(c, **over)


# --------------------------------------------------------------------------
# Butterworth by improved Euler (bw_filter.c, method §5), double precision
# --------------------------------------------------------------------------
def bw_map(wc, Ts, n_pass):
    """D (2x2) of one step: [x1; z2] += D [x1 - u; z2]; dy = wc z2."""
    a = wc * Ts
    Fn = np.array([[0.0, 1.0], [-1.0, -SQRT2]])
    M = 0.5 * a * Fn
    P = np.eye(2)
    for _ in range(n_pass):
        P = np.eye(2) + M @ P
    return P @ (a * Fn)


class FilterBank:
    """S signals x C cases, each through its case's filter."""

    def __init__(self, names, wc, Ts, n_pass):
        self.names = list(names)
        self.idx = {n: i for i, n in enumerate(self.names)}
        S, C = len(self.names), len(wc)
        D = np.stack([bw_map(w, Ts, int(n)) for w, n in zip(wc, n_pass)], axis=-1)  # 2,2,C
        self.D = D
        self.wc = np.asarray(wc, float)
        self.x1 = np.zeros((S, C))
        self.z2 = np.zeros((S, C))

    def step(self, u):
        d = self.x1 - u
        z = self.z2
        self.x1 = self.x1 + self.D[0, 0] * d + self.D[0, 1] * z
        self.z2 = z + self.D[1, 0] * d + self.D[1, 1] * z

    def y(self, name):
        return self.x1[self.idx[name]]

    def dy(self, name):
        return self.wc * self.z2[self.idx[name]]


# --------------------------------------------------------------------------
# the closed loop
# --------------------------------------------------------------------------
@dataclass
class Options:
    pwm_Hz: float = 15000.0
    substeps: int = 4
    # control-side variant: 'firmware' (PI and ifo on the sampled current),
    # 'mean_oracle' (on the true period-mean current, from the plant),
    # 'offset_est' (on the sample + K2n j w_s u Ts^2/12, the estimated
    # sample-to-mean offset of the period's ripple, K2n = k2_scale / sigma Ls)
    control: str = "firmware"
    k2_scale: float = 1.0
    # multi-rate identification: N ISR periods per filter/RLS step
    rate_div: int = 1
    rate_mode: str = "avg"       # 'avg': N-sample mean, filters at N Ts; 'decim': filters at Ts, RLS every N-th
    record_hz: float = 1000.0
    # start from the magnetised steady state (flux Lm i_M on the M axis, loops
    # settled) and accelerate after `premag_s`: the same as an infinitely long
    # magnetisation, without simulating 5..8 Tr of it
    premag: bool = False
    premag_s: float = 0.05
    # double-precision RLS in the loop (method §3, P0 = rls_p0 I in the
    # columns scaled by the nominal K, no forgetting): 'fw' the firmware's
    # regression, 'prop' the proposal with K2 = the RLS's previous estimate
    rls: tuple = ()
    rls_p0: float = 1e4
    # errors of the voltage the identification sees (not of the plant's):
    # a relative gain error (e.g. the bus reading), and a residue of the
    # dead-time compensation along the current (V)
    u_gain_err: float = 0.0
    u_dt_V: float = 0.0
    t_max: float | None = None   # default: end of the last case's RLS window + 0.05 s
    enc_lines: int = 0           # 0: the exact rotor angle; else an encoder of this many lines
    enc_offset: float = 0.5      # its edge grid's offset, fraction of a pitch (motor_sim's 0.5)


class Recorder:
    def __init__(self):
        self.t = []
        self.data = {}

    def add(self, t, **kw):
        self.t.append(t)
        for k, v in kw.items():
            self.data.setdefault(k, []).append(np.array(v, copy=True))

    def arrays(self):
        out = {k: np.array(v) for k, v in self.data.items()}
        out["t"] = np.array(self.t)
        return out


def simulate(cases, opt: Options = Options(), groups=None):
    """Run all cases in one vectorised closed loop.

    groups: {name: fn(sig) -> (X1, X2)}; sig is a dict of per-step quantities
    (filtered and raw, see below); fn returns the columns of row 1 and row 2,
    each an array (C, ncol), whose Gram matrix is accumulated over the RLS
    rows.  Returns a dict with the Gram matrices, end-of-window values and a
    decimated record.
    """
    C = len(cases)
    Ts = 1.0 / opt.pwm_Hz
    h = Ts / opt.substeps
    A = lambda attr: np.array([getattr(c, attr) for c in cases], dtype=float)  # noqa: E731
    Rs, Rr, Lm = A("Rs"), A("Rr"), A("Lm")
    Ls, Lr = Lm + A("Lls"), Lm + A("Llr")
    Dm = Ls * Lr - Lm * Lm
    sls = Ls - Lm * Lm / Lr
    Tr = Lr / Rr
    p = A("p")
    J, Bf = A("J"), A("B")
    w_rated_m = A("rated_speed_rpm") * TWO_PI / 60.0
    lconst, lfan = A("load_const"), A("load_fan")
    im_ref = A("i_m")
    vbase = A("vdc") / math.sqrt(3.0)

    # current loops (drive_init.c): Kp = w_c sigma Ls, Ki = Kp Ts Rs / sigma Ls
    wc_i = TWO_PI * A("current_bw_Hz")
    kp_i = wc_i * sls
    ki_i = kp_i * Ts * Rs / sls
    # speed loop: gain = p Kt / J (electrical rad/s per s per A)
    kt = 1.5 * p * Lm * Lm / Lr * im_ref
    gain = p * kt / A("inertia_ctl")
    wsc = TWO_PI * A("speed_bw_Hz")
    kp_w = wsc / gain
    ki_w = kp_w * Ts * wsc / 4.0
    i_max = A("max_torque_current_A")
    ramp_rate = A("ramp_rpm_s") * TWO_PI / 60.0 * p          # electrical rad/s per s
    ramp2 = np.array([c.ramp2_rpm_s if c.profile == "ramp2" else c.ramp_rpm_s for c in cases]) \
        * TWO_PI / 60.0 * p
    w_tgt = np.array([c.w_target for c in cases])
    learn_lo, learn_hi = A("learn_lo"), A("learn_hi")
    kf_spd = 1.0 - np.exp(-TWO_PI * A("speed_filter_Hz") * Ts)
    # ifo
    kf_tr = 1.0 - np.exp(-Ts / Tr)
    imr_min = 0.2 * im_ref
    k2n = opt.k2_scale / sls

    # sequence timing
    t_mag = np.full(C, opt.premag_s) if opt.premag else A("magnetize_s")
    t_ramp = np.where(
        np.array([c.profile == "ramp2" for c in cases]),
        0.5 * w_tgt / ramp_rate + 0.5 * w_tgt / np.maximum(ramp2, 1e-9),
        w_tgt / ramp_rate)
    t_tail = A("rls_tail_s")
    t_end_case = t_mag + t_ramp + t_tail
    t_max = opt.t_max if opt.t_max is not None else float(np.max(t_end_case)) + 0.05
    nsteps = int(math.ceil(t_max / Ts))

    # filters: all signals the groups may ask for go through one bank
    N = max(1, int(opt.rate_div))
    Ts_f = Ts * N if opt.rate_mode == "avg" else Ts
    wcf = TWO_PI * A("filter_Hz")
    npass = A("euler_passes")
    sig_names = list(RAW_SIGNALS)
    bank = FilterBank(sig_names, wcf, Ts_f, npass)
    acc_u = np.zeros((len(sig_names), C))
    premag_init = opt.premag
    acc_n = 0

    # plant state
    psis = np.zeros(C, complex)
    psir = np.zeros(C, complex)
    wm = np.zeros(C)
    thm = np.zeros(C)

    # controller state
    th_r_hist = np.zeros((16, C))
    hist_i = 0
    th_r_prev = np.zeros(C)
    spd = np.zeros(C)
    th_slip = np.zeros(C)
    th_f_prev = np.zeros(C)
    imr = np.zeros(C)
    ws_ifo = np.zeros(C)
    ramp_out = np.zeros(C)
    ramp_done = np.zeros(C, bool)
    ui_w = np.zeros(C)
    ui_d = np.zeros(C)
    ui_q = np.zeros(C)
    u_next = np.zeros(C, complex)     # computed at ISR k-1: applied over [t_k, t_k+1]
    u_next2 = np.zeros(C, complex)    # computed at ISR k: applied over [t_k+1, t_k+2]
    u_last = np.zeros(C, complex)     # applied over [t_k-1, t_k]
    i_prev_dq = np.zeros(C, complex)  # sample k-1 in its frame
    state = np.zeros(C, int)          # 0 MAGNETIZE, 1 ACCELERATE, 2 SETTLE
    t_state = np.zeros(C)
    rls_on_prev = np.zeros(C, bool)
    shadow_m0 = np.zeros(C, complex)  # shadow current model driven by the trapezoid current
    shadow_m1 = np.zeros(C, complex)  # ... by the ripple correction c (times K2 later)
    shadow_mo = np.zeros(C, complex)  # ... by the oracle mean current
    mean_i_prev = np.zeros(C, complex)
    t_first_rls = np.full(C, np.nan)

    dlt0 = np.zeros(C, complex)       # Euler correction of ifo's flux: half-period shift
    dlt1 = np.zeros(C, complex)       # ... ripple curvature c (times K2 later)
    dltk = np.zeros(C, complex)       # ... both, with the running K2 estimate (RLS)
    mk = np.zeros(C, complex)         # exact shadow model with the running K2 estimate
    k2_nom = 1.0 / sls
    k2_run = k2_nom.copy()
    if opt.premag:
        psir[:] = Lm * im_ref
        psis[:] = Ls * im_ref
        imr[:] = im_ref
        ui_d[:] = Rs * im_ref
        u_next[:] = Rs * im_ref
        u_last[:] = Rs * im_ref
        i_prev_dq[:] = im_ref
        shadow_m0[:] = im_ref
        shadow_mo[:] = im_ref
        mk[:] = im_ref
        mean_i_prev[:] = im_ref

    # moments of the period for the oracle means
    mom_i = np.zeros((4, C), complex)
    mom_r = np.zeros((4, C), complex)
    if opt.premag:
        for n in range(4):
            mom_i[n] = Ts ** (n + 1) / (n + 1) * im_ref
            mom_r[n] = Ts ** (n + 1) / (n + 1) * Lm * im_ref

    rls_state = {}
    for name in opt.rls:
        rls_state[name] = {"th": np.zeros((C, 4)), "P": np.tile(np.eye(4) * opt.rls_p0, (C, 1, 1))}
    K_nom = np.stack([c.true_K(c.Lm * c.i_m) for c in cases])          # (C, 4) scales
    # the proposal's K3'', K4'' are K3, K4 per ampere of flux current
    K_nom_prop = np.column_stack([K_nom[:, 0], K_nom[:, 1], K_nom[:, 2] / im_ref,
                                  K_nom[:, 3] / im_ref])

    groups = groups or {}
    gram = {g: None for g in groups}
    rows = np.zeros(C)
    end = {}
    rec = Recorder()
    rec_every = max(1, int(round(1.0 / (opt.record_hz * Ts))))

    def load_torque(w):
        r = w / w_rated_m
        return np.sign(w) * lconst + np.sign(w) * lfan * r * r

    def deriv(ps, pr, w, u):
        i_s = (Lr * ps - Lm * pr) / Dm
        i_r = (Ls * pr - Lm * ps) / Dm
        dps = u - Rs * i_s
        dpr = -Rr * i_r + 1j * p * w * pr
        te = 1.5 * p * (ps.real * i_s.imag - ps.imag * i_s.real)
        dw = (te - load_torque(w) - Bf * w) / J
        return dps, dpr, dw, i_s

    tau_pow = lambda tau: np.array([1.0, tau, tau * tau, tau ** 3])  # noqa: E731

    for k in range(nsteps):
        t = k * Ts
        # ---- sample at t_k ---------------------------------------------
        i_ab = (Lr * psis - Lm * psir) / Dm
        # the encoder: exact, or counted (x4 lines per revolution, the count's
        # floor, the edges offset by half a pitch from theta = 0 as motor_sim's)
        th_r = p * (thm if opt.enc_lines <= 0 else
                    (np.floor(thm * (4 * opt.enc_lines) / (2 * np.pi) - opt.enc_offset) + opt.enc_offset)
                    * (2 * np.pi / (4 * opt.enc_lines)))
        w1 = (th_r - th_r_prev) / Ts                      # speed_1: over the period
        th_r_prev = th_r
        old = th_r_hist[hist_i].copy()
        th_r_hist[hist_i] = th_r
        hist_i = (hist_i + 1) % 16
        spd_raw = (th_r - old) / (16 * Ts) if k >= 16 else (th_r - 0.0) / (16 * Ts)
        spd = spd + kf_spd * (spd_raw - spd)

        # frame of sample k (ifo_frame_from_rotor)
        th_f = th_r + th_slip
        dth = th_f - th_f_prev
        ws = dth / Ts
        e_k = np.exp(-1j * th_f)
        i_dq = i_ab * e_k
        th_mid = th_f - 0.5 * dth
        u_fw = u_last * np.exp(-1j * th_mid)              # firmware's voltage of the period
        if opt.u_gain_err or opt.u_dt_V:
            u_fw = u_fw * (1.0 + opt.u_gain_err) + opt.u_dt_V * i_dq / np.maximum(np.abs(i_dq), 1e-9)
        snc = np.sinc(dth / (2.0 * np.pi))                # sin(dth/2)/(dth/2)
        u_bar = u_fw * snc                                # exact period mean in the frame

        # oracle period means in the frame (frame angle linear in the period)
        e_prev = np.exp(-1j * th_f_prev)
        rot = np.ones(C, complex)
        ib = np.zeros(C, complex)
        rb = np.zeros(C, complex)
        fact = 1.0
        for n in range(4):
            if n > 0:
                fact *= n
            coef = (-1j * ws) ** n / fact
            ib += coef * mom_i[n]
            rb += coef * mom_r[n]
        i_bar = ib * e_prev / Ts
        psi_bar = rb * e_prev / Ts
        psi_k = psir * e_k                                # rotor flux at the sample, frame
        trap = 0.5 * (i_prev_dq + i_dq)
        c_rip = 1j * ws * u_bar * Ts * Ts / 12.0          # mean = trapezoid + K2 c

        # shadow current models of the rotor flux (in A: psi_r / Lm) in the
        # frame, exact per period for a constant input: driven by the
        # trapezoid current (m0), by c (m1, scaled by K2 later), by the oracle
        # mean current (mo)
        slip_f = ws - w1
        lam = 1.0 / Tr + 1j * slip_f
        ed = np.exp(-lam * Ts)
        gin = (1.0 - ed) / (lam * Tr)
        shadow_m0 = ed * shadow_m0 + gin * trap
        shadow_m1 = ed * shadow_m1 + gin * c_rip
        shadow_mo = ed * shadow_mo + gin * i_bar

        # the firmware-friendly form: ifo's i_mr (on the M axis) plus an Euler
        # correction driven by delta i = (mean of the period) - (the sample
        # ifo held over it) = (i_k - i_k-1)/2 + K2 c
        a_d = 1.0 - kf_tr - 1j * slip_f * Ts
        dlt0 = a_d * dlt0 + kf_tr * 0.5 * (i_dq - i_prev_dq)
        dlt1 = a_d * dlt1 + kf_tr * c_rip
        dltk = a_d * dltk + kf_tr * (0.5 * (i_dq - i_prev_dq) + k2_run * c_rip)
        ik = trap + k2_run * c_rip
        mk = ed * mk + gin * ik
        mdk = imr + dltk

        rls_on = rls_on_prev.copy()
        raw = {
            "iM": i_dq.real, "iT": i_dq.imag, "uM": u_fw.real, "uT": u_fw.imag,
            "wsiT": ws * i_dq.imag, "wsiM": ws * i_dq.real, "wr": w1,
            # implementable corrections
            "tM": trap.real, "tT": trap.imag, "wstT": ws * trap.imag, "wstM": ws * trap.real,
            "cM": c_rip.real, "cT": c_rip.imag, "wscT": ws * c_rip.imag, "wscM": ws * c_rip.real,
            "ubM": u_bar.real, "ubT": u_bar.imag,
            "m0M": shadow_m0.real, "m0T": shadow_m0.imag,
            "wrm0M": w1 * shadow_m0.real, "wrm0T": w1 * shadow_m0.imag,
            "m1M": shadow_m1.real, "m1T": shadow_m1.imag,
            "wrm1M": w1 * shadow_m1.real, "wrm1T": w1 * shadow_m1.imag,
            "imr": imr.copy(), "wrimr": w1 * imr,
            # oracle
            "ibM": i_bar.real, "ibT": i_bar.imag, "wsibT": ws * i_bar.imag, "wsibM": ws * i_bar.real,
            "pbM": psi_bar.real / Lm, "pbT": psi_bar.imag / Lm,
            "wrpbM": w1 * psi_bar.real / Lm, "wrpbT": w1 * psi_bar.imag / Lm,
            "moM": shadow_mo.real, "moT": shadow_mo.imag,
            "wrmoM": w1 * shadow_mo.real, "wrmoT": w1 * shadow_mo.imag,
            "d0M": imr + dlt0.real, "d0T": dlt0.imag, "wrd0M": w1 * (imr + dlt0.real),
            "wrd0T": w1 * dlt0.imag, "d1M": dlt1.real, "d1T": dlt1.imag,
            "wrd1M": w1 * dlt1.real, "wrd1T": w1 * dlt1.imag,
            "ikM": ik.real, "ikT": ik.imag, "wsikT": ws * ik.imag, "wsikM": ws * ik.real,
            "mkM": mk.real, "mkT": mk.imag, "wrmkM": w1 * mk.real, "wrmkT": w1 * mk.imag,
            "mdkM": mdk.real, "mdkT": mdk.imag, "wrmdkM": w1 * mdk.real, "wrmdkT": w1 * mdk.imag,
            "diM": (i_dq.real - i_prev_dq.real) / Ts, "diT": (i_dq.imag - i_prev_dq.imag) / Ts,
            "one": np.ones(C),
        }
        u_vec = np.stack([raw[n] for n in sig_names])
        if premag_init:
            bank.x1[:] = u_vec
            premag_init = False
        do_row = False
        if opt.rate_mode == "avg" and N > 1:
            acc_u += u_vec
            acc_n += 1
            if acc_n == N:
                bank.step(acc_u / N)
                acc_u[:] = 0.0
                acc_n = 0
                do_row = True
        else:
            bank.step(u_vec)
            do_row = (k % N == 0)

        if do_row and rls_state:
            _rls_rows(rls_state, bank, rls_on, K_nom, K_nom_prop)
            if "prop" in rls_state:
                th2 = rls_state["prop"]["th"][:, 1] * K_nom_prop[:, 1]
                good = (th2 > 0.5 * k2_nom) & (th2 < 2.0 * k2_nom)
                k2_run = np.where(good, th2, k2_nom)

        if do_row and groups:
            on = rls_on
            if np.any(on):
                sig = {"f": bank, "raw": raw, "cases": cases}
                for g, fn in groups.items():
                    X1, X2 = fn(sig)
                    X1 = X1 * on[:, None]
                    X2 = X2 * on[:, None]
                    G = np.einsum("ci,cj->cij", X1, X1) + np.einsum("ci,cj->cij", X2, X2)
                    gram[g] = G if gram[g] is None else gram[g] + G
                rows += on
                # values at the last RLS row of each case
                newly = on & np.isnan(t_first_rls)
                t_first_rls[newly] = t
                for key in ("iM", "tM", "m0M", "moM", "pbM", "imr", "d0M", "d1M", "mkM", "mdkM"):
                    v = bank.y(key)
                    end.setdefault(key, np.zeros(C))
                    end[key] = np.where(on, v, end[key])
                end.setdefault("m1M", np.zeros(C))
                end["m1M"] = np.where(on, bank.y("m1M"), end["m1M"])

        # ---- sequence (id_sequence.c) ----------------------------------
        t_state += Ts
        to_acc = (state == 0) & (t_state >= t_mag - 0.5 * Ts)
        to_settle = (state == 1) & ramp_done
        state = np.where(to_acc, 1, np.where(to_settle, 2, state))
        t_state = np.where(to_acc | to_settle, 0.0, t_state)
        in_band = (ramp_out >= learn_lo) & (ramp_out <= learn_hi)
        rls_on_prev = ((state == 1) | ((state == 2) & (t_state <= t_tail + 0.5 * Ts))) & in_band
        speed_loop = state >= 1

        # ---- control ----------------------------------------------------
        tgt = np.where(speed_loop, w_tgt, 0.0)
        rate = np.where(ramp_out < 0.5 * w_tgt, ramp_rate, ramp2)
        step = rate * Ts
        err = tgt - ramp_out
        ramp_out = np.where(err > step, ramp_out + step, np.where(err < -step, ramp_out - step, tgt))
        ramp_done = np.abs(err) <= step
        e_w = ramp_out - spd
        up_w = kp_w * e_w
        ui_w = np.where(speed_loop, ui_w + ki_w * e_w, 0.0)
        ui_w = np.clip(ui_w, -i_max, i_max)
        it_ref = np.where(speed_loop, np.clip(up_w + ui_w, -i_max, i_max), 0.0)

        # feedback current for control and orientation
        if opt.control == "firmware":
            i_fb = i_dq
        elif opt.control == "mean_oracle":
            i_fb = i_bar
        elif opt.control == "offset_est":
            i_fb = i_dq + k2n * c_rip
        else:
            raise ValueError(opt.control)
        ff_d = -ws_ifo * sls * i_fb.imag
        ff_q = ws_ifo * (sls * i_fb.real + Lm * Lm / Lr * imr)
        e_d = im_ref - i_fb.real
        e_q = it_ref - i_fb.imag
        ui_d = np.clip(ui_d + ki_i * e_d, -vbase, vbase)
        ui_q = np.clip(ui_q + ki_i * e_q, -vbase, vbase)
        v_d = np.clip(kp_i * e_d + ui_d + ff_d, -vbase, vbase)
        v_q = np.clip(kp_i * e_q + ui_q + ff_q, -vbase, vbase)

        # ---- orientation (ifo_step_slip) -----------------------------------
        imr = imr + kf_tr * (i_fb.real - imr)
        ok = imr >= imr_min
        wslip = np.where(ok, i_fb.imag / (Tr * np.where(ok, imr, 1.0)), 0.0)
        ws_ifo = spd_raw + wslip
        th_slip = th_slip + wslip * Ts

        # ---- modulation: applied over [t_k+1, t_k+2] --------------------
        u_next2 = (v_d + 1j * v_q) * np.exp(1j * (th_f + 1.5 * ws_ifo * Ts))

        if k % rec_every == 0:
            psi_dq = psir * e_k
            r1 = (bank.dy("iM") - bank.y("wsiT")) - (K_nom[:, 0] * bank.y("iM") + K_nom[:, 1] * bank.y("uM")
                                                     + K_nom[:, 2])
            r2 = (bank.dy("iT") + bank.y("wsiM")) - (K_nom[:, 0] * bank.y("iT") + K_nom[:, 1] * bank.y("uT")
                                                     + K_nom[:, 3] * bank.y("wr"))
            rec.add(t, w=wm * p, iM=i_dq.real, iT=i_dq.imag, psiM=psi_dq.real, psiT=psi_dq.imag,
                    ibM=i_bar.real, ibT=i_bar.imag, rls=rls_on.astype(float), ref=ramp_out,
                    uM=u_fw.real, uT=u_fw.imag, ws=ws, r1=r1, r2=r2, imr=imr.copy())

        # ---- keep for the next sample -----------------------------------
        th_f_prev = th_f
        i_prev_dq = i_dq
        mean_i_prev = i_bar

        # ---- plant over [t_k, t_k+1] with u_next (RK4) ------------------
        u = u_next
        mom_i[:] = 0.0
        mom_r[:] = 0.0
        for s in range(opt.substeps):
            tau0 = s * h
            k1s, k1r, k1w, i1 = deriv(psis, psir, wm, u)
            k2s, k2r, k2w, i2 = deriv(psis + 0.5 * h * k1s, psir + 0.5 * h * k1r, wm + 0.5 * h * k1w, u)
            k3s, k3r, k3w, i3 = deriv(psis + 0.5 * h * k2s, psir + 0.5 * h * k2r, wm + 0.5 * h * k2w, u)
            k4s, k4r, k4w, i4 = deriv(psis + h * k3s, psir + h * k3r, wm + h * k3w, u)
            # moments by the RK4 weights on the stage values (Simpson in tau)
            r1, r2, r4 = psir, psir + 0.5 * h * k1r, psir + h * k3r
            r3 = psir + 0.5 * h * k2r
            tp0, tpm, tp1 = tau_pow(tau0), tau_pow(tau0 + 0.5 * h), tau_pow(tau0 + h)
            for n in range(4):
                mom_i[n] += h / 6.0 * (i1 * tp0[n] + 2 * i2 * tpm[n] + 2 * i3 * tpm[n] + i4 * tp1[n])
                mom_r[n] += h / 6.0 * (r1 * tp0[n] + 2 * r2 * tpm[n] + 2 * r3 * tpm[n] + r4 * tp1[n])
            thm = thm + h / 6.0 * (wm + 2 * (wm + 0.5 * h * k1w) + 2 * (wm + 0.5 * h * k2w)
                                   + (wm + h * k3w))
            psis = psis + h / 6.0 * (k1s + 2 * k2s + 2 * k3s + k4s)
            psir = psir + h / 6.0 * (k1r + 2 * k2r + 2 * k3r + k4r)
            wm = wm + h / 6.0 * (k1w + 2 * k2w + 2 * k3w + k4w)
        u_last = u_next
        u_next = u_next2

        if k * Ts > t_max:
            break

    rls_out = {n: st["th"] * (K_nom if n == "fw" else K_nom_prop) for n, st in rls_state.items()}
    return {"gram": gram, "rows": rows, "end": end, "rec": rec.arrays(), "Ts": Ts, "rls": rls_out,
            "t_first_rls": t_first_rls, "t_end_case": t_end_case}


def _rls_update(th, P, phi, y, on):
    """one scalar RLS update (method §3) per case, where on"""
    Pphi = np.einsum("cij,cj->ci", P, phi)
    den = 1.0 + np.einsum("ci,ci->c", phi, Pphi)
    g = Pphi / den[:, None]
    e = y - np.einsum("ci,ci->c", phi, th)
    th_new = th + g * e[:, None]
    P_new = P - np.einsum("ci,cj->cij", g, Pphi)
    m = on[:, None]
    return np.where(m, th_new, th), np.where(m[:, :, None], P_new, P)


def _rls_rows(state, f, on, K_nom, K_nom_prop):
    y, dy = f.y, f.dy
    C = on.shape[0]
    z = np.zeros(C)
    for name, st in state.items():
        if name == "fw":
            s = K_nom
            r1 = np.column_stack([y("iM"), y("uM"), y("one"), z]) * s
            r2 = np.column_stack([y("iT"), y("uT"), z, y("wr")]) * s
            y1 = dy("iM") - y("wsiT")
            y2 = dy("iT") + y("wsiM")
        else:
            s = K_nom_prop
            r1 = np.column_stack([y("ikM"), y("ubM"), y("mdkM"), -y("wrmdkT")]) * s
            r2 = np.column_stack([y("ikT"), y("ubT"), y("mdkT"), y("wrmdkM")]) * s
            y1 = dy("iM") - y("wsikT")
            y2 = dy("iT") + y("wsikM")
        th, P = st["th"], st["P"]
        th, P = _rls_update(th, P, r1, y1, on)
        th, P = _rls_update(th, P, r2, y2, on)
        st["th"], st["P"] = th, P


RAW_SIGNALS = (
    "iM", "iT", "uM", "uT", "wsiT", "wsiM", "wr",
    "tM", "tT", "wstT", "wstM", "cM", "cT", "wscT", "wscM", "ubM", "ubT",
    "m0M", "m0T", "wrm0M", "wrm0T", "m1M", "m1T", "wrm1M", "wrm1T", "imr", "wrimr",
    "ibM", "ibT", "wsibT", "wsibM", "pbM", "pbT", "wrpbM", "wrpbT",
    "moM", "moT", "wrmoM", "wrmoT", "diM", "diT", "one",
    "d0M", "d0T", "wrd0M", "wrd0T", "d1M", "d1T", "wrd1M", "wrd1T",
    "ikM", "ikT", "wsikT", "wsikM", "mkM", "mkT", "wrmkM", "wrmkT",
    "mdkM", "mdkT", "wrmdkM", "wrmdkT",
)
