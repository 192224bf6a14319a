# SPDX-License-Identifier: MIT
# Toolchain file for bare-metal Arm Cortex-M with the GNU Arm Embedded
# toolchain (Debian: gcc-arm-none-eabi, libnewlib-arm-none-eabi).
#
#   cmake -S . -B build-arm-m4 \
#     -DCMAKE_TOOLCHAIN_FILE=cmake/arm-none-eabi.cmake -DPNEUFRAC_CPU=cortex-m4
#
# The core is chosen by PNEUFRAC_CPU (see lib/CMakeLists.txt), not here, so one
# toolchain file serves every core. Set ARM_NONE_EABI_ROOT (environment or
# cache) when the toolchain is not on PATH.

set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR arm)

# No C runtime to link a test executable against: probe with a static library.
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)

if(NOT ARM_NONE_EABI_ROOT AND DEFINED ENV{ARM_NONE_EABI_ROOT})
  set(ARM_NONE_EABI_ROOT "$ENV{ARM_NONE_EABI_ROOT}")
endif()
set(_pf_arm_hints)
if(ARM_NONE_EABI_ROOT)
  list(APPEND _pf_arm_hints "${ARM_NONE_EABI_ROOT}/bin")
endif()

find_program(ARM_NONE_EABI_GCC     arm-none-eabi-gcc     HINTS ${_pf_arm_hints} REQUIRED)
find_program(ARM_NONE_EABI_AR      arm-none-eabi-ar      HINTS ${_pf_arm_hints} REQUIRED)
find_program(ARM_NONE_EABI_RANLIB  arm-none-eabi-ranlib  HINTS ${_pf_arm_hints} REQUIRED)
find_program(ARM_NONE_EABI_SIZE    arm-none-eabi-size    HINTS ${_pf_arm_hints} REQUIRED)
find_program(ARM_NONE_EABI_NM      arm-none-eabi-nm      HINTS ${_pf_arm_hints} REQUIRED)
find_program(ARM_NONE_EABI_OBJDUMP arm-none-eabi-objdump HINTS ${_pf_arm_hints} REQUIRED)
find_program(ARM_NONE_EABI_OBJCOPY arm-none-eabi-objcopy HINTS ${_pf_arm_hints})

set(CMAKE_C_COMPILER   "${ARM_NONE_EABI_GCC}")
set(CMAKE_ASM_COMPILER "${ARM_NONE_EABI_GCC}")
set(CMAKE_AR           "${ARM_NONE_EABI_AR}"      CACHE FILEPATH "Archiver")
set(CMAKE_RANLIB       "${ARM_NONE_EABI_RANLIB}"  CACHE FILEPATH "Ranlib")
set(CMAKE_NM           "${ARM_NONE_EABI_NM}"      CACHE FILEPATH "nm")
set(CMAKE_OBJDUMP      "${ARM_NONE_EABI_OBJDUMP}" CACHE FILEPATH "objdump")
if(ARM_NONE_EABI_OBJCOPY)
  set(CMAKE_OBJCOPY    "${ARM_NONE_EABI_OBJCOPY}" CACHE FILEPATH "objcopy")
endif()

# Programs come from the host; headers and libraries only from the target.
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
