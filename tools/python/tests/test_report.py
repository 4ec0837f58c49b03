"""motor_sim's report.json: `identified` is what the drive publishes (as the PC tool reads
it from the telemetry), the RLS's last extraction is `last_extraction`."""
import json
import os
import subprocess
import sys
from pathlib import Path

from imfoc import CONFIG_DIR

ROOT = Path(__file__).resolve().parents[3]
KEYS = ("Rs_ohm", "Rr_ohm", "Lm_H", "Lr_H", "psi_r_Wb", "Tr_s")


def run(config, out, rc=0):
    """motor_sim on config; rc: its expected exit status (0 published, 3 not)."""
    build = Path(os.environ.get("IMFOC_LIB_DIR", ROOT / "build" / "host-iq"))
    exe = build / "host_sim" / "sim" / "motor_sim"
    assert exe.is_file(), f"{exe} not built"
    r = subprocess.run([str(exe), "--config", str(config), "--out", str(out)],
                       capture_output=True, text=True)
    assert r.returncode == rc, (r.returncode, r.stderr)
    return json.loads((out / "report.json").read_text()), r.stdout


def test_identified_is_the_published_set_with_tracking(tmp_path):
    rep, table = run(CONFIG_DIR / "paper_motor_wrong_nameplate.ini", tmp_path)
    assert rep["published"] and rep["params_tracked"]
    assert rep["identified"] == rep["published_end"]
    assert rep["error_pct"] == rep["published_end_error_pct"]
    # measured: the fused set within 0.6 %, the RLS's extraction Rr -3.2 %, Tr +3.4 %
    for k in KEYS:
        assert rep["identified"][k] > 0 and abs(rep["error_pct"][k]) < 1.0, k
    assert abs(rep["last_extraction_error_pct"]["Rr_ohm"]) > 1.0
    assert rep["last_extraction_valid"] is True
    # the published set carries a confidence per parameter, each within the drive's 3 %
    # (but the standstill Rs, which the RLS does not judge)
    assert rep["publish_reason"] == "published"
    for k in KEYS:
        c = rep["confidence_pct"][k]
        if k == "Rs_ohm" and c is None:
            continue   # the fused set's Rs is the standstill test's: not judged by the RLS
        assert c is not None and 0.0 <= c <= 3.0, (k, c)
    # the printed table: "published" is the published row, "RLS (paper)" the RLS's
    rows = {}
    for ln in table.splitlines():
        for label in ("published ", "RLS (paper) "):
            if ln.startswith(label):
                rows[label.strip()] = ln[len(label):].split()
    assert abs(float(rows["published"][1]) - rep["identified"]["Rr_ohm"]) <= 5.1e-5
    assert abs(float(rows["RLS (paper)"][1]) - rep["last_extraction"]["Rr_ohm"]) <= 5.1e-5


def test_paper_sequence_publishes_its_extraction(tmp_path):
    rep, _ = run(CONFIG_DIR / "paper_motor.ini", tmp_path)
    assert rep["published"] and not rep["params_tracked"]
    assert rep["identified"] == rep["last_extraction"] == rep["published_end"]


def test_refused_set_reports_why_and_its_extraction(tmp_path):
    """The paper's sequence on the 15 kW motor (w_r Tr 81): the RLS's extraction is
    within 1 % but the data cannot bound Tr within 3 %, so nothing is published: the
    report says why, gives the confidence of the refused set and its extraction, and
    no published numbers; motor_sim exits 3."""
    sys.path.insert(0, str(ROOT / "tools"))
    from sweep_start_errors import PAPER, ini_merge
    paper = tmp_path / "motor_15kw_paper.ini"   # the file's own sequence is the adaptive one
    paper.write_text(ini_merge((CONFIG_DIR / "motor_15kw.ini").read_text(), PAPER))
    rep, table = run(paper, tmp_path, rc=3)
    assert rep["published"] is False and rep["publish_reason"] == "low_confidence"
    assert rep["identified"] is None and rep["published_end"] is None
    conf = rep["confidence_pct"]
    assert max(conf["Rr_ohm"], conf["Tr_s"]) > 3.0
    assert rep["confidence"]["rls_samples"] > 1000
    assert rep["last_extraction"] is not None
    for k in KEYS:
        assert abs(rep["last_extraction_error_pct"][k]) < 3.0, k
    assert "(nothing published: low_confidence)" in table
