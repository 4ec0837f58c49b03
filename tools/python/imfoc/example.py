"""Closed loop: the firmware (libimfoc) drives a numpy induction motor.

    python -m imfoc.example [--config INI] [--duration S] [--csv FILE]

The firmware and the plant read the same INI file (the firmware believes the
nameplate; the plant is the true motor).  The plant's inverter is ideal, so
the firmware's dead-time compensation is switched off ([controller]
dead_time_comp = 0).  Each period: sample the plant (currents, bus, angle at
the period start) -> one ISR -> the duties of the previous ISR act over this
period (the F2812 loads the compare values at the next underflow).
"""
import argparse
import csv
import sys

from .drive import Drive, read_ini, write_config, CONFIG_DIR, STATES
from .plant import InductionMotor, MotorParams
from ._lib import PARAM_NAMES


def truth(prm):
    Lm, Lr = prm.Lm, prm.Lr
    return {"Rs_ohm": prm.Rs, "Rr_ohm": prm.Rr, "Lm_H": Lm, "Lr_H": Lr, "Tr_s": Lr / prm.Rr}


def run(config=None, duration_s=2.5, csv_path=None, every=15, overrides=None):
    """Run the identification; returns a dict with the truth, the estimates (the
    published set, or the live RLS while nothing is published), their errors
    (percent), the last extraction and a few traces.  `overrides`: INI keys
    {"section": {"key": value}} on top of the configuration."""
    base = config or (CONFIG_DIR / "paper_motor.ini")
    over = {"controller": {"dead_time_comp": 0}}   # the ideal inverter below
    for sec, kv in (overrides or {}).items():
        over.setdefault(sec, {}).update(kv)
    ini = write_config(base, over)
    try:
        prm = MotorParams.from_ini(read_ini(ini))
        drv = Drive(ini)
    finally:
        ini.unlink()
    motor = InductionMotor(prm)
    info = drv.info
    Ts = info.Ts_s
    n = int(round(duration_s / Ts))
    active_v, active_on = (0.0, 0.0, 0.0), 0
    rows = []
    reg, k_last_rls = [], None   # the regression rows the RLS used (every `every`-th)
    drv.start_identification()
    psi_at_run = None
    for k in range(n):
        ia, ib, _ic = motor.i_abc
        out = drv.step_phys(ia, ib, prm.vdc, motor.theta_m)
        # this period: the duties of the previous ISR at the true bus
        motor.step(active_v, Ts, powered=bool(active_on))
        d = out.duty
        mean = (d[0] + d[1] + d[2]) / 3.0
        active_v = tuple((d[i] - mean) * prm.vdc for i in range(3))
        active_on = out.pwm_on
        if k % every == 0:
            s = drv.signals()
            if s.state == 5 and psi_at_run is None:
                psi_at_run = motor.psi_r
            if s.rls_on:
                reg.append((s.i_mf, s.u_mf, s.i_tf, s.u_tf, s.wr_f, s.y1, s.y2))
                k_last_rls = list(s.K)
            rows.append((k * Ts, s.state, motor.w_m * 60 / 6.283185307179586, s.speed_rpm,
                         s.i_m_A, s.i_t_A, *s.K, s.live_Rs_ohm, s.live_Rr_ohm, s.live_Lm_H,
                         s.live_Lr_H, s.live_psi_r_Wb, s.live_Tr_s))
    s = drv.signals()
    tr = truth(prm)
    tr["psi_r_Wb"] = psi_at_run if psi_at_run is not None else motor.psi_r
    published = bool(s.params_valid)
    est = drv.parameters(live=not published)
    err = {k: 100.0 * (est[k] - tr[k]) / tr[k] for k in PARAM_NAMES}
    extraction, extraction_valid = drv.last_extraction()
    res = {"state": STATES[s.state], "fault": s.fault, "published": published,
           "params_tracked": bool(s.params_tracked), "extraction": extraction,
           "extraction_valid": extraction_valid, "signals": drv.signals_dict(),
           "truth": tr, "estimate": est, "error_pct": err, "rows": rows,
           "regression": reg, "K_last_rls": k_last_rls, "publication": drv.publication(),
           "speed_rpm": motor.w_m * 60 / 6.283185307179586}
    if csv_path:
        with open(csv_path, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(["t_s", "state", "speed_rpm", "speed_meas_rpm", "i_m_A", "i_t_A",
                        "K1", "K2", "K3", "K4", *PARAM_NAMES])
            w.writerows(rows)
    drv.close()
    return res


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--config", help="simulator INI (default: the paper's motor)")
    ap.add_argument("--duration", type=float, default=2.5, help="simulated seconds")
    ap.add_argument("--csv", help="write a trace (every 1 ms)")
    a = ap.parse_args(argv)
    r = run(a.config, a.duration, a.csv)
    print(f"state {r['state']}, fault {r['fault']}, speed {r['speed_rpm']:.1f} r/min, "
          f"{'published' if r['published'] else 'live'} estimates:")
    for k in PARAM_NAMES:
        print(f"  {k:9s} true {r['truth'][k]:.5g}  identified {r['estimate'][k]:.5g}  "
              f"error {r['error_pct'][k]:+.2f} %")
    return 0 if r["fault"] == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
