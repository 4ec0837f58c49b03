#!/usr/bin/env bash
# Install what the host build, the tests and the tools need on a Debian
# machine (apt-get as root, or through sudo), and the Python packages into
# the project's own virtual environment (.venv).  Idempotent: installs only
# what is missing.
set -euo pipefail
cd "$(dirname "$0")/.."

# libclang-rt-14-dev: clang's sanitizer and libFuzzer runtimes (tools/fuzz.sh);
# only "recommended" by clang, so --no-install-recommends would leave it out.
# gcc-arm-none-eabi + libnewlib-arm-none-eabi (its C library, only suggested
# by the compiler): the stand-in compiler of tools/bench_size.py (the F2812
# code and RAM size, CTests target_ram_fit_*, target_isr_path_cmd_*).
debs=(cmake make gcc pkg-config libcmocka-dev libinih-dev python3
      gcc-avr avr-libc simavr clang cppcheck clang-tidy libclang-rt-14-dev
      gcc-arm-none-eabi libnewlib-arm-none-eabi)
missing=()
for p in "${debs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "install_deps: installing ${missing[*]}"
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

if [ ! -x .venv/bin/python ]; then
  python3 -m venv .venv 2>/dev/null || {
    SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
    $SUDO apt-get install -y -qq python3-venv >/dev/null
    python3 -m venv .venv
  }
fi
if ! .venv/bin/python -c "import numpy, matplotlib, pytest, serial" 2>/dev/null; then
  echo "install_deps: installing Python packages (tools/requirements.txt)"
  .venv/bin/python -m pip install --quiet --disable-pip-version-check -r tools/requirements.txt
fi
# the imfoc package (co-simulation API and the PC tool `imfoc`), editable, so that
# .venv/bin/imfoc runs this checkout's code
if [ ! -x .venv/bin/imfoc ] || ! .venv/bin/python -c "import imfoc.cli" 2>/dev/null; then
  echo "install_deps: installing the imfoc package (tools/python)"
  .venv/bin/python -m pip install --quiet --disable-pip-version-check -e tools/python
fi
