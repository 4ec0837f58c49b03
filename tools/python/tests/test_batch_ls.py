"""tools/batch_ls.py against regressions with a known answer."""
import numpy as np

import batch_ls


def synthetic(theta, n=2000, noise=0.0, seed=1):
    rng = np.random.default_rng(seed)
    t = np.linspace(0, 1, n)
    i_m = 0.33 + 0.01 * np.sin(7 * t)
    u_m = 0.1 + 0.05 * np.cos(5 * t)
    i_t = 0.2 * np.sin(3 * t)
    u_t = 0.4 * t + 0.02 * np.sin(11 * t)
    wr = 0.9 * t
    y1 = theta[0] * i_m + theta[1] * u_m + theta[2] + noise * rng.standard_normal(n)
    y2 = theta[0] * i_t + theta[1] * u_t + theta[3] * wr + noise * rng.standard_normal(n)
    return i_m, u_m, i_t, u_t, wr, y1, y2


def test_exact_data_gives_exact_parameters():
    th = np.array([-0.8433, 1.1638, 0.0493, -0.3088])
    est, rms, _ = batch_ls.fit(*synthetic(th))
    np.testing.assert_allclose(est, th, rtol=1e-9)
    assert rms < 1e-12


def test_noisy_data_within_its_standard_error():
    th = np.array([-0.8433, 1.1638, 0.0493, -0.3088])
    args = synthetic(th, n=20000, noise=1e-3)
    est, rms, _ = batch_ls.fit(*args)
    phi, _ = batch_ls.regression_matrix(*args)
    # standard errors sigma^2 (Phi'Phi)^-1; 5 sigma cannot fail by chance
    se = np.sqrt(np.diag(np.linalg.inv(phi.T @ phi))) * 1e-3
    assert np.all(np.abs(est - th) < 5 * se), (est - th, se)
    assert abs(rms - 1e-3) < 1e-4


def test_parameters_of_the_reference_motor():
    """method §4's check values (SI form of the same formulas): K1 = -264.548,
    K2 = 210.623, K3' = 1.47675 V, K4 = -6.15385 A, i_M = 6.5625 A give the
    reference motor exactly (Rs 1.031, Rr 0.465, Lm 6.4 mH, Lr 9.2 mH)."""
    K2 = 210.623
    p = batch_ls.parameters((-264.548, K2, 1.47675 * K2, -6.15385), 6.5625)
    assert abs(p["Rs"] - 1.031) < 1e-3 * 1.031
    assert abs(p["Rr"] - 0.465) < 1e-3 * 0.465
    assert abs(p["Lm"] - 0.0064) < 1e-3 * 0.0064
    assert abs(p["Lr"] - 0.0092) < 1e-3 * 0.0092
    assert abs(p["Tr"] - 0.0092 / 0.465) < 1e-3 * 0.0092 / 0.465
