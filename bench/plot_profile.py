#!/usr/bin/env python3
"""Draws `penumbra profile` CSV output: ms per frame against passes, stacked by stage.

    python3 bench/plot_profile.py profile.csv profile.png
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# The stage_* columns (shadow/frame_stages.h), in frame order: their means add up to
# ms_mean, the mean frame; ms_total is the median frame.


def main(csv_path, png_path):
    with open(csv_path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"{csv_path}: no rows")
    passes = [int(r["passes_asked"]) for r in rows]
    fig, ax = plt.subplots(figsize=(8, 5), dpi=120)
    bottom = [0.0] * len(rows)
    stages = [k for k in rows[0] if k.startswith("stage_")]
    for i, key in enumerate(stages):
        values = [float(r[key]) for r in rows]
        if max(values) == 0:
            continue
        label = key[len("stage_"):].replace("_", " ")
        ax.fill_between(passes, bottom, [b + v for b, v in zip(bottom, values)], label=label,
                        color=plt.cm.tab20.colors[i % 20], alpha=0.85)
        bottom = [b + v for b, v in zip(bottom, values)]
    ax.plot(passes, [float(r["ms_mean"]) for r in rows], "k.-", label="mean frame (measured)")
    ax.plot(passes, [float(r["ms_total"]) for r in rows], "k:", label="median frame")
    ax.set_xlabel("blending passes (source clusters)")
    ax.set_ylabel("ms per frame (stages: means)")
    ax.set_title("Penumbra: frame time against passes, by stage")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper left", fontsize=8)
    fig.tight_layout()
    fig.savefig(png_path)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
