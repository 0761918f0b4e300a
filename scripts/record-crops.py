#!/usr/bin/env python3
"""Before/after crops of the disparity record (issue 22): the same frame under `--mode exact`,
and a fast mode with `--disparity-record off` (depth through the scene's camera, as before
the record) and `on`, one synthesised view cropped side by side: exact | off | on.

Usage: scripts/record-crops.py OUT_DIR OPENARENA_TRACE JELLYFISH_TRACE   (needs DISPLAY)
"""
import os, subprocess, sys, tempfile
from PIL import Image

HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.path.join(HERE, "target", "release")


def quilt(args, program, frame, mode, record):
    d = tempfile.mkdtemp(prefix="crops-")
    cmd = [os.path.join(BIN, "holoinject"), "run", "--output", "quilt", "--mode", mode,
           "--disparity-record", record, "--dump", d, "--dump-frames", str(frame),
           "--exit-after", str(frame)] + args + ["--"] + program
    subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, timeout=600, check=False)
    pngs = [f for f in os.listdir(d) if f.startswith("f%06d_qs" % frame)]
    return Image.open(os.path.join(d, pngs[0])).convert("RGB")


def tile(q, cols, rows, i):
    w, h = q.size[0] // cols, q.size[1] // rows
    c, r = i % cols, i // cols  # view 0 bottom-left, rows upwards (DESIGN §4)
    return q.crop((c * w, q.size[1] - (r + 1) * h, (c + 1) * w, q.size[1] - r * h))


def strip(name, out, args, program, frame, mode, cols, rows, view, box):
    imgs = [quilt(args, program, frame, m, r) for m, r in (("exact", "on"), (mode, "off"), (mode, "on"))]
    crops = [tile(q, cols, rows, view).crop(box) for q in imgs]
    w, h = crops[0].size
    s = Image.new("RGB", (3 * w + 8, h), (255, 255, 255))
    for k, c in enumerate(crops):
        s.paste(c, (k * (w + 4), 0))
    path = os.path.join(out, f"{name}.png")
    s.save(path)
    print(f"{path}: view {view} of {cols}x{rows}, {mode}: exact | record off | record on")


def main():
    out, oa, jf = sys.argv[1:4]
    os.makedirs(out, exist_ok=True)
    strip("sky-skybox", out, ["--quilt", "5x3", "--tile", "256x192", "--convergence", "5.3461"],
          [os.path.join(BIN, "skybox"), "--backend", "osmesa", "--size", "256x192", "--frames", "10"],
          10, "synth", 5, 3, 0, (0, 0, 256, 96))
    strip("weapon-openarena", out, ["--quilt", "3x3", "--convergence", "12"], ["glretrace", oa],
          56, "hybrid:3", 3, 3, 2, (340, 250, 640, 480))
    strip("jellyfish-glmark2", out, ["--quilt", "5x3", "--tile", "400x300", "--convergence", "49"],
          ["glretrace", jf], 30, "synth", 5, 3, 14, (80, 20, 320, 300))


if __name__ == "__main__":
    main()
