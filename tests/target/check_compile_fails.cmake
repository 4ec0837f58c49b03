# cmake -DCC=... -DSRC=... -DFLAGS="a;b" -DEXPECT="regex" -P check_compile_fails.cmake
# Passes only if compiling SRC fails AND the diagnostics match EXPECT (so it
# fails for the reason we mean, not for a missing header).
execute_process(COMMAND ${CC} ${FLAGS} -fsyntax-only ${SRC}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc EQUAL 0)
  message(FATAL_ERROR "expected a compile error, but ${SRC} compiled")
endif()
if(NOT err MATCHES "${EXPECT}")
  message(FATAL_ERROR "compile failed, but not with '${EXPECT}':\n${err}")
endif()
message(STATUS "failed as expected: ${EXPECT}")
