#!/usr/bin/env python3
"""Draws penumbra-fig3 CSV output: 8-bit error against the occluded share of sources.

    python3 bench/plot_fig3.py fig3.csv fig3.png
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

LABELS = {
    "fig4_50_50": "Fig. 4, fixed 50/50 sets (paper)",
    "graded_q_0.5": "graded, q = 0.5",
    "graded_q_measured": "graded, q = measured occlusion",
}


def main(csv_path, png_path):
    with open(csv_path, newline="") as f:
        rows = list(csv.DictReader(f))
    share = [100 * float(r["occluded_share"]) for r in rows]
    fig, ax = plt.subplots(figsize=(8, 5), dpi=120)
    for key, label in LABELS.items():
        ax.plot(share, [float(r[key + "_mean_abs"]) for r in rows], "-o", ms=3, label=label + " (mean)")
        ax.plot(share, [float(r[key + "_p99_abs"]) for r in rows], ":", label=label + " (99th pct)")
    ax.set_xlabel("sources actually occluded (%)")
    ax.set_ylabel("|error| in 8-bit levels vs T(L - sum occluded)")
    ax.set_title("Gibson 2003 Fig. 3, measured on the showroom")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(png_path)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
