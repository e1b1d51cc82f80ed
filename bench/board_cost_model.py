#!/usr/bin/env python3
"""The simulated board's cost model from counted instructions (issue 13 item 5).

    bench/board_cost_model.py COUNTS_DIR [--markdown OUT.md] [--json OUT.json]

COUNTS_DIR is bench/board_instruction_counts.sh's output: per stage, millions of aarch64
instructions per frame on one thread. This fits each stage to the work that drives it (passes P,
receiver pixels summed over the passes X, shadow-map texels per pass T, product vertices V,
occluder triangles drawn into the maps summed over the passes S),
checks the fit against the counts, and turns instructions into nanoseconds on a Raspberry Pi 4
and 5 under the assumptions stated in ASSUMPTIONS, each with a low and a high end. It prints the
stage table and the `board` keys of a session file (shadow/frame_cost_model.h) for each board.
Plain Python (no numpy): the fits are least squares over at most four unknowns.
"""
import argparse
import csv
import json
import pathlib
import re
import sys

# What drives each stage's instructions. Terms: "1" (once a frame), "P", "PT" (P x texels),
# "X", "V", "PV" (P x V), "S" (occluder triangles drawn, raster::FrameStats::shadowMapTriangles). Which stages run on the renderer's worker threads ("parallel") comes
# from the code: core::forEachChunk / the tile pool (docs/performance.md "The whole kiosk frame").
STAGES = {
    # No per-pass constant of its own: with every map but eight 256², P and P·T move together
    # and a free constant comes out negative; a pass's fixed work is its map (T) and its
    # receivers (X). Its occluder is the proxy, or in the first passes the fine proxy (S, the
    # triangles drawn: with the fine proxy in none or every pass, the bunny's and the
    # teapot's frames differ by 630-1,040 instructions per triangle); the product's own
    # triangles receive for self-shadowing (PV, dropped when the fit makes it negative).
    "raster_passes": (["PT", "X", "PV", "S"], True),
    "pass_list": (["P", "X", "PV"], True),
    "product_transfers": (["1", "V", "PV"], True),
    "product_shading": (["V"], True),  # in the frames the product moved (the profile: all)
    "raster_objects": (["1", "V"], True),
    "room_transfers": (["1", "P"], True),
    "placement": (["1"], False),
    "traversal": (["1"], False),
    "clusters": (["1"], False),
    "frame_content": (["1"], False),
    "raster_finish": (["1"], False),
}
# Stages `penumbra profile` does not run (the kiosk's own): their mean over the demo session.
KIOSK_STAGES = ["camera", "foreground", "HUD", "display", "other"]

# Instructions to time on each board: ns per instruction = 1 / (IPC x GHz); the stages on the
# worker threads divide by the speed-up of the board's four cores. Low / central / high cost.
ASSUMPTIONS = {
    "pi4": {
        "name": "Raspberry Pi 4 (4x Cortex-A72, 1.5 GHz)",
        "ghz": 1.5,
        # The A72 decodes 3 instructions a cycle; on this code's mix of NEON and scalar loads,
        # stores and branches we assume 0.7-1.3 of them retire a cycle, 1.0 central.
        "ipc": (1.3, 1.0, 0.7),
        # 1.96x measured on x86 from 1 to 2 threads (bench-replay showroom-50, docs/performance.md
        # "A busy core"); on 4 cores with the camera stack and the display beside them, 2.0-3.5x.
        "speedup": (3.5, 3.0, 2.0),
    },
    "pi5": {
        "name": "Raspberry Pi 5 (4x Cortex-A76, 2.4 GHz)",
        "ghz": 2.4,
        # The A76 decodes 4 a cycle and has two 128-bit NEON pipes: 1.2-2.0, 1.6 central.
        "ipc": (2.0, 1.6, 1.2),
        "speedup": (3.5, 3.0, 2.0),
    },
}
RANGE_NAMES = ("low", "central", "high")


def read_profiles(directory):
    rows = []
    for path in sorted(directory.glob("profile-*.csv")):
        with open(path) as f:
            for r in csv.DictReader(f):
                r["file"] = path.name
                rows.append(r)
    if not rows:
        sys.exit(f"board_cost_model.py: {directory}: no profile-*.csv")
    return rows


def read_demo(directory):
    path = directory / "demo.txt"
    means = {}
    for line in path.read_text().splitlines():
        m = re.match(r"^(\S+(?: \S+)?)\s+([0-9.]+)\s+([0-9.]+)\s+([0-9.]+)\s+[0-9.]+%$", line)
        if m:
            means[m.group(1).replace(" ", "_")] = float(m.group(2))
    if "board_frame" not in means:
        sys.exit(f"board_cost_model.py: {path}: no stage table")
    return means


def term(r, name):
    p = float(r["passes"])
    return {
        "1": 1.0,
        "P": p,
        "PT": p * float(r["shadow_map_size"]) ** 2,
        "X": float(r["shadowed_pixels"]),
        "V": float(r["product_vertices"]),
        "PV": p * float(r["product_vertices"]),
        "S": float(r["shadow_map_triangles"]),
    }[name]


def solve(a, b):
    """Gaussian elimination with partial pivoting for the small normal equations."""
    n = len(b)
    m = [row[:] + [b[i]] for i, row in enumerate(a)]
    for c in range(n):
        pivot = max(range(c, n), key=lambda i: abs(m[i][c]))
        m[c], m[pivot] = m[pivot], m[c]
        if m[c][c] == 0:
            sys.exit("board_cost_model.py: singular fit (the counts do not vary a term)")
        for i in range(c + 1, n):
            f = m[i][c] / m[c][c]
            for j in range(c, n + 1):
                m[i][j] -= f * m[c][j]
    x = [0.0] * n
    for i in reversed(range(n)):
        x[i] = (m[i][n] - sum(m[i][j] * x[j] for j in range(i + 1, n))) / m[i][i]
    return x


def fit(rows, stage, terms):
    """Least squares of the stage's instructions (M -> instructions) on its terms, each row
    weighted by 1/count so that small frames count as much as large ones (relative error).
    No work costs negative time: a term whose coefficient comes out negative is dropped and
    the rest refitted (an active-set non-negative fit; with these few terms, exact)."""
    coef, worst = fit_terms(rows, stage, terms)
    while min(coef.values()) < 0 and len(coef) > 1:
        terms = [t for t in terms if t != min(coef, key=coef.get)]
        coef, worst = fit_terms(rows, stage, terms)
    return coef, worst


def fit_terms(rows, stage, terms):
    ys = [float(r["stage_" + stage]) * 1e6 for r in rows]
    xs = [[term(r, t) for t in terms] for r in rows]
    w = [1.0 / max(y, 1.0) ** 2 for y in ys]
    n = len(terms)
    a = [[sum(w[k] * xs[k][i] * xs[k][j] for k in range(len(rows))) for j in range(n)]
         for i in range(n)]
    b = [sum(w[k] * xs[k][i] * ys[k] for k in range(len(rows))) for i in range(n)]
    coef = solve(a, b)
    worst = max(abs(sum(c * x for c, x in zip(coef, xs[k])) - ys[k]) / max(ys[k], 1.0)
                for k in range(len(rows)))
    return dict(zip(terms, coef)), worst


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("counts", type=pathlib.Path)
    ap.add_argument("--markdown", type=pathlib.Path)
    ap.add_argument("--json", type=pathlib.Path)
    args = ap.parse_args()
    rows = read_profiles(args.counts)
    demo = read_demo(args.counts)

    fits = {}
    lines = ["| stage | instructions (aarch64, one thread) | worst misfit | threads |",
             "|---|---|---|---|"]
    for stage, (terms, parallel) in STAGES.items():
        coef, worst = fit(rows, stage, terms)
        fits[stage] = coef
        formula = " + ".join(f"{coef[t]:,.1f}·{t}" if t != "1" else f"{coef[t]:,.0f}"
                             for t in coef)
        lines.append(f"| {stage.replace('_', ' ')} | {formula} | {worst * 100:.1f} % | "
                     f"{'workers' if parallel else 'one'} |")
    for stage in KIOSK_STAGES:
        mean = demo.get(stage, 0.0) * 1e6
        fits[stage] = {"1": mean}
        lines.append(f"| {stage} | {mean:,.0f} (demo session's mean) | — | one |")

    # The sum of the fits against each counted frame: what the model gets wrong as a whole.
    misfits = []
    for r in rows:
        model = sum(sum(c * term(r, t) for t, c in fits[stage].items()) for stage in STAGES)
        counted = sum(float(r["stage_" + stage]) * 1e6 for stage in STAGES)
        misfits.append(abs(model - counted) / counted)
    misfits.sort()
    lines.append("")
    lines.append(f"The whole profiled frame (the stages above summed) against the counts, over "
                 f"{len(rows)} frames' means: median misfit {misfits[len(misfits) // 2] * 100:.1f} "
                 f"%, worst {misfits[-1] * 100:.1f} %.")

    # Instructions per cost-model term, split by whether the workers share them.
    def gather(key):
        serial = sum(c.get(key, 0.0) for s, c in fits.items()
                     if not STAGES.get(s, ([], False))[1])
        parallel = sum(c.get(key, 0.0) for s, c in fits.items() if STAGES.get(s, ([], False))[1])
        return serial, parallel

    # The product's shading and transfers are paid only in the frames that work them out again
    # (the product moved, or the clusters changed; in the profile, every frame): their vertex
    # terms are charged per shaded or transferred vertex, the rest per product vertex.
    own = {"product_shading", "product_transfers"}

    def gather_product(key):
        return 0.0, sum(c.get(key, 0.0) for s, c in fits.items() if s not in own)

    terms = {
        "fixed": gather("1"),
        "pass": gather("P"),
        "texel": gather("PT"),
        "pixel": gather("X"),
        "pass_vertex": gather_product("PV"),
        "product_vertex": gather_product("V"),
        "shaded_vertex": (0.0, fits["product_shading"].get("V", 0.0)),
        "transferred_vertex": (0.0, fits["product_transfers"].get("V", 0.0)),
        "pass_transferred_vertex": (0.0, fits["product_transfers"].get("PV", 0.0)),
        "shadow_map_triangle": gather("S"),
    }

    boards = {}
    for key, a in ASSUMPTIONS.items():
        boards[key] = {}
        for i, rname in enumerate(RANGE_NAMES):
            ns = 1.0 / (a["ipc"][i] * a["ghz"])
            s = a["speedup"][i]
            cost = {t: (ser + par / s) * ns for t, (ser, par) in terms.items()}
            boards[key][rname] = {
                "fixed_us": round(cost["fixed"] / 1000),
                "per_pass_us": round(cost["pass"] / 1000),
                "per_texel_ps": round(cost["texel"] * 1000),
                "per_pixel_ps": round(cost["pixel"] * 1000),
                "per_pass_vertex_ps": round(cost["pass_vertex"] * 1000),
                "per_product_vertex_ps": round(cost["product_vertex"] * 1000),
                "per_shaded_vertex_ps": round(cost["shaded_vertex"] * 1000),
                "per_transferred_vertex_ps": round(cost["transferred_vertex"] * 1000),
                "per_pass_transferred_vertex_ps": round(cost["pass_transferred_vertex"] * 1000),
                "per_shadow_map_triangle_ps": round(cost["shadow_map_triangle"] * 1000),
                "ns_per_instruction": ns,
                "speedup": s,
            }

    # The demo session's mean frame per stage on each board (central, with the range).
    table = ["| stage | M instructions | Pi 4 ms (range) | Pi 5 ms (range) |", "|---|---|---|---|"]
    totals = {k: [0.0, 0.0, 0.0] for k in ASSUMPTIONS}
    for stage in list(STAGES) + KIOSK_STAGES:
        m = demo.get(stage, 0.0)
        parallel = STAGES.get(stage, ([], False))[1]
        cells = []
        for key, a in ASSUMPTIONS.items():
            ms = []
            for i in range(3):
                v = m / (a["ipc"][i] * a["ghz"]) / (a["speedup"][i] if parallel else 1.0)
                ms.append(v)
                totals[key][i] += v
            cells.append(f"{ms[1]:.2f} ({ms[0]:.2f}-{ms[2]:.2f})")
        table.append(f"| {stage.replace('_', ' ')} | {m:.2f} | {cells[0]} | {cells[1]} |")
    table.append(f"| **board frame** | {demo['board_frame']:.2f} | " + " | ".join(
        f"**{t[1]:.1f}** ({t[0]:.1f}-{t[2]:.1f})" for t in totals.values()) + " |")

    # How many passes fit a 30 fps frame on each board, per product at its profiled pose (its
    # receiver pixels and occluder triangles per pass from the 64-pass frames at the bundle's
    # settings; shaded every frame: it is moving).
    budget_ns = 1e9 / 30
    products = {}
    for r in rows:
        if re.fullmatch(r"profile-\d+\.csv", r["file"]) and r["passes"] == "64":
            products[int(r["product_vertices"])] = (float(r["shadowed_pixels"]) / 64,
                                                    float(r["shadow_map_triangles"]) / 64)
    fit_lines = ["| product (vertices) | receiver px per pass | occluder triangles per pass | "
                 + " | ".join(f"{a['name'].split(' (')[0]}: passes at 30 fps (range)"
                              for a in ASSUMPTIONS.values()) + " |",
        "|---|---|---|" + "---|" * len(ASSUMPTIONS)]
    for v, (px, tri) in sorted(products.items()):
        cells = []
        for key in ASSUMPTIONS:
            n = []
            for rname in RANGE_NAMES:
                b = boards[key][rname]
                fixed = b["fixed_us"] * 1e3 + (b["per_product_vertex_ps"] + b["per_shaded_vertex_ps"]
                                               + b["per_transferred_vertex_ps"]) * v / 1e3
                per_pass = b["per_pass_us"] * 1e3 + (
                    b["per_texel_ps"] * 256**2 + b["per_pixel_ps"] * px
                    + (b["per_pass_vertex_ps"] + b["per_pass_transferred_vertex_ps"]) * v
                    + b["per_shadow_map_triangle_ps"] * tri) / 1e3
                n.append(max(0, int((budget_ns - fixed) // per_pass)))
            cells.append(f"{n[1]} ({n[2]}-{n[0]})")
        fit_lines.append(f"| {v} | {px:,.0f} | {tri:,.0f} | " + " | ".join(cells) + " |")

    out = ["Stage fits (instructions per frame; P passes, T texels per map, X receiver pixels "
           "over the passes, V product vertices, S occluder triangles drawn over the passes):",
           ""] + lines + [
           "", "The demo session's mean board frame (`penumbra-sim data/sessions/demo.json`, the "
           "counted frames), per stage:", ""] + table + ["", "`board` keys per board (central; "
           "low and high cost in the JSON):", ""]
    for key, b in boards.items():
        keys = {k: v for k, v in b["central"].items() if k not in ("ns_per_instruction", "speedup")}
        out.append(f"- {ASSUMPTIONS[key]['name']}: `{json.dumps(keys)}`; the controller's "
                   f"`fixed_cost_us` {b['low']['fixed_us']} (the fixed part at the low-cost end: "
                   f"frame_rate_controller.h wants an underestimate)")
    out += ["", "Passes that fit a 30 fps frame (33.3 ms), 256² maps, the product moving:",
            ""] + fit_lines
    text = "\n".join(out) + "\n"
    print(text)
    if args.markdown:
        args.markdown.write_text(
            "# The board's cost model, fitted to counted instructions\n\n"
            f"Written by `bench/board_cost_model.py {args.counts}` from the counts of "
            "`bench/board_instruction_counts.sh` (docs/kiosk.md, \"Cost model\"); do not edit.\n\n"
            + text)
    if args.json:
        args.json.write_text(json.dumps({"fits": fits, "boards": boards,
                                         "assumptions": ASSUMPTIONS}, indent=1) + "\n")


if __name__ == "__main__":
    main()
