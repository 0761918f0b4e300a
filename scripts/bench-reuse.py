#!/usr/bin/python3
"""`--reuse` on still scenes (README "--reuse"): how many frames until every view is exact,
and ms/frame after that against `exact` and plain `hybrid:K`.

Scenes: `cubes` and `bloom` (sample apps, `--freeze 0`: every frame draws frame 0), and a real
program: an apitrace recording of `glmark2 -b shading:shading=phong` cut after its 15th frame
(made once, kept in --cache) replayed by `glretrace --loop`, which draws that frame again and
again.
Each run is one program under the layer on an X server (DISPLAY, or `xvfb-run` around this
script) with `--output quilt --log info --exit-after FRAMES`; the layer reports the median
frame time of frames 11..FRAMES and, with `--reuse`, the frame on which every view became
exact (`reuse: frame F: every view exact`). The runs of one scene alternate between the modes
(the order rotates every round) and a cell is the median over ROUNDS runs, so load from other
work spreads over all modes; read the ratios, not the absolute times.

    xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" scripts/bench-reuse.py [--rounds 3] \\
        [--frames 60] [--scenes cubes,bloom,glmark2-phong] [--quilt 3x3] [--tile 320x240] [-k 3]

Nothing is built: binaries come from --bin (default $CARGO_TARGET_DIR/release, else
target/release).
"""
import argparse, os, re, statistics, subprocess, sys, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FRAME_RE = re.compile(r"frame time: median ([0-9.]+) ms over (\d+) frames")
EXACT_RE = re.compile(r"reuse: frame (\d+): every view exact")
RIG = ["--depthiness", "0.12", "--convergence", "9", "--focus", "0"]


def trace(cache):
    """glmark2's phong scene recorded, cut after its 15th frame: `glretrace --loop` replays the
    last frame of a trace, which for a whole recording is the program's teardown."""
    path = os.path.join(cache, "glmark2-phong-frame15.trace")
    if os.path.exists(path):
        return path
    full = os.path.join(cache, "glmark2-phong.trace")
    os.makedirs(cache, exist_ok=True)
    if not os.path.exists(full):
        subprocess.run(["apitrace", "trace", "-o", full, "glmark2", "-s", "400x300", "-b",
                        "shading:shading=phong:nframes=20"], check=True, capture_output=True)
    dump = subprocess.run(["apitrace", "dump", full], check=True, capture_output=True, text=True).stdout
    swaps = [l.split()[0] for l in dump.splitlines() if "glXSwapBuffers(" in l]
    subprocess.run(["apitrace", "trim", f"--calls=0-{swaps[14]}", "-o", path, full],
                   check=True, capture_output=True)
    return path


def command(scene, args):
    if scene == "glmark2-phong":
        return ["glretrace", "--loop=-1", trace(args.cache)], ["--convergence", "auto"]
    app = os.path.join(args.bin, scene)
    w, h = args.tile.split("x")
    return [app, "--backend", "glx", "--size", f"{w}x{h}", "--freeze", "0"], RIG


def run(scene, mode, args):
    cmd, rig = command(scene, args)
    layer = [os.path.join(args.bin, "holoinject"), "run", "--log", "info", "--output", "quilt",
             "--quilt", args.quilt, "--tile", args.tile, "--exit-after", str(args.frames)] + rig
    layer += mode.split()
    out = subprocess.run(layer + ["--"] + cmd, capture_output=True, text=True, timeout=600)
    err = out.stderr
    t = FRAME_RE.search(err)
    if out.returncode != 0 or not t:
        sys.exit(f"{scene} {mode}: no frame time (status {out.returncode}):\n{err[-2000:]}")
    exact = EXACT_RE.search(err)
    return float(t.group(1)), int(exact.group(1)) if exact else None


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--frames", type=int, default=60)
    p.add_argument("--scenes", default="cubes,bloom,glmark2-phong")
    p.add_argument("--quilt", default="3x3")
    p.add_argument("--tile", default="320x240")
    p.add_argument("-k", type=int, default=3)
    target = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
    p.add_argument("--bin", default=os.path.join(target, "release"))
    p.add_argument("--cache", default=os.path.join(tempfile.gettempdir(), "holoinject-bench-cache"))
    args = p.parse_args()
    modes = ["--mode exact", f"--mode hybrid:{args.k}", f"--mode hybrid:{args.k} --reuse"]
    print(f"quilt {args.quilt}, tiles {args.tile}, {args.frames} frames, {args.rounds} rounds")
    print("| scene | exact ms | hybrid ms | reuse ms | reuse/exact | reuse/hybrid | exact at frame |")
    print("|---|---|---|---|---|---|---|")
    for scene in args.scenes.split(","):
        times = {m: [] for m in modes}
        converged = set()
        for r in range(args.rounds):
            for m in modes[r % len(modes):] + modes[:r % len(modes)]:
                t, f = run(scene, m, args)
                times[m].append(t)
                if "--reuse" in m:
                    converged.add(f)
        e, h, u = (statistics.median(times[m]) for m in modes)
        print(f"| {scene} | {e:.2f} | {h:.2f} | {u:.2f} | {u / e:.2f} | {u / h:.2f} | "
              f"{','.join(str(c) for c in sorted(converged, key=lambda c: c or 0))} |")
        sys.stdout.flush()


if __name__ == "__main__":
    main()
