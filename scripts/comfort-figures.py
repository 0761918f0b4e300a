#!/usr/bin/python3
"""The figures of README "Comfort", on `asteroids --deep` (1500 rocks from a few units in front
of the camera to past its far plane at 100: far more depth than a light-field display shows
sharply), frozen on their first frame, at 8x6 views of 320x240,
convergence fixed at 24 (about where auto-convergence settles), depthiness 1.5 (240 px of the
outermost view at infinity, 10 px between neighbouring views, 2.5x the default's 4 px): strong
depth, as a user turning depthiness up gets it.

1. Outer-view disparity histogram (tile px) without and with the remap: per pixel of the app's
   own depth buffer (`--depth-out`, the centre view), D = S(1 - c/w) with S = s*tile_w/2, and
   R(D) for the remap (the f64 twin of the shader's, tested against it on Mesa by
   tests/remap_on_mesa.rs).
2. The outermost view (view 0) and the centre view of the dumped quilt: off, remap, remap +
   DOF + edge fade (scripts/results/comfort-views.png).
3. Cost of the fade, and of DOF + fade: ms/frame (the layer's own median frame time, frames
   11..FRAMES) of exact with the remap against the same with them; runs alternate (the order
   rotates every round), ROUNDS of each, median of the medians. Measured on the asteroids
   field above (an almost empty scene: the app's own frame is cheap, so the effects' per-pixel
   cost weighs most) and on glmark2's `terrain` (a real program, hills to the horizon;
   replayed from an apitrace recording made once with bench-trade.py's recorder, at
   auto-convergence). --baseline DIR adds the same runs with another build's binaries (the
   layer before a change), alternating with this one's.

    xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" scripts/comfort-figures.py [--rounds 5] [--frames 40]
        [--scenes asteroids,glmark2-terrain] [--baseline OTHER/target/release] [--costs-only]

Nothing is built: binaries come from --bin (default $CARGO_TARGET_DIR/release, else target/release).
Needs python3-pil and python3-numpy (Debian).
"""
import argparse, importlib.util, os, re, statistics, subprocess, sys, tempfile
import numpy as np
from PIL import Image

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "scripts", "results")
FRAME_RE = re.compile(r"frame time: median ([0-9.]+) ms over (\d+) frames")
TILE, QUILT, C = (320, 240), (8, 6), 24.0
# asteroids' projection (tests/apps/src/bin/asteroids.rs): near 0.1, far 100.
NEAR, FAR = 0.1, 100.0
# The Portrait's comfortable range (presets/devices/portrait.toml).
REMAP = (43.0, 43.0, 129.0, 129.0)
S = 1.5
RIG = ["--quilt", "8x6", "--tile", "320x240", "--output", "quilt", "--convergence", str(C), "--depthiness", str(S)]
APP_ARGS = ["--backend", "glx", "--size", "320x240", "--freeze", "0", "--draws", "1500", "--deep"]
MODES = {
    "off": [],
    "remap": ["--depth-remap", ",".join(f"{v:g}" for v in REMAP)],
    "remap+fade": ["--depth-remap", ",".join(f"{v:g}" for v in REMAP), "--edge-fade", "32"],
    "remap+dof+fade": ["--depth-remap", ",".join(f"{v:g}" for v in REMAP), "--dof", "on", "--edge-fade", "32"],
}


def remap(x, r=REMAP):
    f, b, df, db = r
    gb, gf = db - b, df - f
    return np.where(x > b, db - gb * (gb / ((x - b) + gb)),
                    np.where(x < -f, -(df - gf * (gf / ((-f - x) + gf))), x))


def histogram(args, tmp):
    depth = os.path.join(tmp, "depth.f32")
    subprocess.run([os.path.join(args.bin, "asteroids")] + APP_ARGS + ["--frames", "2", "--depth-out", depth],
                   check=True, capture_output=True)
    d = np.fromfile(depth, dtype="<f4").astype(np.float64)
    d = d[d < 1.0]  # cleared pixels: nothing drawn
    z = 2.0 * d - 1.0
    w = 2.0 * FAR * NEAR / ((FAR + NEAR) - z * (FAR - NEAR))
    D = S * TILE[0] / 2.0 * (1.0 - C / w)
    R = remap(D)
    edges = [-np.inf, -1000, -300, -129, -86, -43, 0, 43, 86, 129, np.inf]
    lines = ["| outermost-view disparity (tile px) | pixels without remap | with remap 43,43,129,129 |", "|---|---|---|"]
    for lo, hi in zip(edges[:-1], edges[1:]):
        a = np.count_nonzero((D >= lo) & (D < hi)) / D.size * 100
        b = np.count_nonzero((R >= lo) & (R < hi)) / R.size * 100
        lines.append(f"| [{lo:g}, {hi:g}) | {a:.1f} % | {b:.1f} % |")
    lines.append(f"| range (min .. max) | {D.min():.0f} .. {D.max():.1f} | {R.min():.1f} .. {R.max():.1f} |")
    inside = np.count_nonzero((D >= -REMAP[0]) & (D <= REMAP[1])) / D.size * 100
    lines.append(f"\n{D.size} drawn pixels of the centre view; {inside:.1f} % lie in the comfortable range "
                 "[-43, 43] px and are not changed by the remap.")
    return "\n".join(lines)


def bench_trade():
    """scripts/bench-trade.py as a module: its recorder of real programs."""
    spec = importlib.util.spec_from_file_location("bench_trade", os.path.join(ROOT, "scripts", "bench-trade.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def scene_command(args, scene, frames):
    """(rig arguments, program command) of `scene`."""
    if scene == "asteroids":
        return RIG, [os.path.join(args.bin, "asteroids")] + APP_ARGS
    bt = bench_trade()
    display = os.environ.get("DISPLAY")
    if not display:
        sys.exit("real programs need an X display: run under xvfb-run")
    trace = bt.record(scene, args.cache, frames, display)
    rig = [a for a in RIG if a not in ("--convergence", str(C))]
    return rig, ["glretrace", trace]


def run(args, mode, frames, dump=None, scene="asteroids", bin_dir=None):
    rig, prog = scene_command(args, scene, frames)
    cmd = [os.path.join(bin_dir or args.bin, "holoinject"), "run", "--log", "info", "--exit-after", str(frames)] + rig
    cmd += MODES[mode]
    if dump:
        cmd += ["--dump", dump, "--dump-frames", str(frames)]
    cmd += ["--"] + prog
    out = subprocess.run(cmd, capture_output=True, text=True, timeout=1800)
    m = FRAME_RE.search(out.stderr)
    if out.returncode != 0 or not m:
        sys.exit(f"{scene} {mode}: failed\n{out.stderr[-2000:]}")
    return float(m.group(1))


def views_image(args, tmp):
    rows = []
    for mode in ("off", "remap", "remap+dof+fade"):
        dump = os.path.join(tmp, mode)
        run(args, mode, 12, dump)
        q = Image.open(os.path.join(dump, "f000012_qs8x6a1.3333.png")).convert("RGB")
        w, h = TILE
        tile = lambda i: q.crop(((i % 8) * w, (5 - i // 8) * h, (i % 8 + 1) * w, (6 - i // 8) * h))
        row = Image.new("RGB", (2 * w, h))
        row.paste(tile(0), (0, 0))
        row.paste(tile(24), (w, 0))
        rows.append(row)
    out = Image.new("RGB", (2 * TILE[0], len(rows) * TILE[1]))
    for k, r in enumerate(rows):
        out.paste(r, (0, k * TILE[1]))
    path = os.path.join(OUT, "comfort-views.png")
    out.save(path, optimize=True)
    return path


def timing(args, scene):
    builds = [("", args.bin)] + ([("baseline ", args.baseline)] if args.baseline else [])
    modes = ("remap", "remap+fade", "remap+dof+fade")
    runs = [(b, m) for b in builds for m in modes]
    times = {r: [] for r in runs}
    for k in range(args.rounds):
        for build, mode in runs[k % len(runs):] + runs[:k % len(runs)]:
            times[(build, mode)].append(run(args, mode, args.frames, scene=scene, bin_dir=build[1]))
    med = {r: statistics.median(v) for r, v in times.items()}
    lines = [f"| {scene}, 8x6 views of 320x240, exact | median ms/frame | per-run medians |", "|---|---|---|"]
    for (build, mode), v in times.items():
        lines.append(f"| {build[0]}{mode} | {med[(build, mode)]:.1f} | {', '.join(f'{x:.1f}' for x in v)} |")
    lines.append("")
    for build in builds:
        base = med[(build, "remap")]
        fade = med[(build, "remap+fade")] - base
        cost = med[(build, "remap+dof+fade")] - base
        lines.append(f"{scene}{' (' + build[0].strip() + ')' if build[0] else ''}: edge fade {fade:+.1f} ms/frame = "
                     f"{fade / base * 100:+.1f} % of the exact frame time; DOF + edge fade: {cost:+.1f} ms/frame = "
                     f"{cost / base * 100:+.1f} %.")
    return "\n".join(lines)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    target = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
    p.add_argument("--bin", default=os.path.join(target, "release"))
    p.add_argument("--rounds", type=int, default=5)
    p.add_argument("--frames", type=int, default=40)
    p.add_argument("--scenes", default="asteroids,glmark2-terrain")
    p.add_argument("--baseline", help="another build's binaries, timed alternately with --bin's")
    p.add_argument("--cache", default=os.path.join(os.environ.get("XDG_CACHE_HOME", os.path.expanduser("~/.cache")),
                                                  "holoinject", "traces"),
                   help="where apitrace recordings are kept (shared with bench-trade.py)")
    p.add_argument("--costs-only", action="store_true", help="only the timings; comfort.md is not written")
    args = p.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        if not args.costs_only:
            hist = histogram(args, tmp)
            print(hist, flush=True)
            image = views_image(args, tmp)
            print(f"\n{image}", flush=True)
        costs = []
        for scene in args.scenes.split(","):
            costs.append(timing(args, scene))
            print(costs[-1], flush=True)
    if not args.costs_only:
        said = f"Timed: {args.bin}" + (f"; baseline: {args.baseline}" if args.baseline else "")
        with open(os.path.join(OUT, "comfort.md"), "w") as f:
            f.write("# Comfort figures (scripts/comfort-figures.py)\n\n" + hist + "\n\n" + said + ".\n\n"
                    + "\n\n".join(costs) + "\n")


if __name__ == "__main__":
    main()
