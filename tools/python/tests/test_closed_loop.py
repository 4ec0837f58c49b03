"""The firmware (libimfoc) in closed loop with the numpy motor of imfoc.plant."""
import numpy as np

import batch_ls
from imfoc import PARAM_NAMES


def test_identification_converges_on_numpy_plant(paper_run):
    r = paper_run
    assert r["fault"] == 0
    assert r["published"], f"no published parameters, state {r['state']}"
    assert r["state"] == "RUN"
    # Bound 0.5 %: with an ideal inverter and sensors the only imperfection is
    # the 12-bit ADC (README: 0.21 % with ideal sensors in motor_sim; 0.22 %
    # measured here, worst Rr/Tr).  A real fault (voltage timing off by one
    # period, wrong frame angle) costs several percent (README table).
    for k in PARAM_NAMES:
        assert abs(r["error_pct"][k]) < 0.5, (k, r["error_pct"])
    # the speed loop reached the 1400 r/min target (+-5 r/min: the speed
    # measurement resolution at 1000 lines and the loop's steady error)
    assert abs(r["speed_rpm"] - 1400.0) < 5.0
    # the drive's verdict through the API: published, every confidence within its
    # 3 % and above the error it carries here (an ideal plant: Tr's about 1 %)
    pub = r["publication"]
    assert pub["reason"] == "published" and pub["published"]
    for k in PARAM_NAMES:
        c = pub["confidence_pct"][k]
        assert c is not None and abs(r["error_pct"][k]) <= c <= 3.0, (k, c, r["error_pct"][k])
    assert 0.0 < pub["residual_rel"] < 0.01 and pub["excitation"] > 0.2


def test_rls_agrees_with_batch_least_squares(paper_run):
    """The fixed-point RLS against an independent double-precision batch fit
    of the same regression rows (every 15th sample the RLS used)."""
    reg = np.array(paper_run["regression"])
    assert len(reg) > 500          # ~0.7 s ramp + 0.3 s tail at 1 kHz
    theta, rms, cond = batch_ls.fit(*reg.T)
    k_rls = np.array(paper_run["K_last_rls"])
    # 0.5 %: the RLS sees 15x more rows and starts from a finite P(0); on
    # motor_sim traces the two agree within 0.11 % (BENCHMARKS.md)
    assert np.all(np.abs(k_rls - theta) <= 5e-3 * np.abs(theta)), (k_rls, theta)
