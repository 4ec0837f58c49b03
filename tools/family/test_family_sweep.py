"""Checks of tools/family_sweep.py that need no simulator: the operating
choices, the summary line and the expectations check (which must be able to
fail)."""
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
import family_sweep as fs  # noqa: E402


def row(motor="m", seq="paper", status="published", worst=1.0, reason="published"):
    return {"motor": motor, "seq": seq, "build": "iq", "op": "nominal", "status": status,
            "worst_pct": worst, "worst_param": "Tr", "reason": reason, "message": ""}


SPEC = {"bound_pct": 3.0, "motors": {"m": {"paper": {"published": False,
                                                    "reasons": ["low_confidence"]},
                                          "adaptive": {"published": True, "bound_pct": 1.0}}}}


def test_check_bounds_passes_what_it_should():
    rows = [row(seq="paper", status="not_published", worst=4.0, reason="low_confidence"),
            row(seq="adaptive", worst=0.4)]
    assert fs.check_bounds(rows, SPEC) == []


@pytest.mark.parametrize("bad", [
    row(seq="paper", worst=3.5),                                   # published above 3 %
    row(seq="paper", status="not_published", reason="timeout"),    # the wrong reason
    row(seq="adaptive", worst=1.2),                                # above its own bound
    row(seq="adaptive", status="not_published", reason="low_confidence"),
    row(seq="adaptive", status="refused"),
])
def test_check_bounds_fails_what_it_should(bad):
    assert fs.check_bounds([bad], SPEC) != []


EDGE = {"bound_pct": 3.0, "motors": {"m": {"paper": {"published": None, "bound_pct": 1.0,
                                                    "reasons": ["low_confidence"]}}}}


def test_check_bounds_either_verdict():
    """"published": null: published within its bound, or refused for a listed reason."""
    assert fs.check_bounds([row(worst=0.3)], EDGE) == []
    assert fs.check_bounds([row(status="not_published", reason="low_confidence")], EDGE) == []
    assert fs.check_bounds([row(worst=1.2)], EDGE) != []
    assert fs.check_bounds([row(status="not_published", reason="timeout")], EDGE) != []
    assert fs.check_bounds([row(status="refused")], EDGE) != []


def test_summary_worsts_and_counts():
    rows = [row(seq="paper", worst=2.0), row(seq="paper", status="not_published", worst=None),
            row(seq="adaptive", worst=0.5), row(seq="adaptive", worst=0.7),
            row(seq="adaptive", status="refused", worst=None)]
    s = fs.summary(rows, 3)
    assert s["motors"] == 3
    assert s["adaptive_worst_pct"] == 0.7 and s["paper_published_worst_pct"] == 2.0
    assert s["paper_unpublished"] == 1 and s["adaptive_refused"] == 1


def test_operating_choices_scale_with_the_motor():
    m = fs.fam.ci_subset()[3]
    assert fs.OPS["load100"](m)[("load", "fan_Nm")] == pytest.approx(0.75 * m.T_N)
    assert fs.OPS["target0.5"](m)[("ident", "target_speed_rpm")] == pytest.approx(0.5 * m.n_N)
    assert fs.OPS["im1.2"](m)[("controller", "magnetizing_current_A")] == pytest.approx(1.2 * m.i_m)
    assert fs.OPS["nominal"](m) == {}
