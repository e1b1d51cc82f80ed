# Shared by the end-to-end CLI test scripts (sourced, not run): a private scratch directory
# removed on exit, named checks that count failures instead of stopping at the first, and
# readers for the commands' "key value" output lines.
#   source "$(dirname "${BASH_SOURCE[0]}")/check_lib.sh"
#   check NAME $?        after a command or a [[ ]] condition; when NAME holds a $(...),
#                        save $? first (status=$?; check "... $(...)" $status): the
#                        substitution runs before $? is expanded and resets it to its own.
#   finish               prints the tally; exit status 1 when any check failed
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
failures=0
checks=0
check() {  # check NAME EXIT-CODE-OF-CONDITION
  checks=$((checks + 1))
  if [[ "$2" == 0 ]]; then echo "ok   $1"; else echo "FAIL $1"; failures=$((failures + 1)); fi
}
# value KEY FILE: the second word of the line whose first word is KEY ("key value" output).
value() { awk -v k="$1" '$1 == k {print $2}' "$2"; }
# field KEY FILE: the word after KEY anywhere on a line ("a 1 b 2" output).
field() { awk -v k="$1" '{for (i = 1; i < NF; ++i) if ($i == k) print $(i + 1)}' "$2"; }
finish() {
  echo "$((checks - failures)) of $checks checks passed, $failures failed"
  exit $((failures > 0))
}
# The workload of the end-to-end scripts. The asan and tsan test presets set
# PENUMBRA_TEST_WORKLOAD=small: a sanitizer looks for memory errors and races, which a
# 320x240 frame exercises on the same code paths as a 640x480 one, 5-20x slower than
# release; the release and aarch64 stages keep the full size (CI time, issue 2).
small_workload() { [[ "${PENUMBRA_TEST_WORKLOAD:-full}" == small ]]; }
# showroom_scene DATA_DIR: prints the showroom scene to test with: data/showroom/showroom.json,
# or under the small workload a 320x240 copy in $tmp (model paths made absolute).
showroom_scene() {
  local scene="$1/showroom/showroom.json"
  if small_workload; then
    sed -e 's|"image": {"width": 640, "height": 480}|"image": {"width": 320, "height": 240}|' \
        -e "s|\"\\.\\./models/|\"$1/models/|" "$scene" >"$tmp/showroom-small.json"
    grep -q '"width": 320' "$tmp/showroom-small.json" || { echo "showroom_scene: no 640x480 image in $scene" >&2; return 1; }
    scene="$tmp/showroom-small.json"
  fi
  echo "$scene"
}
