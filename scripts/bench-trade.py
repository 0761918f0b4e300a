#!/usr/bin/python3
"""Speed/accuracy trade of the fast modes (DESIGN §5-6): `exact`, `synth`, `hybrid:K` against
each other, per scene, number of views and tile size.

Every run is one program under the layer with `--output quilt --log info --exit-after FRAMES
--measure-error every:10`. Per run the layer itself reports (at exit) the median frame time of
frames 11..FRAMES, leaving out the measured frames (on those it also renders every view
exactly), and per measured frame the PSNR of the synthesised views against exact (mean, worst
view). A cell's ms/frame is the median over ROUNDS runs of those per-run medians; the runs of
one scene/N/tile alternate between the modes (the mode order rotates every round), so load from
other work spreads over all modes. Speed-up is t(exact) / t(mode) for the same scene/N/tile.

Scenes: sample apps on headless OSMesa (its frame boundary is `glFinish`, so a frame's time
includes its rendering), window = one tile; real programs are apitrace recordings (made once,
kept in --cache) replayed by `glretrace` on an X server (DISPLAY, or an Xvfb started here).

    scripts/bench-trade.py --quick                 # one scene, N = 9 and 48, one tile, 1 round
    scripts/bench-trade.py [--rounds 3] [--frames 40] [--scenes cubes,glxgears] \\
        [--modes exact,synth,hybrid:2] [--views 9,48] [--tiles 210x280] [--out scripts/results]

Nothing is built: the binaries are taken from --bin (default $CARGO_TARGET_DIR/release, else
target/release). Writes OUT/trade.md (the table) and OUT/trade.png (ms/frame against PSNR).
"""
import argparse, os, re, shutil, signal, statistics, subprocess, sys, tempfile, time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SAMPLE_APPS = ["cubes", "asteroids", "framebuffers", "bloom", "deferred", "ssao"]
# Real programs: (apitrace recording command, seconds it may run). nframes is filled in so the
# trace holds more frames than a run replays.
REAL = {
    "glmark2-phong": (["glmark2", "-s", "400x300", "-b", "shading:shading=phong:nframes={n}"], 40),
    "glmark2-terrain": (["glmark2", "-s", "400x300", "-b", "terrain:nframes={n}"], 90),
    "glxgears": (["glxgears"], 3),
}
DEFAULT_SCENES = ["cubes", "asteroids", "framebuffers", "bloom", "glmark2-phong", "glmark2-terrain", "glxgears"]
QUILTS = {9: "3x3", 24: "6x4", 48: "8x6"}
PSNR_CEILING = 60.0
FRAME_RE = re.compile(r"frame time: median ([0-9.]+) ms over (\d+) frames")
ERR_RE = re.compile(r"measure-error: frame (\d+): (\d+) synthesised views against exact: "
                    r"PSNR mean ([0-9.inf]+) dB, worst ([0-9.inf]+) dB \(view (\d+)\)"
                    r"(?:; holes filled ([0-9.]+)% of their pixels)?")


def quilt_of(n):
    if n in QUILTS:
        return QUILTS[n]
    sys.exit(f"bench-trade: no quilt layout for {n} views (use {', '.join(map(str, QUILTS))})")


def mode_args(mode):
    """A mode with an optional warp: `synth+grid` is `--mode synth --synth-warp grid`."""
    m, _, warp = mode.partition("+")
    return ["--mode", m] + (["--synth-warp", warp] if warp else [])


def hybrid_k(mode):
    m = mode.partition("+")[0]
    return int(m.split(":")[1]) if m.startswith("hybrid:") else None


class Display:
    """DISPLAY for the real programs: the caller's, or an Xvfb of our own (stopped at exit)."""

    def __init__(self):
        self.proc = None
        self.display = os.environ.get("DISPLAY")

    def get(self):
        if self.display:
            return self.display
        if not shutil.which("Xvfb"):
            raise RuntimeError("no DISPLAY and no Xvfb (scripts/setup-debian.sh)")
        r, w = os.pipe()
        self.proc = subprocess.Popen(
            ["Xvfb", "-displayfd", str(w), "-screen", "0", "1280x1024x24", "-nolisten", "tcp"],
            pass_fds=(w,), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        os.close(w)
        with os.fdopen(r) as f:
            num = f.readline().strip()
        if not num:
            raise RuntimeError("Xvfb did not start")
        self.display = f":{num}"
        print(f"bench-trade: started Xvfb on {self.display} (pid {self.proc.pid})", file=sys.stderr)
        return self.display

    def stop(self):
        if self.proc:
            self.proc.terminate()
            try:
                self.proc.wait(5)
            except subprocess.TimeoutExpired:
                self.proc.kill()


def record(name, cache, frames, display):
    """The trace of real program `name`, recorded into `cache` the first time."""
    cmd, seconds = REAL[name]
    n = frames + 20
    trace = os.path.join(cache, f"{name}-{n}.trace" if any("{n}" in a for a in cmd) else f"{name}.trace")
    if os.path.exists(trace) and os.path.getsize(trace) > 1000:
        return trace
    os.makedirs(cache, exist_ok=True)
    prog = [a.replace("{n}", str(n)) for a in cmd]
    print(f"bench-trade: recording {name}: {' '.join(prog)}", file=sys.stderr)
    # timeout signals the whole group; apitrace's handler in the traced program has been seen
    # to hang under load, hence the KILL 5 s later (glretrace replays truncated traces). On a
    # loaded machine a program can spend its recording time starting (glxgears recorded
    # nothing in 3 s, terrain 17 of 60 frames in 90 s): then it is recorded for four times as long.
    tmp = trace + ".part"
    got = -1
    for limit in (seconds, seconds * 4):
        subprocess.run(["timeout", "-k", "5", str(limit), "apitrace", "trace", "--api", "gl", "-o", tmp, *prog],
                       env={**os.environ, "DISPLAY": display}, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        if not os.path.exists(tmp) or os.path.getsize(tmp) < 1000:
            continue
        # How many frames it holds (a plain benchmark replay).
        p = subprocess.run(["timeout", "300", "glretrace", "-b", tmp], capture_output=True, text=True,
                           env={**os.environ, "DISPLAY": display})
        m = re.search(r"Rendered (\d+) frames", p.stdout + p.stderr)
        got = int(m.group(1)) if m else -1
        print(f"bench-trade: {name}: {got} frames recorded in {limit} s", file=sys.stderr)
        if got >= frames:
            break
    if not os.path.exists(tmp) or os.path.getsize(tmp) < 1000:
        raise RuntimeError(f"apitrace recorded nothing for {name} (apitrace installed? scripts/setup-debian.sh)")
    os.replace(tmp, trace)
    if 0 <= got < frames:
        print(f"bench-trade: warning: {name} trace has {got} < {frames} frames: its runs will fail", file=sys.stderr)
    return trace


def program(scene, tile, frames, a, display):
    """(command, extra environment) of scene `scene` with windows of one tile."""
    if scene in SAMPLE_APPS:
        return [os.path.join(a.bin, scene), "--backend", "osmesa", "--size", tile, "--frames", str(frames)], {}
    if scene in REAL:
        d = display.get()
        return ["glretrace", record(scene, a.cache, frames, d)], {"DISPLAY": d}
    raise RuntimeError(f"unknown scene {scene}")


def run_once(scene, mode, n, tile, a, display):
    """One run: {'ms', 'frames', 'psnr_mean', 'psnr_worst', 'worst_view', 'measured'} or {'error'}."""
    try:
        prog, env = program(scene, tile, a.frames, a, display)
    except RuntimeError as e:
        return {"error": str(e)}
    cmd = [os.path.join(a.bin, "holoinject"), "run", "--log", "info", "--output", "quilt",
           "--quilt", quilt_of(n), "--tile", tile, *mode_args(mode), "--exit-after", str(a.frames),
           "--measure-error", f"every:{a.measure_every}", *a.layer_arg, "--", *prog]
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=a.timeout,
                           env={**os.environ, "ALSOFT_DRIVERS": "null", **env}, start_new_session=True)
    except subprocess.TimeoutExpired:
        return {"error": f"timed out after {a.timeout} s"}
    m = FRAME_RE.search(p.stderr)
    if p.returncode != 0 or not m:
        tail = [l for l in p.stderr.splitlines() if "error" in l.lower() or "panic" in l.lower()][-2:]
        return {"error": f"status {p.returncode}, {'frame time logged' if m else 'no frame time'}"
                         + (f": {' | '.join(tail)}" if tail else ""), "stderr": p.stderr}
    errs = [(float(x.group(3)), float(x.group(4)), int(x.group(5)), x.group(6)) for x in ERR_RE.finditer(p.stderr)]
    r = {"ms": float(m.group(1)), "frames": int(m.group(2)), "measured": len(errs)}
    if errs:
        r["psnr_mean"] = statistics.fmean(e[0] for e in errs)
        worst = min(errs, key=lambda e: e[1])
        r["psnr_worst"], r["worst_view"] = worst[1], worst[2]
        holes = [float(e[3]) for e in errs if e[3] is not None]
        if holes:
            r["holes"] = statistics.fmean(holes)
    elif mode != "exact":
        r["note"] = "no measure-error line (stayed exact?)"
    return r


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rounds", type=int, default=3, help="runs per cell (default 3)")
    ap.add_argument("--frames", type=int, default=40, help="frames per run, timed from frame 11 (default 40)")
    ap.add_argument("--scenes", default=",".join(DEFAULT_SCENES),
                    help=f"comma-separated, from {', '.join(SAMPLE_APPS + list(REAL))}")
    ap.add_argument("--modes", default="exact,synth,synth+grid,synth:pixel,hybrid:2,hybrid:4", help="comma-separated (exact is always added); MODE+grid|rows picks the warp, e.g. synth+grid")
    ap.add_argument("--views", default="9,24,48", help="numbers of views: 9 (3x3), 24 (6x4), 48 (8x6)")
    ap.add_argument("--tiles", default="210x280,420x560", help="tile sizes WxH")
    ap.add_argument("--quick", action="store_true", help="cubes, N = 9 and 48, tile 210x280, 1 round")
    ap.add_argument("--measure-every", type=int, default=10, help="--measure-error every:N (default 10)")
    ap.add_argument("--timeout", type=int, default=900, help="seconds before a run counts as failed")
    ap.add_argument("--layer-arg", action="append", default=[], help="extra holoinject option (repeatable, e.g. --layer-arg=--synth-threshold=2)")
    ap.add_argument("--bin", default=os.path.join(os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target")), "release"))
    ap.add_argument("--cache", default=os.path.join(os.environ.get("XDG_CACHE_HOME", os.path.expanduser("~/.cache")), "holoinject", "traces"),
                    help="where apitrace recordings are kept")
    ap.add_argument("--out", default=os.path.join(ROOT, "scripts", "results"))
    ap.add_argument("--replot", metavar="TRADE_MD", help="only redraw OUT/trade.png from a table this script wrote")
    a = ap.parse_args()
    if a.replot:
        plot(a, rows_of_table(a.replot))
        return
    if a.quick:
        a.scenes, a.views, a.tiles, a.rounds = "cubes", "9,48", "210x280", 1
    a.layer_arg = [x for arg in a.layer_arg for x in (arg.split("=", 1) if arg.startswith("--") and "=" in arg else [arg])]
    for f in ["holoinject", "libholoinject.so"]:
        if not os.path.exists(os.path.join(a.bin, f)):
            sys.exit(f"bench-trade: {a.bin}/{f} missing: build first (cargo build --workspace --release) or pass --bin")
    scenes = [s for s in a.scenes.split(",") if s]
    for s in scenes:
        if s not in SAMPLE_APPS and s not in REAL:
            sys.exit(f"bench-trade: unknown scene {s}")
    modes = [m for m in a.modes.split(",") if m]
    if "exact" not in modes:
        modes.insert(0, "exact")
    views = [int(v) for v in a.views.split(",")]
    for v in views:
        quilt_of(v)
    tiles = a.tiles.split(",")
    configs = [(s, n, t) for s in scenes for n in views for t in tiles]
    cell_modes = {c: [m for m in modes if hybrid_k(m) is None or hybrid_k(m) < c[1]] for c in configs}
    total = a.rounds * sum(len(v) for v in cell_modes.values())
    results = {}  # (scene, n, tile, mode) -> list of run dicts
    display = Display()
    started, done = time.time(), 0
    try:
        for rnd in range(a.rounds):
            for c in configs:
                ms = cell_modes[c]
                ms = ms[rnd % len(ms):] + ms[:rnd % len(ms)]  # rotate the order every round
                for mode in ms:
                    scene, n, tile = c
                    done += 1
                    r = run_once(scene, mode, n, tile, a, display)
                    results.setdefault((*c, mode), []).append(r)
                    what = f"[{done}/{total}] {scene} {mode} {quilt_of(n)} {tile}:"
                    if "error" in r:
                        print(f"{what} FAILED ({r['error']})", file=sys.stderr)
                    else:
                        ps = f", PSNR {r['psnr_mean']:.1f}/{r['psnr_worst']:.1f} dB" if "psnr_mean" in r else ""
                        print(f"{what} {r['ms']:.0f} ms{ps}  ({time.time() - started:.0f} s)", file=sys.stderr)
    finally:
        display.stop()
    rows = summarise(configs, cell_modes, results)
    os.makedirs(a.out, exist_ok=True)
    write_table(a, rows, time.time() - started)
    plot(a, rows)


def summarise(configs, cell_modes, results):
    rows = []
    for c in configs:
        cell = {}
        for mode in cell_modes[c]:
            runs = [r for r in results.get((*c, mode), []) if "error" not in r]
            failed = len(results.get((*c, mode), [])) - len(runs)
            d = {"runs": len(runs), "failed": failed}
            if runs:
                d["ms"] = statistics.median(r["ms"] for r in runs)
                pm = [r["psnr_mean"] for r in runs if "psnr_mean" in r]
                if pm:
                    d["psnr_mean"] = statistics.median(pm)
                    d["psnr_worst"] = min(r["psnr_worst"] for r in runs if "psnr_worst" in r)
                hs = [r["holes"] for r in runs if "holes" in r]
                if hs:
                    d["holes"] = statistics.median(hs)
                d["notes"] = sorted({r["note"] for r in runs if "note" in r})
            cell[mode] = d
        exact = cell.get("exact", {}).get("ms")
        for mode, d in cell.items():
            if exact and "ms" in d:
                d["speedup"] = exact / d["ms"]
            rows.append((*c, mode, d))
    return rows


def fmt_row(scene, n, tile, mode, d):
    q = f"{n} ({quilt_of(n)})"
    if "ms" not in d:
        return f"| {scene} | {q} | {tile} | {mode} | failed | – | – | – | – |"
    ms = f"{d['ms']:.1f}" + (f" ({d['failed']} failed)" if d["failed"] else "")
    sp = f"{d['speedup']:.2f}×" if "speedup" in d else "–"
    if mode == "exact":
        pm = pw = "∞ (reference)"
    elif "psnr_mean" in d:
        pm, pw = f"{d['psnr_mean']:.1f}", f"{d['psnr_worst']:.1f}"
    else:
        pm = pw = "n/a"
    holes = f"{d['holes']:.2f}" if "holes" in d else "–"
    return f"| {scene} | {q} | {tile} | {mode} | {ms} | {sp} | {pm} | {pw} | {holes} |"


def write_table(a, rows, elapsed):
    try:
        rev = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    except OSError:
        rev = "?"
    extra = f", layer options {' '.join(a.layer_arg)}" if a.layer_arg else ""
    lines = [
        f"Speed/accuracy trade of the fast modes (scripts/bench-trade.py, {rev}, {time.strftime('%Y-%m-%d')}): "
        f"Mesa llvmpipe, {os.cpu_count()} cores shared with other work (absolute times are noisy; read the ratios). "
        f"`--output quilt`, default depthiness and auto-convergence{extra}; sample apps on headless OSMesa (window = one tile), "
        f"real programs as apitrace replays (`glretrace`, their own window size) on Xvfb.",
        "",
        f"ms/frame: median over {a.rounds} alternating run(s) of the layer's own frame-time median of frames 11-{a.frames} "
        f"(frames under `--measure-error every:{a.measure_every}` left out). Speed-up: t(exact) / t(mode), same scene, N and tile. "
        f"PSNR (dB) of the synthesised views against exact, from the same runs: mean over views and measured frames, "
        f"and the worst view of any measured frame. Holes: % of synthesised pixels filled because no source pixel landed "
        f"there (disocclusions, and beyond the view's edge; the row warp counts them, the grid does not). Took {elapsed / 60:.0f} min.",
        "",
        "| scene | N | tile | mode | ms/frame | speed-up vs exact | PSNR mean | PSNR worst | holes % |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    lines += [fmt_row(*r) for r in rows]
    notes = sorted({f"{r[0]} {r[3]} {quilt_of(r[1])} {r[2]}: {n}" for r in rows for n in r[4].get("notes", [])})
    if notes:
        lines += ["", *[f"- {n}" for n in notes]]
    text = "\n".join(lines) + "\n"
    with open(os.path.join(a.out, "trade.md"), "w") as f:
        f.write(text)
    print(text)


def rows_of_table(path):
    """(scene, n, tile, mode, {'ms', 'psnr_mean'}) rows back from a trade.md table."""
    rows = []
    for line in open(path):
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) < 7 or not cells[1].split(" ")[0].isdigit():
            continue
        d = {}
        try:
            d["ms"] = float(cells[4].split(" ")[0])
        except ValueError:
            pass
        try:
            d["psnr_mean"] = float(cells[6])
        except ValueError:
            pass
        rows.append((cells[0], int(cells[1].split(" ")[0]), cells[2], cells[3], d))
    return rows


def plot(a, rows):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("bench-trade: matplotlib missing (apt-get install python3-matplotlib): no plot", file=sys.stderr)
        return
    panels = sorted({(r[1], r[2]) for r in rows}, key=lambda p: (p[0], [int(x) for x in p[1].split("x")]))
    scenes = list(dict.fromkeys(r[0] for r in rows))
    cols = len({p[0] for p in panels})
    nrows = -(-len(panels) // cols)
    fig, axes = plt.subplots(nrows, cols, figsize=(5.2 * cols, 4.2 * nrows), squeeze=False)
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    tiles = sorted({p[1] for p in panels}, key=lambda t: [int(x) for x in t.split("x")])
    for (n, tile), ax in zip(sorted(panels, key=lambda p: (tiles.index(p[1]), p[0])), axes.flat):
        for i, s in enumerate(scenes):
            pts = []
            for sc, nn, tt, mode, d in rows:
                if (sc, nn, tt) != (s, n, tile) or "ms" not in d:
                    continue
                y = PSNR_CEILING if mode == "exact" else d.get("psnr_mean")
                if y is not None:
                    pts.append((d["ms"], min(y, PSNR_CEILING), mode))
            if not pts:
                continue
            pts.sort()
            c = colours[i % len(colours)]
            ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-", color=c, label=s)
            for x, y, mode in pts:
                ax.annotate(mode.replace("hybrid:", "h"), (x, y), textcoords="offset points", xytext=(4, 3), fontsize=7, color=c)
        ax.set_xscale("log")
        ax.set_title(f"{n} views ({quilt_of(n)}), tiles {tile}", fontsize=10)
        ax.set_xlabel("ms / frame (log)")
        ax.set_ylabel("PSNR mean vs exact (dB)")
        ax.axhline(PSNR_CEILING, color="grey", lw=0.5, ls=":")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    for ax in list(axes.flat)[len(panels):]:
        ax.axis("off")
    fig.suptitle("Speed/accuracy trade on llvmpipe (up and left is better)")
    fig.text(0.01, 0.005, f"exact has no error (PSNR ∞): plotted at a ceiling of {PSNR_CEILING:.0f} dB. "
             f"Labels: h2 = hybrid:2, h4 = hybrid:4.", fontsize=8)
    fig.tight_layout(rect=(0, 0.03, 1, 0.96))
    fig.savefig(os.path.join(a.out, "trade.png"), dpi=100)


if __name__ == "__main__":
    main()
