#!/usr/bin/env python3
"""Where a synthesised view's time goes, per pass, against the floor, in one run.

Alternates the layer builds given with --lib (e.g. main's and a branch's) on each scene, and
runs ../shared/tools/fill-floor (one full-tile pass reading a texture and writing colour and
depth: DESIGN section 5) before and after, so that every figure comes from the same minutes of
a shared machine. Each run is `holoinject run --mode synth --log trace` over a quilt of
synthesised views; the layer's trace line per frame gives each pass's GPU time; the medians
over frames after warm-up, divided by the synthesised views, are the cost per view.

    scripts/warp-passes.py --lib old=/tmp/old.so --lib new=target/release/libholoinject.so \
        --scenes cubes,asteroids --quilt 8x6 --tile 420x560 --rounds 3 [--out FILE.md]
"""
import argparse
import os
import re
import statistics
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PASS = re.compile(r"([a-z+]+) ([0-9.]+) ms \(cpu")


def floor(tool, tile, quilt):
    """ms per view of `copy + gl_FragDepth`, from fill-floor."""
    w, h = tile.split("x")
    c, r = quilt.split("x")
    out = subprocess.run([tool, w, h, c, r], capture_output=True, text=True, check=True).stdout
    for line in out.splitlines():
        if line.startswith("copy + gl_FragDepth"):
            return float(line.split()[3])
    sys.exit(f"warp-passes: no 'copy + gl_FragDepth' line from {tool}:\n{out}")


def passes(binary, lib, scene, quilt, tile, frames, warp):
    """Median ms per frame of each synthesis pass (frames after the first two)."""
    lib, *extra = lib.split()
    env = dict(os.environ, HOLOINJECT_LIB=lib)
    args = [binary, "run", "--mode", "synth", "--synth-warp", warp, *extra, "--output", "quilt", "--quilt", quilt,
            "--tile", tile, "--log", "trace", "--exit-after", str(frames), "--", scene, "--backend", "osmesa",
            "--size", tile, "--frames", str(frames)]
    err = subprocess.run(args, env=env, capture_output=True, text=True).stderr
    laps = {}
    lines = [l for l in err.splitlines() if "synthesis passes:" in l]
    if len(lines) < 3:
        sys.exit(f"warp-passes: {scene} under {lib} gave {len(lines)} trace lines:\n{err[-2000:]}")
    for line in lines[2:]:
        for name, ms in PASS.findall(line):
            laps.setdefault(name, []).append(float(ms))
    return {k: statistics.median(v) for k, v in laps.items()}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--lib", action="append", required=True,
                    help="NAME=PATH of a libholoinject.so, optionally followed by options of its run "
                         "(\"gpu=target/release/libholoinject.so --rows-on gpu\")")
    ap.add_argument("--bin", default=os.path.join(ROOT, "target/release/holoinject"))
    ap.add_argument("--floor-tool", default="/tmp/fill-floor",
                    help="fill-floor built from ../shared/tools/fill-floor.c")
    ap.add_argument("--scenes", default="cubes,asteroids")
    ap.add_argument("--quilt", default="8x6")
    ap.add_argument("--tile", default="420x560")
    ap.add_argument("--frames", type=int, default=12)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--warp", default="rows")
    ap.add_argument("--out")
    a = ap.parse_args()
    libs = [l.split("=", 1) for l in a.lib]
    c, r = (int(v) for v in a.quilt.split("x"))
    views = c * r - 1
    floors = [floor(a.floor_tool, a.tile, a.quilt)]
    runs = {}
    for _ in range(a.rounds):
        for scene in a.scenes.split(","):
            for name, lib in libs:
                runs.setdefault((scene, name), []).append(passes(a.bin, lib, scene, a.quilt, a.tile, a.frames, a.warp))
    floors.append(floor(a.floor_tool, a.tile, a.quilt))
    fl = statistics.median(floors)
    rows = [f"Floor (fill-floor `copy + gl_FragDepth`, {a.tile}, before/after): "
            f"{floors[0]:.3f} / {floors[-1]:.3f} ms per view.", "",
            f"Per synthesised view ({views} of a {a.quilt} quilt, `--synth-warp {a.warp}`), median of "
            f"{a.rounds} alternating runs, each the median over frames 3..{a.frames}:", "",
            "| scene | build | " + " | ".join(["pass ms/view"]) + " | total ms/view | x floor |",
            "|---|---|---|---|---|"]
    for (scene, name), rs in runs.items():
        names = list(rs[0].keys())
        med = {k: statistics.median(r.get(k, 0.0) for r in rs) / views for k in names}
        warp = sum(v for k, v in med.items() if k not in ("copy", "parallax"))
        detail = ", ".join(f"{k} {v:.2f}" for k, v in med.items())
        rows.append(f"| {scene} | {name} | {detail} | {warp:.2f} | {warp / fl:.1f}x |")
    text = "\n".join(rows) + "\n\n(total: the passes that run per synthesised view, not the per-source copy and parallax)\n"
    print(text)
    if a.out:
        with open(a.out, "w") as f:
            f.write(text)


if __name__ == "__main__":
    main()
