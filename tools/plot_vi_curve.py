#!/usr/bin/env python3
"""The bridge's voltage error measured at standstill against the simulated bridge's.

Runs motor_sim with [ident] vi_test = 1 (the default: the drive measures the
bridge's voltage error against the current in CALIBRATE, include/vi_curve.h,
and nobody sets the compensation's zone) for the whole default run, prints report.json's "vi_curve" (the fitted E and
band, and the table of measured error against the true one of
host_sim/model/inverter_model.h at each measured current) and draws
OUT/vi_curve.png: the measured points over the true curve
(2/3) E (s(I) + s(I/2)), s(i) = sat(i / b, -1, 1).

Usage: plot_vi_curve.py [--config INI]... [--build DIR] [--out DIR]
(after `cmake --build --preset host-iq`; numpy and matplotlib from .venv)
"""
import argparse
import configparser
import json
import subprocess
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
DEFAULT = ["paper_motor", "motor_1kw", "motor_15kw"]


def true_curve(e, b, i):
    """The simulated bridge's alpha-axis error at current i (vi_curve.h (1))."""
    return 2.0 / 3.0 * e * (np.clip(i / b, -1, 1) + np.clip(0.5 * i / b, -1, 1))


def measure(exe, ini, tmp):
    """One run with the test on; report.json's vi_curve."""
    cp = configparser.ConfigParser(inline_comment_prefixes=(";",))
    cp.optionxform = str
    cp.read(ini)
    if not cp.has_section("ident"):
        cp.add_section("ident")
    cp.set("ident", "vi_test", "1")
    path = tmp / "config.ini"
    with path.open("w") as f:
        cp.write(f)
    # the whole default run (the test is its first seconds; a second or so of wall time)
    p = subprocess.run([str(exe), "--config", str(path), "--quiet", "--out", str(tmp)],
                       capture_output=True, text=True)
    if p.returncode not in (0, 3):
        raise SystemExit(f"plot_vi_curve: motor_sim failed ({p.returncode}): {p.stderr}")
    return json.loads((tmp / "report.json").read_text())["vi_curve"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--config", action="append",
                    help="INI (repeatable; default the paper, 1.1 kW and 15 kW motors)")
    ap.add_argument("--build", default=str(ROOT / "build" / "host-iq"))
    ap.add_argument("--out", default=str(ROOT / "out" / "vi_curve"))
    a = ap.parse_args()
    exe = Path(a.build) / "host_sim" / "sim" / "motor_sim"
    inis = a.config or [str(ROOT / "host_sim" / "config" / f"{m}.ini") for m in DEFAULT]
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    fig, axes = plt.subplots(1, len(inis), figsize=(5 * len(inis), 4), squeeze=False)
    for ini, ax in zip(inis, axes[0]):
        with tempfile.TemporaryDirectory() as tmp:
            v = measure(exe, ini, Path(tmp))
        name = Path(ini).stem
        e, b, et, bt = v["e_pole_V"], v["band_A"], v["true_e_pole_V"], v["true_band_A"]
        print(f"{name}: {v['status']}; E {e:.4f} V (true {et:.4f}, {100 * (e / et - 1):+.2f} %), "
              f"b {b:.4f} A (true {bt:.4f}, {100 * (b / bt - 1):+.2f} %, from {v['n_band']} of 6 "
              f"voltage levels), "
              f"Rs {v['rs_ohm']:.4f} ohm, vdc {v['vdc_V']:.2f} V")
        print(f"  {'I / A':>9} {'measured / V':>13} {'true / V':>9} {'error':>8}")
        for i, u, ut in v["table"]:
            print(f"  {i:>+9.4f} {u:>+13.4f} {ut:>+9.4f} {100 * (u / ut - 1):>+7.2f}%")
        tab = np.array(v["table"])
        x = np.linspace(-4 * bt, 4 * bt, 400)
        ax.plot(x, true_curve(et, bt, x), "k-", lw=1, label="simulated bridge (true)")
        ax.plot(x, true_curve(e, b, x), "C0--", lw=1, label="fitted E, b")
        ax.plot(tab[:, 0], tab[:, 1], "C1o", label="measured levels")
        ax.set_xlim(-5 * bt, 5 * bt)
        ax.set_xlabel("i_alpha / A (the levels at +-i1, +-2 i1 lie beyond)")
        ax.set_ylabel("u_ref - Rs i / V")
        ax.set_title(name)
        ax.grid(True, alpha=0.3)
        ax.legend(loc="lower right", fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "vi_curve.png", dpi=110)
    print(f"wrote {out / 'vi_curve.png'}")


if __name__ == "__main__":
    main()
