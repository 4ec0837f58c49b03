"""The drive's verdict on an identification's set, read the same way from the telemetry's
$Q frame (the PC tool) and from imfoc_signals_t (the Python API).

The drive sends each parameter's confidence as a fraction (0.01 = 1 %: the relative bound
of its error; negative: not available for that parameter).  Those fields hold this run's
numbers only once the set was judged: while the verdict is pending, after a stop or a
fault they are an earlier run's, and a set whose extraction was implausible is refused
with every field 0 (drive_background.c judge_rls), which must not read as "0 %".  So a
confidence is None unless the set was judged, and a refused set is shown as refused with
its confidences.
"""
from .protocol import REASONS

PARAM_SI = ("Rs_ohm", "Rr_ohm", "Lm_H", "Lr_H", "psi_r_Wb", "Tr_s")   # the $Q/conf_* order
SHORT = dict(zip(PARAM_SI, ("Rs", "Rr", "Lm", "Lr", "psi_r", "Tr")))
NO_VERDICT = ("pending", "stopped", "fault")   # the confidence fields are not this run's


def judged(reason, fractions, residual, amplification):
    """Did the drive judge this set (are the confidence fields its own)?"""
    if reason in NO_VERDICT or reason not in REASONS:
        return False
    return any(x != 0.0 for x in fractions) or residual != 0.0 or amplification != 0.0


def confidence_pct(reason, fractions, residual, amplification):
    """{Rs_ohm: percent or None (not available), ...}, every value None if not judged."""
    ok = judged(reason, fractions, residual, amplification)
    return {n: (100.0 * x if ok and x >= 0.0 else None) for n, x in zip(PARAM_SI, fractions)}


def summary(reason, conf):
    """One line: "published, confidence Rs 0.21 %, ...", "refused (low_confidence),
    confidence ...", "refused (implausible), not judged", "pending: no verdict yet"."""
    if reason == "pending":
        return "pending: no verdict yet"
    head = "published" if reason == "published" else f"refused ({reason})"
    vals = [f"{SHORT[n]} {v:.2f} %" for n, v in conf.items() if v is not None]
    if not vals:
        return f"{head}, not judged (no confidence)"
    return f"{head}, confidence " + ", ".join(vals)
