# shellcheck shell=bash
# What .ci/board-vm and .ci/board-vm-quick share (sourced; each defines fail()).

# find_deb: sets `deb` to $PENUMBRA_ARM64_DEB, or to the newer of the full build's and the
# package-only build's package (bash .ci/arm64-package [--no-tests]).
find_deb() {
  deb="${PENUMBRA_ARM64_DEB:-}"
  if [[ -z "$deb" ]]; then
    local f
    for f in build/aarch64-full/penumbra_*_arm64.deb build/aarch64-pkg/penumbra_*_arm64.deb; do
      if [[ -f "$f" && (-z "$deb" || "$f" -nt "$deb") ]]; then deb="$f"; fi
    done
    [[ -n "$deb" ]] || fail "no build/aarch64-{full,pkg}/penumbra_*_arm64.deb: run bash .ci/arm64-package"
  fi
  [[ -f "$deb" ]] || fail "$deb: no such package"
}

# vimc_bundle OUT: the showroom precomputed for a 480x360 view, by this machine's `penumbra
# precompute` ($PENUMBRA, default build/ci/bin/penumbra; the arm64 kiosk reads the x86-made
# bundle as it reads the shipped one). libcamera 0.0.3's Vimc pipeline handler delivers only sizes that are multiples of 6
# (vimc's scaler scales by 3, its sensor moves in 2-pixel steps): not the shipped bundle's
# 640x480 view, which the kiosk rightly refuses to film at another size (the calibration holds
# for one view). The libcamera runs show this bundle.
vimc_bundle() {
  local out="$1" penumbra="${PENUMBRA:-$PWD/build/ci/bin/penumbra}" scene
  [[ -x "$penumbra" ]] || fail "$penumbra: not built (the ci preset; or set PENUMBRA)"
  scene="$(mktemp -d)"
  mkdir -p "$scene/showroom"
  ln -s "$PWD/data/models" "$scene/models"  # the scene names its models ../models/...
  sed 's/"image": {"width": 640, "height": 480}/"image": {"width": 480, "height": 360}/' \
    data/showroom/showroom.json >"$scene/showroom/showroom-480x360.json"
  grep -q '"width": 480, "height": 360' "$scene/showroom/showroom-480x360.json" ||
    { rm -rf "$scene"; fail "data/showroom/showroom.json: no 640x480 image size to change"; }
  "$penumbra" precompute "$scene/showroom/showroom-480x360.json" -o "$out" >"$scene/log" 2>&1 ||
    { cat "$scene/log" >&2; rm -rf "$scene"; fail "penumbra precompute (480x360)"; }
  rm -rf "$scene"
}

# kiosk_json BUNDLE LAST_GOOD CAMERA GPIO_CHIP HUD STALE_MS [PASSES [DISPLAY]]: a kiosk
# configuration as a site would write it (docs/kiosk.md, "The board program"), on stdout. Attract
# mode off (the pose stays the bundle's start pose, for the screendumps); STALE_MS generous, as
# TCG is ~10x slower than the board; the passes fixed when PASSES is given (may be empty);
# DISPLAY "drm" or "sdl" (the default).
kiosk_json() {
  local passes=""
  if [[ -n "${7:-}" ]]; then
    passes=", \"min_passes\": $7, \"max_passes\": $7, \"initial_passes\": $7"
  fi
  cat <<EOF
{
  "bundle": "$1",
  "last_good_bundle": "$2",
  "camera": "$3",
  "camera_fallback": "photograph",
  "gpio_chip": "$4",
  "led_line": 12,
  "display": "${8:-sdl}",
  "fullscreen": true,
  "threads": 0,
  "loop": {"fps": 30, "quality_fps": 15, "hud": "$5", "attract_after_ms": 3600000,
           "stale_after_ms": $6$passes}
}
EOF
}

# camera_outage: reads a kiosk log on stdin and prints its last camera outage line, if the
# camera did not come back after it. The kiosk says "camera: no frame yet" when its first frame
# finds none, "no new frame" when frames stop, and "camera: live again" when one comes; a camera
# that delivers leaves the last of these lines the third, or none (a frame was waiting).
camera_outage() {
  grep -E 'camera: (no frame yet|no new frame|live again)' | tail -n1 | grep -v 'camera: live again' || true
}
