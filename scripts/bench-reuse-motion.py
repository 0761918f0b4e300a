#!/usr/bin/python3
"""`--reuse` with a moving camera (README "--reuse"): per-frame PSNR against exact of plain
`hybrid:K`, `--reuse --reuse-motion off` (camera motion drops the kept views, the behaviour
before kept views followed the camera) and `--reuse` (kept views moved by the camera's
motion), and the cost of the reprojection.

Scene: `cubes --orbit DEG --spin S` (the camera orbits the centre by DEG degrees a frame; the
cubes spin S times their usual speed, 0 = still). 9x1 quilt of 320x240 tiles, the synthesis
tests' rig.

1. PSNR: one run per mode with `--measure-error` on frames 2..FRAMES (the layer renders the
   exact quilt too on those frames and logs the synthesised views' mean PSNR).
2. ms/frame: ROUNDS runs per mode without measurement, the modes alternating (the order
   rotates every round); a cell is the median over rounds of the layer's median frame time.
3. The reprojection passes alone: one `--log trace` run, whose per-pass timings wait for the
   GPU after every pass (`glFinish`): the median per frame of depth copy + fetch.

    xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" scripts/bench-reuse-motion.py \\
        [--rounds 3] [--frames 40] [--orbit 0.5] [--spin 0] [-k 2] [--out FILE.md]

Nothing is built: binaries come from --bin (default $CARGO_TARGET_DIR/release, else
target/release).
"""
import argparse, os, re, statistics, subprocess, sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FRAME_RE = re.compile(r"frame time: median ([0-9.]+) ms")
PSNR_RE = re.compile(r"measure-error: frame (\d+): .*PSNR mean ([0-9.]+) dB, worst ([0-9.]+) dB")
PASS_RE = re.compile(r"reproject (?:depth copy|fetch) ([0-9.]+) ms")
RIG = ["--depthiness", "0.12", "--convergence", "9", "--focus", "0"]


def run(args, mode, frames, extra=()):
    layer = [os.path.join(args.bin, "holoinject"), "run", "--log", "info", "--output", "quilt",
             "--quilt", "9x1", "--exit-after", str(frames)] + RIG + mode.split() + list(extra)
    app = [os.path.join(args.bin, "cubes"), "--backend", "glx", "--size", "320x240",
           "--orbit", str(args.orbit), "--spin", str(args.spin)]
    out = subprocess.run(layer + ["--"] + app, capture_output=True, text=True, timeout=900)
    if out.returncode != 0:
        sys.exit(f"{mode}: status {out.returncode}:\n{out.stderr[-2000:]}")
    return out.stderr


def psnr(args, mode):
    frames = ",".join(str(f) for f in range(2, args.frames + 1))
    err = run(args, mode, args.frames, ["--measure-error", frames])
    return {int(f): (float(m), float(w)) for f, m, w in PSNR_RE.findall(err)}


def frame_time(args, mode):
    t = FRAME_RE.search(run(args, mode, args.frames))
    if not t:
        sys.exit(f"{mode}: no frame time")
    return float(t.group(1))


def reprojection_ms(args, mode):
    err = run(args, mode, args.frames, ["--log", "trace"])
    per_frame = [sum(float(x) for x in PASS_RE.findall(l))
                 for l in err.splitlines() if "synthesis passes: reproject" in l]
    return statistics.median(per_frame) if per_frame else None


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--frames", type=int, default=40)
    p.add_argument("--orbit", type=float, default=0.5)
    p.add_argument("--spin", type=float, default=0.0)
    p.add_argument("-k", type=int, default=2)
    p.add_argument("--out", help="also write the tables to this Markdown file")
    target = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
    p.add_argument("--bin", default=os.path.join(target, "release"))
    args = p.parse_args()
    k = args.k
    modes = [f"--mode hybrid:{k}", f"--mode hybrid:{k} --reuse --reuse-motion off", f"--mode hybrid:{k} --reuse"]
    names = [f"hybrid:{k}", "--reuse, motion off", "--reuse"]
    lines = [f"cubes --orbit {args.orbit} --spin {args.spin}, 9x1 quilt of 320x240, {args.frames} frames, "
             f"{args.rounds} rounds", "",
             "PSNR (dB) of the synthesised views against exact, mean (worst view):", "",
             "| frame | " + " | ".join(names) + " |", "|---|" + "---|" * len(names)]
    measured = [psnr(args, m) for m in modes]
    frames = sorted(set.intersection(*(set(m) for m in measured)))
    for f in frames:
        lines.append(f"| {f} | " + " | ".join(f"{m[f][0]:.2f} ({m[f][1]:.2f})" for m in measured) + " |")
    means = [statistics.mean(m[f][0] for f in frames) for m in measured]
    lines.append("| mean | " + " | ".join(f"{x:.2f}" for x in means) + " |")
    times = {m: [] for m in modes}
    for r in range(args.rounds):
        for m in modes[r % len(modes):] + modes[:r % len(modes)]:
            times[m].append(frame_time(args, m))
    t = [statistics.median(times[m]) for m in modes]
    lines += ["", "| ms/frame | " + " | ".join(names) + " | --reuse / motion off |",
              "|---|" + "---|" * (len(names) + 1),
              "| median | " + " | ".join(f"{x:.2f}" for x in t) + f" | {t[2] / t[1]:.2f} |"]
    rp = reprojection_ms(args, modes[2])
    lines += ["", f"reprojection passes (depth copy + fetch, each waited for): median "
              f"{rp:.2f} ms/frame" if rp is not None else "reprojection passes: none ran"]
    text = "\n".join(lines)
    print(text)
    if args.out:
        with open(args.out, "w") as f:
            f.write(text + "\n")


if __name__ == "__main__":
    main()
