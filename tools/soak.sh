#!/usr/bin/env bash
# Soak (long-run robustness): ten minutes of simulated time (default; tools/soak.sh SECONDS
# for another length) of the paper motor after its identification: speed
# reversals every 4 s and load steps, in the IQ_MATH and FLOAT_MATH builds.
# Prints the figures (faults, control-path saturation flags, RLS counters and
# estimate bounds, published parameters); exits non-zero if a bound of
# tests/soak/test_soak.c is broken.  CTest runs the same program for 30 s
# (label soak).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-600}"
tools/install_deps.sh
for preset in host-iq host-float; do
  cmake --preset "$preset" >/dev/null
  cmake --build --preset "$preset" -j2 --target soak >/dev/null
  echo "== $preset"
  MC_SOAK_S="$seconds" "build/$preset/tests/soak/soak" || {
    echo "soak: $preset broke a bound (see above)" >&2
    exit 1
  }
done
