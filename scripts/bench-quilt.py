#!/usr/bin/python3
"""Exact-quilt benchmarks (DESIGN §6), all ratios measured within one run.
`--app legacy --cost-only` measures the fixed-function app the same way.

1. Injection cost: t(injected exact quilt) / t(app's own reference quilt), `cubes`, 8x6
   views of 420x560 (Looking Glass Portrait), headless OSMesa: its frame boundary is
   `glFinish`, so a frame's time includes its rendering (an EGL pbuffer swap does not wait). Runs alternate injected /
   reference ROUNDS times; each run reports the median of its per-frame times (app's own
   `--timing`, after 10 warm-up frames); the figure is the ratio of the medians of medians.
2. Frame time against the number of views (1, 9, 24, 48) and against the tile size, as a
   table (markdown) and a plot (PNG).

    scripts/bench-quilt.py [--rounds 3] [--frames 40] [--out scripts/results]
"""
import argparse, os, re, statistics, subprocess, sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.path.join(ROOT, "target", "release")
RIG = ["--depthiness", "0.1", "--convergence", "19"]


def median_ms(cmd):
    p = subprocess.run(cmd, capture_output=True, text=True, env={**os.environ, "ALSOFT_DRIVERS": "null"})
    m = re.search(r"median_frame_ms=([0-9.]+)", p.stderr)
    if p.returncode != 0 or not m:
        sys.exit(f"benchmark run failed: {' '.join(cmd)}\n{p.stderr}")
    return float(m.group(1))


APP = "cubes"
BACKEND = "osmesa"


def app(size, frames):
    return [os.path.join(BIN, APP), "--backend", BACKEND, "--size", size, "--frames", str(frames)]


LAYER_ARGS = []


def injected(quilt, tile, size, frames):
    layer = [os.path.join(BIN, "holoinject"), "run", "--quilt", quilt, "--tile", tile, *RIG, *LAYER_ARGS, "--"]
    return layer + app(size, frames) + ["--timing"]


def reference(quilt, tile, size, frames):
    return app(size, frames) + ["--reference-quilt", quilt, "--tile", tile, "--bench-quilt", "--out", "/dev/null", *RIG]


def measure(quilt, tile, size, frames, rounds):
    inj, ref = [], []
    for _ in range(rounds):
        inj.append(median_ms(injected(quilt, tile, size, frames)))
        ref.append(median_ms(reference(quilt, tile, size, frames)))
    return statistics.median(inj), statistics.median(ref)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--frames", type=int, default=40)
    ap.add_argument("--out", default=os.path.join(ROOT, "scripts", "results"))
    ap.add_argument("--app", default="cubes", help="sample app to measure (default cubes)")
    ap.add_argument("--backend", default="osmesa", help="osmesa (default: its glFinish frame boundary waits for rendering) or egl")
    ap.add_argument("--layer-arg", action="append", default=[], help="extra holoinject option (repeatable)")
    ap.add_argument("--cost-only", action="store_true", help="only the 8x6 420x560 injection cost")
    a = ap.parse_args()
    global APP, BACKEND  # noqa: PLW0603
    APP, BACKEND = a.app, a.backend
    LAYER_ARGS.extend(a.layer_arg)
    subprocess.run(["cargo", "build", "--workspace", "--release", "--locked", "-q"], cwd=ROOT, check=True)
    os.makedirs(a.out, exist_ok=True)
    rows = []
    if a.cost_only:
        inj, ref = measure("8x6", "420x560", "420x560", a.frames, a.rounds)
        extra = " ".join(LAYER_ARGS)
        print(f"{APP} 8x6 420x560 {extra}: injected {inj:.2f} ms, reference {ref:.2f} ms, injection cost {inj / ref:.3f}")
        return
    for quilt in ["1x1", "3x3", "6x4", "8x6"]:
        inj, ref = measure(quilt, "420x560", "420x560", a.frames, a.rounds)
        rows.append(("views", quilt, "420x560", inj, ref))
        print(f"{quilt} 420x560: injected {inj:.2f} ms, reference {ref:.2f} ms, ratio {inj / ref:.3f}", file=sys.stderr)
    for tile in ["210x280", "630x840"]:
        inj, ref = measure("8x6", tile, tile, a.frames, a.rounds)
        rows.append(("tile", "8x6", tile, inj, ref))
        print(f"8x6 {tile}: injected {inj:.2f} ms, reference {ref:.2f} ms, ratio {inj / ref:.3f}", file=sys.stderr)
    write_table(a.out, rows, a)
    plot(a.out, rows)


def write_table(out, rows, a):
    lines = [
        f"{APP}, headless {BACKEND} on llvmpipe; medians of {a.rounds} runs x {a.frames} frames (10 warm-up frames dropped)",
        "",
        "| quilt | views | tile | injected (ms/frame) | app's own reference quilt (ms/frame) | injection cost |",
        "|---|---|---|---|---|---|",
    ]
    for _, quilt, tile, inj, ref in rows:
        c, r = map(int, quilt.split("x"))
        lines.append(f"| {quilt} | {c * r} | {tile} | {inj:.2f} | {ref:.2f} | {inj / ref:.3f} |")
    text = "\n".join(lines) + "\n"
    open(os.path.join(out, "quilt-benchmark.md"), "w").write(text)
    print(text)


def plot(out, rows):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib missing: no plot", file=sys.stderr)
        return
    views = [r for r in rows if r[0] == "views"]
    n = [int(q.split("x")[0]) * int(q.split("x")[1]) for _, q, _, _, _ in views]
    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    ax[0].plot(n, [r[3] for r in views], "o-", label="injected (holoinject)")
    ax[0].plot(n, [r[4] for r in views], "s--", label="app's own reference quilt")
    ax[0].set_xlabel("views (420x560 tiles)")
    ax[0].set_ylabel("ms / frame")
    ax[0].legend()
    tiles = [r for r in rows if r[1] == "8x6"]
    px = [int(t.split("x")[0]) * int(t.split("x")[1]) * 48 / 1e6 for _, _, t, _, _ in tiles]
    order = sorted(range(len(px)), key=px.__getitem__)
    ax[1].plot([px[i] for i in order], [tiles[i][3] for i in order], "o-", label="injected")
    ax[1].plot([px[i] for i in order], [tiles[i][4] for i in order], "s--", label="reference")
    ax[1].set_xlabel("quilt megapixels (8x6 views)")
    ax[1].set_ylabel("ms / frame")
    ax[1].legend()
    fig.suptitle(f"{APP} on llvmpipe: frame time of the exact quilt")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "quilt-benchmark.png"), dpi=100)


if __name__ == "__main__":
    main()
