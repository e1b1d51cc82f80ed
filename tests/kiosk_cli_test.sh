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
            "loop: 25 fps, quality 15 fps" "HUD service (hold next + previous 2000 ms)"; do
  grep -qF -- "$line" "$tmp/check" || fail "--check does not say '$line': $(cat "$tmp/check")"
done
if "$kiosk" --check "$tmp/models.json" >"$tmp/check2" 2>"$tmp/check2_err"; then fail "--check passed a bad product file"; fi
grep -q "truncated.obj: line 174" "$tmp/check2_err" || fail "--check: product file error unclear: $(cat "$tmp/check2_err")"
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
