# SPDX-License-Identifier: BSD-3-Clause
# CMake toolchain file: bare-metal Cortex-M3 (ARMv7-M, no FPU: float and
# double are libgcc's soft float), Debian's gcc-arm-none-eabi with newlib.
#   cmake -S mcu -B build-mcu-m3 -DCMAKE_TOOLCHAIN_FILE=$PWD/cmake/arm-none-eabi-cortex-m3.cmake
# On this target the fixed-point kinematics (kinctl/fx.h) is the one to use
# in the cycle; mcu/ builds only its programs here.
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR cortex-m3)

set(CMAKE_C_COMPILER arm-none-eabi-gcc)
set(CMAKE_CXX_COMPILER arm-none-eabi-g++)
# gcc-ar and gcc-ranlib: the archive's index must list the symbols of
# objects holding link-time-optimisation bytecode (mcu/'s KINCTL_MCU_LTO).
set(CMAKE_AR arm-none-eabi-gcc-ar)
set(CMAKE_RANLIB arm-none-eabi-gcc-ranlib)
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)

set(KINCTL_MCU_CPU_FLAGS -mcpu=cortex-m3 -mthumb -mfloat-abi=soft)
string(JOIN " " _kinctl_cpu ${KINCTL_MCU_CPU_FLAGS})
set(CMAKE_C_FLAGS_INIT "${_kinctl_cpu} -fno-math-errno -ffunction-sections -fdata-sections")
# C++ (a program of one's own, mcu/CMakeLists.txt): without exceptions and
# RTTI, which need the C++ runtime.
set(CMAKE_CXX_FLAGS_INIT "${CMAKE_C_FLAGS_INIT} -fno-exceptions -fno-rtti -fno-threadsafe-statics")
set(CMAKE_EXE_LINKER_FLAGS_INIT "${_kinctl_cpu} -Wl,--gc-sections")

set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
