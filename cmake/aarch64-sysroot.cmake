# Cross toolchain for the full-featured board build: Debian 12 amd64 host -> aarch64 against a
# Debian 12 arm64 sysroot (libcamera, libgpiod, SDL2, OpenCV, OpenEXR, tinygltf,
# meshoptimizer, Highway), the libraries a Raspberry Pi running Debian 12 has. The sysroot is
# unpacked from Debian's arm64 packages by `bash .ci/arm64-sysroot` (mmdebstrap's extract
# variant: nothing of arm64 runs) into build/sysroot-arm64, or wherever
# PENUMBRA_ARM64_SYSROOT points. Unlike cmake/aarch64-linux-gnu.cmake (multiarch on /,
# static, no optional libraries: the qemu-user test stage), nothing here mixes with the host's
# amd64 -dev packages, whose arm64 twins (OpenCV, OpenEXR) cannot be co-installed.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)

if(NOT PENUMBRA_ARM64_SYSROOT)
  if(DEFINED ENV{PENUMBRA_ARM64_SYSROOT})
    set(PENUMBRA_ARM64_SYSROOT "$ENV{PENUMBRA_ARM64_SYSROOT}")
  else()
    get_filename_component(PENUMBRA_ARM64_SYSROOT "${CMAKE_CURRENT_LIST_DIR}/../build/sysroot-arm64"
                           ABSOLUTE)
  endif()
endif()
set(PENUMBRA_ARM64_SYSROOT "${PENUMBRA_ARM64_SYSROOT}" CACHE PATH "the Debian arm64 sysroot")
if(NOT EXISTS "${PENUMBRA_ARM64_SYSROOT}/usr/include/libcamera")
  message(FATAL_ERROR "no arm64 sysroot at ${PENUMBRA_ARM64_SYSROOT}: run `bash .ci/arm64-sysroot`")
endif()
set(CMAKE_SYSROOT "${PENUMBRA_ARM64_SYSROOT}")

set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
set(PENUMBRA_AARCH64_CPU "cortex-a72" CACHE STRING "-mcpu for the aarch64 cross build")
set(CMAKE_C_FLAGS_INIT "-mcpu=${PENUMBRA_AARCH64_CPU}")
set(CMAKE_CXX_FLAGS_INIT "-mcpu=${PENUMBRA_AARCH64_CPU}")

set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
# pkg-config (libcamera, libgpiod, SDL2) reads the sysroot's .pc files and prefixes their paths.
set(ENV{PKG_CONFIG_SYSROOT_DIR} "${PENUMBRA_ARM64_SYSROOT}")
set(ENV{PKG_CONFIG_LIBDIR}
    "${PENUMBRA_ARM64_SYSROOT}/usr/lib/aarch64-linux-gnu/pkgconfig:${PENUMBRA_ARM64_SYSROOT}/usr/share/pkgconfig")

# Programs and tests run under qemu-user with a Pi 4 CPU, their shared libraries from the
# sysroot.
if(NOT DEFINED CMAKE_CROSSCOMPILING_EMULATOR)
  set(CMAKE_CROSSCOMPILING_EMULATOR qemu-aarch64;-cpu;${PENUMBRA_AARCH64_CPU};-L;${PENUMBRA_ARM64_SYSROOT})
endif()
