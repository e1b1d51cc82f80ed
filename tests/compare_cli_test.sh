#!/usr/bin/env bash
# `penumbra compare` end to end on the committed showroom renders (docs/*.png): an image
# against itself is perfect, two different renders are not, the FLIP heat map is written,
# and bad input (missing file, size mismatch, mask of the wrong size) fails with a message
# naming the file, exit 1, and no JSON or heat map written.
#   tests/compare_cli_test.sh PENUMBRA SOURCE_DIR [EMULATOR...]
set -uo pipefail
penumbra="$1" src="$2"
shift 2
run=("$@" "$penumbra")
source "$(dirname "${BASH_SOURCE[0]}")/check_lib.sh"
py=/usr/bin/python3
bunny="$src/docs/showroom-bunny.png" chair="$src/docs/showroom-chair.png"
fig3="$src/docs/fig3.png"

"${run[@]}" compare "$bunny" "$bunny" --json "$tmp/self.json" --heatmap "$tmp/self.png" \
  --ppd 20 >"$tmp/out" 2>"$tmp/err"
rc=$?
[[ $rc == 0 && -s "$tmp/self.png" ]] && $py -c "
import json,sys; d=json.load(open(sys.argv[1])); f=d['frame']
assert f['mean_abs']==0 and f['max_abs']==0 and f['p99_abs']==0 and f['psnr'] is None
assert f['identical'] and d['ssim']==1.0 and f['flip_mean']==0 and d['flip_ppd']==20
" "$tmp/self.json"
check "self-compare: 0 error, psnr null (infinite), ssim 1, flip 0, heat map written" $?

"${run[@]}" compare "$bunny" "$chair" --mask "$bunny" --ppd 20 >"$tmp/diff.json" 2>"$tmp/err"
rc=$?
[[ $rc == 0 ]] && $py -c "
import json,sys; d=json.load(open(sys.argv[1])); f=d['frame']; m=d['mask']
assert f['mean_abs']>0 and f['max_abs']>=f['p99_abs']>0 and f['psnr']>0
assert 0<d['ssim']<1 and 0<f['flip_mean']<1 and 0<m['pixels']<=640*480
" "$tmp/diff.json"
check "bunny vs chair: nonzero errors on stdout JSON, with a mask" $?

expect_fail() {  # expect_fail NAME NEEDLE ARGS...
  local name="$1" needle="$2"
  shift 2
  rm -f "$tmp/bad.json" "$tmp/bad.png"
  "${run[@]}" compare "$@" --json "$tmp/bad.json" --heatmap "$tmp/bad.png" >"$tmp/out" 2>"$tmp/err"
  local rc=$?
  [[ $rc != 0 && ! -e "$tmp/bad.json" && ! -e "$tmp/bad.png" ]] && grep -qF "$needle" "$tmp/err"
  status=$?
  check "$name (stderr: $(head -c 160 "$tmp/err" | tr '\n' ' '))" $status
}
expect_fail "missing file" "$tmp/nope.png" "$bunny" "$tmp/nope.png"
echo "not a png" >"$tmp/junk.png"
expect_fail "undecodable file" "$tmp/junk.png" "$tmp/junk.png" "$bunny"
expect_fail "size mismatch" "$fig3" "$bunny" "$fig3"
expect_fail "mask of the wrong size" "$fig3" "$bunny" "$chair" --mask "$fig3"

# `penumbra accuracy` (needs precompute, i.e. the lighting library): with the stand-in's own
# settings the frame equals the stand-in reference; a reference of the wrong size is refused.
# The small workload (check_lib.sh) compares at 512 instead of the stand-in's 2048 map.
if "${run[@]}" precompute --help >/dev/null 2>&1; then
  scene="$(showroom_scene "$src/data")" || exit 1
  maps=(--shadow-map 2048)
  if small_workload; then maps=(--shadow-map 512 --reference-map 512); fi
  "${run[@]}" precompute "$scene" -o "$tmp/s.bundle" >/dev/null 2>&1
  "${run[@]}" accuracy "$tmp/s.bundle" --passes 5,1000 --frames 1 "${maps[@]}" --penumbra-reference \
    --json "$tmp/acc.json" >"$tmp/out" 2>"$tmp/err"
  rc=$?
  [[ $rc == 0 ]] && $py -c "
import json,sys; d=json.load(open(sys.argv[1])); r=d['results']
assert d['reference']['kind']=='penumbra' and [x['passes_asked'] for x in r]==[5,1000]
assert r[0]['mean_abs_shadow']>0 and r[0]['ssim']<1 and r[0]['flip']>0 and r[0]['ms_per_frame']>0
assert r[1]['mean_abs_shadow']==0 and r[1]['psnr'] is None and r[1]['ssim']==1 and r[1]['flip']==0
" "$tmp/acc.json"
  check "accuracy: 5 passes has error, all passes equal the stand-in reference (${maps[*]})" $?
  rm -f "$tmp/bad.json"
  "${run[@]}" accuracy "$tmp/s.bundle" --passes 5 --frames 1 --reference "$fig3" \
    --json "$tmp/bad.json" >"$tmp/out" 2>"$tmp/err"
  rc=$?
  [[ $rc != 0 && ! -e "$tmp/bad.json" ]] && grep -qF "$fig3" "$tmp/err"
  status=$?
  check "accuracy: reference of the wrong size (stderr: $(head -c 160 "$tmp/err"))" $status
  if "${run[@]}" reference --help >/dev/null 2>&1; then
    # Against the ray tracer (a quick, noisy one): errors are finite and the mask non-empty.
    "${run[@]}" accuracy "$tmp/s.bundle" --passes 20 --frames 1 --spp 1 --light-samples 4 \
      --json "$tmp/rt.json" >"$tmp/out" 2>"$tmp/err"
    rc=$?
    [[ $rc == 0 ]] && $py -c "
import json,sys; d=json.load(open(sys.argv[1])); r=d['results'][0]
assert d['reference']['kind']=='raytraced' and d['reference']['spp']==1
assert r['shadow_pixels']>100 and 0<r['mean_abs_shadow']<50 and 0<r['ssim']<1 and r['psnr']>10
" "$tmp/rt.json"
    check "accuracy: against the ray-traced reference (spp 1)" $?
  fi
fi
finish
