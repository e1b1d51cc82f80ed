# Cross toolchain: Debian 12 amd64 host -> aarch64 (Raspberry Pi 4, Cortex-A72).
#
# Needs (see .ci/install-deps.sh --cross):
#   dpkg --add-architecture arm64 && apt-get update
#   apt-get install g++-aarch64-linux-gnu qemu-user \
#       libhwy-dev:arm64 libgtest-dev:arm64 libpng-dev:arm64 zlib1g-dev:arm64
#
# Debian multiarch keeps the arm64 libraries beside the amd64 ones:
#   /usr/lib/aarch64-linux-gnu            libhwy.so, libgtest.a, libpng16.so, libz.so
#   /usr/lib/aarch64-linux-gnu/cmake      hwy/, GTest/ package configs
#   /usr/include, /usr/share/cmake        arch-independent headers and configs
#                                         (nlohmann_json, CLI11, glm)
# so the "sysroot" is / and CMAKE_LIBRARY_ARCHITECTURE picks the arm64 directories;
# the amd64 ones (/usr/lib/x86_64-linux-gnu) are never searched.
#
# Tests run under qemu with a Pi 4 CPU model. qemu's default CPU ("max") has SVE2, and
# Highway would pick SVE and never run NEON (docs/design.md §6).

set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)

set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)

# Pi 4: Cortex-A72, ARMv8.0-A + CRC, no crypto (AES), no SVE. Override with
# -DPENUMBRA_AARCH64_CPU=cortex-a76 for a Pi 5.
set(PENUMBRA_AARCH64_CPU "cortex-a72" CACHE STRING "-mcpu for the aarch64 cross build")
set(CMAKE_C_FLAGS_INIT "-mcpu=${PENUMBRA_AARCH64_CPU}")
set(CMAKE_CXX_FLAGS_INIT "-mcpu=${PENUMBRA_AARCH64_CPU}")

# The cross libc/libstdc++ live in /usr/aarch64-linux-gnu, the multiarch arm64 packages in
# /usr/lib/aarch64-linux-gnu; tell the linker where shared-library dependencies are.
set(_penumbra_aarch64_link
    "-Wl,-rpath-link,/usr/lib/aarch64-linux-gnu -Wl,-rpath-link,/lib/aarch64-linux-gnu")
set(CMAKE_EXE_LINKER_FLAGS_INIT "${_penumbra_aarch64_link}")
set(CMAKE_SHARED_LINKER_FLAGS_INIT "${_penumbra_aarch64_link}")
set(CMAKE_MODULE_LINKER_FLAGS_INIT "${_penumbra_aarch64_link}")

# Search libraries, headers and package configs in the cross prefix and in / (multiarch);
# programs (protoc, python, ...) only on the host.
set(CMAKE_FIND_ROOT_PATH /usr/aarch64-linux-gnu /)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)

# ctest / add_test / gtest_discover_tests run aarch64 binaries through qemu with a
# Pi 4 CPU. A preset or -D on the command line may override this.
if(NOT DEFINED CMAKE_CROSSCOMPILING_EMULATOR)
  set(CMAKE_CROSSCOMPILING_EMULATOR qemu-aarch64;-cpu;cortex-a72;-L;/usr/aarch64-linux-gnu)
endif()
