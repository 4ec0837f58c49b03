# Strict JSON check of a file (RFC 8259: no NaN, no infinity, no bare words):
#   cmake -DF=report.json [-DKEYS=a|b|c] -P json_valid.cmake
# Fails (status 1, the parser's message) unless F parses as JSON and has
# every top-level member of KEYS.  CMake's parser (jsoncpp, strict for
# numbers) refuses "nan", "-nan", "inf", "NaN", "Infinity" and 1e999.
cmake_minimum_required(VERSION 3.25)
file(READ "${F}" json)
string(JSON n ERROR_VARIABLE e LENGTH "${json}")
if(e)
  message(FATAL_ERROR "${F} is not valid JSON: ${e}")
endif()
if(DEFINED KEYS)
  string(REPLACE "|" ";" keys "${KEYS}")
  foreach(k ${keys})
    string(JSON t ERROR_VARIABLE e TYPE "${json}" ${k})
    if(e)
      message(FATAL_ERROR "${F}: no member '${k}': ${e}")
    endif()
  endforeach()
endif()
