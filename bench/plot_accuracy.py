#!/usr/bin/env python3
"""Draws `penumbra accuracy --json` output as the paper's Fig. 9 curve, measured: ms/frame
and the shadow-region error against blending passes, against the reference it names.

    /usr/bin/python3 bench/plot_accuracy.py accuracy.json accuracy.png [accuracy.csv]
"""
import csv
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

FIELDS = ["passes_asked", "passes", "ms_per_frame", "mean_abs_shadow", "p99_abs_shadow",
          "ssim", "psnr", "flip", "flip_shadow", "mean_abs_frame", "shadow_pixels"]


def main(json_path, png_path, csv_path=None):
    with open(json_path) as f:
        d = json.load(f)
    rows = d["results"]
    if not rows:
        sys.exit(f"{json_path}: no results")
    if csv_path:
        with open(csv_path, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=FIELDS, extrasaction="ignore")
            w.writeheader()
            w.writerows(rows)
    ref = d["reference"]
    if ref["kind"] == "raytraced":
        label = (f"ray-traced reference ({ref['spp']} spp, {ref['light_samples']} shadow rays, "
                 f"{ref['bounces']} bounces)")
    elif ref["kind"] == "image":
        label = f"reference image {ref['file']}"
    else:
        label = f"Penumbra stand-in reference ({ref['passes']} passes, map {ref['shadow_map']})"
    n = [r["passes_asked"] for r in rows]
    fig, ax = plt.subplots(figsize=(8, 5), dpi=120)
    ax.plot(n, [r["ms_per_frame"] for r in rows], "o-", color="tab:blue")
    ax.set_xscale("log")
    ax.set_xlabel("blending passes asked (used passes ≤ occluded clusters)")
    ax.set_ylabel("ms per frame (median)", color="tab:blue")
    ax2 = ax.twinx()
    ax2.plot(n, [r["mean_abs_shadow"] for r in rows], "s--", color="tab:red",
             label="mean |error| in shadow")
    ax2.plot(n, [r["p99_abs_shadow"] for r in rows], "^:", color="tab:orange",
             label="p99 |error| in shadow")
    ax2.set_ylabel("8-bit error in the shadow region", color="tab:red")
    ax2.legend(loc="upper center", fontsize=8)
    ax.set_title(f"Fig. 9 measured: ms/frame and error vs passes, map {d['shadow_map']}\n"
                 f"against the {label}", fontsize=9)
    fig.tight_layout()
    fig.savefig(png_path)


if __name__ == "__main__":
    if len(sys.argv) not in (3, 4):
        sys.exit(__doc__)
    main(*sys.argv[1:])
