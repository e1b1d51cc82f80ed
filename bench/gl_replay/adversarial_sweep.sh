#!/usr/bin/env bash
# The GL replay against Penumbra's Renderer on random adversarial traces (raster/
# adversarial_trace.h; docs/performance.md, "A faithful replay"): writes COUNT traces from
# FIRST_SEED with penumbra-synth-trace --random, replays each with penumbra-gl-replay
# --compare, and prints min / median / max of the identical byte share, how many traces are
# byte-identical, and the median GL and Penumbra ms per frame over the traces.
#
#   bench/gl_replay/adversarial_sweep.sh [BIN_DIR] [COUNT] [FIRST_SEED]
#
# BIN_DIR defaults to build/ci/bin; GL_REPLAY=path replaces its penumbra-gl-replay (to
# measure another build of the replay on the same traces); FRAMES (default 3) frames timed.
set -euo pipefail
bin=${1:-build/ci/bin}
count=${2:-100}
first=${3:-1}
replay=${GL_REPLAY:-$bin/penumbra-gl-replay}
frames=${FRAMES:-3}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
"$bin/penumbra-synth-trace" --random "$first" --count "$count" -o "$dir" > /dev/null
results="$dir/results.txt"
for ((k = 0; k < count; ++k)); do
  seed=$((first + k))
  "$replay" "$dir/random-$seed.json" --compare --frames "$frames" 2> /dev/null |
    python3 -c 'import json, sys; j = json.load(sys.stdin); print(sys.argv[1], j["identical_byte_share"], j["max_abs_diff"], j["gl_ms_median"], j["penumbra_ms_median"])' "$seed" >> "$results"
done
python3 - "$results" <<'PY'
import statistics, sys
rows = [line.split() for line in open(sys.argv[1])]
share = sorted(float(r[1]) for r in rows)
worst = min(rows, key=lambda r: float(r[1]))
print(f"traces {len(rows)}: identical byte share min {share[0]:.6f} (seed {worst[0]}, "
      f"max diff {worst[2]}), median {statistics.median(share):.6f}, max {share[-1]:.6f}; "
      f"byte-identical {sum(1 for s in share if s == 1.0)}")
print(f"median ms per frame: GL {statistics.median(float(r[3]) for r in rows):.3f}, "
      f"Penumbra {statistics.median(float(r[4]) for r in rows):.3f}")
PY
