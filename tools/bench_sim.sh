#!/usr/bin/env bash
# Simulator speed: simulated seconds per wall-clock second for the default
# scenario (paper motor, identification run), in the IQ_MATH and FLOAT_MATH
# builds, best of 5 runs, without the trace file.  A benchmark, not a test.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install_deps.sh
for preset in host-iq host-float; do
  cmake --preset "$preset" >/dev/null
  cmake --build --preset "$preset" -j2 --target motor_sim >/dev/null
  best=0
  for _ in 1 2 3 4 5; do
    d=$(mktemp -d)
    "build/$preset/host_sim/sim/motor_sim" --quiet --duration 10 --out "$d" >/dev/null
    x=$(.venv/bin/python -c "import json,sys; r=json.load(open('$d/report.json')); print(r['duration_s']/max(r['wall_s'],1e-9))")
    best=$(.venv/bin/python -c "print(max($best, $x))")
    rm -rf "$d"
  done
  printf '%-11s %6.0f x real time (10 s simulated, best of 5, trace written)\n' "$preset" "$best"
done
