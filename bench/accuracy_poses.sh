#!/usr/bin/env bash
# Issue 15 item 7: the accuracy of every product of the showroom at a set of poses, each
# against its own ray-traced reference:
#   bench/accuracy_poses.sh BUILD_DIR BUNDLE OUT_DIR [SPP] [ACCUMULATION] [SAMPLING]
# writes OUT_DIR/<product>-<place>.json (penumbra accuracy's JSON, `--pose`/`--product`), the
# reference, its bounds and shadow region as <product>-<place>-{ref,lower,upper,mask}.png (so
# `penumbra accuracy --reference ... --reference-bounds ... --mask ...` measures again without
# ray tracing) and OUT_DIR/poses.md, a table per pose: mean abs / p99 in the shadow at 50
# passes and at the most passes, the same beyond the reference's bounds (what the
# photograph's 8 bits leave open, docs/reference.md), the error's largest rise with passes,
# and the contact band's mean signed error.
# SPP: the reference's samples per pixel (default 16, what the targets are stated for; a pose
# takes about a minute on 2 cores); ACCUMULATION: linear (default), fixed8_8 or u8; SAMPLING:
# jittered (default: the reference's camera rays spread over each pixel, anti-aliased) or
# centres (through the pixel centres, as the rasterizer samples; `--pixel-centres`).
#
# The set, per product (data/showroom/showroom.json: chair 0, bunny 1, teapot 2; the room's
# far walls are x = 6 and z = 5, the desk stands at x 4.4-5.8, z 3.4-4.2): open floor, against
# the x = 6 wall, in the corner between that wall and the desk, lifted off the floor, rotated.
set -euo pipefail
if [[ $# -lt 3 ]]; then
  echo "usage: bench/accuracy_poses.sh BUILD_DIR BUNDLE OUT_DIR [SPP] [ACCUMULATION] [SAMPLING]" >&2
  exit 2
fi
build="$1" bundle="$2" out="$3" spp="${4:-16}" accumulation="${5:-linear}"
sampling="${6:-jittered}"
case "$sampling" in
  jittered) sampling_flag=() ;;
  centres) sampling_flag=(--pixel-centres) ;;
  *) echo "accuracy_poses.sh: SAMPLING must be jittered or centres, not $sampling" >&2; exit 2 ;;
esac
penumbra="$build/bin/penumbra"
[[ -x "$penumbra" ]] || { echo "accuracy_poses.sh: $penumbra: not built" >&2; exit 1; }
[[ -f "$bundle" ]] || { echo "accuracy_poses.sh: $bundle: no such bundle" >&2; exit 1; }
mkdir -p "$out"

# name product X,LIFT,Z,YAW
poses=(
  "chair-open-floor 0 3.0,0,2.4,0"
  "chair-wall 0 5.45,0,2.2,90"
  "chair-corner 0 5.45,0,2.9,90"
  "chair-lifted 0 3.0,0.3,2.4,0"
  "chair-rotated 0 2.6,0,2.0,60"
  "bunny-open-floor 1 3.0,0,2.4,0"
  "bunny-wall 1 5.6,0,2.2,0"
  "bunny-corner 1 5.6,0,3.05,0"
  "bunny-lifted 1 3.0,0.5,2.4,0"
  "bunny-rotated 1 2.6,0,2.0,120"
  "teapot-open-floor 2 3.0,0,2.4,0"
  "teapot-wall 2 5.6,0,2.2,0"
  "teapot-corner 2 5.6,0,3.05,0"
  "teapot-lifted 2 3.0,0.5,2.4,0"
  "teapot-rotated 2 2.6,0,2.0,90"
)
for entry in "${poses[@]}"; do
  read -r name product pose <<<"$entry"
  echo "accuracy_poses.sh: $name (product $product, pose $pose)" >&2
  "$penumbra" accuracy "$bundle" --product "$product" --pose "$pose" --passes 10,30,50,82 \
    --spp "$spp" "${sampling_flag[@]}" --frames 1 --threads 2 --accumulation "$accumulation" \
    --reference-out "$out/$name-ref.png" --mask-out "$out/$name-mask.png" \
    --reference-bounds-out "$out/$name-lower.png,$out/$name-upper.png" \
    --json "$out/$name.json.part" >/dev/null
  mv "$out/$name.json.part" "$out/$name.json"
done

/usr/bin/python3 - "$out" "${poses[@]}" <<'EOF'
import json, sys
out = sys.argv[1]
rows = []
for entry in sys.argv[2:]:
    name = entry.split()[0]
    with open(f"{out}/{name}.json") as f:
        j = json.load(f)
    results = j["results"]
    at50 = next(r for r in results if r["passes_asked"] == 50)
    last = results[-1]
    means = [r["mean_abs_shadow"] for r in results]
    rise = max([b - a for a, b in zip(means, means[1:])] + [0.0])
    rows.append((name, at50, last, rise))
with open(f"{out}/poses.md.part", "w") as f:
    f.write("| pose | 50 passes: mean / p99 | beyond bounds | most passes (used): mean / p99 | "
            "beyond bounds | largest rise | contact band at 50: mean signed |\n"
            "|---|---|---|---|---|---|---|\n")
    for name, at50, last, rise in rows:
        f.write(f"| {name} | {at50['mean_abs_shadow']:.3f} / {at50['p99_abs_shadow']:.0f} | "
                f"{at50['mean_beyond_bounds_shadow']:.3f} / {at50['p99_beyond_bounds_shadow']:.0f} | "
                f"{last['mean_abs_shadow']:.3f} / {last['p99_abs_shadow']:.0f} ({last['passes']}) | "
                f"{last['mean_beyond_bounds_shadow']:.3f} / {last['p99_beyond_bounds_shadow']:.0f} | "
                f"{rise:.3f} | {at50['mean_signed_contact']:+.2f} |\n")
    for key, what in (("", "error"), ("beyond_bounds_", "error beyond the bounds")):
        worst50 = max(r[1][f"mean_{key or 'abs_'}shadow"] for r in rows)
        worstP99 = max(r[1][f"p99_{key or 'abs_'}shadow"] for r in rows)
        f.write(f"\nWorst pose at 50 passes, {what}: mean {worst50:.3f}, p99 {worstP99:.0f}.\n")
import os
os.replace(f"{out}/poses.md.part", f"{out}/poses.md")
EOF
cat "$out/poses.md"
