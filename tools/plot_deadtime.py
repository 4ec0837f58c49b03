#!/usr/bin/env python3
"""Dead-time and device-drop compensation, with and without.

Runs motor_sim (start scenario) on a motor config twice, with
[controller] dead_time_comp = 1 and = 0, prints the voltage-reconstruction
error along the current (steady state), its describing-function reference
(4/pi)(vdc td/Ts + v_drop) and the identified Rs and Rr errors, and draws
OUT/deadtime.png: the live Rs and Rr estimates of both runs against time with
the true values as lines.

Usage: plot_deadtime.py [--config INI] [--build DIR] [--out DIR]
(after `cmake --build --preset host-iq`; tools/run_identification.sh installs
numpy and matplotlib in .venv)
"""
import argparse
import configparser
import json
import math
import subprocess
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent


def run(exe, ini_text, comp, out):
    """One motor_sim run with dead_time_comp = comp; returns (report, trace)."""
    cp = configparser.ConfigParser(inline_comment_prefixes=(";",))
    cp.optionxform = str
    cp.read_string(ini_text)
    if not cp.has_section("controller"):
        cp.add_section("controller")
    cp.set("controller", "dead_time_comp", str(comp))
    out.mkdir(parents=True, exist_ok=True)
    ini = out / "config.ini"
    with ini.open("w") as f:
        cp.write(f)
    p = subprocess.run([str(exe), "--config", str(ini), "--quiet", "--out", str(out)])
    if p.returncode not in (0, 3):   # 3: the run completed, the drive published nothing
        raise SystemExit(f"plot_deadtime: motor_sim failed ({p.returncode})")
    rep = json.loads((out / "report.json").read_text())
    trace = np.genfromtxt(out / "trace.csv", delimiter=",", names=True)
    return rep, trace, cp


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--config", default=str(ROOT / "host_sim" / "config" / "paper_motor.ini"))
    ap.add_argument("--build", default=str(ROOT / "build" / "host-iq"))
    ap.add_argument("--out", default=str(ROOT / "out" / "deadtime"))
    a = ap.parse_args()
    exe = Path(a.build) / "host_sim" / "sim" / "motor_sim"
    text = Path(a.config).read_text()
    out = Path(a.out)
    res = {}
    with tempfile.TemporaryDirectory() as tmp:
        for comp in (1, 0):
            res[comp] = run(exe, text, comp, Path(tmp) / f"comp{comp}")
    cp = res[1][2]
    # the simulated bridge: [inverter], each value the [board]'s unless given
    def bridge(key, default):
        return float(cp.get("inverter", key, fallback=cp.get("board", default[0],
                                                              fallback=default[1])))
    f_pwm = float(cp.get("board", "pwm_freq_Hz", fallback="15000"))
    v_dt = (bridge("vdc_V", ("vdc_nominal_V", "60")) *
            bridge("dead_time_s", ("dead_time_s", "1e-6")) * f_pwm +
            bridge("device_drop_V", ("device_drop_V", "0.3")))
    ref = 4.0 / math.pi * v_dt
    print(f"describing function (4/pi)(vdc td/Ts + v_drop) = {ref:.4f} V")
    print(f"{'compensation':<13} {'V err along i':>14} {'across':>9} {'mean |i|':>9} "
          f"{'Rs err':>8} {'Rr err':>8} {'Tr err':>8}  (the RLS's extraction) verdict")
    for comp in (1, 0):
        r = res[comp][0]
        e = r["last_extraction_error_pct"] or {}
        print(f"{('on' if comp else 'off'):<13} {r['v_err_along_i_V']:>12.4f} V "
              f"{r['v_err_across_i_V']:>7.4f} V {r['i_mag_steady_A']:>7.3f} A "
              f"{e.get('Rs_ohm', float('nan')):>+7.2f}% {e.get('Rr_ohm', float('nan')):>+7.2f}% "
              f"{e.get('Tr_s', float('nan')):>+7.2f}%  {r['publish_reason']}")

    fig, ax = plt.subplots(2, 1, figsize=(9, 7), sharex=True)
    for i, key in enumerate(("Rs_ohm", "Rr_ohm")):
        for comp, style in ((1, "-"), (0, "--")):
            rep, tr, _ = res[comp]
            ok = tr["est_valid"] > 0
            ax[i].plot(tr["t_s"][ok], tr[key][ok], style,
                       label=f"compensation {'on' if comp else 'off'}")
        ax[i].axhline(res[1][0]["true"][key], color="k", lw=0.8, label="true")
        ax[i].set_ylabel(key)
        ax[i].grid(True, alpha=0.3)
        ax[i].legend(loc="best")
    ax[-1].set_xlabel("t / s")
    fig.suptitle(f"Dead-time compensation: uncompensated voltage error {res[0][0]['v_err_along_i_V']:.3f} V "
                 f"along i (describing function {ref:.3f} V)")
    fig.tight_layout()
    out.mkdir(parents=True, exist_ok=True)
    fig.savefig(out / "deadtime.png", dpi=110)
    print(f"wrote {out / 'deadtime.png'}")


if __name__ == "__main__":
    main()
