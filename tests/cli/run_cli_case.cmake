# One hostile-input case of motor_sim (tests/cli/CMakeLists.txt):
#   cmake -DEXE=motor_sim -DARGS=a|b|c -DRC=1 -DERR=regex [-DOUT=regex]
#         [-DJSON=file -DJSON_CONFIG=expected [-DJSON_REASON=name]] -P run_cli_case.cmake
# Runs EXE with ARGS ("|" separates the arguments), then asserts
#   - the exit status is exactly RC, or one of "a|b" (0 published, 1 usage/config error, 2 run
#     failed, 3 the run completed and nothing was published),
#   - stderr matches the regular expression ERR (an empty ERR: stderr empty),
#   - stdout matches OUT when given, and is empty for an error (RC 1 or 2),
#   - no sanitizer report and no crash (ASan/UBSan exit with 1 too, so the
#     status alone would not tell them from a clean error),
#   - JSON, when given, is valid JSON whose "config" equals JSON_CONFIG, and
#     each "path=value" of JSON_EXPECT ("|" between them; a path's members
#     and array indices joined by ".", e.g. faults.0.name=bus_overvoltage)
#     holds (booleans read ON / OFF).
#   - TRACE_ROWS_MAX, when given: the trace.csv next to JSON has at most
#     that many lines.
#   - ABSENT, when given ("|" between files): none of these exists after the run
#     (an earlier run's report.json and trace.csv in the --out of one that fails).
#   - the report's "publish_reason" is JSON_REASON when given ("published" then
#     also needs "published": true, any other reason "published": false).
cmake_minimum_required(VERSION 3.25)

string(REPLACE "|" ";" args "${ARGS}")
execute_process(COMMAND ${EXE} ${args}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err
                TIMEOUT 120)

set(problems "")
if(NOT rc MATCHES "^(${RC})$")
  string(APPEND problems "exit status '${rc}', expected ${RC}\n")
endif()
if(err MATCHES "Sanitizer|runtime error:|Segmentation|Aborted|core dumped")
  string(APPEND problems "sanitizer report or crash on stderr\n")
endif()
if(ERR STREQUAL "")
  if(NOT err STREQUAL "")
    string(APPEND problems "stderr should be empty\n")
  endif()
elseif(NOT err MATCHES "${ERR}")
  string(APPEND problems "stderr does not match /${ERR}/\n")
endif()
if(DEFINED OUT AND NOT out MATCHES "${OUT}")
  string(APPEND problems "stdout does not match /${OUT}/\n")
endif()
if((RC STREQUAL "1" OR RC STREQUAL "2") AND NOT out STREQUAL "")
  string(APPEND problems "an error must not print to stdout\n")
endif()
if(DEFINED ABSENT)
  string(REPLACE "|" ";" absent "${ABSENT}")
  foreach(a ${absent})
    if(EXISTS "${a}")
      string(APPEND problems "${a} is still there\n")
    endif()
  endforeach()
endif()
if(DEFINED JSON)
  if(NOT EXISTS "${JSON}")
    string(APPEND problems "${JSON} was not written\n")
  else()
    file(READ "${JSON}" json)
    string(JSON cfg ERROR_VARIABLE json_err GET "${json}" config)
    if(json_err)
      string(APPEND problems "${JSON} is not valid JSON: ${json_err}\n")
    elseif(NOT cfg STREQUAL "${JSON_CONFIG}")
      string(APPEND problems "${JSON}: config is '${cfg}', expected '${JSON_CONFIG}'\n")
    endif()
    if(DEFINED JSON_EXPECT)
      string(REPLACE "|" ";" expects "${JSON_EXPECT}")
      foreach(e ${expects})
        string(REGEX REPLACE "=.*" "" path "${e}")
        string(REGEX REPLACE "^[^=]*=" "" want "${e}")
        string(REPLACE "." ";" members "${path}")
        string(JSON got ERROR_VARIABLE get_err GET "${json}" ${members})
        if(get_err)
          string(APPEND problems "${JSON}: no ${path}: ${get_err}\n")
        elseif(NOT got STREQUAL "${want}")
          string(APPEND problems "${JSON}: ${path} is '${got}', expected '${want}'\n")
        endif()
      endforeach()
    endif()
    if(DEFINED TRACE_ROWS_MAX)
      get_filename_component(dir "${JSON}" DIRECTORY)
      file(STRINGS "${dir}/trace.csv" rows)
      list(LENGTH rows n)
      if(n GREATER TRACE_ROWS_MAX)
        string(APPEND problems "${dir}/trace.csv has ${n} lines, more than ${TRACE_ROWS_MAX}\n")
      endif()
    endif()
    if(DEFINED JSON_REASON)
      string(JSON reason ERROR_VARIABLE json_err GET "${json}" publish_reason)
      string(JSON published ERROR_VARIABLE json_err2 GET "${json}" published)
      if(json_err OR json_err2)
        string(APPEND problems "${JSON}: no publish_reason or published\n")
      elseif(NOT reason STREQUAL "${JSON_REASON}")
        string(APPEND problems "${JSON}: publish_reason is '${reason}', expected '${JSON_REASON}'\n")
      elseif(JSON_REASON STREQUAL "published" AND NOT published STREQUAL "ON")
        string(APPEND problems "${JSON}: published is '${published}' with the reason published\n")
      elseif(NOT JSON_REASON STREQUAL "published" AND NOT published STREQUAL "OFF")
        string(APPEND problems "${JSON}: published is '${published}' with the reason ${reason}\n")
      endif()
    endif()
  endif()
endif()

if(NOT problems STREQUAL "")
  message(FATAL_ERROR "motor_sim ${args}\n${problems}--- stdout:\n${out}\n--- stderr:\n${err}")
endif()
