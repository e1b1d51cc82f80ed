#!/usr/bin/env bash
# Issue 13 item 5: how many aarch64 instructions each stage of the kiosk frame executes, counted
# by QEMU rather than estimated. The static aarch64 build (preset aarch64-cross) runs as the init
# of a throw-away initramfs on Debian's own arm64 kernel under
#
#   qemu-system-aarch64 -M virt -cpu cortex-a72 -smp 1 -icount shift=0
#
# With `-icount shift=0` the guest's clock advances exactly 1 ns per executed instruction (QEMU's
# precise icount mode: one instruction every 2^shift ns of virtual time), so every "ms" the
# programs print for a stage is a count of millions of instructions of that stage, on one thread
# (the kernel's own timer ticks at 250 Hz of virtual time add well under 0.1 %). The counts depend
# on the code and the compiler, not on this machine's load.
#
#   bench/board_instruction_counts.sh AARCH64_BUILD_DIR OUT_DIR [FRAMES]
#
# AARCH64_BUILD_DIR: build/aarch64 (`cmake --preset aarch64-cross && cmake --build
# build/aarch64 --target penumbra penumbra-sim`). OUT_DIR receives
#   profile-<product>.csv   `penumbra profile` per product (chair 0, bunny 1, teapot 2) at
#                           8, 16, 32 and 64 passes, the product sliding every frame (so it is
#                           shaded every frame): stage columns in M instructions per frame
#   profile-<product>-map<size>.csv
#                           the chair and the teapot at 16 and 64 passes on 64² and 128² shadow
#                           maps (the controller's ladder; the others use 256²)
#   profile-<product>-fine<n>.csv
#                           the bunny and the teapot at 16 and 64 passes with their fine shadow
#                           proxies in none or every pass (--fine-proxy-passes 0 and 50; the
#                           others use the bundle's counts): the occluder triangles' own cost
#   demo.txt                `penumbra-sim data/sessions/demo.json --bench` over FRAMES frames
#                           (default 240): the whole board frame by stage, M instructions
#   console.log             the VM's serial console
# Needs qemu-system-arm, cpio (`bash .ci/install-deps.sh --board-vm`) and the arm64 architecture
# in dpkg (`--cross` adds it; the kernel and busybox-static packages are fetched with
# `apt-get download`).
# About 3 minutes on this machine (TCG runs ~200 M guest instructions a second).
set -euo pipefail
if [[ $# -lt 2 ]]; then
  echo "usage: bench/board_instruction_counts.sh AARCH64_BUILD_DIR OUT_DIR [FRAMES]" >&2
  exit 2
fi
build="$(realpath "$1")" out="$2" frames="${3:-240}"
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
for program in penumbra penumbra-sim; do
  [[ -x "$build/bin/$program" ]] || {
    echo "board_instruction_counts.sh: $build/bin/$program: not built (preset aarch64-cross)" >&2
    exit 1
  }
  file "$build/bin/$program" | grep -q "ARM aarch64.*statically linked" || {
    echo "board_instruction_counts.sh: $build/bin/$program: not a static aarch64 program" >&2
    exit 1
  }
done
for tool in qemu-system-aarch64 cpio; do
  command -v "$tool" >/dev/null || {
    echo "board_instruction_counts.sh: $tool not found (bash .ci/install-deps.sh --board-vm)" >&2
    exit 1
  }
done
mkdir -p "$out"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# Debian's arm64 kernel of the current point release, and a static busybox for /init's shell.
(
  cd "$work"
  kernel_pkg="$(apt-cache depends linux-image-arm64:arm64 | sed -n 's/.*Depends: \(linux-image-[^ ]*\):arm64.*/\1/p' | head -1)"
  [[ -n "$kernel_pkg" ]] || { echo "board_instruction_counts.sh: no linux-image-arm64 in apt's lists (apt-get update; dpkg --add-architecture arm64)" >&2; exit 1; }
  apt-get download "$kernel_pkg:arm64" busybox-static:arm64 >/dev/null 2>&1 || {
    echo "board_instruction_counts.sh: apt-get download $kernel_pkg:arm64 busybox-static:arm64 failed" >&2
    exit 1
  }
  mkdir kernel busybox
  dpkg-deb -x linux-image-*_arm64.deb kernel
  dpkg-deb -x busybox-static_*_arm64.deb busybox
)

initramfs="$work/initramfs"
mkdir -p "$initramfs"/{bin,proc,sys,dev,tmp,data/showroom,data/sessions}
cp "$work/busybox/bin/busybox" "$build/bin/penumbra" "$build/bin/penumbra-sim" "$initramfs/bin/"
cp "$root/data/showroom/showroom.bundle" "$initramfs/data/showroom/"
cp "$root/data/sessions/demo.json" "$initramfs/data/sessions/"
cat >"$initramfs/init" <<EOF
#!/bin/busybox sh
/bin/busybox mount -t proc proc /proc
/bin/busybox mount -t sysfs sys /sys
/bin/busybox mount -t devtmpfs dev /dev
cd /data
# profile NAME PRODUCT PASSES [FLAGS...]: one product's profile, printed between markers.
profile() {
  name=\$1 product=\$2 passes=\$3
  shift 3
  /bin/penumbra profile showroom/showroom.bundle --product \$product --passes \$passes \
      --frames 8 --threads 1 "\$@" --csv /tmp/profile.csv >/dev/null
  echo "=== begin \$name.csv"
  /bin/busybox cat /tmp/profile.csv
  echo "=== end"
}
for product in 0 1 2; do profile profile-\$product \$product 8,16,32,64; done
for size in 64 128; do
  for product in 0 2; do
    profile profile-\$product-map\$size \$product 16,64 --shadow-map-size \$size
  done
done
for fine in 0 50; do
  for product in 1 2; do
    profile profile-\$product-fine\$fine \$product 16,64 --fine-proxy-passes \$fine
  done
done
echo "=== begin demo.txt"
/bin/penumbra-sim sessions/demo.json --threads 1 --frames $frames --bench
echo "=== end"
/bin/busybox poweroff -f
EOF
chmod +x "$initramfs/init"
(cd "$initramfs" && find . | cpio -o -H newc --quiet | gzip -1 >"$work/initrd.gz")

timeout 3600 qemu-system-aarch64 -M virt -cpu cortex-a72 -smp 1 -m 1024 -icount shift=0 \
  -nic none -nographic -no-reboot -kernel "$work"/kernel/boot/vmlinuz-* -initrd "$work/initrd.gz" \
  -append "console=ttyAMA0 rdinit=/init quiet" | tr -d '\r' >"$out/console.log"

# Split the console into the files between the markers; a missing one fails the run.
awk -v dir="$out" '
  /^=== begin / { name = $3; file = dir "/" name ".part"; printf "" > file; next }
  /^=== end/    { close(file); system("mv \"" file "\" \"" dir "/" name "\""); file = ""; next }
  file != ""    { print >> file }
' "$out/console.log"
for f in profile-{0,1,2}.csv profile-{0,2}-map{64,128}.csv profile-{1,2}-fine{0,50}.csv demo.txt; do
  [[ -s "$out/$f" ]] || {
    echo "board_instruction_counts.sh: $out/$f missing; see $out/console.log" >&2
    exit 1
  }
done
echo "board_instruction_counts.sh: counts in $out (M instructions per stage and frame)"
