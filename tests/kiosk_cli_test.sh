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
# SDL's offscreen driver shows nothing: the kiosk must say so (a black screen otherwise).
grep -q "display: SDL chose its 'offscreen' video driver, which shows nothing on a screen" "$tmp/err" ||
  fail "offscreen display not said"
grep -q "render: 2 threads" "$tmp/err" || fail "--threads 2 not used"
# Exposure bracketing needs a camera whose exposure can be fixed: none here, a clear error.
if "$kiosk" "$tmp/kiosk.json" --bracket "$tmp/bracket" 2>"$tmp/err4"; then fail "bracket without a camera succeeded"; fi
grep -q -- "--bracket needs a libcamera camera with exposure control" "$tmp/err4" || fail "unclear bracket error: $(cat "$tmp/err4")"
[ ! -e "$tmp/bracket" ] || fail "bracket folder written without a camera"
# A DRM display that is not there (or a build without libdrm): said, and the kiosk runs
# without a screen.
cat >"$tmp/drm.json" <<JSON
{"bundle": "$data/showroom/showroom.bundle", "camera": "none", "display": "drm",
 "drm_device": "$tmp/no-card", "gpio_chip": "/dev/gpiochip-penumbra-absent"}
JSON
"$kiosk" "$tmp/drm.json" --frames 3 --threads 2 >"$tmp/out6" 2>"$tmp/err6" ||
  fail "kiosk with an absent DRM card failed: $(cat "$tmp/err6")"
grep -q "3 frames" "$tmp/out6" || fail "did not run 3 frames without the DRM card"
grep -q "display: $tmp/no-card: No such file or directory; running without a screen" "$tmp/err6" ||
  grep -q "display: built without libdrm; running without a screen" "$tmp/err6" ||
  fail "absent DRM card not said: $(cat "$tmp/err6")"
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
# --check: everything the kiosk would load, what it would use, no device opened.
cat >"$tmp/site.json" <<JSON
{"bundle": "$data/showroom/showroom.bundle", "camera": "auto", "camera_rotation": 180,
 "camera_flip": "horizontal", "gpio_chip": "/dev/gpiochip-penumbra-absent",
 "gpio_lines": {"next": 17, "quality": 4}, "led_line": -1, "threads": 3,
 "loop": {"fps": 25, "service_hold_ms": 2000},
 "product_files": [{"product": "chair", "file": "$data/models/chair.obj"}]}
JSON
"$kiosk" --check "$tmp/site.json" >"$tmp/check" 2>"$tmp/check_err" || fail "--check refused a good config: $(cat "$tmp/check_err")"
for line in "config: $tmp/site.json: valid" "products chair" "product file: chair <- $data/models/chair.obj" \
            "-> V4L2 /dev/video0 (not present) -> the calibration photograph" "mirrored top-bottom" \
            "lines next 17 previous 6 left 13 right 19 forward 26 back 16 rotate 20 quality 4, LED none" \
            "gpiochip-penumbra-absent (not present: no buttons, no LED)" "render: 3 threads" \
            "loop: 25 fps, quality 15 fps" "HUD service (hold next + previous 2000 ms)" \
            "environment camera: none (the bundle's captured light)"; do
  grep -qF -- "$line" "$tmp/check" || fail "--check does not say '$line': $(cat "$tmp/check")"
done
if "$kiosk" --check "$tmp/models.json" >"$tmp/check2" 2>"$tmp/check2_err"; then fail "--check passed a bad product file"; fi
grep -q "truncated.obj: line 174" "$tmp/check2_err" || fail "--check: product file error unclear: $(cat "$tmp/check2_err")"
# The environment camera of live lighting: --check says what it would open and with what;
# the kiosk without it (no device here) says so in one line and runs on the captured light.
cat >"$tmp/env.json" <<JSON
{"bundle": "$data/showroom/showroom.bundle", "camera": "none", "display": "none",
 "gpio_chip": "/dev/gpiochip-penumbra-absent",
 "environment": {"device": "/dev/video-penumbra-absent", "width": 480, "height": 480,
                 "lens": "equidistant180", "response": 2.2, "exposure_scale": 0.25,
                 "samples": 64, "lights": 8, "yaw_deg": 30, "stale_after_ms": 400}}
JSON
"$kiosk" --check "$tmp/env.json" >"$tmp/check_env" 2>"$tmp/check_env_err" || fail "--check refused an environment camera: $(cat "$tmp/check_env_err")"
for line in "environment camera: /dev/video-penumbra-absent (not present)" "-> the bundle's captured light; 480x480" \
            "equidistant 180 lens f 152.789 152.789 centre 240 240 reach 90 deg, response gamma 2.2, exposure scale 0.25" \
            "live lighting: 64 samples, at most 8 lights, yaw 30 deg, radiance scale 1, stale after 400 ms"; do
  grep -qF -- "$line" "$tmp/check_env" || fail "--check does not say '$line': $(cat "$tmp/check_env")"
done
# With a calibrated response file and an exposure bracket (docs/kiosk.md, "HDR").
python3 - "$tmp/response.json" <<'PY'
import json, sys
g = [(z - 128) / 40 for z in range(256)]
json.dump({"format": "penumbra-camera-response", "version": 1,
           "log_exposure": {"r": g, "g": g, "b": g}}, open(sys.argv[1], "w"))
PY
sed 's|"response": 2.2|"response": "response.json", "bracket_us": [200, 1600, 12800], "settle_frames": 3|' \
  "$tmp/env.json" >"$tmp/env_hdr.json"
"$kiosk" --check "$tmp/env_hdr.json" >"$tmp/check_hdr" 2>"$tmp/check_hdr_err" || fail "--check refused an HDR environment camera: $(cat "$tmp/check_hdr_err")"
grep -qF -- "response calibrated $tmp/response.json, exposure scale 0.25, HDR from the exposure bracket 200/1600/12800 us (3 frames dropped after each change)" "$tmp/check_hdr" ||
  fail "--check does not describe the HDR environment camera: $(cat "$tmp/check_hdr")"
"$kiosk" "$tmp/env.json" --frames 3 --threads 2 >"$tmp/out7" 2>"$tmp/err7" || fail "kiosk with an absent environment camera failed: $(cat "$tmp/err7")"
grep -q "3 frames" "$tmp/out7" || fail "did not run 3 frames without the environment camera"
grep -qF "environment camera: cannot open /dev/video-penumbra-absent: no such device; live lighting off, the bundle's captured light" "$tmp/err7" ||
  fail "absent environment camera not said: $(cat "$tmp/err7")"
# A node that is no camera goes through the OpenCV module (where built), whose refusal is said.
if [ -e "$(dirname "$kiosk")/libpenumbra_opencv_camera.so" ]; then
  sed 's|/dev/video-penumbra-absent|/dev/null|' "$tmp/env.json" >"$tmp/env_null.json"
  "$kiosk" "$tmp/env_null.json" --frames 2 --threads 2 >"$tmp/out8" 2>"$tmp/err8" || fail "kiosk with /dev/null as environment camera failed: $(cat "$tmp/err8")"
  grep -qF "environment camera: cannot open /dev/null: cannot be opened with V4L2; live lighting off" "$tmp/err8" ||
    fail "the module's refusal not said: $(cat "$tmp/err8")"
  # A recording (an image sequence beside the configuration): a 96-pixel fisheye disc with a
  # lamp that clips. The kiosk plays it, lights from it, and says the lamp is saturated.
  mkdir "$tmp/env_frames"
  python3 - "$tmp/env_frames" <<'PY'
import math, sys
n = 96
for k in range(3):
    px = bytearray()
    for y in range(n):
        for x in range(n):
            r = math.hypot(x + 0.5 - n / 2, y + 0.5 - n / 2)
            v = 40 + int(30 * (1 - r / (n / 2))) if r < n / 2 else 0
            px += bytes((255, 240, 200) if math.hypot(x - 64, y - 40) < 5 else (v, v, v + 10))
    with open("%s/f_%03d.ppm" % (sys.argv[1], k), "wb") as f:
        f.write(b"P6\n%d %d\n255\n" % (n, n) + px)
PY
  cat >"$tmp/env_rec.json" <<JSON
{"bundle": "$data/showroom/showroom.bundle", "camera": "none", "display": "none",
 "gpio_chip": "/dev/gpiochip-penumbra-absent",
 "environment": {"device": "env_frames/f_%03d.ppm", "width": 96, "height": 96,
                 "lens": "equidistant180", "samples": 64, "lights": 16}}
JSON
  "$kiosk" "$tmp/env_rec.json" --frames 20 --threads 2 >"$tmp/out9" 2>"$tmp/err9" || fail "kiosk with a recorded environment failed: $(cat "$tmp/err9")"
  grep -qF "live lighting: fisheye recording $tmp/env_frames/f_%03d.ppm via OpenCV, 96x96" "$tmp/err9" ||
    fail "the recording is not the environment camera: $(cat "$tmp/err9")"
  grep -q "environment camera: [0-9]* of 9216 pixels saturated" "$tmp/err9" || fail "saturated lamp not said: $(cat "$tmp/err9")"
  if grep -qE "environment frame refused|environment camera lost|environment camera: no frame yet" "$tmp/err9"; then
    fail "the recording did not light the kiosk: $(cat "$tmp/err9")"
  fi
fi
sed 's|"equidistant180"|"fisheye"|' "$tmp/env.json" >"$tmp/env_bad.json"
if "$kiosk" --check "$tmp/env_bad.json" 2>"$tmp/env_bad_err"; then fail "--check passed a bad lens"; fi
grep -qF "env_bad.json: environment.lens: \"fisheye\": no such lens file ($tmp/fisheye)" "$tmp/env_bad_err" ||
  fail "unclear lens error: $(cat "$tmp/env_bad_err")"
# A lens file of `penumbra calibrate-fisheye` (docs/calibration.md), relative to the
# configuration: --check names it with the lens's reach; one that does not see 90 degrees
# (f = 165 on 480 pixels: 240 / 165 rad = 83.34 deg) is refused naming the file and the reach.
mkdir -p "$tmp/lenses"
for f in 146 165; do
  cat >"$tmp/lenses/lens$f.json" <<JSON
{"format": "penumbra-fisheye-lens", "version": 1, "image_size": [480, 480], "fx": $f, "fy": $f,
 "cx": 240, "cy": 240, "k": [0, 0, 0, 0], "rms_px": 0.05, "views": 13}
JSON
  sed "s|\"equidistant180\"|\"lenses/lens$f.json\"|" "$tmp/env.json" >"$tmp/env_lens$f.json"
done
"$kiosk" --check "$tmp/env_lens146.json" >"$tmp/check_lens" 2>"$tmp/check_lens_err" || fail "--check refused a lens file: $(cat "$tmp/check_lens_err")"
grep -qF -- "480x480, lens file $tmp/lenses/lens146.json: fisheye lens f 146 146 centre 240 240 k 0 0 0 0 reach 94.18 deg, response" "$tmp/check_lens" ||
  fail "--check does not name the lens file and its reach: $(cat "$tmp/check_lens")"
if "$kiosk" --check "$tmp/env_lens165.json" 2>"$tmp/lens165_err"; then fail "--check passed a lens of 83 degrees"; fi
grep -qF "env_lens165.json: environment.lens: $tmp/lenses/lens165.json sees 83.34 deg from its axis towards the nearest image edge: the hemisphere map needs 90 deg" "$tmp/lens165_err" ||
  fail "narrow lens not refused by its reach: $(cat "$tmp/lens165_err")"
echo '{"bundle": "x.bundle", "gpio_lines": {"next": 6}}' >"$tmp/dup.json"
if "$kiosk" --check "$tmp/dup.json" 2>"$tmp/dup_err"; then fail "--check passed two buttons on one line"; fi
grep -q "dup.json: gpio_lines: next and previous are both on line 6" "$tmp/dup_err" || fail "unclear: $(cat "$tmp/dup_err")"
if "$kiosk" 2>"$tmp/usage_err"; then fail "no CONFIG accepted"; fi
grep -q "CONFIG is required" "$tmp/usage_err" || fail "unclear usage error: $(cat "$tmp/usage_err")"
"$kiosk" --list-cameras >"$tmp/cams" 2>/dev/null || fail "--list-cameras failed"
grep -q "^libcamera: " "$tmp/cams" && grep -q "^V4L2: " "$tmp/cams" || fail "--list-cameras: $(cat "$tmp/cams")"
# Under systemd (Type=notify, WatchdogSec=): a socket where systemd's would be receives
# READY=1 after the first frame and WATCHDOG=1 pings; SIGTERM (systemctl stop) ends the loop
# cleanly: exit 0, STOPPING=1, said in the log.
python3 - "$kiosk" "$tmp" <<'PY' || fail "systemd notification"
import os, signal, socket, subprocess, sys, time
kiosk, tmp = sys.argv[1:]
path = os.path.join(tmp, "notify.sock")
s = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
s.bind(path)
s.settimeout(60)
env = dict(os.environ, NOTIFY_SOCKET=path, WATCHDOG_USEC="200000")
p = subprocess.Popen([kiosk, os.path.join(tmp, "sim.json"), "--threads", "2"], env=env,
                     stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
messages = [s.recv(4096).decode()]
assert messages[0].startswith("READY=1\nSTATUS=showing "), messages
while messages.count("WATCHDOG=1") < 2:
    messages.append(s.recv(4096).decode())
p.send_signal(signal.SIGTERM)
out, err = p.communicate(timeout=60)
messages.append(s.recv(4096).decode())
assert p.returncode == 0, (p.returncode, err)
assert messages[-1] == "STOPPING=1", messages
assert "systemd: notifying, watchdog 200 ms" in err, err
assert "stopping: signal received" in err, err
print("notify: %d messages, exit %d" % (len(messages), p.returncode))
PY
echo '{"bundle": "x.bundle", "screen": "big"}' >"$tmp/bad.json"
if "$kiosk" "$tmp/bad.json" --frames 1 2>"$tmp/err2"; then fail "bad config accepted"; fi
grep -q "bad.json: screen: unknown field" "$tmp/err2" || fail "unclear error: $(cat "$tmp/err2")"
echo '{"bundle": "missing.bundle", "display": "none", "camera": "none"}' >"$tmp/nob.json"
if "$kiosk" "$tmp/nob.json" --frames 1 2>"$tmp/err3"; then fail "missing bundle accepted"; fi
grep -q "missing.bundle" "$tmp/err3" || fail "missing bundle not named: $(cat "$tmp/err3")"
echo PASS
