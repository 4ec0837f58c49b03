#!/usr/bin/env bash
# Bounded libFuzzer run of the two fuzz targets (tests/fuzz): arbitrary ADC
# and QEP sequences into the control ISR (fuzz_drive_step) and arbitrary
# bytes into the INI parser (fuzz_sim_config), under ASan + UBSan.
# fuzz_drive_step's first byte picks the configuration (the paper's
# sequence, three faster variants, each also with the adaptive sequence:
# observer, standstill tests, passes, tracking) and whether commands are
# handled at once or wait for the 1 kHz background tick, so that several
# (reset, stop, start) meet in one period as from the button and the link;
# the seeds (tests/fuzz/gen_drive_seeds.py) include stop / fault / reset /
# restart sequences in both sequences.
#
#   tools/fuzz.sh [--seconds N | --runs N] [--math IQ_MATH|FLOAT_MATH] [--build DIR]
#
# Builds with clang into DIR (default build/fuzz-iq or build/fuzz-float):
# the whole core instrumented for coverage (-fsanitize=fuzzer-no-link),
# ASan + UBSan (MC_SANITIZE), the targets linked with libFuzzer.  Each target
# runs N seconds (default 60) from the committed corpus
# (tests/fuzz/corpus/<target>, and host_sim/config for the parser); new
# inputs go to DIR/corpus/<target>, never into the source tree.  A crash,
# a sanitizer report or a violated property stops the run with status 1 and
# leaves the input as DIR/crash-*: add it to tests/fuzz/corpus/<target>/
# once fixed, and the CTest replay (fuzz_*_corpus) keeps it fixed.
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=60
runs=""
math=IQ_MATH
build=""
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds) seconds="${2:?--seconds needs a value}"; shift 2 ;;
    --runs) runs="${2:?--runs needs a value}"; shift 2 ;;
    --math) math="${2:?--math needs a value}"; shift 2 ;;
    --build) build="${2:?--build needs a value}"; shift 2 ;;
    -h|--help) sed -n '2,23p' "$0"; exit 0 ;;
    *) echo "fuzz.sh: unknown option '$1'" >&2; exit 2 ;;
  esac
done
case "$seconds" in ''|*[!0-9]*) echo "fuzz.sh: --seconds must be a whole number" >&2; exit 2 ;; esac
case "$runs" in *[!0-9]*) echo "fuzz.sh: --runs must be a whole number" >&2; exit 2 ;; esac
case "$math" in
  IQ_MATH) build="${build:-build/fuzz-iq}" ;;
  FLOAT_MATH) build="${build:-build/fuzz-float}" ;;
  *) echo "fuzz.sh: --math must be IQ_MATH or FLOAT_MATH" >&2; exit 2 ;;
esac
command -v clang >/dev/null || { echo "fuzz.sh: clang not found (tools/install_deps.sh)" >&2; exit 2; }

cmake -S . -B "$build" -DCMAKE_C_COMPILER=clang -DMATH_TYPE="$math" -DMC_SANITIZE=ON \
      -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_C_FLAGS=-fsanitize=fuzzer-no-link" >/dev/null
cmake --build "$build" -j2 --target fuzz_drive_step fuzz_sim_config >"$build/build.log" 2>&1 || {
  tail -n 40 "$build/build.log" >&2; echo "fuzz.sh: build failed ($build/build.log)" >&2; exit 2; }

export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:allocator_may_return_null=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"

run() {
  local target=$1 max_len=$2 n=$3; shift 3
  local work="$build/corpus/$target" log="$build/$target.log" rc=0 budget
  if [ -n "$runs" ]; then
    # CI: a fixed number of inputs from a fixed seed and a fresh work corpus,
    # so that a run is reproducible and a red CI is a finding, not luck
    rm -rf "$work"
    budget=(-runs="$n" -seed=1)
    echo "=== $target ($math): $n inputs, seed 1"
  else
    budget=(-max_total_time="$seconds")
    echo "=== $target ($math): $seconds s"
  fi
  mkdir -p "$work"
  # -timeout: one input must never take 10 s (a hang is a bug); the first
  # corpus directory receives the new inputs, the others are only read
  "$build/tests/fuzz/$target" "${budget[@]}" -max_len="$max_len" -timeout=10 \
      -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix="$build/" \
      "$work" "$@" >"$log" 2>&1 || rc=$?
  grep -E '^(Done|stat::(number_of_executed_units|average_exec_per_sec|new_units_added|peak_rss_mb))' "$log" || true
  if [ "$rc" -ne 0 ]; then
    tail -n 60 "$log" >&2
    echo "fuzz.sh: $target failed (status $rc); input: $(ls "$build"/crash-* "$build"/timeout-* \
          "$build"/oom-* "$build"/leak-* 2>/dev/null | tr '\n' ' '); log: $log" >&2
    return 1
  fi
}

rm -f "$build"/crash-* "$build"/timeout-* "$build"/oom-* "$build"/leak-*
# drive inputs: 1 + 8 bytes per record; 4 kB is ~500 records, more than the
# 16 384 ISRs an input may run.  INI inputs: the real files are ~2 kB.
# with --runs N: N inputs of the ISR target, 50 N of the parser (~60x faster)
run fuzz_drive_step 4097 "${runs:-0}" tests/fuzz/corpus/drive_step
run fuzz_sim_config 16384 "$(( ${runs:-0} * 50 ))" tests/fuzz/corpus/sim_config host_sim/config
if [ -n "$runs" ]; then
  echo "fuzz.sh: no failure in $runs + $(( runs * 50 )) inputs"
else
  echo "fuzz.sh: no failure in $seconds s per target"
fi
