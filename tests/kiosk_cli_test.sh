#!/usr/bin/env bash
# penumbra-kiosk on a machine without the kiosk's hardware (issue 6): no camera, no GPIO
# chip, SDL's offscreen screen. It must fall back per peripheral, say so, and run; a bad
# configuration is refused naming the file and the key.
set -euo pipefail
kiosk=$1 data=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
cat >"$tmp/kiosk.json" <<JSON
{"bundle": "$data/showroom/showroom.bundle", "camera": "auto",
 "gpio_chip": "/dev/gpiochip-penumbra-absent", "display": "sdl", "fullscreen": false}
JSON
# "auto" tries libcamera, then /dev/video0: skip the run when this machine has a webcam.
if [ -e /dev/video0 ]; then echo "SKIP: /dev/video0 exists"; exit 0; fi
SDL_VIDEODRIVER=offscreen "$kiosk" "$tmp/kiosk.json" --frames 5 --threads 2 >"$tmp/out" 2>"$tmp/err" ||
  fail "kiosk failed: $(cat "$tmp/err")"
grep -q "5 frames" "$tmp/out" || fail "did not run 5 frames"
grep -q "libcamera: no camera found" "$tmp/err" || fail "no libcamera fallback message"
grep -q "/dev/video0: no such device" "$tmp/err" || fail "no V4L2 fallback"
grep -q "camera: none; showing the calibration photograph" "$tmp/err" || fail "no photograph fallback"
grep -q "gpiochip-penumbra-absent.*no buttons, no status LED" "$tmp/err" || fail "no GPIO fallback"
grep -q "led: degraded (NO CAMERA - CALIBRATION PHOTOGRAPH; NO BUTTONS)" "$tmp/err" || fail "no LED state"
# Exposure bracketing needs a camera whose exposure can be fixed: none here, a clear error.
if "$kiosk" "$tmp/kiosk.json" --bracket "$tmp/bracket" 2>"$tmp/err4"; then fail "bracket without a camera succeeded"; fi
grep -q -- "--bracket needs a libcamera camera with exposure control" "$tmp/err4" || fail "unclear bracket error: $(cat "$tmp/err4")"
[ ! -e "$tmp/bracket" ] || fail "bracket folder written without a camera"
# The configured last fallback: the simulated camera filming the bundle's photograph.
cat >"$tmp/sim.json" <<JSON
{"bundle": "$data/showroom/showroom.bundle", "camera": "auto", "camera_fallback": "simulated",
 "camera_controls": {"exposure_us": 8000, "analogue_gain": 1.5, "colour_gains": [1.9, 1.6]},
 "gpio_chip": "/dev/gpiochip-penumbra-absent", "display": "none"}
JSON
"$kiosk" "$tmp/sim.json" --frames 5 --threads 2 >"$tmp/out5" 2>"$tmp/err5" || fail "simulated fallback failed: $(cat "$tmp/err5")"
grep -q "camera: using the simulated camera" "$tmp/err5" || fail "simulated fallback not said"
grep -q "camera: simulated camera" "$tmp/err5" || fail "simulated camera not described"
if grep -q "CALIBRATION PHOTOGRAPH" "$tmp/err5"; then fail "photograph shown although the simulated camera runs"; fi
# A corrupt product file at start-up: refused with the reason, the bundle's model kept.
cat >"$tmp/models.json" <<JSON
{"bundle": "$data/showroom/showroom.bundle", "camera": "none", "display": "none",
 "gpio_chip": "/dev/gpiochip-penumbra-absent",
 "product_files": [{"product": "chair", "file": "$data/sessions/faulty-models/truncated.obj"}]}
JSON
"$kiosk" "$tmp/models.json" --frames 3 --threads 2 >"$tmp/out6" 2>"$tmp/err6" || fail "kiosk with a bad product file failed: $(cat "$tmp/err6")"
grep -q "product chair: refused .*truncated.obj: line 174: face needs at least 3 vertices" "$tmp/err6" || fail "bad product file not refused with its reason: $(cat "$tmp/err6")"
grep -q "MODEL REFUSED: chair" "$tmp/err6" || fail "refused product file not on the LED/HUD"
echo '{"bundle": "x.bundle", "screen": "big"}' >"$tmp/bad.json"
if "$kiosk" "$tmp/bad.json" --frames 1 2>"$tmp/err2"; then fail "bad config accepted"; fi
grep -q "bad.json: screen: unknown field" "$tmp/err2" || fail "unclear error: $(cat "$tmp/err2")"
echo '{"bundle": "missing.bundle", "display": "none", "camera": "none"}' >"$tmp/nob.json"
if "$kiosk" "$tmp/nob.json" --frames 1 2>"$tmp/err3"; then fail "missing bundle accepted"; fi
grep -q "missing.bundle" "$tmp/err3" || fail "missing bundle not named: $(cat "$tmp/err3")"
echo PASS
