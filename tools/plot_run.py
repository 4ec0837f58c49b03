#!/usr/bin/env python3
"""PNG plots of an identification run: motor_sim's DIR/trace.csv (and DIR/report.json), or
a telemetry log of `imfoc monitor --csv FILE` / `imfoc identify --out DIR`.

  run.png         speed reference and speed, M/T currents, rotor-flux q/d (motor_sim),
                  the sequence's state; the verdict (published / refused) marked
  parameters.png  each parameter against time with its true value as a line (motor_sim),
                  like the paper's figures 2-6, the verdict in the titles

Usage: plot_run.py DIR|LOG.csv [OUT_DIR]     (default OUT_DIR: the log's folder)
"""
import sys
from pathlib import Path

# the imfoc package of this checkout (also installed into .venv by tools/install_deps.sh)
sys.path.insert(0, str(Path(__file__).resolve().parent / "python"))
from imfoc.plots import PlotError, plot_dir  # noqa: E402


def main(argv):
    if len(argv) not in (2, 3) or argv[1] in ("-h", "--help"):
        print(__doc__, file=sys.stderr)
        return 1 if len(argv) not in (2, 3) else 0
    try:
        outs = plot_dir(argv[1], argv[2] if len(argv) == 3 else None)
    except PlotError as e:
        print(f"plot_run: {e}", file=sys.stderr)
        return 1
    print(f"wrote {outs[0]} and {outs[1]}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
