#!/usr/bin/env bash
# Simulator speed: simulated seconds per wall-clock second of motor_sim's
# closed loop (the report's wall_s: configuration and start-up excluded), the
# paper motor, no trace (one row at the start), best of N runs, for
#   - the default identification run (standstill to the drive's verdict), and
#   - 10 s of it,
# in the IQ_MATH and FLOAT_MATH builds.  With --before COMMIT the same for
# that commit, built beside this tree in build/bench_sim_before (a git
# worktree), so that both figures come from the same machine and load.
# A benchmark, not a test.
#
#   tools/bench_sim.sh [--before COMMIT] [--runs N]
set -euo pipefail
cd "$(dirname "$0")/.."
before=""
runs=5
while [ $# -gt 0 ]; do
  case "$1" in
    --before) before="${2:?--before needs a commit}"; shift 2 ;;
    --runs) runs="${2:?--runs needs a number}"; shift 2 ;;
    -h|--help) sed -n '2,12p' "$0"; exit 0 ;;
    *) echo "bench_sim: unknown option $1" >&2; exit 1 ;;
  esac
done
tools/install_deps.sh >/dev/null
py=.venv/bin/python

build() {   # $1 source tree, $2 build dir, $3 MATH_TYPE
  cmake -S "$1" -B "$2" -DMATH_TYPE="$3" -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
  cmake --build "$2" -j"$(nproc)" --target motor_sim >/dev/null
}

# "<label> default run S s: Nx; 10 s: Mx" for motor_sim in build dir $2
report() {
  "$py" - "$1" "$2/host_sim/sim/motor_sim" "$runs" <<'PY'
import json, subprocess, sys, tempfile
label, exe, runs = sys.argv[1], sys.argv[2], int(sys.argv[3])
cfg = "host_sim/config/paper_motor.ini"
def best(extra):
    top, dur = 0.0, 0.0
    for _ in range(runs):
        with tempfile.TemporaryDirectory() as d:
            subprocess.run([exe, "--config", cfg, "--quiet", "--out", d,
                            "--trace-every", "1000000000"] + extra,
                           check=False, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            r = json.load(open(f"{d}/report.json"))
        dur = r["duration_s"]
        top = max(top, dur / max(r["wall_s"], 1e-9))
    return dur, top
d0, x0 = best([])
_, x10 = best(["--duration", "10"])
print(f"{label:<24} default run ({d0:.2f} s simulated) {x0:4.0f}x real time;"
      f" 10 s {x10:4.0f}x")
PY
}

echo "motor_sim, paper motor, no trace, best of $runs:"
for mt in IQ_MATH FLOAT_MATH; do
  build . "build/bench_sim/$mt" "$mt"
  report "this tree, $mt" "build/bench_sim/$mt"
done
if [ -n "$before" ]; then
  wt=build/bench_sim_before
  rm -rf "$wt"
  git worktree prune
  git worktree add -q --detach "$wt/src" "$before"
  for mt in IQ_MATH FLOAT_MATH; do
    build "$wt/src" "$wt/$mt" "$mt"
    report "$(git rev-parse --short "$before"), $mt" "$wt/$mt"
  done
  git worktree remove --force "$wt/src"
fi
