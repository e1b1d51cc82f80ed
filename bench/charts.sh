#!/usr/bin/env bash
# Regenerates every accuracy chart of issue 5 (PNG + CSV) into OUT_DIR:
#   bench/charts.sh BUILD_DIR OUT_DIR [--small] [--reference REF.png] [--targets TABLE.md]
# (a) fig9-raytraced.png + accuracy.json/.csv  from `penumbra accuracy` against the ray-traced
#     reference (when penumbra is built with it); its reference.png and shadow-mask.png then
#     serve as the reference of (b) and of ms-vs-passes.png
# (a) ms-vs-passes.png, (b) pareto.png   from penumbra-accuracy-sweep -> sweep.csv
# (c) fig3.png                           from penumbra-fig3 -> fig3.csv (bench/plot_fig3.py)
# (d) drift.png                          from penumbra-drift -> drift.csv
# --small: a few configurations and a noisy 1-spp reference (CI). --reference: errors
# against this PNG instead; without the ray tracer and without --reference, against a
# 2048-map, most-passes Penumbra render (the chart titles say which). --targets: also write
# issue 5's targets with their measured values as a markdown table (bench/accuracy_targets.py;
# needs the ray-traced run).
# Needs the bench targets built (cmake --build BUILD_DIR --target penumbra-accuracy-sweep
# penumbra-drift penumbra-fig3) and Debian's /usr/bin/python3 with python3-matplotlib.
set -euo pipefail
build="$1" out="$2"
shift 2
small=0 ref=() targets=""
while [[ $# -gt 0 ]]; do
  case "$1" in
    --small) small=1 ;;
    --reference) ref=(--reference "$2"); shift ;;
    --targets) targets="$2"; shift ;;
    *) echo "charts.sh: unknown option $1" >&2; exit 2 ;;
  esac
  shift
done
here="$(cd "$(dirname "$0")" && pwd)"
scene="$here/../data/showroom/showroom.json"
py=/usr/bin/python3
mkdir -p "$out"
if [[ $small == 1 ]]; then
  sweep=(--shares 0.5,0.9 --maps 128,256 --passes 1,5,20 --curve-share 0.9 --curve-map 256
         --curve-passes 1,2,5,10,20,50 --frames 2)
  drift=(--max-passes 200 --vertices 16)
  fig3=(--trials 20)
  acc=(--passes 1,5,10,20,50 --frames 1 --spp 1 --light-samples 8)
else
  sweep=(--shares 0.5,0.7,0.9 --maps 64,128,256,512 --passes 1,2,5,10,20,50,100,200
         --curve-share 0.9 --curve-map 256 --frames 7)
  drift=(--max-passes 200)
  fig3=()
  acc=(--passes 1,2,3,4,5,6,8,10,12,15,20,25,30,40,50,60,80,100,150,200 --frames 7 --spp 16)
fi
penumbra="$build/bin/penumbra"
accuracy=0
if [[ ${#ref[@]} == 0 ]] && "$penumbra" reference --help >/dev/null 2>&1 \
   && "$penumbra" accuracy --help >/dev/null 2>&1; then
  "$penumbra" precompute "$scene" -o "$out/showroom.bundle" >/dev/null
  "$penumbra" accuracy "$out/showroom.bundle" "${acc[@]}" --json "$out/accuracy.json" \
    --reference-out "$out/reference.png" --mask-out "$out/shadow-mask.png"
  $py "$here/plot_accuracy.py" "$out/accuracy.json" "$out/fig9-raytraced.png" "$out/accuracy.csv"
  accuracy=1
  ref=(--reference "$out/reference.png" --mask "$out/shadow-mask.png")
  rm -f "$out/showroom.bundle"
fi
"$build/bin/penumbra-accuracy-sweep" "$scene" --csv "$out/sweep.csv" "${sweep[@]}" "${ref[@]}" \
  --reference-out "$out/reference-used.png"
"$build/bin/penumbra-drift" --csv "$out/drift.csv" "${drift[@]}"
"$build/bin/penumbra-fig3" "$scene" --csv "$out/fig3.csv" "${fig3[@]}"
$py "$here/plot_charts.py" "$out/sweep.csv" "$out/drift.csv" "$out"
$py "$here/plot_fig3.py" "$out/fig3.csv" "$out/fig3.png"
if [[ -n $targets ]]; then
  if [[ $accuracy == 0 ]]; then
    echo "charts.sh: --targets needs penumbra built with the ray tracer, and no --reference" >&2
    exit 2
  fi
  $py "$here/accuracy_targets.py" "$out/accuracy.json" "$out/drift.csv" "$targets"
fi
ls "$out"
