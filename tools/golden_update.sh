#!/usr/bin/env bash
# Rewrites the bit-exact trace digests (tests/golden/<build>/*.sha256) from
# the present tree, both math builds.  Only for a change that means to alter
# the numbers: say which and why in its commit.  A pure move or rename must
# pass `ctest -L golden` unchanged instead.
set -euo pipefail
cd "$(dirname "$0")/.."
for p in host-iq host-float; do
  cmake --preset "$p" >/dev/null
  cmake --build --preset "$p" -j"$(nproc)" --target motor_sim >/dev/null
  GOLDEN_UPDATE=1 ctest --preset "$p" -L golden -E detects_change -j"$(nproc)" >/dev/null
done
git status --short tests/golden
