#!/usr/bin/env bash
# `penumbra calibrate` end to end: the real opencv-doc chessboard photos, the bundled
# vanishing-point and room-corner marks, and for bad input a clear error naming the file
# and the mark, exit 1 and no JSON written.
#   tests/calibrate_cli_test.sh PENUMBRA DATA_DIR [EMULATOR...]
set -uo pipefail
penumbra="$1" data="$2"
shift 2
run=("$@" "$penumbra")
source "$(dirname "${BASH_SOURCE[0]}")/check_lib.sh"

"${run[@]}" calibrate --help >"$tmp/help" 2>&1
check "help: penumbra calibrate --help" $?

photos=/usr/share/doc/opencv-doc/examples/data
if [[ -e "$photos/left01.jpg" ]]; then
  "${run[@]}" calibrate --chessboard 9x6 "$photos"/left0*.jpg "$photos"/left1*.jpg \
    --json "$tmp/chess.json" >"$tmp/out" 2>"$tmp/err"
  rc=$?
  err="$(value reprojection_error_px "$tmp/out")"
  [[ $rc == 0 && -n "$err" ]] && awk -v e="$err" 'BEGIN {exit !(e > 0 && e < 0.5)}' \
    && python3 -c "import json,sys; d=json.load(open(sys.argv[1])); assert abs(d['reprojection_error_px']-$err)<1e-5" "$tmp/chess.json"
  check "chessboard: opencv-doc left*.jpg, reprojection_error_px $err < 0.5, JSON written" $?

  "${run[@]}" calibrate --chessboard 9x6 "$photos/left01.jpg" "$photos/left02.jpg" \
    --json "$tmp/few.json" >"$tmp/out" 2>"$tmp/err"
  rc=$?
  [[ $rc == 1 && ! -e "$tmp/few.json" ]] && grep -q "need at least 3" "$tmp/err"
  status=$?
  check "chessboard: two photos rejected (exit $rc): $(head -c 150 "$tmp/err")" $status

  "${run[@]}" calibrate --chessboard 7x7 "$photos/left01.jpg" "$photos/left02.jpg" \
    "$photos/left03.jpg" >"$tmp/out" 2>"$tmp/err"
  rc=$?
  [[ $rc == 1 ]] && grep -q "left03.jpg: no 7x7 chessboard found" "$tmp/err"
  check "chessboard: wrong board size names each photo (exit $rc)" $?
else
  echo "skip chessboard checks: opencv-doc not installed"
fi

"${run[@]}" calibrate --vanishing "$data/calibration/vanishing-marks.json" \
  --corners "$data/calibration/room-corners.json" --json "$tmp/vp.json" >"$tmp/out" 2>"$tmp/err"
rc=$?
fx="$(value fx "$tmp/out")" err="$(value reprojection_error_px "$tmp/out")"
cerr="$(value corners_reprojection_error_px "$tmp/out")"
[[ $rc == 0 && -e "$tmp/vp.json" ]] && awk -v f="$fx" -v e="$err" -v c="$cerr" \
  'BEGIN {exit !(f > 693 && f < 707 && e < 0.5 && c != "" && c < 0.5)}'
check "vanishing: f $fx (true 700), reprojection_error_px $err, corners $cerr" $?

# expect_error NAME TEXT-IN-STDERR ARGS...: exit 1, stderr names the problem, no JSON.
expect_error() {
  local name="$1" text="$2"
  shift 2
  rm -f "$tmp/bad.json"
  "${run[@]}" calibrate "$@" --json "$tmp/bad.json" >"$tmp/out" 2>"$tmp/err"
  local rc=$?
  [[ $rc == 1 && ! -e "$tmp/bad.json" ]] && grep -q -- "$text" "$tmp/err"
  status=$?
  check "error ($name): exit $rc, $(head -c 200 "$tmp/err")" $status
}
python3 - "$data/calibration/vanishing-marks.json" "$tmp" <<'PY'
import json, sys, os
doc = json.load(open(sys.argv[1])); d = sys.argv[2]
def write(name, mutate):
    x = json.loads(json.dumps(doc)); mutate(x); json.dump(x, open(os.path.join(d, name), "w"))
# Two parallel x lines: vanishing point at infinity.
write("parallel.json", lambda x: x["vanishing_lines"].__setitem__("x", [[[0, 100], [600, 130]], [[0, 300], [600, 330]]]))
# Both vanishing points on the same side: f^2 <= 0.
write("fsq.json", lambda x: x["vanishing_lines"].update({"x": [[[0, 200], [500, 240]], [[0, 300], [500, 260]]],
                                                          "z": [[[0, 100], [500, 200]], [[0, 400], [500, 300]]]}))
write("missing-axis.json", lambda x: x["axis_points"].pop("z"))
write("string.json", lambda x: x.__setitem__("origin", ["nan", 3]))
PY
expect_error "parallel lines" "parallel.json: vanishing_lines.x" --vanishing "$tmp/parallel.json"
expect_error "f^2 <= 0" "fsq.json: vanishing_lines: f^2" --vanishing "$tmp/fsq.json"
expect_error "axis point missing" "missing-axis.json: axis_points.z" --vanishing "$tmp/missing-axis.json"
expect_error "not a number" "string.json: origin\[0\]" --vanishing "$tmp/string.json"
expect_error "no such marks file" "nothere.json" --vanishing "$tmp/nothere.json"
expect_error "no mode" "exactly one of"
echo '{"corners": [{"world": [0, 0, 0], "image": [1, 2]}]}' >"$tmp/corners.json"
expect_error "too few corners" "corners.json: 1 corner mark(s), need at least 4" \
  --vanishing "$data/calibration/vanishing-marks.json" --corners "$tmp/corners.json"

# `penumbra camera-response` (also built with OpenCV; its result is checked end to end by
# EnvironmentHdr.* in the kiosk tests): help, and every refusal exits non-zero naming the
# shot or the file, with no response file written.
"${run[@]}" camera-response --help >"$tmp/help" 2>&1
check "help: penumbra camera-response --help" $?
response_error() {  # response_error WHAT EXIT PATTERN ARGS...
  local what="$1" want="$2" pattern="$3"
  shift 3
  rm -f "$tmp/response.json"
  "${run[@]}" camera-response "$@" -o "$tmp/response.json" >"$tmp/out" 2>"$tmp/err"
  local rc=$?
  [[ $rc == "$want" && ! -e "$tmp/response.json" ]] && grep -q -- "$pattern" "$tmp/err"
  local status=$?  # before the message's $(...) resets $?
  check "camera-response: $what (exit $rc): $(head -c 150 "$tmp/err")" $status
}
response_error "no exposure" 2 "a.png: expected IMAGE:EXPOSURE_US" a.png b.png:100
response_error "exposure not a number" 2 "a.png:1e3: the exposure must be a whole number" a.png:1e3 b.png:100
response_error "exposure 0" 2 "the exposure must be a whole number of microseconds" a.png:0 b.png:100
response_error "one shot" 2 "need at least two IMAGE:EXPOSURE_US" a.png:100
response_error "missing image" 1 "$tmp/nothere.png" "$tmp/nothere.png:100" "$tmp/nothere2.png:200"

# `penumbra calibrate-fisheye` (OpenCV's fisheye module): its refusals exit non-zero naming the
# photo or the flag, and write no lens file. A good calibration, through a known lens, and the
# kiosk's verdict on it are FisheyeCalibrationTest.* in the kiosk tests.
"${run[@]}" calibrate-fisheye --help >"$tmp/help" 2>&1
check "help: penumbra calibrate-fisheye --help" $?
fisheye_error() {  # fisheye_error WHAT EXIT PATTERN ARGS...
  local what="$1" want="$2" pattern="$3"
  shift 3
  rm -f "$tmp/lens.json"
  "${run[@]}" calibrate-fisheye "$@" -o "$tmp/lens.json" >"$tmp/out" 2>"$tmp/err"
  local rc=$?
  [[ $rc == "$want" && ! -e "$tmp/lens.json" ]] && grep -q -- "$pattern" "$tmp/err"
  local status=$?
  check "calibrate-fisheye: $what (exit $rc): $(head -c 150 "$tmp/err")" $status
}
fisheye_error "no --board" 2 "board is required" "$tmp/a.png" --square 0.025
fisheye_error "no --square" 2 "square is required" "$tmp/a.png" --board 9x6
fisheye_error "bad --board" 2 "--board: chessboard size '9by6'" "$tmp/a.png" --board 9by6 --square 1
fisheye_error "board too small" 2 "--board: chessboard 1x6: needs at least 2x2" "$tmp/a.png" --board 1x6 --square 1
fisheye_error "square 0" 2 "--square: expects a number from 1e-06 to 1e+06, got '0'" "$tmp/a.png" --board 9x6 --square 0
fisheye_error "missing photo" 1 "$tmp/nothere.png: no such file" "$tmp/nothere.png" --board 9x6 --square 1
"${run[@]}" calibrate-fisheye "$data/calibration/vanishing-marks.json" --board 9x6 --square 1 \
  -o "$tmp/no/lens.json" >"$tmp/out" 2>"$tmp/err"
rc=$?
[[ $rc == 1 && ! -e "$tmp/no" ]] && grep -q -- "$tmp/no/lens.json: no such folder" "$tmp/err"
status=$?
check "calibrate-fisheye: output folder missing (exit $rc): $(head -c 150 "$tmp/err")" $status
if [[ -e "$photos/left01.jpg" ]]; then
  fisheye_error "two photos" 1 "2 of 2 photos show the whole 9x6 board, need at least 3" \
    "$photos/left01.jpg" "$photos/left02.jpg" --board 9x6 --square 1
  fisheye_error "wrong board" 1 "left03.jpg: no 7x7 chessboard found" \
    "$photos/left01.jpg" "$photos/left02.jpg" "$photos/left03.jpg" --board 7x7 --square 1
fi
finish
