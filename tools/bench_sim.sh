#!/usr/bin/env bash
# The simulator's speed: simulated seconds per wall-clock second of motor_sim
# (IQ_MATH build, no trace, the paper motor), the best of several runs of
#   - the default identification run (standstill to the drive's verdict), and
#   - 20 s of it (the steady part weighs more),
# and, with --before COMMIT, the same for that commit built beside this tree
# (a git worktree under build/bench_sim_before), so that both figures come
# from the same machine and load.
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
    -h|--help) sed -n '2,11p' "$0"; exit 0 ;;
    *) echo "bench_sim: unknown option $1" >&2; exit 1 ;;
  esac
done

build() {   # $1 source tree, $2 build dir
  cmake -S "$1" -B "$2" -DMATH_TYPE=IQ_MATH -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
  cmake --build "$2" -j"$(nproc)" --target motor_sim >/dev/null
}

# best wall time of $runs runs of motor_sim $2.. built in $1; prints "sim_s wall_s"
measure() {
  local exe="$1/host_sim/sim/motor_sim"; shift
  local cfg="$1"; shift
  python3 - "$exe" "$cfg" "$runs" "$@" <<'PY'
import subprocess, sys, time
exe, cfg, runs, extra = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4:]
best = None
for _ in range(runs):
    t0 = time.perf_counter()
    # --quiet, no --out: no trace (sim_seconds asks the run's length)
    subprocess.run([exe, "--config", cfg, "--quiet"] + extra, check=False,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    w = time.perf_counter() - t0
    best = w if best is None else min(best, w)
print(best)
PY
}

sim_seconds() {   # simulated seconds of the default run (one run with a report)
  local exe="$1/host_sim/sim/motor_sim" d
  d=$(mktemp -d)
  "$exe" --config "$2" --quiet --out "$d" >/dev/null 2>&1 || true
  python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['duration_s'])" "$d/report.json"
  rm -rf "$d"
}

report() {   # $1 label, $2 build dir
  local cfg=host_sim/config/paper_motor.ini s w20 w
  s=$(sim_seconds "$2" "$cfg")
  w=$(measure "$2" "$cfg")
  w20=$(measure "$2" "$cfg" --duration 20)
  python3 -c "
import sys
s, w, w20 = float(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4])
print(f'{sys.argv[1]:<10} default run {s:.2f} s in {w*1e3:.0f} ms: {s/w:.0f}x real time;'
      f' 20 s in {w20*1e3:.0f} ms: {20/w20:.0f}x')" "$1" "$s" "$w" "$w20"
}

build . build/bench_sim
echo "motor_sim, IQ_MATH, no trace, paper motor, best of $runs (wall clock incl. start-up):"
report "this tree" build/bench_sim
if [ -n "$before" ]; then
  wt=build/bench_sim_before
  rm -rf "$wt"
  git worktree prune
  git worktree add -q --detach "$wt/src" "$before"
  build "$wt/src" "$wt/build"
  report "$(git rev-parse --short "$before")" "$wt/build"
  git worktree remove --force "$wt/src"
fi
