# One bit-exact trace case (tests/golden/CMakeLists.txt):
#   cmake -DEXE=motor_sim -DARGS=a|b|c -DOUT=dir -DEXPECT=file.sha256
#         -P golden_trace.cmake
# Runs EXE ARGS --out OUT, then hashes OUT/trace.csv and OUT/report.json
# (without its two lines that name the host: "wall_s", the run's wall time,
# and "config", the path it was given) with SHA-256 and compares the digest
# with the one in EXPECT.  A refactoring of the application layer moves code
# and renames it: every row of every period, and the report's confidences,
# must then come out byte for byte the same.  GOLDEN_UPDATE=1 in the
# environment writes EXPECT instead
# (tools/golden_update.sh: only for a change that means to alter the
# numbers, stated in its commit).
cmake_minimum_required(VERSION 3.25)

string(REPLACE "|" ";" args "${ARGS}")
file(REMOVE_RECURSE "${OUT}")
execute_process(COMMAND ${EXE} ${args} --quiet --out ${OUT}
                RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err TIMEOUT 300)
if(NOT rc MATCHES "^[03]$")
  message(FATAL_ERROR "motor_sim exited with '${rc}': ${err}")
endif()
file(SHA256 "${OUT}/trace.csv" trace_sha)
file(STRINGS "${OUT}/report.json" lines)
set(report "")
foreach(l IN LISTS lines)
  if(NOT l MATCHES "^  \"(wall_s|config)\":")
    string(APPEND report "${l}\n")
  endif()
endforeach()
string(SHA256 report_sha "${report}")
set(digest "trace ${trace_sha}\nreport ${report_sha}\n")
if("$ENV{GOLDEN_UPDATE}")
  file(WRITE "${EXPECT}" "${digest}")
  message(STATUS "wrote ${EXPECT}")
  return()
endif()
if(NOT EXISTS "${EXPECT}")
  message(FATAL_ERROR "${EXPECT} missing (tools/golden_update.sh writes it)")
endif()
file(READ "${EXPECT}" want)
if(NOT want STREQUAL digest)
  message(FATAL_ERROR "not bit-exact to the recorded run:\n expected\n${want} got\n${digest}"
          " (the trace is kept in ${OUT} to compare with the tree before)")
endif()
file(REMOVE_RECURSE "${OUT}")
