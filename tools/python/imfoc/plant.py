"""A simple induction-motor plant in numpy, for closed loops with the firmware.

Fifth-order model in the stationary (alpha-beta) frame with the stator current
and the rotor flux as states (the same equations as method.md §1 in the frame
at rest), plus the mechanical speed and angle:

    sigma = 1 - Lm^2/(Ls Lr),  Tr = Lr/Rr,  w_r = p w_m (electrical)
    dpsi_r/dt = (Lm/Tr) i - psi_r/Tr + w_r J psi_r          J = [[0, -1], [1, 0]]
    di/dt     = (u - Rs i - (Lm/Lr) dpsi_r/dt) / (sigma Ls)
    Te        = 1.5 p (Lm/Lr) (psi_ra i_b - psi_rb i_a)
    J dw_m/dt = Te - T_load(w_m) - B w_m,    dtheta_m/dt = w_m

integrated by classical RK4 over each PWM period with the phase voltages held
(an averaged, ideal inverter: no dead time, no drops).  With the bridge off
the stator is open: the currents are held at zero (valid while the back-EMF
stays below the bus, i.e. the diodes do not conduct).
"""
from dataclasses import dataclass
import math

import numpy as np

SQRT3 = math.sqrt(3.0)


@dataclass
class MotorParams:
    Rs: float
    Rr: float
    Lm: float
    Ls: float
    Lr: float
    p: int
    J: float
    B: float = 0.0
    load_const: float = 0.0     # N m, opposing the motion
    load_prop: float = 0.0      # N m s
    load_fan: float = 0.0       # N m at rated speed, quadratic
    rated_rpm: float = 1.0
    vdc: float = 60.0

    @classmethod
    def from_ini(cls, cp):
        """The true motor, load and bus of a simulator INI (a ConfigParser):
        [plant] (each motor parameter the [nameplate]'s unless given), [load],
        [inverter] vdc_V (default [board] vdc_nominal_V)."""
        sec = lambda name: cp[name] if cp.has_section(name) else {}
        np_, pl, ld, inv, bd = (sec(n) for n in ("nameplate", "plant", "load", "inverter", "board"))
        g = lambda s, k, d=0.0: float(s.get(k, d))
        true = lambda k: g(pl, k, g(np_, k))   # the plant's, else the nameplate's
        Lm = true("Lm_H")
        return cls(Rs=true("Rs_ohm"), Rr=true("Rr_ohm"), Lm=Lm, Ls=Lm + true("Lls_H"),
                   Lr=Lm + true("Llr_H"), p=int(g(np_, "pole_pairs")), J=g(pl, "J_kgm2"),
                   B=g(pl, "B_Nm_s"), load_const=g(ld, "const_Nm"), load_prop=g(ld, "prop_Nm_s"),
                   load_fan=g(ld, "fan_Nm"), rated_rpm=g(np_, "rated_speed_rpm", 1.0),
                   vdc=g(inv, "vdc_V", g(bd, "vdc_nominal_V", 60.0)))

    @property
    def Tr(self):
        return self.Lr / self.Rr


class InductionMotor:
    """State x = [i_alpha, i_beta, psi_ralpha, psi_rbeta, w_m, theta_m] (SI)."""

    def __init__(self, prm: MotorParams):
        self.p = prm
        self.x = np.zeros(6)
        self.sigma_ls = prm.Ls - prm.Lm ** 2 / prm.Lr
        self.w_rated = prm.rated_rpm * 2.0 * math.pi / 60.0

    # phase quantities (amplitude-invariant Clarke) ----------------------------
    @property
    def i_abc(self):
        ia, ib = self.x[0], self.x[1]
        return ia, -0.5 * ia + 0.5 * SQRT3 * ib, -0.5 * ia - 0.5 * SQRT3 * ib

    @property
    def w_m(self):
        return self.x[4]

    @property
    def theta_m(self):
        return self.x[5]

    @property
    def psi_r(self):
        return math.hypot(self.x[2], self.x[3])

    def load_torque(self, w_m):
        q = self.p
        s = np.sign(w_m)
        return s * q.load_const + q.load_prop * w_m + s * q.load_fan * (w_m / self.w_rated) ** 2

    def torque(self, x):
        q = self.p
        return 1.5 * q.p * q.Lm / q.Lr * (x[2] * x[1] - x[3] * x[0])

    def deriv(self, x, u_ab, powered=True):
        q = self.p
        wr = q.p * x[4]
        dpsi = np.array([(q.Lm * x[0] - x[2]) / q.Tr - wr * x[3],
                         (q.Lm * x[1] - x[3]) / q.Tr + wr * x[2]])
        if powered:
            di = (u_ab - q.Rs * x[:2] - (q.Lm / q.Lr) * dpsi) / self.sigma_ls
        else:
            di = np.zeros(2)
        dw = (self.torque(x) - self.load_torque(x[4]) - q.B * x[4]) / q.J
        return np.concatenate((di, dpsi, (dw, x[4])))

    def step(self, v_abc, dt, powered=True):
        """Advance by dt with the phase-to-neutral voltages v_abc held (RK4)."""
        va, vb, vc = v_abc
        u = np.array([(2.0 * va - vb - vc) / 3.0, (vb - vc) / SQRT3])
        x = self.x
        k1 = self.deriv(x, u, powered)
        k2 = self.deriv(x + 0.5 * dt * k1, u, powered)
        k3 = self.deriv(x + 0.5 * dt * k2, u, powered)
        k4 = self.deriv(x + dt * k3, u, powered)
        self.x = x + (dt / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
        if not powered:
            self.x[:2] = 0.0
