#!/usr/bin/env bash
# Static analysis: cppcheck and clang-tidy, with their configuration in the
# repository (tools/cppcheck-suppressions.txt, .clang-tidy).  Exit status 1
# on any finding, so CI (.ci/run) fails on a new one.
#
#   tools/static_analysis.sh [--only cppcheck|clang-tidy]
#
# What is analysed, with the flags of the real build (compile_commands.json
# of an IQ_MATH and a FLOAT_MATH configuration in build/analysis-*):
#   cppcheck    src/, host_sim/, tests/fuzz, tests/cli and the firmware's
#               portable files of the host build in both math types, and all
#               of firmware/ against the TI register shim (tests/target/ti_shim)
#   clang-tidy  src/ in both math types, host_sim/ and tests/fuzz, tests/cli,
#               all of firmware/ against the shim
# The cmocka unit tests are not in the scope (the cmocka macros would be
# what is flagged).
set -euo pipefail
cd "$(dirname "$0")/.."

only=""
case "${1:-}" in
  "") ;;
  --only) only="${2:?--only needs cppcheck or clang-tidy}" ;;
  -h|--help) sed -n '2,17p' "$0"; exit 0 ;;
  *) echo "static_analysis.sh: unknown option '$1'" >&2; exit 2 ;;
esac
for tool in cppcheck clang-tidy; do
  command -v "$tool" >/dev/null || { echo "static_analysis.sh: $tool not found (tools/install_deps.sh)" >&2; exit 2; }
done

for m in iq:IQ_MATH float:FLOAT_MATH; do
  cmake -S . -B "build/analysis-${m%%:*}" -DMATH_TYPE="${m#*:}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
        -DCMAKE_EXPORT_COMPILE_COMMANDS=ON >/dev/null
  # the generated board_config.c files are in the compilation database:
  # make them (board_config_gen, from host_sim/config/*.ini)
  cmake --build "build/analysis-${m%%:*}" -j2 --target board_config_c board_config_sources \
        >/dev/null
done
# the firmware against TI's register names, as the target_fw_syntax tests do
fw_defs=(-Ifirmware -Iinclude -Itests/target/ti_shim -Ihost_sim/iqmath -DMATH_TYPE=IQ_MATH
         -DGLOBAL_Q=24)
status=0

if [ -z "$only" ] || [ "$only" = cppcheck ]; then
  common=(--enable=warning,style,performance,portability --std=c99 --inline-suppr --quiet
          --suppressions-list=tools/cppcheck-suppressions.txt --error-exitcode=1 -j2
          "--template={file}:{line}: {severity}: {message} [{id}]")
  for m in iq float; do
    echo "=== cppcheck: src/, host_sim/, firmware's portable files, tests/fuzz, tests/cli ($m)"
    cppcheck "${common[@]}" --project="build/analysis-$m/compile_commands.json" \
             --file-filter='src/*' --file-filter='host_sim/*' --file-filter='firmware/*' \
             --file-filter='tests/fuzz/*' --file-filter='tests/cli/*' || status=1
  done
  echo "=== cppcheck: firmware/ (TI shim)"
  cppcheck "${common[@]}" "${fw_defs[@]}" firmware/*.c || status=1
fi

if [ -z "$only" ] || [ "$only" = clang-tidy ]; then
  # files of a compile database under the given folders
  files_of() {
    local db=$1; shift
    python3 - "$db" "$@" <<'PY'
import json, os, sys
db, roots = sys.argv[1], [os.path.abspath(r) + os.sep for r in sys.argv[2:]]
seen = set()
for e in json.load(open(db)):
    f = os.path.abspath(os.path.join(e["directory"], e["file"]))
    if any(f.startswith(r) for r in roots) and f not in seen:
        seen.add(f)
        print(f)
PY
  }
  tidy() {   # tidy BUILD_DIR FILE...: 2 in parallel, a finding is an error (.clang-tidy)
    local build=$1; shift
    printf '%s\n' "$@" | xargs -P2 -n4 clang-tidy -p "$build" --quiet 2>/dev/null
  }
  echo "=== clang-tidy: src/, host_sim/, tests/fuzz, tests/cli (IQ_MATH)"
  mapfile -t files < <(files_of build/analysis-iq/compile_commands.json src host_sim tests/fuzz tests/cli)
  tidy build/analysis-iq "${files[@]}" || status=1
  echo "=== clang-tidy: src/ (FLOAT_MATH)"
  mapfile -t files < <(files_of build/analysis-float/compile_commands.json src)
  tidy build/analysis-float "${files[@]}" || status=1
  echo "=== clang-tidy: firmware/ (TI shim)"
  for f in firmware/*.c; do
    clang-tidy --quiet "$f" -- -std=c99 "${fw_defs[@]}" -Wno-unknown-pragmas 2>/dev/null || status=1
  done
fi

if [ "$status" -ne 0 ]; then
  echo "static_analysis.sh: findings above" >&2
else
  echo "static_analysis.sh: clean"
fi
exit "$status"
