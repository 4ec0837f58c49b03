#!/usr/bin/env bash
# The main job: build the host simulator (fixed point, as on the F2812), run
# the identification on the paper's motor with the drive's best sequence (the
# adaptive one: host_sim/config/paper_motor_adaptive.ini), print the published
# set beside the paper's RLS result, and leave out/trace.csv, out/report.json
# and PNG plots in out/.
#   tools/run_identification.sh [motor_sim options...]
#   tools/run_identification.sh --config host_sim/config/paper_motor.ini   (the paper's sequence)
# Exit status: motor_sim's (0 published; 3 the drive refused its set, report.json says why).
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install_deps.sh
cmake --preset host-iq >/dev/null
# motor_sim, and libimfoc for the Python API (python -m imfoc.example after this job)
cmake --build --preset host-iq -j2 --target motor_sim imfoc >/dev/null
out=out
args=("$@")
for ((i = 0; i < ${#args[@]}; i++)); do
  [ "${args[$i]}" = "--out" ] && out="${args[$((i + 1))]}"
done
[ " ${args[*]-} " == *" --out "* ] || args+=(--out "$out")
[ " ${args[*]-} " == *" --config "* ] || args=(--config host_sim/config/paper_motor_adaptive.ini "${args[@]}")
rc=0
build/host-iq/host_sim/sim/motor_sim "${args[@]}" || rc=$?
# the plots whether or not the drive published (3): the run completed
if [ "$rc" -eq 0 ] || [ "$rc" -eq 3 ]; then
  .venv/bin/python tools/plot_run.py "$out"
fi
exit "$rc"
