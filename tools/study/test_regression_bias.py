"""Checks of the regression-bias study (tools/study/regression_bias.md), on two
short runs (~15 s):

    .venv/bin/python -m pytest -q tools/study
"""
import sys
from pathlib import Path

import numpy as np
import pytest

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import ideal_drive as idd  # noqa: E402
import regfit as rf  # noqa: E402
import regression_bias as rb  # noqa: E402


def test_filter_map_equals_the_n_pass_iteration():
    """bw_map is improved Euler with N corrector passes (method §5)."""
    wc, Ts, N = 2 * np.pi * 10, 1 / 15000, 10
    D = idd.bw_map(wc, Ts, N)
    Fn = np.array([[0.0, 1.0], [-1.0, -np.sqrt(2)]])
    rng = np.random.default_rng(1)
    s = rng.normal(size=2)
    u = 0.3
    f = lambda x: wc * Ts * (Fn @ np.array([x[0] - u, x[1]]))  # noqa: E731
    c = s + f(s)
    for _ in range(N):
        c = s + 0.5 * (f(s) + f(c))
    assert np.allclose(s + D @ np.array([s[0] - u, s[1]]), c, rtol=0, atol=1e-14)


@pytest.fixture(scope="module")
def runs():
    paper = rb.idd.case_from_ini(rb.CONFIG / "paper_motor.ini", name="paper",
                                 target_rpm=700.0, rls_tail_s=0.1)
    s077 = rb.case_from_motor(rb.s077_motor(), ramp_rpm_s=6000.0, rls_tail_s=0.1)
    cases = [paper, s077]
    res = idd.simulate(cases, idd.Options(premag=True, rls=("prop",)),
                       groups={"fw": rf.fw_group(None), "propd": rf.propd_group, "ex": rf.ex_group})
    return cases, res


def test_decomposition_closes_and_the_exact_period_model_fits(runs):
    cases, res = runs
    for ci, c in enumerate(cases):
        G = res["gram"]["fw"][ci]
        iM = res["end"]["iM"][ci]
        th, causes, total = rf.diagnose(G, c, iM, res["rows"][ci])
        reg = [0, 1, 2, 3]
        d_total = rf.proj(G, reg, total)
        d_sum = sum(rf.proj(G, reg, rc) for rc in causes.values())
        # what the causes leave out (w_r varying within a period) is < 0.1 % of the bias
        assert np.all(np.abs(d_total - d_sum) <= 1e-3 * np.abs(d_total) + 1e-8 * np.abs(th))
        # the plant's period means and rotor flux satisfy the regression exactly
        th_x, _ = rf.ls_from_gram(res["gram"]["ex"][ci], [0, 1, 2, 3], 4)
        m = res["end"]["pbM"][ci]
        e = rf.errors_pct(rf.extract(np.array([th_x[0], th_x[1], th_x[2] * m, th_x[3] * m]), m),
                          rb.truth(c, res, ci))
        assert max(abs(v) for v in e.values()) < 0.02


def test_the_firmware_regression_is_biased_and_the_proposal_is_not(runs):
    cases, res = runs
    e_fw, _ = rb.fit_fw(cases[1], res, 1)
    assert e_fw["Rr"] > 1.0                     # the motor
    for ci, c in enumerate(cases):
        e_p, _ = rb.fit_prop(c, res, ci, "propd")
        assert max(abs(v) for v in e_p.values()) < 0.05, (c.name, e_p)
        e_r = rb.fit_rls(c, res, ci, "prop")    # double RLS, K2 from its own estimate
        assert max(abs(v) for v in e_r.values()) < 0.05, (c.name, e_r)


def test_the_ripple_offset_is_the_mean_minus_the_sample():
    """sample - mean = -K2 c on the issue's motor at speed: the M part is about
    (w_s Ts)^2 i_M / (12 sigma) (K2 u_T ~ w_s i_M / sigma)"""
    c = rb.case_from_motor(rb.s077_motor(), ramp_rpm_s=12000.0, rls_tail_s=0.05)
    res = idd.simulate([c], idd.Options(premag=True))
    r = res["rec"]
    j = len(r["t"]) - 1
    ws = r["ws"][j, 0]
    rel = (r["iM"][j, 0] - r["ibM"][j, 0]) / r["iM"][j, 0]
    expect = (ws / 15000.0) ** 2 / (12 * c.sigma)
    assert abs(rel / expect - 1) < 0.05
