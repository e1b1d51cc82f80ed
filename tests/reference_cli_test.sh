#!/usr/bin/env bash
# `penumbra reference` end to end on the showroom bundle: the product out of the room leaves
# the background photograph byte for byte; in place it casts a shadow (mask written); the
# bytes do not depend on --threads; bad arguments -> a clear error, exit non-zero, no image.
#   tests/reference_cli_test.sh PENUMBRA DATA_DIR
set -uo pipefail
penumbra="$1" data="$2"
source "$(dirname "${BASH_SOURCE[0]}")/check_lib.sh"

scene="$(showroom_scene "$data")" || exit 1
"$penumbra" precompute "$scene" -o "$tmp/s.bundle" >"$tmp/pre" 2>&1
check "precompute: showroom bundle" $?
ref=("$penumbra" reference "$tmp/s.bundle" --spp 1 --light-samples 4)

"${ref[@]}" --pose 100,0,100 --out "$tmp/far.png" >"$tmp/far" 2>"$tmp/far.err"
rc=$?
[[ $rc == 0 && -s "$tmp/far.png" ]] && [[ "$(field changed_pixels "$tmp/far")" == 0 ]] \
  && [[ "$(field shadow_pixels "$tmp/far")" == 0 ]] && grep -q "100%" "$tmp/far.err"
status=$?
check "product far away: the background byte for byte ($(grep -o 'changed_pixels [0-9]*' "$tmp/far"))" $status

"${ref[@]}" --threads 1 --out "$tmp/t1.png" --shadow-mask "$tmp/mask.png" >"$tmp/t1" 2>&1
rc=$?
[[ $rc == 0 && -s "$tmp/mask.png" ]] && (($(field shadow_pixels "$tmp/t1") > 500)) \
  && (($(field product_pixels "$tmp/t1") > 500))
status=$?
check "product at the start pose: shadow and product ($(grep -o 'shadow_pixels.*' "$tmp/t1"))" $status

"${ref[@]}" --threads 2 --out "$tmp/t2.png" >/dev/null 2>&1
cmp -s "$tmp/t1.png" "$tmp/t2.png"
check "same bytes for --threads 1 and 2" $?

bad() {  # bad NAME EXPECTED-TEXT ARGS...
  local name="$1" text="$2"
  shift 2
  "$penumbra" reference "$@" --out "$tmp/bad.png" >"$tmp/out" 2>"$tmp/err"
  local rc=$?
  [[ $rc != 0 && ! -e "$tmp/bad.png" ]] && grep -q -- "$text" "$tmp/err"
  status=$?
  check "bad: $name (exit $rc): $(head -c 160 "$tmp/err" | tr '\n' ' ')" $status
}
bad "missing bundle" "nope.bundle" "$tmp/nope.bundle"
bad "pose not numbers" "pose" "$tmp/s.bundle" --pose 1,x,2
bad "product out of range" "product" "$tmp/s.bundle" --product 7
bad "spp 0" "spp" "$tmp/s.bundle" --spp 0
bad "non-finite pose" "finite" "$tmp/s.bundle" --pose 1,0,inf
finish
