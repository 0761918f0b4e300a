"""The figures of scripts/bench-trade.py: one small panel per scene (rows) and number of views
and tile size (columns); x = speed-up over exact, y = the error of the views the fast modes
synthesise. Each mode is one marker, the same in every panel, named in one legend (no labels
beside the points to collide). The dashed line is the Pareto front: the modes no other mode
beats in both speed-up and quality, exact included at (1, its reference value).

Rows are (scene, N, tile, mode, {'ms', 'speedup', 'psnr_mean', 'flip_mean', ...}) as
bench-trade.py's summarise() or rows_of_table() gives them.
"""
import os
import sys

PSNR_CEILING = 60.0
MARKERS = "osD^vP*Xph<>"
# (file, row key, axis label, quality is higher?, exact's value)
FIGURES = [
    ("trade.png", "psnr_mean", "PSNR mean (dB)", True, PSNR_CEILING),
    ("trade-flip.png", "flip_mean", "FLIP mean (lower is better)", False, 0.0),
]


def tile_key(tile):
    return [int(x) for x in tile.split("x")]


def speedups(rows):
    """{(scene, n, tile, mode): t(exact) / t(mode)} from ms/frame (the table's speed-up column
    rounds; an old table may lack it)."""
    exact = {r[:3]: r[4]["ms"] for r in rows if r[3] == "exact" and "ms" in r[4]}
    out = {}
    for scene, n, tile, mode, d in rows:
        if (scene, n, tile) in exact and "ms" in d:
            out[(scene, n, tile, mode)] = exact[(scene, n, tile)] / d["ms"]
        elif "speedup" in d:
            out[(scene, n, tile, mode)] = d["speedup"]
    return out


def points(rows, key, reference, ceiling):
    """{(scene, n, tile): [(speed-up, y, mode)]}: exact at its reference, modes without the
    figure left out."""
    sp = speedups(rows)
    out = {}
    for scene, n, tile, mode, d in rows:
        x = sp.get((scene, n, tile, mode))
        y = reference if mode == "exact" else d.get(key)
        if x is None or y is None:
            continue
        if ceiling:
            y = min(y, reference)
        out.setdefault((scene, n, tile), []).append((x, y, mode))
    return out


def pareto(pts, higher):
    """The points no other point beats in speed-up and quality (ties kept), by speed-up."""
    q = lambda p: p[1] if higher else -p[1]
    front = [p for p in pts if not any(o[0] >= p[0] and q(o) >= q(p) and (o[0] > p[0] or q(o) > q(p)) for o in pts)]
    return sorted(front)


def panel(ax, pts, style, higher, title):
    import matplotlib.ticker as ticker
    for x, y, mode in pts:
        ax.plot([x], [y], linestyle="none", **style[mode])
    front = pareto(pts, higher)
    ax.plot([p[0] for p in front], [p[1] for p in front], "--", color="grey", lw=1, zorder=0)
    ax.set_xscale("log", base=2)
    ax.margins(0.1)  # markers at the extremes stay whole
    ax.xaxis.set_major_formatter(ticker.FormatStrFormatter("%g"))
    ax.xaxis.set_minor_formatter(ticker.NullFormatter())
    ax.axvline(1.0, color="grey", lw=0.5, ls=":")
    if not higher:
        ax.invert_yaxis()  # up is better in both figures
    ax.set_title(title, fontsize=8)
    ax.tick_params(labelsize=7)
    ax.grid(True, which="major", alpha=0.3)


def styles(rows):
    """A marker and colour per mode, fixed over every panel and figure."""
    import matplotlib.pyplot as plt
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    modes = list(dict.fromkeys(r[3] for r in rows))
    return {m: {"marker": MARKERS[i % len(MARKERS)], "color": "black" if m == "exact" else colours[i % len(colours)],
                "markersize": 6, "label": m} for i, m in enumerate(modes)}


def figure(path, rows, key, label, higher, reference):
    """One figure: a grid of panels, scenes down, (N, tile) across. False when no row has `key`."""
    import matplotlib.pyplot as plt
    pts = points(rows, key, reference, ceiling=higher)
    if not any(p[2] != "exact" for v in pts.values() for p in v):
        return False
    scenes = list(dict.fromkeys(r[0] for r in rows))
    cols = sorted({(r[1], r[2]) for r in rows}, key=lambda c: (c[0], tile_key(c[1])))
    style = styles(rows)
    ncol = min(len(style) + 1, max(6, 2 * len(cols)))
    top = 0.4 + 0.22 * -(-(len(style) + 1) // ncol)  # inches: title, then the legend's rows
    fig, axes = plt.subplots(len(scenes), len(cols), squeeze=False,
                             figsize=(max(6.5, 2.9 * len(cols) + 0.6), 2.4 * len(scenes) + 0.7 + top))
    for i, s in enumerate(scenes):
        for j, (n, tile) in enumerate(cols):
            ax = axes[i][j]
            if (s, n, tile) not in pts:
                ax.axis("off")
                continue
            panel(ax, pts[(s, n, tile)], style, higher, f"{s}, {n} views, {tile}")
            if j == 0:
                ax.set_ylabel(label, fontsize=7)
            if i == len(scenes) - 1:
                ax.set_xlabel("speed-up over exact (log)", fontsize=7)
    legend(fig, style, ncol)
    fig.suptitle("Speed/accuracy trade on llvmpipe (up and right is better)", fontsize=9, y=1 - 0.08 / fig.get_figheight())
    fig.text(0.01, 0.01, f"exact has no error: drawn at {reference:g}" + (" dB, a ceiling." if higher else "."),
             fontsize=7)
    fig.tight_layout(rect=(0, 0.2 / fig.get_figheight(), 1, 1 - top / fig.get_figheight()))
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return True


def legend(fig, style, ncol):
    """One legend for every panel, under the title: a marker per mode and the front's line."""
    from matplotlib.lines import Line2D
    handles = [Line2D([], [], linestyle="none", **v) for v in style.values()]
    handles.append(Line2D([], [], ls="--", color="grey", label="Pareto front"))
    fig.legend(handles=handles, loc="upper center", ncol=ncol, fontsize=8, frameon=False,
               bbox_to_anchor=(0.5, 1 - 0.3 / fig.get_figheight()))


def plot(out, rows):
    """OUT/trade.png (PSNR) and, when any row has FLIP, OUT/trade-flip.png."""
    try:
        import matplotlib
        matplotlib.use("Agg")
    except ImportError:
        print("bench-trade: matplotlib missing (apt-get install python3-matplotlib): no plot", file=sys.stderr)
        return
    for name, key, label, higher, reference in FIGURES:
        path = os.path.join(out, name)
        if figure(path, rows, key, label, higher, reference):
            print(f"bench-trade: wrote {path}", file=sys.stderr)
