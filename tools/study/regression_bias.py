#!/usr/bin/env python3
"""Which term of the identification regression (method §1-2, eq. 7) the data
do not satisfy on small-leakage, high-w_r Tr motors, and a regression that
they do satisfy.  Double precision, ideal plant (tools/study/ideal_drive.py);
the findings and numbers are in tools/study/regression_bias.md.

    regression_bias.py diagnose   [--out DIR]   residual of each row with the true K's split
                                                into its causes, and the bias of each
    regression_bias.py validate   [--grid] ...  the firmware's regression and the proposal,
                                                batch fit, all six parameters (CI subset +
                                                named motors; --grid: the 56-motor family)
    regression_bias.py swing      ...           operating choices one at a time
    regression_bias.py rate       ...           multi-rate identification, N = 1, 2, 4, 8
    regression_bias.py isr        ...           ISR (PWM) rate 8..45 kHz
    regression_bias.py sensitivity              a voltage error (real-plant residue) against
                                                the learning speed (not an ideal-plant result)
    regression_bias.py motor_sim  ...           the fixed-point motor_sim, ideal sensors, with
                                                the paper's rows and the firmware's period-mean
                                                rows ([ident] period_mean = 1, regression_bias.md
                                                §10) (needs build/host-iq: tools/run_identification.sh
                                                or cmake --build --preset host-iq --target motor_sim)
    regression_bias.py write-s077 FILE          the issue's motor on the ideal plant as an INI
                                                (tests/sim/motor_1kw_s077_ideal.ini)
    regression_bias.py family-seeds [--seeds 8] the paper's against the period-mean rows on the
                                                grid, ideal bridge, 8 noise seeds (FLOAT build)

Each prints a markdown table and writes DIR/<command>.json (default
out/regression_bias).  Cases run vectorised in one closed loop per command
(numpy); `validate --grid` takes ~10 min on one core, the others 2..10 min.

The proposal (regression_bias.md, "The change"), per period k in the
controller's frame:
    u_bar = sinc(dtheta/2) u_fw                       exact mean voltage of the period
    i_bar = (i_k-1 + i_k)/2 + K2^ c,  c = j w_s u_bar Ts^2/12   mean current of the period
    m     = (i_mr, 0) + Delta,  Delta += kf (i_bar - i_k-1 - Delta) - j w_sl Ts Delta
                                                      rotor flux / Lm in the frame
    row 1: d/dt i_Mf - (w_s i_bar_T)f = K1 i_bar_Mf + K2 u_bar_Mf + K3'' m_Mf - K4'' (w_r m_T)f
    row 2: d/dt i_Tf + (w_s i_bar_M)f = K1 i_bar_Tf + K2 u_bar_Tf + K3'' m_Tf + K4'' (w_r m_M)f
with K3'' = K3 / i_M, K4'' = K4 / i_M and K2^ the RLS's previous K2 (here:
the batch fit iterated to its fixed point, and a double-precision RLS).
"""
from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys
import tempfile
from dataclasses import replace
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(ROOT / "tools" / "family"))

import ideal_drive as idd  # noqa: E402
import motors as fam  # noqa: E402
import regfit as rf  # noqa: E402

CONFIG = ROOT / "host_sim" / "config"
SQRT3 = math.sqrt(3.0)

# the ideal plant for motor_sim (and the meaning of "ideal" here)
IDEAL_EXTRA = fam.IDEAL_PLANT


# --------------------------------------------------------------------------
# motors
# --------------------------------------------------------------------------
def s077_motor():
    """Reconstruction of the issue's motor (method §7 point 5): 1 kW, 4 poles,
    sigma 0.077, w_r Tr = 69 at 3000 r/min (100 Hz): the family generator's
    1 kW 4-pole 100 Hz 400 V motor with Tr set to 69 / (2 pi 100) = 0.1098 s,
    identified up to 3000 r/min.  Its other values are the generator's (the
    issue's file is not in the repository)."""
    return fam.design(1.0, 4, 100.0, 400.0, 0.077, Tr=69.0 / (2 * math.pi * 100.0),
                      target_rpm=3000.0, name="1kW_s077_3000rpm")


def case_from_motor(m, **over):
    return idd.case_from_ini(None, name=m.name, text=fam.to_ini(m, "current"), **over)


def named_cases():
    return [idd.case_from_ini(CONFIG / "paper_motor.ini", name="paper 250 W"),
            idd.case_from_ini(CONFIG / "motor_1kw.ini", name="1.1 kW (motor_1kw)"),
            idd.case_from_ini(CONFIG / "motor_15kw.ini", name="15 kW (motor_15kw)"),
            case_from_motor(s077_motor())]


def ci_cases():
    return [case_from_motor(m) for m in fam.ci_subset()]


def grid_cases():
    return [case_from_motor(m) for m in fam.grid()]


# --------------------------------------------------------------------------
# fits
# --------------------------------------------------------------------------
def pu_scale(c, flux_cols=False):
    """per-unit column scales for the condition number (batch_ls.py's bases);
    the proposal's flux columns m, w_r m are taken per i_M (m / i_M ~ 1, the
    firmware's constant regressor), so that both numbers compare"""
    Ib, Vb, wb = c.hall_fs_A, c.vdc / SQRT3, 2 * math.pi * c.rated_freq_Hz
    if flux_cols:
        return [1 / Ib, 1 / Vb, 1 / c.i_m, 1 / (wb * c.i_m)]
    return [1 / Ib, 1 / Vb, 1.0, 1 / wb]


def truth(c, res, ci):
    t = c.true_params()
    t["psi_r"] = c.Lm * res["end"]["pbM"][ci]       # the plant's actual rotor flux
    return t


def fit_fw(c, res, ci):
    G = res["gram"]["fw"][ci]
    th, cond = rf.ls_from_gram(G, [0, 1, 2, 3], 4, scale=pu_scale(c))
    est = rf.extract(th, res["end"]["iM"][ci])
    return rf.errors_pct(est, truth(c, res, ci)), cond


PC = {n: i for i, n in enumerate(rf.PROP_COLS)}


def _prop_mats(kappa, flux=True, curv=True, y_mean=False, sample_i=False, fw_u=False):
    """y_mean: the derivative from the filter of the mean current (one filter
    per axis instead of two) instead of the sample's; sample_i, fw_u: the
    firmware's sample current / voltage in the K1 / K2 columns (ablations)"""
    nc = len(rf.PROP_COLS)
    R = np.zeros((nc, 4))
    yv = np.zeros(nc)
    if sample_i:
        R[PC["s_i"], 0] = 1.0
    else:
        R[PC["B1"], 0] = 1.0
        R[PC["E1"], 0] = kappa if curv else 0.0
    R[PC["s_u" if fw_u else "B2"], 1] = 1.0
    if flux:
        R[PC["B3"], 2] = 1.0
        R[PC["E3"], 2] = kappa if curv else 0.0
        R[PC["B4"], 3] = 1.0
        R[PC["E4"], 3] = kappa if curv else 0.0
    else:
        R[PC["one"], 2] = 1.0
        R[PC["wr"], 3] = 1.0
    yb, ye = ("yB2", "yE2") if y_mean else ("yB", "yE")
    yv[PC[yb]] = 1.0
    yv[PC[ye]] = kappa if curv else 0.0
    return R, yv


def fit_prop(c, res, ci, group="propd", kappa=None, k0=1.5, flux=True, curv=True, y_mean=False,
             **abl):
    """The proposal, batch fit.  kappa: the K2 of the ripple correction; None:
    iterate kappa <- fitted K2 from k0 x the nameplate's (the batch analogue of
    using the RLS's previous estimate)."""
    G = res["gram"][group][ci]
    k2n = 1.0 / (c.sigma * c.Ls)
    scale = pu_scale(c, flux_cols=flux)
    if kappa is None:
        kappa = k0 * k2n
        for _ in range(12):
            R, yv = _prop_mats(kappa, flux, curv, y_mean, **abl)
            th, _ = rf.ls_from_gram(G, R, yv)
            if abs(th[1] / kappa - 1) < 1e-12:
                break
            kappa = th[1]
    R, yv = _prop_mats(kappa, flux, curv, y_mean, **abl)
    th, cond = rf.ls_from_gram(G, R, yv, scale=scale)
    keys = ("d0M", "d1M") if group == "propd" else ("m0M", "m1M")
    if flux:
        m = res["end"][keys[0]][ci] + (kappa if curv else 0.0) * res["end"][keys[1]][ci]
        K = np.array([th[0], th[1], th[2] * m, th[3] * m])
    else:
        m = res["end"]["tM"][ci]
        K = th
    return rf.errors_pct(rf.extract(K, m), truth(c, res, ci)), cond


def fit_rls(c, res, ci, name):
    th = res["rls"][name][ci]
    if name == "fw":
        est = rf.extract(th, res["end"]["iM"][ci])
    else:
        m = res["end"]["mdkM"][ci]
        est = rf.extract(np.array([th[0], th[1], th[2] * m, th[3] * m]), m)
    return rf.errors_pct(est, truth(c, res, ci))


GROUPS_ALL = {"fw": rf.fw_group(None), "prop": rf.prop_group, "propd": rf.propd_group}
GROUPS_MIN = {"fw": rf.fw_group(None), "propd": rf.propd_group}


def beta(c):
    """w_r Tr (w_e Ts)^2 / (12 sigma) at the target speed, 15 kHz: the size
    of the ripple's flux effect against the resistive term (see the .md)"""
    we = c.w_target * (1.0 + 0.02)
    return c.w_target * c.Tr * (we / 15000.0) ** 2 / (12.0 * c.sigma)


def fmt_err(e):
    k, v = rf.worst(e)
    return f"{k} {v:+.2f}"


def fmt_err3(e):
    k, v = rf.worst(e)
    return f"{k} {v:+.3f}"


def motor_cols(c):
    return {"motor": c.name, "sigma": round(c.sigma, 3), "Tr_s": round(c.Tr, 4),
            "wrTr": round(c.w_target * c.Tr, 1), "beta": round(beta(c), 4)}


def md_table(rows, cols, heads=None):
    heads = heads or cols
    out = ["| " + " | ".join(heads) + " |", "|" + "---|" * len(cols)]
    for r in rows:
        out.append("| " + " | ".join(str(r.get(c, "")) for c in cols) + " |")
    return "\n".join(out)


def save(out, name, obj):
    out.mkdir(parents=True, exist_ok=True)
    (out / f"{name}.json").write_text(json.dumps(obj, indent=1, default=float))


# --------------------------------------------------------------------------
# commands
# --------------------------------------------------------------------------
def cmd_diagnose(a):
    cases = named_cases() + ci_cases()
    res = idd.simulate(cases, idd.Options(), groups={"fw": rf.fw_group(None)})
    rows, causes_all = [], []
    for ci, c in enumerate(cases):
        G = res["gram"]["fw"][ci]
        iM = res["end"]["iM"][ci]
        n = res["rows"][ci]
        th, causes, total = rf.diagnose(G, c, iM, n)
        reg = [0, 1, 2, 3]
        e_fw, cond = fit_fw(c, res, ci)
        K3 = th[2]
        # row residuals at the end of the ramp (recorded, psi0 = Lm i_M ref)
        r = res["rec"]
        on = r["rls"][:, ci] > 0.5
        iend = np.nonzero(on)[0]
        t_end_ramp = c.magnetize_s + c.w_target / (c.ramp_rpm_s * 2 * math.pi / 60 * c.p)
        jr = iend[np.argmin(np.abs(r["t"][iend] - t_end_ramp))] if len(iend) else 0
        K3n = c.true_K(c.Lm * c.i_m)[2]
        psi = r["psiM"][:, ci] + 1j * r["psiT"][:, ci]
        row = motor_cols(c)
        row.update({"cond_pu": round(cond, 1), "firmware": fmt_err(e_fw),
                    "Rr_fw": round(e_fw["Rr"], 3), "Rs_fw": round(e_fw["Rs"], 3),
                    "Tr_fw": round(e_fw["Tr"], 3),
                    "row1_mean_pctK3": round(float(G[2] @ total) / n / K3 * 100, 3),
                    "row1_end_ramp_pctK3": round(float(r["r1"][jr, ci]) / K3n * 100, 2),
                    "psi_change_pct": round(float(abs(psi[iend[-1]]) / abs(psi[iend[0]]) - 1) * 100, 3),
                    "qd_end_pct": round(float(psi[jr].imag / psi[jr].real) * 100, 3)})
        cz = {"motor": c.name}
        for name, rc in causes.items():
            d = rf.proj(G, reg, rc)
            e = rf.errors_pct(rf.extract(th + d, iM), rf.extract(th, iM))
            cz[name] = {"Rr": round(e["Rr"], 3), "Rs": round(e["Rs"], 3), "Tr": round(e["Tr"], 3),
                        "Lm": round(e["Lm"], 3),
                        "row1_mean_pctK3": round(float(G[2] @ rc) / n / K3 * 100, 3),
                        "rms_pctK3": round(float(np.sqrt(max(rc @ G @ rc, 0) / (2 * n)) / K3 * 100), 3)}
        rows.append(row)
        causes_all.append(cz)
    print("### Firmware regression (eq. 7, constant third regressor), batch fit, ideal plant\n")
    print(md_table(rows, ["motor", "sigma", "Tr_s", "wrTr", "beta", "cond_pu", "Rr_fw", "Rs_fw",
                          "Tr_fw", "firmware", "row1_mean_pctK3", "row1_end_ramp_pctK3",
                          "psi_change_pct", "qd_end_pct"],
                   ["motor", "sigma", "Tr s", "w_r Tr", "beta", "cond (pu)", "Rr %", "Rs %",
                    "Tr %", "worst %", "row 1 mean, % K3", "row 1 at ramp end, % K3",
                    "|psi_r| change in window %", "psi q/d at ramp end %"]))
    print("\n### Bias of the batch fit from each cause alone: Rr % (Rs %)\n")
    heads = ["motor"] + [n.split(" ", 1)[0] for n in rf.CAUSES]
    crow = []
    for cz in causes_all:
        d = {"motor": cz["motor"]}
        for n in rf.CAUSES:
            d[n.split(" ", 1)[0]] = f"{cz[n]['Rr']:+.2f} ({cz[n]['Rs']:+.2f})"
        crow.append(d)
    print(md_table(crow, heads))
    print("\n" + "\n".join(f"- {n}" for n in rf.CAUSES))
    print("\n### Mean row-1 residual of each cause over the RLS window, % of K3\n")
    crow = []
    for cz in causes_all:
        d = {"motor": cz["motor"]}
        for n in rf.CAUSES:
            d[n.split(" ", 1)[0]] = f"{cz[n]['row1_mean_pctK3']:+.3f}"
        crow.append(d)
    print(md_table(crow, heads))
    save(a.out, "diagnose", {"rows": rows, "causes": causes_all})


def cmd_validate(a):
    cases = named_cases() + (grid_cases() if a.grid else ci_cases())
    res = idd.simulate(cases, idd.Options(rls=("fw", "prop")), groups=GROUPS_ALL)
    rows = []
    worst_prop = {k: 0.0 for k in rf.PARAMS}
    for ci, c in enumerate(cases):
        e_fw, cond = fit_fw(c, res, ci)
        e_p, condp = fit_prop(c, res, ci, "propd")
        e_pm, _ = fit_prop(c, res, ci, "propd", y_mean=True)   # the form of §5.1 (d)
        e_x, _ = fit_prop(c, res, ci, "prop")
        e_r = fit_rls(c, res, ci, "prop")
        e_rf = fit_rls(c, res, ci, "fw")
        for k in rf.PARAMS:
            worst_prop[k] = max(worst_prop[k], abs(e_p[k]), abs(e_r[k]), abs(e_pm[k]))
        row = motor_cols(c)
        row.update({"cond_fw": round(cond, 1), "cond_prop": round(condp, 1),
                    "fw_batch": fmt_err(e_fw), "fw_rls": fmt_err(e_rf),
                    "prop_batch": fmt_err3(e_p), "prop_exact_shadow": fmt_err3(e_x),
                    "prop_ymean": fmt_err3(e_pm),
                    "prop_rls": fmt_err3(e_r),
                    "prop_all": {k: round(v, 4) for k, v in e_p.items()},
                    "prop_ymean_all": {k: round(v, 4) for k, v in e_pm.items()},
                    "fw_all": {k: round(v, 3) for k, v in e_fw.items()}})
        rows.append(row)
    print(md_table(rows, ["motor", "sigma", "Tr_s", "wrTr", "beta", "cond_fw", "fw_batch", "fw_rls",
                          "cond_prop", "prop_batch", "prop_ymean", "prop_exact_shadow", "prop_rls"],
                   ["motor", "sigma", "Tr s", "w_r Tr", "beta", "cond fw", "firmware batch: worst %",
                    "firmware RLS (double)", "cond prop.", "proposal batch: worst %",
                    "d/dt of filtered i_bar", "with exact shadow flux", "proposal RLS (double)"]))
    print("\nlargest |error| of the proposal over these motors (batch and RLS), %: "
          + ", ".join(f"{k} {v:.3f}" for k, v in worst_prop.items()))
    abl_rows = []
    if not a.grid:
        variants = (
            ("proposal", {}),
            ("K2 of the correction = nameplate x0.8", {"kappa": "0.8"}),
            ("K2 of the correction = nameplate x1.2", {"kappa": "1.2"}),
            ("no ripple correction (K2 c = 0)", {"curv": False}),
            ("sample current in the K1 column", {"sample_i": True}),
            ("firmware voltage (no sinc)", {"fw_u": True}),
            ("constant flux (1, w_r) with i_bar, u_bar", {"flux": False}),
            ("derivative of the filtered mean current", {"y_mean": True}))
        for ci, c in enumerate(cases):
            d = {"motor": c.name}
            for lab, kw in variants:
                kw = dict(kw)
                if "kappa" in kw:
                    kw["kappa"] = float(kw["kappa"]) / (c.sigma * c.Ls)
                e, _ = fit_prop(c, res, ci, "propd", **kw)
                d[lab] = fmt_err(e)
            abl_rows.append(d)
        labs = [v[0] for v in variants]
        print("\n### What each piece of the proposal does (batch fit, worst parameter %)\n")
        print(md_table(abl_rows, ["motor"] + labs))
    save(a.out, "validate_grid" if a.grid else "validate",
         {"rows": rows, "worst_prop": worst_prop, "ablation": abl_rows})


def swing_variants(c, excitation=False):
    """the operating choices of the issue, one at a time, scaled to the motor"""
    T_N = c.T_N
    frac = (c.load_const + c.load_fan) / T_N if T_N > 0 else 0.4

    def load(L):
        return {"load_const": 0.25 * L * T_N, "load_fan": 0.75 * L * T_N}

    def vdc_for(i_m):
        w = c.w_target * 1.05
        need = math.hypot(c.Rs * i_m, w * c.Ls * i_m) + w * c.sigma * c.Ls * c.max_torque_current_A
        return max(c.vdc, 1.2 * SQRT3 * need)
    v = [("nominal", {}),
         ("rls_tail_s 0", {"rls_tail_s": 0.0}), ("rls_tail_s 0.6", {"rls_tail_s": 0.6}),
         ("i_M x0.75", {"i_m": 0.75 * c.i_m}),
         ("i_M x1.5", {"i_m": 1.5 * c.i_m, "vdc": vdc_for(1.5 * c.i_m)}),
         ("ramp x0.5", {"ramp_rpm_s": 0.5 * c.ramp_rpm_s}), ("ramp x2", {"ramp_rpm_s": 2 * c.ramp_rpm_s}),
         ("no load", load(0.0)), ("load 100 %", load(1.0)),
         ("target x0.5", {"target_rpm": 0.5 * c.target_rpm})]
    if excitation:
        # the proposed excitation: two ramp rates, the second half of the
        # speed range at a third of the first's (a step of the acceleration
        # torque at half speed, independent of the load)
        r2 = {"profile": "ramp2", "ramp2_rpm_s": c.ramp_rpm_s / 3.0}
        v += [("two-rate ramp", r2), ("two-rate ramp, no load", {**r2, **load(0.0)}),
              ("two-rate ramp, target x0.5", {**r2, "target_rpm": 0.5 * c.target_rpm}),
              ("two-rate ramp, i_M x1.5", {**r2, "i_m": 1.5 * c.i_m, "vdc": vdc_for(1.5 * c.i_m)})]
    return v, frac


def cmd_swing(a):
    bases = [case_from_motor(s077_motor())] + (ci_cases() if not a.quick else [])
    cases, meta = [], []
    for b in bases:
        vs, frac = swing_variants(b, excitation=True)
        for lab, over in vs:
            cases.append(replace(b, name=f"{b.name} | {lab}", **over))
            meta.append((b.name, lab))
    res = idd.simulate(cases, idd.Options(), groups=GROUPS_MIN)
    table = {}
    for ci, c in enumerate(cases):
        e_fw, cond = fit_fw(c, res, ci)
        e_p, condp = fit_prop(c, res, ci, "propd")
        table.setdefault(meta[ci][0], []).append(
            {"choice": meta[ci][1], "cond": round(cond, 1), "fw_Rr": round(e_fw["Rr"], 2),
             "fw_worst": fmt_err(e_fw), "prop_Rr": round(e_p["Rr"], 3), "prop_worst": fmt_err3(e_p),
             "fw_all": e_fw, "prop_all": e_p})
    for name, rows in table.items():
        print(f"\n#### {name}\n")
        print(md_table(rows, ["choice", "cond", "fw_Rr", "fw_worst", "prop_Rr", "prop_worst"],
                       ["operating choice", "cond (pu)", "firmware Rr %", "firmware worst %",
                        "proposal Rr %", "proposal worst %"]))
        fw_span = max(r["fw_Rr"] for r in rows) - min(r["fw_Rr"] for r in rows)
        pw = max(abs(v) for r in rows for v in r["prop_all"].values())
        print(f"\nspread of the firmware's Rr over the choices: {fw_span:.2f} points; "
              f"proposal: every parameter within {pw:.3f} %")
    save(a.out, "swing", table)


def cmd_rate(a):
    bases = [case_from_motor(s077_motor())] + (ci_cases() if not a.quick else []) \
        + [idd.case_from_ini(CONFIG / "motor_15kw.ini", name="15 kW (motor_15kw)")]
    rows = []
    for N, mode in ((1, "avg"), (2, "avg"), (4, "avg"), (8, "avg"), (2, "decim"), (4, "decim"),
                    (8, "decim")):
        res = idd.simulate(bases, idd.Options(rate_div=N, rate_mode=mode), groups=GROUPS_MIN)
        for ci, c in enumerate(bases):
            e_fw, _ = fit_fw(c, res, ci)
            e_p, _ = fit_prop(c, res, ci, "propd")
            rows.append({"motor": c.name, "N": N, "mode": mode, "fw_worst": fmt_err(e_fw),
                         "prop_worst": fmt_err3(e_p), "fw_all": e_fw, "prop_all": e_p})
        print(f"N={N} {mode} done", file=sys.stderr)
    print(md_table(rows, ["motor", "N", "mode", "fw_worst", "prop_worst"],
                   ["motor", "N", "mode", "firmware worst %", "proposal worst %"]))
    save(a.out, "rate", rows)


def cmd_isr(a):
    base = case_from_motor(s077_motor())
    rows = []
    for f in (8000.0, 15000.0, 20000.0, 30000.0, 45000.0):
        res = idd.simulate([base], idd.Options(pwm_Hz=f), groups=GROUPS_MIN)
        e_fw, _ = fit_fw(base, res, 0)
        e_p, _ = fit_prop(base, res, 0, "propd")
        we = base.w_target * 1.02
        rows.append({"isr_kHz": f / 1e3, "weTs": round(we / f, 4), "fw_Rr": round(e_fw["Rr"], 2),
                     "fw_Rs": round(e_fw["Rs"], 2), "prop_worst": fmt_err3(e_p),
                     "fw_all": e_fw, "prop_all": e_p})
        print(f"{f} done", file=sys.stderr)
    print(md_table(rows, ["isr_kHz", "weTs", "fw_Rr", "fw_Rs", "prop_worst"],
                   ["ISR kHz", "w_e Ts at target", "firmware Rr %", "firmware Rs %",
                    "proposal worst %"]))
    save(a.out, "isr", rows)


def cmd_sensitivity(a):
    """Not an ideal-plant result: how a small error of the voltage the
    identification sees (what a real drive's reconstruction leaves) reaches
    the proposal's parameters, against the speed it learns up to (w_r Tr)."""
    bases = [case_from_motor(s077_motor()),
             case_from_motor(fam.design(11.0, 4, 50.0, 690.0, 0.05))]
    cases = []
    for b in bases:
        for f in (1.0, 0.5, 0.25):
            cases.append(replace(b, name=f"{b.name}, target x{f:g}", target_rpm=f * b.target_rpm))
    rows = {}
    for lab, kw in (("ideal", {}), ("voltage gain +0.1 %", {"u_gain_err": 1e-3}),
                    ("0.5 V along the current", {"u_dt_V": 0.5})):
        res = idd.simulate(cases, idd.Options(**kw), groups=GROUPS_MIN)
        for ci, c in enumerate(cases):
            e_fw, _ = fit_fw(c, res, ci)
            e_p, _ = fit_prop(c, res, ci, "propd")
            r = rows.setdefault(c.name, {"case": c.name, "wrTr": round(c.w_target * c.Tr, 1)})
            r[f"{lab}: firmware"] = f"Rr {e_fw['Rr']:+.2f} Rs {e_fw['Rs']:+.2f}"
            r[f"{lab}: proposal"] = f"Rr {e_p['Rr']:+.2f} Rs {e_p['Rs']:+.2f}"
        print(f"{lab} done", file=sys.stderr)
    rows = list(rows.values())
    cols = list(rows[0].keys())
    print(md_table(rows, cols))
    save(a.out, "sensitivity", rows)


def run_motor_sim(ini_text, tag, tmp):
    exe = ROOT / "build" / "host-iq" / "host_sim" / "sim" / "motor_sim"
    if not exe.exists():
        raise SystemExit(f"{exe} missing: cmake --preset host-iq && cmake --build --preset host-iq "
                         f"-j2 --target motor_sim")
    ini = tmp / f"{tag}.ini"
    ini.write_text(ini_text)
    out = tmp / f"out_{tag}"
    p = subprocess.run([str(exe), "--config", str(ini), "--out", str(out), "--quiet"],
                       stdout=subprocess.DEVNULL)
    if p.returncode not in (0, 3):   # 3: the run completed, the drive published nothing
        raise SystemExit(f"motor_sim failed ({p.returncode}) on {ini}")
    rep = json.loads((out / "report.json").read_text())
    bl = subprocess.run([sys.executable, str(ROOT / "tools" / "batch_ls.py"), str(out), "--json"],
                        check=True, capture_output=True, text=True)
    b = json.loads(bl.stdout)   # the paper's rows (eq. 7), whatever form the drive ran
    e = rep.get("last_extraction_error_pct") or {}   # the RLS's, published or not
    keymap = {"Rs": "Rs_ohm", "Rr": "Rr_ohm", "Lm": "Lm_H", "Lr": "Lr_H", "psi_r": "psi_r_Wb",
              "Tr": "Tr_s"}
    rls = {k: e.get(v) for k, v in keymap.items()} if e else None
    batch = ({k: (1 + rls[k] / 100) / (1 + b["params_diff_pct"][k] / 100) * 100 - 100
              for k in keymap} if rls else None)
    return {"rls": rls, "batch": batch, "cond": b["condition"],
            "qd": rep.get("max_flux_q_over_d"), "published": rep.get("published")}


def cmd_motor_sim(a):
    m = s077_motor()
    rows = []
    with tempfile.TemporaryDirectory() as td:
        tmp = Path(td)
        c = case_from_motor(m)
        vs, _ = swing_variants(c)
        key = {"rls_tail_s": ("ident", "rls_tail_s"), "i_m": ("controller", "magnetizing_current_A"),
               "ramp_rpm_s": ("controller", "speed_ramp_rpm_s"), "load_const": ("load", "const_Nm"),
               "load_fan": ("load", "fan_Nm"), "target_rpm": ("ident", "target_speed_rpm"),
               "vdc": ("board", "vdc_nominal_V")}
        for plant in ("ideal", "realistic"):
            for lab, over in (vs if plant == "ideal" else vs[:1]):
                extra = dict(IDEAL_EXTRA) if plant == "ideal" else {}
                for k, v in over.items():
                    extra[key[k]] = v
                if "vdc" in over:   # keep the trips and the sensor range around the raised bus
                    extra[("controller", "vdc_max_V")] = 1.25 * over["vdc"]
                    extra[("controller", "vdc_min_V")] = 0.75 * over["vdc"]
                    extra[("board", "vdc_full_scale_V")] = 50 * math.ceil(over["vdc"] * 5 / 3 / 50)
                r = run_motor_sim(fam.to_ini(m, extra=extra), f"{plant}_{len(rows)}", tmp)
                # the same with the firmware's period-mean regression (§10)
                extra[("ident", "period_mean")] = 1
                q = run_motor_sim(fam.to_ini(m, extra=extra), f"{plant}_{len(rows)}_pm", tmp)
                worst = (max(q["rls"].items(), key=lambda kv: abs(kv[1])) if q["rls"] else None)
                rows.append({"plant": plant, "choice": lab, "cond": round(r["cond"], 1),
                             "rls_Rr": None if not r["rls"] else round(r["rls"]["Rr"], 2),
                             "rls_Tr": None if not r["rls"] else round(r["rls"]["Tr"], 2),
                             "batch_Rr": None if not r["batch"] else round(r["batch"]["Rr"], 2),
                             "pm_Rr": None if not q["rls"] else round(q["rls"]["Rr"], 2),
                             "pm_Tr": None if not q["rls"] else round(q["rls"]["Tr"], 2),
                             "pm_worst": None if not worst else f"{worst[0]} {worst[1]:+.2f}",
                             "rls": r["rls"], "batch": r["batch"], "pm": q["rls"]})
    print(md_table(rows, ["plant", "choice", "cond", "rls_Rr", "rls_Tr", "batch_Rr", "pm_Rr",
                          "pm_Tr", "pm_worst"],
                   ["plant", "operating choice", "cond (pu)", "RLS (fixed point) Rr %",
                    "RLS Tr %", "batch LS of its trace Rr %", "period_mean 1: RLS Rr %",
                    "RLS Tr %", "worst %"]))
    save(a.out, "motor_sim", rows)


S077_HEADER = """; The issue's small-leakage motor at high speed (docs/accuracy.md, tools/study/
; regression_bias.md §3): 1 kW, 4 poles, 100 Hz, 400 V, sigma 0.077, Tr set to
; 69 / (2 pi 100) s (w_r Tr = 69 at 3000 r/min), on the ideal plant (motors.py
; IDEAL_PLANT: no dead time, drop, ripple, sensor errors or noise).  Written by
;   tools/study/regression_bias.py write-s077 tests/sim/motor_1kw_s077_ideal.ini
; for the CTest sim_period_mean; not a user's file.
"""


def cmd_write_s077(a):
    """The issue's motor on the ideal plant as an INI file (the CTest's)."""
    if a.target is None:
        raise SystemExit("regression_bias.py write-s077 FILE")
    Path(a.target).write_text(S077_HEADER + fam.to_ini(s077_motor(), extra=dict(IDEAL_EXTRA)))
    print(f"wrote {a.target}")


def cmd_family_seeds(a):
    """The paper's rows against the period-mean rows (`[ident] period_mean`)
    on the 56-motor grid, ideal bridge with the sensors' noise (motors.py
    IDEAL_BRIDGE), FLOAT_MATH motor_sim, noise seeds 1..N: per motor the mean
    over the seeds of each parameter's error (the RLS's extraction), its
    largest, and that parameter's standard deviation over the seeds."""
    import statistics
    from concurrent.futures import ProcessPoolExecutor
    sys.path.insert(0, str(ROOT / "tools"))
    import family_sweep as fs
    names = [m.name for m in fam.grid()]
    plants = []
    for s in range(1, a.seeds + 1):
        fs.PLANTS[f"ideal_bridge_seed{s}"] = {**fam.IDEAL_BRIDGE, ("sensors", "seed"): s}
        plants.append(f"ideal_bridge_seed{s}")
    jobs = [(n, "nominal", seq, "float", None, {}, pl) for n in names
            for seq in ("paper", "paper_pm") for pl in plants]
    with ProcessPoolExecutor(max_workers=a.jobs) as pool:
        rows = list(pool.map(fs.run_one, jobs, chunksize=1))
    keys = ("Rs", "Rr", "Lm", "Lr", "psi_r", "Tr")
    per = {}
    for r in rows:
        if r["rls_Rr"] is None:
            continue
        per.setdefault((r["motor"], r["seq"]), []).append([r["rls_" + k] for k in keys])
    out = {}
    for (name, seq), errs in per.items():
        means = [statistics.mean(e[i] for e in errs) for i in range(6)]
        i = max(range(6), key=lambda j: abs(means[j]))
        sd = statistics.stdev(e[i] for e in errs) if len(errs) > 1 else 0.0
        out.setdefault(seq, []).append({"motor": name, "param": keys[i], "mean": means[i],
                                        "sd": sd, "n": len(errs)})
    lines = [f"| rows | motors | median of the worst mean % | 90th percentile | largest | "
             f"within 0.5 % | within 1 % | median sd over the seeds % |", "|---|---|---|---|---|---|---|---|"]
    for seq, label in (("paper", "paper's (eq. 7)"), ("paper_pm", "period-mean")):
        v = sorted(abs(x["mean"]) for x in out.get(seq, []))
        if not v:
            continue
        sds = sorted(x["sd"] for x in out[seq])
        lines.append(f"| {label} | {len(v)} | {statistics.median(v):.2f} | "
                     f"{v[min(len(v) - 1, int(0.9 * len(v)))]:.2f} | {v[-1]:.2f} | "
                     f"{sum(x <= 0.5 for x in v)} | {sum(x <= 1.0 for x in v)} | "
                     f"{statistics.median(sds):.2f} |")
    print("\n".join(lines))
    worst = sorted(out.get("paper_pm", []), key=lambda x: -abs(x["mean"]))[:6]
    print("\nlargest means, period-mean rows: " +
          ", ".join(f"{x['motor']} {x['param']} {x['mean']:+.2f} (sd {x['sd']:.2f})" for x in worst))
    save(a.out, "family_seeds", out)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("command", choices=("diagnose", "validate", "swing", "rate", "isr", "motor_sim",
                                        "sensitivity", "write-s077", "family-seeds"))
    ap.add_argument("target", nargs="?", help="write-s077: the INI file to write")
    ap.add_argument("--seeds", type=int, default=8, help="family-seeds: noise seeds per motor "
                    "(four understated the scatter: regression_bias.md §10)")
    ap.add_argument("--jobs", type=int, default=2, help="family-seeds: motor_sim runs at a time")
    ap.add_argument("--grid", action="store_true", help="validate: the whole family grid")
    ap.add_argument("--quick", action="store_true", help="swing/rate: the 1 kW motor only")
    ap.add_argument("--out", type=Path, default=ROOT / "out" / "regression_bias")
    a = ap.parse_args(argv)
    {"diagnose": cmd_diagnose, "validate": cmd_validate, "swing": cmd_swing, "rate": cmd_rate,
     "isr": cmd_isr, "motor_sim": cmd_motor_sim, "sensitivity": cmd_sensitivity,
     "write-s077": cmd_write_s077, "family-seeds": cmd_family_seeds}[a.command](a)
    return 0


if __name__ == "__main__":
    sys.exit(main())
