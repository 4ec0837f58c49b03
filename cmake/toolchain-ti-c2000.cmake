# CMake toolchain file for the TMS320F2812 target build with TI's C2000 code
# generation tools (cl2000, COFF ABI, large memory model, no FPU).
#
#   cmake -S firmware -B build/f2812 \
#         -DCMAKE_TOOLCHAIN_FILE=cmake/toolchain-ti-c2000.cmake \
#         -DC2000_CGT_ROOT=/opt/ti/ti-cgt-c2000_22.6.1.LTS \
#         -DDSP281X_HEADERS_ROOT=/opt/ti/DSP281x/v120 \
#         -DC2000_IQMATH_ROOT=/opt/ti/C2000Ware/libraries/math/IQmath/c28
#   cmake --build build/f2812
#
# Cache variables (all three required):
#   C2000_CGT_ROOT        the code generation tools: bin/cl2000, bin/hex2000,
#                         lib/rts2800_ml.lib
#   DSP281X_HEADERS_ROOT  TI's DSP281x header files (SPRC097): the folder
#                         holding DSP281x_headers/include/DSP281x_Device.h and
#                         DSP281x_headers/source/DSP281x_GlobalVariableDefs.c
#   C2000_IQMATH_ROOT     TI's C28x IQmath (SPRC087, or C2000Ware's
#                         libraries/math/IQmath/c28): include/IQmathLib.h and
#                         lib/IQmath_coff.lib (C2000Ware) or lib/IQmath.lib
#                         (SPRC087, COFF)
# and C2000_ABI (default coffabi, the only one the F2812 build supports).
# The host IQmath (host_sim/iqmath) is never on the target's include path:
# firmware/CMakeLists.txt checks that.

set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR c28x)

set(C2000_CGT_ROOT "" CACHE PATH "TI C2000 code generation tools root (bin/cl2000)")
set(DSP281X_HEADERS_ROOT "" CACHE PATH "TI DSP281x header files (SPRC097) root")
set(C2000_IQMATH_ROOT "" CACHE PATH "TI C28x IQmath library root (include/IQmathLib.h, lib/IQmath.lib)")

if(NOT C2000_CGT_ROOT)
  message(FATAL_ERROR "Set -DC2000_CGT_ROOT=<TI C2000 code generation tools folder>")
endif()

find_program(C2000_CL2000 cl2000 PATHS "${C2000_CGT_ROOT}/bin" NO_DEFAULT_PATH)
find_program(C2000_HEX2000 hex2000 PATHS "${C2000_CGT_ROOT}/bin" NO_DEFAULT_PATH)
if(NOT C2000_CL2000)
  message(FATAL_ERROR "cl2000 not found in ${C2000_CGT_ROOT}/bin")
endif()

set(CMAKE_C_COMPILER "${C2000_CL2000}")
set(CMAKE_ASM_COMPILER "${C2000_CL2000}")

# The processor options, in CMAKE_<LANG>_FLAGS: CMake's TI rules put them in
# <FLAGS> of every compile and, on the link line, before --run_linker, where
# the shell still reads them (after --run_linker every option is the
# linker's: SPRU514 "Invoking the linker through the compiler").
# C28x (-v28), large memory model (-ml), unified memory (-mt), no FPU.
set(C2000_ABI "coffabi" CACHE STRING "cl2000 --abi (coffabi or eabi)")
set(CMAKE_C_FLAGS_INIT "-v28 -ml -mt --float_support=none --abi=${C2000_ABI}")
set(CMAKE_ASM_FLAGS_INIT "-v28 -ml -mt --float_support=none --abi=${C2000_ABI}")
# the compiler cannot link a test program without a linker command file
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)

set(CMAKE_FIND_ROOT_PATH "${C2000_CGT_ROOT}")
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
