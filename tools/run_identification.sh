#!/usr/bin/env bash
# The main job: build the host simulator (fixed point, as on the F2812), run
# the identification on the paper's motor, print the Table-1-like result and
# leave out/trace.csv, out/report.json and PNG plots in out/.
#   tools/run_identification.sh [motor_sim options...]   (default: paper motor)
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install_deps.sh
cmake --preset host-iq >/dev/null
cmake --build --preset host-iq -j2 --target motor_sim >/dev/null
out=out
args=("$@")
for ((i = 0; i < ${#args[@]}; i++)); do
  [ "${args[$i]}" = "--out" ] && out="${args[$((i + 1))]}"
done
[ " ${args[*]-} " == *" --out "* ] || args+=(--out "$out")
build/host-iq/host_sim/sim/motor_sim "${args[@]}"
.venv/bin/python tools/plot_run.py "$out"
