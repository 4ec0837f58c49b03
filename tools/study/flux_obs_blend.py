#!/usr/bin/env python3
"""Study for src/orient/flux_obs.c: steady-state angle error of the closed-loop
rotor-flux observer against speed, from the continuous-time blend (flux_obs.h),
for the paper's motor at its rated operating point (i_M 0.328 pu, i_T 0.25 pu).

Prints, for crossovers w_c and two blends (the textbook PI with zeta = 0.707,
and the module's PI + roll-off with a triple pole at w_c), the angle error in
degrees caused by: Tr +-30 % in the current model, Rs +-10 % and sigma Ls
+-10 % in the voltage model.  Pure standard library (cmath); no arguments.
The module's own numbers (discrete, Q24) agree with this to < 3 % + 0.01 deg:
tests/orient/test_flux_obs.c.
"""
import cmath
import math

# paper motor, pu (bases 20 A, 34.64 V, 50 Hz)
ZB = 34.6410161513775 / 20.0
WB = 2 * math.pi * 50.0
LB = ZB / WB
RS, RR, LM, LS, LR = 1.031 / ZB, 0.465 / ZB, 6.4e-3 / LB, 9.2e-3 / LB, 9.2e-3 / LB
SLS = LS - LM * LM / LR
TR = LR / RR
ID, IQ = 6.5625 / 20.0, 0.25


def blend(kind, s, wc):
    """(H_c, H_e): current-model weight and voltage-error -> flux gain."""
    if kind == "PI":
        kp, ki = math.sqrt(2.0) * wc, wc * wc
        d = s * s + kp * s + ki
        return (kp * s + ki) / d, s / d
    d = (s + wc) ** 3
    return (3 * wc * wc * s + wc ** 3) / d, s * (s + 3 * wc) / d


def angle_err(kind, we, wc, k_tr=1.0, k_rs=1.0, k_sls=1.0):
    s = 1j * we
    hc, he = blend(kind, s, wc)
    i = ID + 1j * IQ
    psir = LM * ID
    psis = LS * ID + 1j * SLS * IQ
    wsl = IQ / (TR * ID)
    sls_b = SLS * k_sls                        # believed sigma Ls
    psi_cm = LM * i / (1 + 1j * wsl * TR * k_tr)
    psis_cm = LM / LR * psi_cm + sls_b * i
    psis_hat = (1 - hc) * psis + hc * psis_cm + he * RS * (1 - k_rs) * i
    psir_hat = LR / LM * (psis_hat - sls_b * i)
    return math.degrees(cmath.phase(psir_hat / psir))


def main():
    speeds = [0.02, 0.06, 0.1, 0.2, 0.4, 0.6, 0.9333]
    print("paper motor: Rs %.3f, Lm %.3f, Ls=Lr %.3f, sigma Ls %.3f pu, Tr %.2f pu; "
          "i_M %.3f, i_T %.3f pu" % (RS, LM, LS, SLS, TR, ID, IQ))
    print("angle error (deg) of the observer's rotor flux against speed w_e (pu)\n")
    for wc_hz in (1.0, 3.0, 5.0):
        wc = wc_hz / 50.0
        for kind in ("PI", "PI+rolloff"):
            print("w_c = %.0f Hz, %s" % (wc_hz, kind))
            print("  %-14s" % "w_e (pu)" + "".join("%9.4f" % w for w in speeds))
            rows = [("Tr x0.7", dict(k_tr=0.7)), ("Tr x1.3", dict(k_tr=1.3)),
                    ("Rs x0.9", dict(k_rs=0.9)), ("Rs x1.1", dict(k_rs=1.1)),
                    ("sigmaLs x0.9", dict(k_sls=0.9)), ("sigmaLs x1.1", dict(k_sls=1.1))]
            for name, kw in rows:
                print("  %-14s" % name + "".join("%9.3f" % angle_err(kind, w, wc, **kw)
                                                for w in speeds))
            print()
    print("Above w_c the Rs error gives about dRs / (w_e Lm^2/Lr) rad (load and flux "
          "independent): %.2f deg at 0.9333 pu for 10 %%." %
          math.degrees(0.1 * RS / (0.9333 * LM * LM / LR)))


if __name__ == "__main__":
    main()
