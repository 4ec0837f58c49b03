#!/usr/bin/env bash
# All tests: the cmocka/CTest suites in the three host builds (IQ_MATH,
# FLOAT_MATH, IQ_MATH under ASan+UBSan), then the Python tests.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install_deps.sh
for preset in host-iq host-float host-asan; do
  echo "=== $preset"
  cmake --preset "$preset" >/dev/null
  cmake --build --preset "$preset" -j2
  ctest --preset "$preset" -j2
done
if [ -f tools/python/pyproject.toml ]; then
  echo "=== python"
  # the package wraps the shared library of the host-iq build
  .venv/bin/python -m pip install --quiet --disable-pip-version-check -e tools/python
  # -rs: the skipped docs blocks and tables, with their reasons (test_docs.py)
  IMFOC_LIB_DIR="$PWD/build/host-iq" .venv/bin/python -m pytest -q -rs tools/python/tests
fi
# the motor family's generator and sweep (tools/family, tools/family_sweep.py)
.venv/bin/python -m pytest -q tools/family
