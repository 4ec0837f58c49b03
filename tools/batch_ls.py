#!/usr/bin/env python3
"""Offline batch least squares of the identification regression, as an
independent check of the firmware's fixed-point RLS.

Reads DIR/trace.csv (motor_sim --out DIR) and fits, on the rows where the RLS
was updating (column rls_on), the same two-row regression (method §2, eq. 7,
constant third regressor, all signals filtered, pu):

    y1 = K1 i_Mf + K2 u_Mf + K3 * 1
    y2 = K1 i_Tf + K2 u_Tf          + K4 w_rf

by numpy's lstsq over all rows at once (no recursion, no prior, double
precision), then compares K1..K4 and the parameters they give (method §4, in
pu; i_M = the filtered M current at the last RLS row) with the RLS estimate
the firmware held at its last update.  The trace is written at 1 kHz, so the
batch fit sees every 15th sample of what the RLS saw (same regression, fewer
rows); with P(0) large and no forgetting both estimate the same minimiser.

Usage: batch_ls.py DIR|trace.csv [--json]
Exit status 0, or 1 if the trace has no RLS rows.
"""
import argparse
import json
import sys
from pathlib import Path

import numpy as np

K_NAMES = ("K1", "K2", "K3", "K4")
REG_COLUMNS = ("rls_on", "y1", "y2", "i_mf", "u_mf", "i_tf", "u_tf", "wr_f")


def regression_matrix(i_mf, u_mf, i_tf, u_tf, wr_f, y1, y2):
    """Stacked rows [row 1 of every sample; row 2 of every sample]."""
    n = len(y1)
    z, one = np.zeros(n), np.ones(n)
    phi = np.vstack((np.column_stack((i_mf, u_mf, one, z)),
                     np.column_stack((i_tf, u_tf, z, wr_f))))
    return phi, np.concatenate((y1, y2))


def fit(i_mf, u_mf, i_tf, u_tf, wr_f, y1, y2):
    """theta = [K1, K2, K3, K4] minimising sum(e1^2 + e2^2); also returns the
    rms residual and the condition number of the scaled regression."""
    phi, y = regression_matrix(*(np.asarray(a, float) for a in
                                 (i_mf, u_mf, i_tf, u_tf, wr_f, y1, y2)))
    theta, _res, _rank, sv = np.linalg.lstsq(phi, y, rcond=None)
    rms = float(np.sqrt(np.mean((y - phi @ theta) ** 2)))
    cond = float(sv[0] / sv[-1]) if sv[-1] > 0 else float("inf")
    return theta, rms, cond


def parameters(K, i_m):
    """method §4 (Ls = Lr), pu; constant form: K3' = K3 / K2."""
    K1, K2, K3, K4 = K
    K3p = K3 / K2
    a = -K4 / (K2 * i_m)
    Lr = 1.0 / K2 + a
    Lm = float(np.sqrt(a * Lr)) if a * Lr > 0 else float("nan")
    return {"Rs": -K1 / K2 - K3p / i_m, "Rr": K3p * Lr / (a * i_m), "Lm": Lm, "Lr": Lr,
            "psi_r": Lm * i_m, "Tr": -K4 / (K2 * K3p)}


def load(path):
    p = Path(path)
    if p.is_dir():
        p = p / "trace.csv"
    d = np.genfromtxt(p, delimiter=",", names=True)
    missing = [c for c in REG_COLUMNS + K_NAMES if c not in d.dtype.names]
    if missing:
        raise SystemExit(f"batch_ls: {p} lacks columns {missing} (an older motor_sim?)")
    return d


def check(d):
    on = d["rls_on"] > 0.5
    if not np.any(on):
        return None
    sel = {c: d[c][on] for c in ("i_mf", "u_mf", "i_tf", "u_tf", "wr_f", "y1", "y2")}
    theta, rms, cond = fit(**sel)
    last = np.nonzero(on)[0][-1]
    k_rls = np.array([d[k][last] for k in K_NAMES])
    i_m = float(d["i_mf"][last])
    p_ls, p_rls = parameters(theta, i_m), parameters(k_rls, i_m)
    return {
        "rows": int(on.sum()),
        "rms_residual_pu": rms,
        "condition": cond,
        "K_batch": dict(zip(K_NAMES, map(float, theta))),
        "K_rls": dict(zip(K_NAMES, map(float, k_rls))),
        "K_diff_pct": {k: float(100 * (k_rls[i] - theta[i]) / theta[i])
                       for i, k in enumerate(K_NAMES)},
        "params_batch_pu": p_ls,
        "params_rls_pu": p_rls,
        "params_diff_pct": {k: 100 * (p_rls[k] - p_ls[k]) / p_ls[k] for k in p_ls},
    }


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("trace", help="motor_sim output directory or its trace.csv")
    ap.add_argument("--json", action="store_true", help="print JSON")
    a = ap.parse_args(argv)
    r = check(load(a.trace))
    if r is None:
        print("batch_ls: no rows with rls_on = 1", file=sys.stderr)
        return 1
    if a.json:
        print(json.dumps(r, indent=2))
        return 0
    print(f"batch LS over {r['rows']} samples x 2 rows, rms residual {r['rms_residual_pu']:.3g} "
          f"pu, condition {r['condition']:.3g}")
    print("        batch LS        RLS (firmware)   RLS - LS")
    for k in K_NAMES:
        print(f"  {k}  {r['K_batch'][k]:+.8f}  {r['K_rls'][k]:+.8f}  {r['K_diff_pct'][k]:+.3f} %")
    print("  parameters (method §4, pu):")
    for k in r["params_batch_pu"]:
        print(f"  {k:5s} {r['params_batch_pu'][k]:.6g}  {r['params_rls_pu'][k]:.6g}  "
              f"{r['params_diff_pct'][k]:+.3f} %")
    return 0


if __name__ == "__main__":
    sys.exit(main())
