#!/usr/bin/python3
"""The guard band (`--guard-band`, issue 23) with and without, per program: quality of the
synthesised views against exact, and what it costs.

Per program (run as scripts/disparity_programs.py runs them: sample apps on OSMesa, real
programs replayed from apitrace recordings) frame F is dumped under `--mode exact` (its
auto-convergence estimate then fixed for every run), then `--mode synth` with
`--guard-band off` and with each band asked for (--bands, default `auto`):
- PSNR (dB, per tile, 8-bit RGB) of every synthesised view against exact: mean and worst;
- of the two outer views: the PSNR of their outer 5 % of columns on each side (the worse
  side), and the share of their squared error that lies in those columns;
- the band's width the layer drew, and the share of the frame its strips took (its log).
Cost: each setting timed in runs of --timing-frames frames without dumps (the layer's own
frame-time median), alternated --rounds times; the median of the rounds. And what a GPU would
pay: draw calls submitted and fragments shaded per frame (`--gpu-counts`).

    scripts/guard-band.py                                  # the default programs, 8x6 of 320x240
    scripts/guard-band.py --programs neverball,cubes --bands auto,8,32 --keep /tmp/gb

Writes OUT/guard-band.md and prints it. Needs what scripts/disparity-agreement.py needs, and
Neverball for its recording (`apt-get install neverball`; not in scripts/setup-debian.sh: no
test runs it).
"""
import argparse, os, re, shutil, subprocess, sys, tempfile, time

sys.dont_write_bytecode = True
import numpy as np
from PIL import Image
from disparity_programs import PROGRAMS, Display, cached_frames, command, log, parse_frame, run_layer

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT = "neverball,cubes,model,legacy,shadowmap,skybox,asteroids,glmark2-shading,glmark2-build,glxgears"
FRAME_TIME = re.compile(r"frame time: median ([0-9.]+) ms over (\d+) frames")
COUNTS = re.compile(r"gpu counts: .*?draws submitted (\d+) .*?fragments (\d+|n/a)")
BAND = re.compile(r"guard band: (\d+) columns each side of the rendered views")
COST = re.compile(r"guard band: its strips take ([0-9.]+) % of the frame[^\n]*?(off, tried again in \d+ frames)?$", re.M)
BORDER = 0.05


def tiles(path, cols, rows):
    q = np.asarray(Image.open(path).convert("RGB"), dtype=np.float64)
    th, tw = q.shape[0] // rows, q.shape[1] // cols
    # View 0 bottom-left (DESIGN §4): row r counted from the bottom of the image.
    return [q[q.shape[0] - (v // cols + 1) * th:q.shape[0] - (v // cols) * th, (v % cols) * tw:(v % cols + 1) * tw]
            for v in range(cols * rows)]


def psnr(se, n):
    return float("inf") if se == 0 else 10 * np.log10(255.0 ** 2 / (se / n))


def quality(exact, fast, cols, rows):
    """Per-view PSNR of the synthesised views, and the outer views' border figures."""
    e, f = tiles(exact, cols, rows), tiles(fast, cols, rows)
    n = cols * rows
    views = [v for v in range(n) if v != n // 2]
    per = {v: psnr(((e[v] - f[v]) ** 2).sum(), e[v].size) for v in views}
    out = {"mean": float(np.mean([min(p, 99.0) for p in per.values()])), "worst": min(per.values())}
    borders, shares = [], []
    for v in (0, n - 1):
        d = (e[v] - f[v]) ** 2
        b = max(1, round(d.shape[1] * BORDER))
        left, right = d[:, :b].sum(), d[:, -b:].sum()
        cells = d[:, :b].size
        borders.append(min(psnr(left, cells), psnr(right, cells)))
        shares.append((left + right) / max(d.sum(), 1e-9))
    out["border"] = min(borders)
    out["border_share"] = float(np.mean(shares))
    return out


def timed(a, prog, env, extra, frames):
    """Frame-time median (ms), draws submitted and fragments per frame, the strips' share of
    the frame (%, and whether `auto` dropped the band for it), over one run."""
    cmd = [os.path.join(a.layer, "holoinject"), "run", "--preset", "none", "--log", "info", "--output", "quilt",
           "--quilt", a.quilt, "--tile", a.tile, "--mode", "synth", "--gpu-counts", *extra,
           "--exit-after", str(frames), "--", *prog]
    p = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, stdin=subprocess.DEVNULL, text=True,
                       env={**os.environ, "ALSOFT_DRIVERS": "null", **env}, timeout=a.timeout)
    t, c, g = FRAME_TIME.search(p.stderr), COUNTS.search(p.stderr), COST.search(p.stderr)
    return (float(t.group(1)) if t else None, int(c.group(1)) if c else None,
            int(c.group(2)) if c and c.group(2) != "n/a" else None,
            (float(g.group(1)), bool(g.group(2))) if g else None)


def measure(name, frame, a, display, work):
    spec = PROGRAMS[name]
    r = {"program": name, "settings": {}}
    pdir = os.path.join(work, name)
    os.makedirs(pdir, exist_ok=True)
    prog, env, _, frame = command(name, spec, frame, a, display, pdir)
    r["frame"] = frame
    timing_frames = a.timing_frames
    if spec["kind"] == "app":
        prog = [x if x != str(frame) else str(max(frame, timing_frames)) for x in prog]
    elif spec["kind"] == "trace":
        timing_frames = min(timing_frames, cached_frames(prog[1], spec, display.get()))
    d = os.path.join(pdir, "exact")
    shutil.rmtree(d, ignore_errors=True)
    ex = run_layer(a, prog, env, "exact", "auto", frame, d)
    if "error" in ex:
        raise RuntimeError(ex["error"])
    conv = f"{ex['scene_at']:g}" if "scene_at" in ex else "auto"
    r["convergence"] = conv
    settings = ["off", *a.bands.split(",")]
    for s in settings:
        d = os.path.join(pdir, f"band-{s}")
        shutil.rmtree(d, ignore_errors=True)
        x = run_layer(a, prog, env, "synth", conv, frame, d, extra=("--guard-band", s))
        if "error" in x:
            raise RuntimeError(x["error"])
        q = quality(ex["quilt"], x["quilt"], *a.grid)
        band = BAND.findall(x["stderr"])
        q["drawn"] = band[0] if band else "0"
        r["settings"][s] = q
    for s in settings:
        r["settings"][s]["runs"] = []
    extra = {s: ["--convergence", conv, "--guard-band", s] for s in settings}
    for _ in range(a.rounds):
        for s in settings:
            r["settings"][s]["runs"].append(timed(a, prog, env, extra[s], timing_frames))
    for s in settings:
        runs = r["settings"][s]["runs"]
        ms = [t for t, _, _, _ in runs if t is not None]
        r["settings"][s]["ms"] = float(np.median(ms)) if ms else None
        r["settings"][s]["draws"] = runs[-1][1]
        r["settings"][s]["fragments"] = runs[-1][2]
        r["settings"][s]["cost"] = runs[-1][3]
    return r


def row(r, s, base):
    q = r["settings"][s]
    ms = q.get("ms")
    shown = lambda x, f: f.format(x) if x is not None else "n/a"
    cost = q.get("cost")
    strips = "–" if cost is None else f"{cost[0]:.1f} %" + (" (dropped)" if cost[1] else "")
    frag = shown(q.get("fragments") and q["fragments"] / 1e6, "{:.2f} M")
    return (f"| {r['program']} | {s} | {q['drawn']} | {q['mean']:.2f} | {q['worst']:.2f} | {q['border']:.2f} | "
            f"{q['border_share'] * 100:.1f} % | {shown(ms, '{:.1f}')} | {shown(ms and base and ms / base, '{:.3f}')} | "
            f"{strips} | {shown(q.get('draws'), '{}')} | {frag} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--programs", default=DEFAULT, help=f"comma-separated NAME or NAME@FRAME (default {DEFAULT})")
    ap.add_argument("--bands", default="auto", help="guard bands to compare with off (default auto)")
    ap.add_argument("--quilt", default="8x6")
    ap.add_argument("--tile", default="320x240", help="WxH (also the programs' window)")
    ap.add_argument("--depthiness", help="--depthiness S for every run (default: the layer's)")
    ap.add_argument("--rounds", type=int, default=2, help="timing rounds, settings alternated (default 2)")
    ap.add_argument("--timing-frames", type=int, default=40, help="frames per timing run (default 40)")
    ap.add_argument("--layer", default=os.path.join(ROOT, "target", "release"))
    ap.add_argument("--apps", help="directory with the sample apps (default: --layer)")
    ap.add_argument("--cache", default=os.path.join(os.path.expanduser("~/.cache"), "holoinject", "traces"))
    ap.add_argument("--out", default=os.path.join(ROOT, "scripts", "results"))
    ap.add_argument("--keep", metavar="DIR", help="keep the quilts in DIR")
    ap.add_argument("--timeout", type=int, default=300)
    a = ap.parse_args()
    a.apps = a.apps or a.layer
    a.grid = tuple(int(x) for x in a.quilt.split("x"))
    work = a.keep or tempfile.mkdtemp(prefix="guard-band-")
    display = Display()
    started = time.time()
    results = []
    try:
        for p in filter(None, a.programs.split(",")):
            name, _, fr = p.partition("@")
            if name not in PROGRAMS:
                sys.exit(f"guard-band: unknown program {name}")
            t0 = time.time()
            try:
                results.append(measure(name, parse_frame(fr) if fr else PROGRAMS[name]["frame"], a, display, work))
                log(f"{name}: done ({time.time() - t0:.0f} s)")
            except (RuntimeError, OSError, subprocess.TimeoutExpired) as e:
                log(f"{name}: FAILED ({e})")
                results.append({"program": name, "error": str(e)})
    finally:
        display.stop()
        if not a.keep:
            shutil.rmtree(work, ignore_errors=True)
    lines = [
        "# Guard band: with and without",
        "",
        f"`scripts/guard-band.py {' '.join(sys.argv[1:])}` ({time.time() - started:.0f} s): `--mode synth`, "
        f"{a.quilt} of {a.tile}, convergence fixed at exact's auto estimate. PSNR over the synthesised views "
        f"against exact; *border*: the outer two views' outer 5 % of columns (the worse side); *border share*: "
        f"the share of those views' squared error in those columns; *ms*: the layer's frame-time median "
        f"(median of {a.rounds} alternated runs of {a.timing_frames} frames), *×*: against `off`; draws submitted "
        f"and fragments per frame (`--gpu-counts`). *drawn*: the columns the layer drew each side at the dumped "
        f"frame (its log); *strips*: the share of the frame the layer measured in the strips' draws; *dropped*: "
        f"`auto` turned the band off in the timed runs (its strips above 10 % of the frame, or under 0.5 % of its "
        f"pixels differing from the tile's border: a plain background).",
        "",
        "| program | band | drawn | PSNR mean | worst | border | border share | ms | × off | strips | draws | fragments |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in results:
        if "error" in r:
            lines.append(f"| {r['program']} | failed: {r['error']} |||||||||")
            continue
        base = r["settings"]["off"].get("ms")
        lines += [row(r, s, base) for s in r["settings"]]
    text = "\n".join(lines) + "\n"
    os.makedirs(a.out, exist_ok=True)
    with open(os.path.join(a.out, "guard-band.md"), "w") as f:
        f.write(text)
    print(text)


if __name__ == "__main__":
    main()
