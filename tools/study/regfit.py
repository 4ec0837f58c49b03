"""Regression groups, batch least squares from Gram matrices, and the parameter
extraction of method §4, for tools/study/regression_bias.py.

A group is a function sig -> (X1, X2): the filtered columns of row 1 and row 2
of every sample (arrays (C, ncol)); ideal_drive.simulate accumulates
G = sum x x^T over the RLS rows.  Column layouts are fixed here (the *_COLS
tuples) so that the fits can pick their columns by name.
"""
from __future__ import annotations

import numpy as np

# --------------------------------------------------------------------------
# column layouts
# --------------------------------------------------------------------------
# The firmware's regression (method §2, eq. 7, constant third regressor) and
# the residual pieces of the diagnosis (each a column, zero in the other row).
FW_COLS = ("phi1", "phi2", "phi3", "phi4", "y",
           # C1 flux magnitude: row 1 K3c (psibar_M - psi0), row 2 -Kq (w_r psibar_M - w_r psi0),
           # split into the current model's flux (ifo's i_mr: the build-up) and the
           # true flux against it (what the period-mean current does)
           "r1_pM", "r1_one", "r2_wrpM", "r2_wr", "r1_imr", "r2_wrimr",
           # C2 flux q component: row 1 Kq w_r psibar_T, row 2 K3c psibar_T
           "r1_wrpT", "r2_pT",
           # C3 sampled vs mean current: shift (trapezoid - sample) and curvature (mean - trapezoid)
           "r1_shM", "r1_shwsT", "r2_shT", "r2_shwsM",
           "r1_cvM", "r1_cvwsT", "r2_cvT", "r2_cvwsM",
           # C4 voltage: exact period mean (sinc) - firmware's
           "r1_uM", "r2_uT",
           # C5 the filter's derivative output - the filtered period difference
           "r1_dy", "r2_dy")

# The proposal: period-mean current (trapezoid + K2 c), exact period-mean voltage,
# the rotor flux of a shadow current model in the controller's frame (m = m0 + K2 m1),
# plus the constant and w_r columns (for hybrids): phi = B + K2 E, y = yB + K2 yE.
PROP_COLS = ("B1", "B2", "B3", "B4", "E1", "E3", "E4", "one", "wr", "yB", "yE",
             "s_i", "s_u",  # the firmware's sample current and voltage, for ablations
             "yB2", "yE2")  # y with the derivative of the filtered mean current instead of the sample's

# the exact-oracle regression (period means and true rotor flux from the plant)
EX_COLS = ("phi1", "phi2", "phi3", "phi4", "y")


def fw_group(K):
    """The firmware's regression and the diagnosis columns; K: per-case dict of
    constants (not used here: the constants are applied after the run)."""
    def fn(sig):
        f = sig["f"]
        y, dy = f.y, f.dy
        C = y("iM").shape[0]
        z = np.zeros(C)
        one = y("one")
        wr = y("wr")
        y1 = dy("iM") - y("wsiT")
        y2 = dy("iT") + y("wsiM")
        X1 = np.column_stack([
            y("iM"), y("uM"), one, z, y1,
            y("pbM"), one, z, z, y("imr"), z,
            y("wrpbT"), z,
            y("tM") - y("iM"), y("wstT") - y("wsiT"), z, z,
            y("ibM") - y("tM"), y("wsibT") - y("wstT"), z, z,
            y("ubM") - y("uM"), z,
            dy("iM") - y("diM"), z])
        X2 = np.column_stack([
            y("iT"), y("uT"), z, wr, y2,
            z, z, y("wrpbM"), wr, z, y("wrimr"),
            z, y("pbT"),
            z, z, y("tT") - y("iT"), y("wstM") - y("wsiM"),
            z, z, y("ibT") - y("tT"), y("wsibM") - y("wstM"),
            z, y("ubT") - y("uT"),
            z, dy("iT") - y("diT")])
        return X1, X2
    return fn


def prop_group(sig):
    f = sig["f"]
    y, dy = f.y, f.dy
    C = y("iM").shape[0]
    z = np.zeros(C)
    X1 = np.column_stack([
        y("tM"), y("ubM"), y("m0M"), -y("wrm0T"),
        y("cM"), y("m1M"), -y("wrm1T"), y("one"), z,
        dy("iM") - y("wstT"), -y("wscT"), y("iM"), y("uM"),
        dy("tM") - y("wstT"), dy("cM") - y("wscT")])
    X2 = np.column_stack([
        y("tT"), y("ubT"), y("m0T"), y("wrm0M"),
        y("cT"), y("m1T"), y("wrm1M"), z, y("wr"),
        dy("iT") + y("wstM"), y("wscM"), y("iT"), y("uT"),
        dy("tT") + y("wstM"), dy("cT") + y("wscM")])
    return X1, X2


def propd_group(sig):
    """as prop_group, the flux in the firmware-friendly form: ifo's i_mr on the
    M axis plus an Euler correction (d0 + K2 d1)"""
    f = sig["f"]
    y, dy = f.y, f.dy
    C = y("iM").shape[0]
    z = np.zeros(C)
    X1 = np.column_stack([
        y("tM"), y("ubM"), y("d0M"), -y("wrd0T"),
        y("cM"), y("d1M"), -y("wrd1T"), y("one"), z,
        dy("iM") - y("wstT"), -y("wscT"), y("iM"), y("uM"),
        dy("tM") - y("wstT"), dy("cM") - y("wscT")])
    X2 = np.column_stack([
        y("tT"), y("ubT"), y("d0T"), y("wrd0M"),
        y("cT"), y("d1T"), y("wrd1M"), z, y("wr"),
        dy("iT") + y("wstM"), y("wscM"), y("iT"), y("uT"),
        dy("tT") + y("wstM"), dy("cT") + y("wscM")])
    return X1, X2


def propk_group(sig):
    """the proposal as the firmware would form it with the RLS's running K2
    (firmware-friendly flux form): regressors and y, ready to fit"""
    f = sig["f"]
    y, dy = f.y, f.dy
    X1 = np.column_stack([y("ikM"), y("ubM"), y("mdkM"), -y("wrmdkT"), dy("iM") - y("wsikT")])
    X2 = np.column_stack([y("ikT"), y("ubT"), y("mdkT"), y("wrmdkM"), dy("iT") + y("wsikM")])
    return X1, X2


def ex_group(sig):
    f = sig["f"]
    y, dy = f.y, f.dy
    X1 = np.column_stack([y("ibM"), y("ubM"), y("pbM"), -y("wrpbT"), dy("iM") - y("wsibT")])
    X2 = np.column_stack([y("ibT"), y("ubT"), y("pbT"), y("wrpbM"), dy("iT") + y("wsibM")])
    return X1, X2


def imr_group(sig):
    """the firmware's signals, but the flux-bearing columns scaled by ifo's i_mr"""
    f = sig["f"]
    y, dy = f.y, f.dy
    C = y("iM").shape[0]
    z = np.zeros(C)
    X1 = np.column_stack([y("iM"), y("uM"), y("imr"), z, dy("iM") - y("wsiT")])
    X2 = np.column_stack([y("iT"), y("uT"), z, y("wrimr"), dy("iT") + y("wsiM")])
    return X1, X2


# --------------------------------------------------------------------------
# least squares from a Gram matrix
# --------------------------------------------------------------------------
def ls_from_gram(G, reg, yc, scale=None):
    """theta minimising |y - Phi theta|^2; G: (ncol, ncol) Gram matrix of the
    columns, reg: indices (or a (ncol, P) combination matrix) of the regressors,
    yc: index (or combination vector) of y.  Returns theta and the condition
    number of the (scaled) regression matrix.  scale: per-regressor factors
    (e.g. per-unit) for the condition number only."""
    ncol = G.shape[0]
    R = _as_matrix(reg, ncol)
    yv = _as_vector(yc, ncol)
    A = R.T @ G @ R
    b = R.T @ G @ yv
    d = np.sqrt(np.diag(A))
    d[d == 0] = 1.0
    As = A / np.outer(d, d)
    theta = np.linalg.solve(As, b / d) / d
    if scale is not None:
        s = np.asarray(scale, float)
        Ap = A * np.outer(s, s)
        ev = np.linalg.eigvalsh(Ap)
        cond = float(np.sqrt(ev[-1] / ev[0])) if ev[0] > 0 else float("inf")
    else:
        ev = np.linalg.eigvalsh(As)
        cond = float(np.sqrt(ev[-1] / ev[0])) if ev[0] > 0 else float("inf")
    return theta, cond


def proj(G, reg, rc):
    """(Phi^T Phi)^-1 Phi^T r for a residual column combination rc."""
    ncol = G.shape[0]
    R = _as_matrix(reg, ncol)
    rv = _as_vector(rc, ncol)
    A = R.T @ G @ R
    d = np.sqrt(np.diag(A))
    d[d == 0] = 1.0
    return np.linalg.solve(A / np.outer(d, d), (R.T @ G @ rv) / d) / d


def _as_matrix(reg, ncol):
    R = np.asarray(reg)
    if R.ndim == 1:
        M = np.zeros((ncol, len(R)))
        M[R.astype(int), np.arange(len(R))] = 1.0
        return M
    return R


def _as_vector(c, ncol):
    v = np.asarray(c, float)
    if v.ndim == 0:
        out = np.zeros(ncol)
        out[int(c)] = 1.0
        return out
    return v


# --------------------------------------------------------------------------
# method §4
# --------------------------------------------------------------------------
def extract(K, i_m):
    """method §4 (Ls = Lr), constant form (K3 = K3' K2): K = [K1, K2, K3, K4] in
    SI with K3, K4 for the flux psi_r = Lm i_m."""
    K1, K2, K3, K4 = K
    K3p = K3 / K2
    a = -K4 / (K2 * i_m)
    Lr = 1.0 / K2 + a
    Lm = np.sqrt(a * Lr) if a * Lr > 0 else np.nan
    return {"Rs": -K1 / K2 - K3p / i_m, "Rr": K3p * Lr / (a * i_m), "Lm": Lm, "Lr": Lr,
            "psi_r": Lm * i_m, "Tr": -K4 / (K2 * K3p)}


PARAMS = ("Rs", "Rr", "Lm", "Lr", "psi_r", "Tr")


def errors_pct(est, true):
    return {k: 100.0 * (est[k] - true[k]) / true[k] for k in PARAMS}


def worst(err):
    k = max(PARAMS, key=lambda q: abs(err[q]))
    return k, err[k]


# --------------------------------------------------------------------------
# diagnosis of the firmware's regression: the residual with the true K's
# split into its causes, and the bias each cause alone gives the batch fit
# --------------------------------------------------------------------------
CAUSES = ("C1a flux build-up (ifo i_mr vs i_M)", "C1b flux vs current model (mean current)",
          "C2 flux q (orientation)", "C3a current: sample vs trapezoid",
          "C3b current: ripple curvature", "C4 voltage: rotation in the period",
          "C5 filter derivative")


def fw_constants(case, psi0):
    sls = case.sigma * case.Ls
    K3c = case.Lm * case.Rr / (sls * case.Lr ** 2)
    Kq = case.Lm / (sls * case.Lr)
    K1 = -(case.Rs / sls + case.Rr * case.Lm ** 2 / (sls * case.Lr ** 2))
    K2 = 1.0 / sls
    return K1, K2, K3c, Kq


def diagnose(G, case, i_m_end, n_rows):
    """Returns (theta_true, {cause: rc vector}, rc_total)."""
    ix = {n: i for i, n in enumerate(FW_COLS)}
    ncol = len(FW_COLS)
    psi0 = case.Lm * i_m_end
    K1, K2, K3c, Kq = fw_constants(case, psi0)
    th = np.array([K1, K2, K3c * psi0, -Kq * psi0])

    def vec(**w):
        v = np.zeros(ncol)
        for k, val in w.items():
            v[ix[k]] += val
        return v

    total = vec(y=1.0)
    for j in range(4):
        total[ix[f"phi{j + 1}"]] -= th[j]
    causes = {
        CAUSES[0]: vec(r1_imr=K3c * case.Lm, r1_one=-K3c * psi0, r2_wrimr=-Kq * case.Lm,
                       r2_wr=Kq * psi0),
        CAUSES[1]: vec(r1_pM=K3c * case.Lm, r1_imr=-K3c * case.Lm, r2_wrpM=-Kq * case.Lm,
                       r2_wrimr=Kq * case.Lm),
        CAUSES[2]: vec(r1_wrpT=Kq * case.Lm, r2_pT=K3c * case.Lm),
        CAUSES[3]: vec(r1_shM=K1, r1_shwsT=1.0, r2_shT=K1, r2_shwsM=-1.0),
        CAUSES[4]: vec(r1_cvM=K1, r1_cvwsT=1.0, r2_cvT=K1, r2_cvwsM=-1.0),
        CAUSES[5]: vec(r1_uM=K2, r2_uT=K2),
        CAUSES[6]: vec(r1_dy=1.0, r2_dy=1.0),
    }
    return th, causes, total
