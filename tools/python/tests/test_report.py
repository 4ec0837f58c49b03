"""motor_sim's report.json: `identified` is what the drive publishes (as the PC tool reads
it from the telemetry), the RLS's last extraction is `last_extraction`."""
import json
import os
import subprocess
from pathlib import Path

from imfoc import CONFIG_DIR

ROOT = Path(__file__).resolve().parents[3]
KEYS = ("Rs_ohm", "Rr_ohm", "Lm_H", "Lr_H", "psi_r_Wb", "Tr_s")


def run(config, out):
    build = Path(os.environ.get("IMFOC_LIB_DIR", ROOT / "build" / "host-iq"))
    exe = build / "host_sim" / "sim" / "motor_sim"
    assert exe.is_file(), f"{exe} not built"
    r = subprocess.run([str(exe), "--config", str(config), "--out", str(out)],
                       capture_output=True, text=True, check=True)
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
    # the printed table: "identified" is the published row, "extraction" the RLS's
    rows = {ln.split()[0]: ln.split()[1:] for ln in table.splitlines()
            if ln.startswith(("identified ", "extraction "))}
    assert abs(float(rows["identified"][1]) - rep["identified"]["Rr_ohm"]) <= 5.1e-5
    assert abs(float(rows["extraction"][1]) - rep["last_extraction"]["Rr_ohm"]) <= 5.1e-5


def test_paper_sequence_publishes_its_extraction(tmp_path):
    rep, _ = run(CONFIG_DIR / "paper_motor.ini", tmp_path)
    assert rep["published"] and not rep["params_tracked"]
    assert rep["identified"] == rep["last_extraction"] == rep["published_end"]
