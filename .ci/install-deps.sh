#!/usr/bin/env bash
# Installs everything Penumbra needs to build, test and benchmark on Debian 12 (bookworm).
#
#   bash .ci/install-deps.sh            native amd64 (or arm64) toolchain and libraries
#   bash .ci/install-deps.sh --cross    + the aarch64 cross toolchain, qemu and arm64 libraries
#   bash .ci/install-deps.sh --board-vm + what .ci/board-vm needs: mmdebstrap, qemu-system-arm,
#                                         qemu-user-static (binfmt for the arm64 chroot), ssh;
#                                         and bench/board_instruction_counts.sh (cpio)
#
# Idempotent: packages already installed are left alone. Runs apt-get update once.
# Uses sudo when not root.
set -euo pipefail

cross=0
board_vm=0
for arg in "$@"; do
  case "$arg" in
    --cross) cross=1 ;;
    --board-vm) board_vm=1 ;;
    -h|--help) sed -n '2,11p' "$0"; exit 0 ;;
    *) echo "install-deps.sh: unknown argument '$arg'" >&2; exit 2 ;;
  esac
done

SUDO=""
if [[ $(id -u) -ne 0 ]]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive

# Retries transient mirror/network failures (and a held dpkg lock) a few times.
retry() {
  local n=1 max=4
  until "$@"; do
    if (( n >= max )); then
      echo "install-deps.sh: '$*' failed $max times" >&2
      return 1
    fi
    echo "install-deps.sh: '$*' failed (attempt $n/$max), retrying in $((n * 10)) s" >&2
    sleep $((n * 10))
    n=$((n + 1))
  done
}

apt_opts=(-y -q -o Dpkg::Use-Pty=0 -o DPkg::Lock::Timeout=300 -o Acquire::Retries=3
          --no-install-recommends)

native=(
  build-essential cmake ninja-build pkg-config git file clang-format clang-tidy cppcheck
  clang libclang-rt-14-dev
  libhwy-dev libglm-dev nlohmann-json3-dev libcli11-dev
  libpng-dev zlib1g-dev libgtest-dev libgmock-dev libbenchmark-dev
  libegl-dev libgles-dev libegl-mesa0 libgl1-mesa-dri
  libembree-dev libmeshoptimizer-dev
  python3-matplotlib
  libopencv-dev libopenexr-dev libtinygltf-dev
  libcamera-dev libgpiod-dev libsdl2-dev libdrm-dev
  blender-data opencv-doc
  systemd
)
# clang, libclang-rt-14-dev: the asan preset (clang's sanitizers, libFuzzer: tests/fuzz).
# blender-data: the CC0 lat-long HDR light probes (studiolights/world/*.exr);
# clang-tidy, cppcheck: .ci/static-analysis.
# opencv-doc: real 640x480 chessboard photographs (examples/data/left*.jpg).
# Both are test inputs of the capture pipeline (issue 4).
# systemd: systemd-analyze verifies the package's unit (.ci/package); not run as init.
cross_pkgs=(
  g++-aarch64-linux-gnu qemu-user
  libhwy-dev:arm64 libgtest-dev:arm64 libgmock-dev:arm64 libpng-dev:arm64 zlib1g-dev:arm64
)
# .ci/board-vm-image and .ci/board-vm (docs/kiosk.md, "The board in a VM"); qemu-utils: qemu-img;
# cpio: bench/board_instruction_counts.sh's initramfs.
board_vm_pkgs=(
  mmdebstrap arch-test qemu-system-arm qemu-utils qemu-user-static e2fsprogs openssh-client cpio kmod
)
# Not in the cross set: libopenexr-dev:arm64 conflicts with the amd64 one (../shared/design.md §6).

if (( cross )) && ! dpkg --print-foreign-architectures | grep -qx arm64; then
  if [[ $(dpkg --print-architecture) != arm64 ]]; then
    $SUDO dpkg --add-architecture arm64
  fi
fi

retry $SUDO apt-get update -q
pkgs=("${native[@]}")
if (( cross )); then pkgs+=("${cross_pkgs[@]}"); fi
if (( board_vm )); then pkgs+=("${board_vm_pkgs[@]}"); fi
retry $SUDO apt-get install "${apt_opts[@]}" "${pkgs[@]}"

echo "install-deps.sh: done ($(cmake --version | head -n1), $(g++ --version | head -n1))"
