#!/usr/bin/env python3
"""Draws the accuracy charts of issue 5 from the CSVs bench/charts.sh writes.

    /usr/bin/python3 bench/plot_charts.py sweep.csv drift.csv OUT_DIR

(a) OUT_DIR/ms-vs-passes.png: ms/frame against blending passes (Gibson 2003 Fig. 9 as a
    curve) at the sweep's curve share and map size, with the shadow-region error beside it;
(b) OUT_DIR/pareto.png: ms/frame against mean shadow-region error over passes x shadow-map
    size x source share, the Pareto front drawn as a line;
(d) OUT_DIR/drift.png: 8-bit drift against the number of faint passes (Gibson 2003 §10).
Chart (c), Fig. 3, is bench/plot_fig3.py. Titles name the reference the errors are against.
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"{path}: no rows")
    return rows


def chart_a(rows, out):
    curve = sorted((r for r in rows if r["curve"] == "1"), key=lambda r: int(r["passes_asked"]))
    if not curve:
        sys.exit("sweep CSV has no curve rows (curve == 1)")
    n = [int(r["passes_asked"]) for r in curve]
    fig, ax = plt.subplots(figsize=(8, 5), dpi=120)
    ax.plot(n, [float(r["ms_frame"]) for r in curve], "o-", color="tab:blue", label="ms/frame")
    ax.set_xlabel("blending passes asked (used passes ≤ occluded clusters)")
    ax.set_ylabel("ms per frame (median)", color="tab:blue")
    ax2 = ax.twinx()
    ax2.plot(n, [float(r["mean_abs_shadow"]) for r in curve], "s--", color="tab:red",
             label="mean |error| in shadow")
    ax2.set_ylabel("mean abs error in the shadow region (8-bit levels)", color="tab:red")
    ax.set_xscale("log")
    c = curve[0]
    ax.set_title(f"ms/frame vs passes (Fig. 9), share {c['share']}, map {c['map']}\n"
                 f"{c['reference']}", fontsize=9)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "ms-vs-passes.png"))


def chart_b(rows, out):
    pts = [(float(r["ms_frame"]), float(r["mean_abs_shadow"]), r) for r in rows]
    fig, ax = plt.subplots(figsize=(8, 5), dpi=120)
    for share in sorted({r["share"] for r in rows}):
        for m in sorted({r["map"] for r in rows}, key=int):
            sel = [p for p in pts if p[2]["share"] == share and p[2]["map"] == m]
            ax.scatter([p[0] for p in sel], [p[1] for p in sel], s=18,
                       label=f"share {share}, map {m}")
    front, best = [], float("inf")
    for p in sorted(pts, key=lambda p: (p[0], p[1])):
        if p[1] < best:
            front.append(p)
            best = p[1]
    ax.plot([p[0] for p in front], [p[1] for p in front], "k-", lw=1, label="Pareto front")
    for p in front:
        ax.annotate(p[2]["passes"], (p[0], p[1]), fontsize=7, xytext=(3, 3),
                    textcoords="offset points")
    ax.set_xlabel("ms per frame (median)")
    ax.set_ylabel("mean abs error in the shadow region (8-bit levels)")
    ax.set_title(f"cost vs error over passes x map size x source share\n{rows[0]['reference']}",
                 fontsize=9)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "pareto.png"))


def chart_d(rows, out):
    fig, ax = plt.subplots(figsize=(8, 5), dpi=120)
    for mask, style in (("255", "-"), ("128", "--")):
        for policy in ("independent", "fig4", "graded", "graded-fixed8_8"):
            sel = [r for r in rows if r["mask"] == mask and r["policy"] == policy]
            if sel:
                ax.plot([int(r["passes"]) for r in sel], [float(r["mean_abs"]) for r in sel],
                        style, label=f"{policy}, mask {mask}")
    ax.axhline(2.0, color="grey", lw=0.8, ls=":", label="target ≤ 2 LSB")
    ax.set_yscale("symlog", linthresh=1.0)
    ax.set_ylim(bottom=0)
    ax.set_xlabel("faint passes N")
    ax.set_ylabel("mean |8-bit result − HDR answer| (levels)")
    ax.set_title("8-bit drift of N faint passes (Gibson 2003 §10), against the exact HDR answer",
                 fontsize=9)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "drift.png"))


def main(sweep, drift, out):
    os.makedirs(out, exist_ok=True)
    rows = read(sweep)
    chart_a(rows, out)
    chart_b(rows, out)
    chart_d(read(drift), out)


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    main(*sys.argv[1:])
