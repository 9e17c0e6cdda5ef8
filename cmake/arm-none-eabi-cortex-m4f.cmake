# SPDX-License-Identifier: BSD-3-Clause
# CMake toolchain file: bare-metal Cortex-M4F (ARMv7E-M with the single-
# precision FPv4-SP-D16 unit), Debian's gcc-arm-none-eabi with newlib.
#   cmake -S mcu -B build-mcu -DCMAKE_TOOLCHAIN_FILE=$PWD/cmake/arm-none-eabi-cortex-m4f.cmake
# The core is meant to be built with KINCTL_REAL=float on this target: the
# FPU has no double, so every double operation would be a libgcc call.
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR cortex-m4)

set(CMAKE_C_COMPILER arm-none-eabi-gcc)
set(CMAKE_CXX_COMPILER arm-none-eabi-g++)
# gcc-ar and gcc-ranlib: the archive's index must list the symbols of
# objects holding link-time-optimisation bytecode (mcu/'s KINCTL_MCU_LTO).
set(CMAKE_AR arm-none-eabi-gcc-ar)
set(CMAKE_RANLIB arm-none-eabi-gcc-ranlib)
set(CMAKE_SIZE arm-none-eabi-size CACHE FILEPATH "size of the target's objects")
set(CMAKE_NM arm-none-eabi-nm)
set(CMAKE_OBJDUMP arm-none-eabi-objdump)
# No host program can run: try_compile builds a library instead.
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)

# -fno-math-errno: sqrtf is then the single VSQRT.F32, without the call to
# newlib's sqrtf that only sets errno on a negative argument (the core tests
# its arguments; errno is not its error channel). Results are unchanged.
set(KINCTL_MCU_CPU_FLAGS -mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16)
string(JOIN " " _kinctl_cpu ${KINCTL_MCU_CPU_FLAGS})
set(CMAKE_C_FLAGS_INIT "${_kinctl_cpu} -fno-math-errno -ffunction-sections -fdata-sections")
# C++ (a program of one's own, mcu/CMakeLists.txt): without exceptions and
# RTTI, which need the C++ runtime.
set(CMAKE_CXX_FLAGS_INIT "${CMAKE_C_FLAGS_INIT} -fno-exceptions -fno-rtti -fno-threadsafe-statics")
set(CMAKE_EXE_LINKER_FLAGS_INIT "${_kinctl_cpu} -Wl,--gc-sections")

set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
