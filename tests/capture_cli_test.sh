#!/usr/bin/env bash
# `penumbra capture` end to end: synthetic photographs, probe and marks of the showroom
# (penumbra-capture-synth) -> bundle -> `penumbra render` draws the product with shadows;
# bad manifests -> a clear error naming the file and the field, exit 1, no bundle.
#   tests/capture_cli_test.sh PENUMBRA PENUMBRA_CAPTURE_SYNTH DATA_DIR
set -uo pipefail
penumbra="$1" synth="$2" data="$3"
source "$(dirname "${BASH_SOURCE[0]}")/check_lib.sh"

# The capture is written beside a copy of the scene (and its models), then the whole folder
# is moved: capture.json names the scene relative to itself, so the capture still loads.
mkdir -p "$tmp/made"
cp -r "$data/showroom" "$data/models" "$tmp/made/"
"$synth" "$tmp/made/showroom/showroom.json" "$tmp/made/in" >"$tmp/synth" 2>&1
check "synth: inputs written" $?
scene_field="$(python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["scene"])' \
  "$tmp/made/in/capture.json")"
[[ "$scene_field" == "../showroom/showroom.json" ]]
check "synth: capture.json names the scene relative to itself ($scene_field)" $?
mv "$tmp/made" "$tmp/moved"
in="$tmp/moved/in"

# stderr is a file here, not a terminal: progress is one plain line per stage, no "\r".
"$penumbra" capture "$in/capture.json" -o "$tmp/c.bundle" --threads 2 >"$tmp/out" 2>"$tmp/err"
rc=$?
f="$(awk '$1 == "focal_px" {print $2}' "$tmp/out")"
[[ $rc == 0 && -s "$tmp/c.bundle" ]] && grep -q "^reprojection_error_px" "$tmp/out" \
  && grep -q "^patches 1341 sources [1-9]" "$tmp/out" && grep -q "^dynamic_range stops" "$tmp/out" \
  && grep -q "irradiance volume" "$tmp/err" \
  && awk -v f="$f" 'BEGIN {exit !(f > 413.6 && f < 417.8)}'
check "capture (moved folder): bundle written, summary (focal $f px, true 415.69) and progress" $?
! grep -q $'\r' "$tmp/err" && grep -qE '^capture +1/[0-9]+ ' "$tmp/err"
status=$?
check "capture: progress without a terminal is plain lines ($(grep -c '^capture ' "$tmp/err") stages)" $status

"$penumbra" render "$tmp/c.bundle" --passes 30 --out "$tmp/frame.png" >"$tmp/render" 2>&1
rc=$?
[[ $rc == 0 && -s "$tmp/frame.png" ]] && grep -q "^passes [1-9]" "$tmp/render"
check "render: the captured bundle drives a frame" $?

bad() {  # bad NAME SED-EXPRESSION EXPECTED-TEXT
  sed "$2" "$in/capture.json" >"$in/bad.json"
  "$penumbra" capture "$in/bad.json" -o "$tmp/bad.bundle" >"$tmp/out" 2>"$tmp/err"
  local rc=$?
  [[ $rc == 1 && ! -e "$tmp/bad.bundle" ]] && grep -q "$3" "$tmp/err"
  status=$?
  check "bad manifest: $1 (exit $rc): $(grep -o 'error: .*' "$tmp/err" | head -c 160)" $status
}
bad "live exposure out of range" 's/"index": 4/"index": 9/' "bad.json: live_exposure.index: 9 is not in"
bad "unknown field" 's/"mapping"/"colour": 1, "mapping"/' "bad.json: probe.colour: unknown field"
bad "probe outside the room" 's/"position": \[/"position": [-9, 1, 1], "_was": [/' "bad.json: probe: .*sees no patch"
bad "missing probe file" 's/probe.exr/nope.exr/' "nope.exr: cannot open file (no such file)"
bad "missing photograph" 's/bracket-2.png/nope.png/' "nope.png"
finish
