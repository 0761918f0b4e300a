"""The table of scripts/bench-trade.py (OUT/trade.md): a cell per scene/N/tile/mode from its
timed runs and quilt metrics, the paragraphs defining every column, and the rows read back for
`--replot`. Definitions: bench-trade.py's module doc and header_text() below.
"""
import os
import statistics
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
QUILTS = {9: "3x3", 24: "6x4", 48: "8x6"}


def quilt_of(n):
    if n in QUILTS:
        return QUILTS[n]
    sys.exit(f"bench-trade: no quilt layout for {n} views (use {', '.join(map(str, QUILTS))})")


COUNT_COLUMNS = ["draws", "layer_draws", "fragments", "tiles", "read_back"]
QUILT_KEYS = ["flip_mean", "flip_worst", "flip_worst_view", "disp_median", "disp_p95", "disp_blocks",
              "disp_not_found", "convergence"]


def cell_summary(runs, failed, quilt):
    """One table cell (scene/N/tile/mode) from its successful timed runs and its quilt metrics."""
    d = {"runs": len(runs), "failed": failed, "notes": sorted({r["note"] for r in runs if "note" in r})}
    if runs:
        d["ms"] = statistics.median(r["ms"] for r in runs)
        pm = [r["psnr_mean"] for r in runs if "psnr_mean" in r]
        if pm:
            d["psnr_mean"] = statistics.median(pm)
            d["psnr_worst"] = min(r["psnr_worst"] for r in runs if "psnr_worst" in r)
        for key in ["holes", *COUNT_COLUMNS]:
            vals = [r[key] for r in runs if key in r]
            if vals:
                d[key] = statistics.median(vals)
    d.update({k: quilt[k] for k in QUILT_KEYS if k in quilt})
    if "note" in quilt:
        d["notes"].append(quilt["note"])
    return d


def summarise(configs, cell_modes, results, quilts):
    rows = []
    for c in configs:
        cell = {}
        for mode in cell_modes[c]:
            all_runs = results.get((*c, mode), [])
            runs = [r for r in all_runs if "error" not in r]
            cell[mode] = cell_summary(runs, len(all_runs) - len(runs), quilts.get((*c, mode), {}))
        exact = cell.get("exact", {}).get("ms")
        for mode, d in cell.items():
            if exact and "ms" in d:
                d["speedup"] = exact / d["ms"]
            rows.append((*c, mode, d))
    return rows


def size_text(b):
    if b < 1024 * 1024:
        return f"{b / 1024:.1f} KiB" if b else "0"
    return f"{b / (1024 * 1024):.1f} MiB"


def count_text(x):
    """A count as the layer gave it (medians of an even number of frames end in .5)."""
    return f"{x:.0f}" if x == int(x) else f"{x:.1f}"


def counts_cells(d):
    """draws submitted (layer's own), fragments (M), tile-equivalents, read back."""
    if "draws" not in d:
        return ["–"] * 4
    draws = count_text(d["draws"]) + (f" ({count_text(d['layer_draws'])})" if "layer_draws" in d else "")
    frags = f"{d['fragments'] / 1e6:.2f}" if "fragments" in d else "n/a"
    tiles = f"{d['tiles']:.1f}" if "tiles" in d else "n/a"
    return [draws, frags, tiles, size_text(d["read_back"]) if "read_back" in d else "n/a"]


def error_cells(mode, d):
    """PSNR mean, PSNR worst, FLIP mean, FLIP worst (view), disparity error median / p95 (blocks)."""
    if mode == "exact":
        return ["∞ (reference)", "∞ (reference)", "0 (reference)", "0 (reference)", "0 (reference)"]
    pm, pw = (f"{d['psnr_mean']:.1f}", f"{d['psnr_worst']:.1f}") if "psnr_mean" in d else ("n/a", "n/a")
    fm, fw = (f"{d['flip_mean']:.4f}", f"{d['flip_worst']:.4f} (view {d['flip_worst_view']})") \
        if "flip_mean" in d else ("n/a", "n/a")
    if "disp_median" in d:
        lost = f", {d['disp_not_found']} not found" if d["disp_not_found"] else ""
        disp = f"{d['disp_median']:.1f} / {d['disp_p95']:.1f} ({d['disp_blocks']}{lost})"
    else:
        disp = "n/a"
    return [pm, pw, fm, fw, disp]


def fmt_row(scene, n, tile, mode, d):
    q = f"{n} ({quilt_of(n)})"
    if "ms" not in d:
        return f"| {scene} | {q} | {tile} | {mode} | failed |" + " – |" * (len(HEADER) - 5)
    ms = f"{d['ms']:.1f}" + (f" ({d['failed']} failed)" if d["failed"] else "")
    sp = f"{d['speedup']:.2f}×" if "speedup" in d else "–"
    holes = f"{d['holes']:.2f}" if "holes" in d else "–"
    cells = [scene, q, tile, mode, ms, sp, *error_cells(mode, d), holes, *counts_cells(d)]
    return "| " + " | ".join(cells) + " |"


HEADER = ["scene", "N", "tile", "mode", "ms/frame", "speed-up vs exact", "PSNR mean", "PSNR worst", "FLIP mean",
          "FLIP worst", "disparity error median / p95 px (blocks)", "holes %", "draws submitted (layer's own)",
          "fragments (M)", "tile-equivalents", "read back"]


def renderer(a):
    """The GL renderer the sample apps got (their HOLOAPPS_VERBOSE line), or what is known."""
    try:
        r = subprocess.run([os.path.join(a.bin, "cubes"), "--backend", a.backend, "--size", "64x64", "--frames", "1"],
                           capture_output=True, text=True, timeout=60, env={**os.environ, "HOLOAPPS_VERBOSE": "1"})
        line = r.stderr.strip().splitlines()[0] if r.stderr.strip() else ""
        return line.partition(": ")[2].split(" (depth")[0] or "GL renderer unknown"
    except (OSError, subprocess.SubprocessError):
        return "GL renderer unknown"


def header_text(a, elapsed, frame):
    """The paragraphs above the table: what ran, and every column's definition."""
    rev = subprocess.run(["git", "-C", ROOT, "describe", "--always", "--dirty"], capture_output=True, text=True).stdout.strip() or "?"
    extra = f", layer options {' '.join(a.layer_arg)}" if a.layer_arg else ""
    f, m = frame, a.measure_every
    counts = ("`--gpu-counts` on in the timed runs" if a.counts_arg else "no counts (`--counts` off, or this holoinject has no `--gpu-counts`)")
    if not a.quilt_metrics:
        counts += "; no quilt runs (`--no-quilt-metrics`, or numpy/PIL missing): FLIP and disparity error n/a"
    elif a.flip is None:
        counts += "; flip-evaluator not installed: FLIP n/a"
    return [
        f"Speed/accuracy trade of the fast modes (scripts/bench-trade.py, tree at {rev}, {time.strftime('%Y-%m-%d')}; "
        f"command: `scripts/bench-trade.py {' '.join(a.argv)}`): {renderer(a)}, {os.cpu_count()} CPU cores shared with other "
        f"work (absolute times are noisy; read the ratios). `--output quilt`, default depthiness{extra}; sample apps on "
        f"headless {a.backend} (`--backend {a.backend}`, window = one tile), real programs as apitrace replays (`glretrace`, "
        f"their own window size) on Xvfb; {counts}. Took {elapsed / 60:.0f} min.",
        "",
        f"- **ms/frame**: median over {a.rounds} alternating timed run(s) (auto-convergence) of the layer's own frame-time "
        f"median of frames 11-{a.frames} (frames under `--measure-error every:{m}` left out). **Speed-up**: "
        f"t(exact) / t(mode), same scene, N and tile.",
        f"- **PSNR** (dB) of the synthesised views against exact, measured by the layer in the timed runs (every {m}th "
        f"frame, exact rendered in the same process): mean over views and measured frames (median over runs), and the "
        f"worst view of any measured frame. **Holes**: % of synthesised pixels filled because no source pixel landed "
        f"there (disocclusions, and beyond the view's edge; the row warp counts them, the grid does not).",
        f"- Quilt runs (once per scene/N/tile/mode): frame {f} (a measured frame of the timed runs) dumped under exact and "
        f"under the mode at one convergence, exact's auto estimate from its timed runs (`--convergence C`), so the views "
        f"a mode renders are exact's. Synthesised views: from the mode, not from the pixels: all but the centre view "
        f"N/2 for synth, all but the K evenly spaced views (both ends included) for hybrid:K. **FLIP**: NVIDIA's "
        f"reference implementation (`flip-evaluator`, LDR, 67 pixels per degree), mean of each synthesised tile's "
        f"per-pixel FLIP against exact's tile; mean over the synthesised views, and the worst view (0 = identical, 1 = "
        f"maximal). **Disparity error**: each textured 16x16 block of exact's centre view (luminance std ≥ 8 levels) is "
        f"searched for in view i of exact and of the mode (integer horizontal shift, least SSD of RGB, reach "
        f"max(16, {a.shift_per_view:g}·|i − N/2|) px); where exact's shift is distinct and unique "
        f"(scripts/disparity_blocks.py), |shift_exact − shift_mode| in tile px, median / 95th percentile over blocks "
        f"and synthesised views; in brackets the (block, view) pairs counted, and those the mode shows nowhere "
        f"distinctly (not found, left out).",
        "- Counts (the layer's `--gpu-counts`, per frame, median over the timed frames of a run, then over runs): "
        "**draws submitted**: draw calls that reached the driver, the program's once per view they were replayed into "
        "plus the layer's own draws, dispatches, clears and blits (in brackets); **fragments**: fragment-shader "
        "invocations (pipeline-statistics query), millions; **tile-equivalents**: fragments / pixels of one tile; "
        "**read back**: bytes the layer read back to the CPU. n/a: the driver could not count it.",
        "",
        "| " + " | ".join(HEADER) + " |",
        "|" + "---|" * len(HEADER),
    ]


def write_table(a, rows, elapsed, frame):
    lines = header_text(a, elapsed, frame) + [fmt_row(*r) for r in rows]
    notes = sorted({f"{r[0]} {r[3]} {quilt_of(r[1])} {r[2]}: {n}" for r in rows for n in r[4].get("notes", [])})
    if notes:
        lines += ["", *[f"- {n}" for n in notes]]
    conv = {f"{r[0]} {quilt_of(r[1])} {r[2]}: " + ("auto" if r[4]["convergence"] is None else f"{r[4]['convergence']:g}")
            for r in rows if "convergence" in r[4]}
    if conv:
        lines += ["", "Convergence of the quilt runs (exact's auto estimate; auto where it logged none): "
                  + "; ".join(sorted(conv)) + "."]
    text = "\n".join(lines) + "\n"
    with open(os.path.join(a.out, "trade.md"), "w") as f:
        f.write(text)
    print(text)


# The figures --replot needs, by column name (tables of any version of this script).
REPLOT_COLUMNS = {"ms/frame": "ms", "speed-up vs exact": "speedup", "PSNR mean": "psnr_mean", "FLIP mean": "flip_mean"}


def rows_of_table(path):
    """(scene, n, tile, mode, {'ms', 'speedup', 'psnr_mean', 'flip_mean'}) rows back from a
    trade.md table; columns are found by their header."""
    rows, cols = [], None
    for line in open(path):
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if cells[:4] == ["scene", "N", "tile", "mode"]:
            cols = {name: i for i, name in enumerate(cells)}
            continue
        if cols is None or len(cells) < len(cols) or not cells[1].split(" ")[0].isdigit():
            continue
        d = {}
        for name, key in REPLOT_COLUMNS.items():
            try:
                d[key] = float(cells[cols[name]].split(" ")[0].rstrip("×"))
            except (KeyError, ValueError):
                pass
        rows.append((cells[0], int(cells[1].split(" ")[0]), cells[2], cells[3], d))
    return rows
