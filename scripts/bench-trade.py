#!/usr/bin/python3
"""Speed/accuracy trade of the fast modes (DESIGN §5-6): `exact`, `synth`, `hybrid:K` against
each other, per scene, number of views and tile size: frame time, error of the synthesised
views (PSNR, FLIP, disparity) and what a frame asks of the GPU (counts).

Timed runs. Every run is one program under the layer with `--output quilt --log info
--exit-after FRAMES --measure-error every:M` (M = --measure-every, default 10). Per run the
layer itself reports (at exit) the median frame time of frames 11..FRAMES, leaving out the
measured frames (on those it also renders every view exactly), and per measured frame the PSNR
of the synthesised views against exact (mean, worst view). A cell's ms/frame is the median over
ROUNDS runs of those per-run medians; the runs of one scene/N/tile alternate between the modes
(the mode order rotates every round), so load from other work spreads over all modes. Speed-up
is t(exact) / t(mode) for the same scene/N/tile.

Quilt runs (--quilt-metrics, default on). Per scene/N/tile, after the timed runs, frame F =
the last measured frame (the largest multiple of M up to FRAMES; FRAMES when M > FRAMES) is
dumped once under exact and once under each fast mode (`--dump DIR --dump-frames F
--exit-after F`, the fast modes also `--measure-error F`), all at one convergence: exact's
auto-convergence estimate from its timed runs (`auto-convergence: scene at C`, passed as
`--convergence C`; auto when exact logs none). Under auto each mode estimates its own (hybrid:K
from its synthesised centre view), and its rendered views would not be exact's. Once per cell,
not per round: frame F is the same picture in every run (sample apps animate by frame number,
replays follow their recording). From the two quilts (scripts/trade_quilts.py), over the views
the mode synthesises — from the mode, as the layer's plan: all but the centre view N/2 for
synth, all but the K evenly spaced views (both ends included) for hybrid:K; never from which
tiles differ:
- FLIP: NVIDIA's `flip_evaluator` (pip flip-evaluator; LDR, 67 pixels per degree), mean of
  each synthesised tile's error map against exact's tile; mean over those views and the worst;
- disparity error: for each textured 16x16 block of exact's centre view, |shift in exact's
  view - shift in the mode's view| (px, integer SSD search), pooled over blocks and synthesised
  views; median and 95th percentile;
- their PSNR, checked against the layer's own PSNR of frame F (a note when they differ).

Counts (--counts; default: when `holoinject run --help` lists --gpu-counts). The timed runs
add `--gpu-counts` and the layer's exit line `gpu counts: per frame, median over N frames: app
draws A, draws submitted D (layer's own L), fragments F, compute invocations C,
tile-equivalents T, bytes read back B` (medians over the timed frames) is kept; a cell shows
the median over its runs.

Scenes: sample apps headless (--backend osmesa, the default: its frame boundary is `glFinish`,
so a frame's time includes its rendering; egl, egl-device), window = one tile; real programs
are apitrace recordings (made once, kept in --cache) replayed by `glretrace` on an X server
(DISPLAY, or an Xvfb started here).

    scripts/bench-trade.py --quick                 # one scene, N = 9 and 48, one tile, 1 round
    scripts/bench-trade.py [--rounds 3] [--frames 40] [--scenes cubes,glxgears] \\
        [--modes exact,synth,hybrid:2] [--views 9,48] [--tiles 210x280] [--out scripts/results]
    scripts/bench-trade.py --replot scripts/results/trade.md --out /tmp/plots

Nothing is built: the binaries are taken from --bin (default $CARGO_TARGET_DIR/release, else
target/release). Writes OUT/trade.md (the table), OUT/trade.png (speed-up against PSNR) and
OUT/trade-flip.png (speed-up against FLIP; scripts/trade_plot.py). Needs numpy and PIL for the
quilt metrics, flip-evaluator for FLIP (scripts/setup-debian.sh), matplotlib for the plots.
"""
import argparse, importlib.util, os, re, shutil, statistics, subprocess, sys, tempfile, time

sys.dont_write_bytecode = True  # no __pycache__ beside the scripts for the modules below
from trade_plot import plot
from trade_table import quilt_of, rows_of_table, summarise, write_table

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SAMPLE_APPS = ["cubes", "asteroids", "framebuffers", "bloom", "deferred", "ssao"]
BACKENDS = ["osmesa", "egl", "egl-device"]
# Real programs: (apitrace recording command, seconds it may run). nframes is filled in so the
# trace holds more frames than a run replays.
REAL = {
    "glmark2-phong": (["glmark2", "-s", "400x300", "-b", "shading:shading=phong:nframes={n}"], 40),
    "glmark2-terrain": (["glmark2", "-s", "400x300", "-b", "terrain:nframes={n}"], 90),
    "glxgears": (["glxgears"], 3),
}
DEFAULT_SCENES = ["cubes", "asteroids", "framebuffers", "bloom", "glmark2-phong", "glmark2-terrain", "glxgears"]
FRAME_RE = re.compile(r"frame time: median ([0-9.]+) ms over (\d+) frames")
ERR_RE = re.compile(r"measure-error: frame (\d+): (\d+) synthesised views against exact: "
                    r"PSNR mean ([0-9.inf]+) dB, worst ([0-9.inf]+) dB \(view (\d+)\)"
                    r"(?:; holes filled ([0-9.]+)% of their pixels)?")
SCENE_AT = re.compile(r"auto-convergence: scene at ([0-9.eE+-]+)")
RENDERED = re.compile(r"synthesis: (\d+) of (\d+) views rendered")
STAYS_EXACT = "every view is rendered exactly"
# The layer's exit line under --gpu-counts; a figure the driver cannot count reads "n/a" and is
# left out, as is the whole line from a layer without the option.
COUNTS_RE = re.compile(r"gpu counts: per frame, median over (\d+) frames: ([^\n]*)")
NUM = r"([0-9]+(?:\.[0-9]*)?(?:[eE][+-]?[0-9]+)?)"
COUNT_FIELD_RE = re.compile(r"(app draws|draws submitted|layer's own|fragments|compute invocations|"
                            r"tile-equivalents|bytes read back) " + NUM)
COUNT_KEYS = {"app draws": "app_draws", "draws submitted": "draws", "layer's own": "layer_draws",
              "fragments": "fragments", "compute invocations": "compute", "tile-equivalents": "tiles",
              "bytes read back": "read_back"}
# Identical PSNRs print alike; beyond this the quilts are not what the layer compared.
PSNR_AGREE_DB = 0.05


def mode_args(mode):
    """A mode with an optional warp: `synth+grid` is `--mode synth --synth-warp grid`."""
    m, _, warp = mode.partition("+")
    return ["--mode", m] + (["--synth-warp", warp] if warp else [])


def hybrid_k(mode):
    m = mode.partition("+")[0]
    return int(m.split(":")[1]) if m.startswith("hybrid:") else None


def parse_counts(stderr):
    """{'app_draws', 'draws', 'layer_draws', 'fragments', 'compute', 'tiles', 'read_back',
    'count_frames'} of the layer's last `gpu counts:` line, or {} without one."""
    found = COUNTS_RE.findall(stderr)
    if not found:
        return {}
    frames, fields = found[-1]
    d = {COUNT_KEYS[k]: float(v) for k, v in COUNT_FIELD_RE.findall(fields)}
    d["count_frames"] = int(frames)
    return d


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
        return [os.path.join(a.bin, scene), "--backend", a.backend, "--size", tile, "--frames", str(frames)], {}
    if scene in REAL:
        d = display.get()
        return ["glretrace", record(scene, a.cache, frames, d)], {"DISPLAY": d}
    raise RuntimeError(f"unknown scene {scene}")


def run_layer(scene, mode, n, tile, a, display, options):
    """One program under the layer, ended after frame `--exit-after`: (status, stderr), or
    (None, error text). `options` are the layer options of this kind of run."""
    try:
        prog, env = program(scene, tile, a.frames, a, display)
    except RuntimeError as e:
        return None, str(e)
    cmd = [os.path.join(a.bin, "holoinject"), "run", "--log", "info", "--output", "quilt",
           "--quilt", quilt_of(n), "--tile", tile, *mode_args(mode), *options, *a.layer_arg, "--", *prog]
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=a.timeout,
                           env={**os.environ, "ALSOFT_DRIVERS": "null", **env}, start_new_session=True)
    except subprocess.TimeoutExpired:
        return None, f"timed out after {a.timeout} s"
    return p.returncode, p.stderr


def failure(status, stderr, what):
    tail = [l for l in stderr.splitlines() if "error" in l.lower() or "panic" in l.lower()][-2:]
    return f"status {status}, {what}" + (f": {' | '.join(tail)}" if tail else "")


def run_once(scene, mode, n, tile, a, display):
    """One timed run: {'ms', 'frames', 'psnr_mean', 'psnr_worst', 'worst_view', 'measured',
    'scene_at', counts…} or {'error'}."""
    options = ["--exit-after", str(a.frames), "--measure-error", f"every:{a.measure_every}", *a.counts_arg]
    status, err = run_layer(scene, mode, n, tile, a, display, options)
    if status is None:
        return {"error": err}
    m = FRAME_RE.search(err)
    if status != 0 or not m:
        return {"error": failure(status, err, "frame time logged" if m else "no frame time"), "stderr": err}
    r = {"ms": float(m.group(1)), "frames": int(m.group(2)), **parse_counts(err), **measured_error(err)}
    at = SCENE_AT.findall(err)
    if at:
        r["scene_at"] = float(at[-1])
    if mode != "exact" and not r["measured"]:
        r["note"] = "no measure-error line (stayed exact?)"
    return r


def measured_error(stderr):
    """The layer's PSNR lines of one run, summed up: {'measured', 'psnr_mean', 'psnr_worst',
    'worst_view', 'holes'}."""
    errs = [(float(x.group(3)), float(x.group(4)), int(x.group(5)), x.group(6)) for x in ERR_RE.finditer(stderr)]
    r = {"measured": len(errs)}
    if errs:
        r["psnr_mean"] = statistics.fmean(e[0] for e in errs)
        worst = min(errs, key=lambda e: e[1])
        r["psnr_worst"], r["worst_view"] = worst[1], worst[2]
        holes = [float(e[3]) for e in errs if e[3] is not None]
        if holes:
            r["holes"] = statistics.fmean(holes)
    return r


# ---------------------------------------------------------------------------------- quilt runs

def quilt_frame(a):
    """Frame F of the quilt runs: the timed runs' last measured frame."""
    return a.frames // a.measure_every * a.measure_every or a.frames


def pinned_convergence(runs):
    """Exact's auto-convergence estimate from its timed runs (the last logged), or None."""
    found = [r["scene_at"] for r in runs if "scene_at" in r]
    return found[-1] if found else None


def dump_quilt(cell, mode, conv, a, display, work):
    """Frame F of one mode dumped: {'quilt', 'stderr'} or {'error'}."""
    scene, n, tile = cell
    f = quilt_frame(a)
    d = os.path.join(work, f"{scene}-{n}-{tile}", mode.replace(":", "-").replace("+", "-"))
    shutil.rmtree(d, ignore_errors=True)
    options = ["--dump", d, "--dump-frames", str(f), "--exit-after", str(f)]
    options += ["--convergence", f"{conv:g}"] if conv is not None else []
    options += ["--measure-error", str(f)] if mode != "exact" else []
    status, err = run_layer(scene, mode, n, tile, a, display, options)
    if status is None:
        return {"error": err}
    quilts = [x for x in os.listdir(d) if x.startswith(f"f{f:06}_qs")] if os.path.isdir(d) else []
    if status != 0 or not quilts:
        return {"error": failure(status, err, f"no quilt of frame {f}"), "stderr": err}
    return {"quilt": os.path.join(d, quilts[0]), "stderr": err}


def rendered_set(mode, n, a):
    """The views `mode` renders, derived from the mode; or (None, why there are none)."""
    from trade_quilts import rendered_views
    if "--reuse" in a.layer_arg:
        return None, "--reuse rotates the rendered views: no quilt metrics"
    views = rendered_views(mode, n)
    if views is None:
        return None, f"{mode} picks its rendered views per frame: no quilt metrics"
    return views, None


def layer_disagrees(mode, views, err):
    """Why the quilt run's log contradicts `views` (None when it does not)."""
    if STAYS_EXACT in err:
        return "stayed exact in the quilt run: nothing synthesised"
    m = RENDERED.search(err)
    if m and int(m.group(1)) != len(views):
        return f"the layer renders {m.group(1)} views, {mode} should render {len(views)}: no quilt metrics"
    return None


def compare_mode(exact, x, mode, views, n, a, cache):
    """Quilt metrics of one fast mode's dump `x` against exact's: a dict (with 'note' on doubts)."""
    import trade_quilts
    why = layer_disagrees(mode, views, x["stderr"])
    if why:
        return {"note": why}
    cols, rows = (int(v) for v in quilt_of(n).split("x"))
    r = trade_quilts.compare(exact, x["quilt"], cols, rows, views, a.shift_per_view, cache, a.flip)
    notes = [] if r["rendered_identical"] else [f"quilt run: {mode}'s rendered views differ from exact's"]
    layer = ERR_RE.search(x["stderr"])
    if layer and "q_psnr_mean" in r and abs(float(layer.group(3)) - r["q_psnr_mean"]) > PSNR_AGREE_DB:
        notes.append(f"quilt run: PSNR of the dumped quilts {r['q_psnr_mean']:.2f} dB, the layer's in-process "
                     f"{float(layer.group(3)):.2f} dB (the exact dump is not the layer's reference)")
    if notes:
        r["note"] = "; ".join(notes)
    return r


def quilt_mode(cell, mode, exact, conv, a, display, work, cache):
    """Quilt metrics of one fast mode of one scene/N/tile."""
    views, why = rendered_set(mode, cell[1], a)
    if views is None:
        return {"note": why}
    x = dump_quilt(cell, mode, conv, a, display, work)
    if "error" in x:
        return {"note": f"quilt run failed ({x['error']})"}
    return compare_mode(exact, x, mode, views, cell[1], a, cache)


def quilt_cell(cell, modes, conv, a, display, work, cache):
    """{mode: quilt metrics} of one scene/N/tile (module doc, "Quilt runs")."""
    fast = [m for m in modes if m != "exact"]
    exact = dump_quilt(cell, "exact", conv, a, display, work)
    if "error" in exact:
        return {m: {"note": f"quilt run of exact failed ({exact['error']})"} for m in fast}
    return {m: quilt_mode(cell, m, exact["quilt"], conv, a, display, work, cache) for m in fast}


def quilt_phase(configs, cell_modes, results, a, display):
    """{(scene, n, tile, mode): quilt metrics} of every cell; quilts kept in --keep, else removed."""
    import trade_quilts
    work = a.keep or tempfile.mkdtemp(prefix="bench-trade-")
    cache, out, started = trade_quilts.ExactShifts(), {}, time.time()
    # A convergence given with --layer-arg is the user's, in every run.
    given = any(x.startswith("--convergence") for x in a.layer_arg)
    try:
        for c in configs:
            conv = None if given else pinned_convergence(results.get((*c, "exact"), []))
            for mode, q in quilt_cell(c, cell_modes[c], conv, a, display, work, cache).items():
                q["convergence"] = conv
                out[(*c, mode)] = q
                print(f"[quilts] {c[0]} {mode} {quilt_of(c[1])} {c[2]}: {quilt_text(q)}  "
                      f"({time.time() - started:.0f} s)", file=sys.stderr)
    finally:
        if not a.keep:
            shutil.rmtree(work, ignore_errors=True)
    return out


def quilt_text(q):
    parts = []
    if "flip_mean" in q:
        parts.append(f"FLIP {q['flip_mean']:.4f}, worst {q['flip_worst']:.4f} (view {q['flip_worst_view']})")
    if "q_psnr_mean" in q:
        parts.append(f"PSNR {q['q_psnr_mean']:.2f} dB")
    if "disp_median" in q:
        parts.append(f"disparity error {q['disp_median']:.1f} / {q['disp_p95']:.1f} px over {q['disp_blocks']} blocks")
    return ", ".join(parts + ([q["note"]] if "note" in q else [])) or "nothing measured"


# ---------------------------------------------------------------------------------- sweep

def arguments():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rounds", type=int, default=3, help="runs per cell (default 3)")
    ap.add_argument("--frames", type=int, default=40, help="frames per run, timed from frame 11 (default 40)")
    ap.add_argument("--scenes", default=",".join(DEFAULT_SCENES),
                    help=f"comma-separated, from {', '.join(SAMPLE_APPS + list(REAL))}")
    ap.add_argument("--modes", default="exact,synth,synth+grid,synth:pixel,hybrid:2,hybrid:4", help="comma-separated (exact is always added); MODE+rows|grid|gather picks the warp, e.g. synth+gather")
    ap.add_argument("--views", default="9,24,48", help="numbers of views: 9 (3x3), 24 (6x4), 48 (8x6)")
    ap.add_argument("--tiles", default="210x280,420x560", help="tile sizes WxH")
    ap.add_argument("--backend", default="osmesa", choices=BACKENDS, help="the sample apps' --backend (default osmesa)")
    ap.add_argument("--quick", action="store_true", help="cubes, N = 9 and 48, tile 210x280, 1 round")
    ap.add_argument("--measure-every", type=int, default=10, help="--measure-error every:N (default 10)")
    ap.add_argument("--counts", action=argparse.BooleanOptionalAction, default=None,
                    help="add the layer's --gpu-counts to the timed runs (default: when this holoinject has it)")
    ap.add_argument("--quilt-metrics", action=argparse.BooleanOptionalAction, default=True,
                    help="dump frame F per mode and measure FLIP and disparity error (default on)")
    ap.add_argument("--shift-per-view", type=float, default=8.0,
                    help="disparity error: block search reach in px per view from the centre (default 8, at least 16)")
    ap.add_argument("--keep", metavar="DIR", help="keep the quilt runs' PNGs in DIR (default: removed)")
    ap.add_argument("--timeout", type=int, default=900, help="seconds before a run counts as failed")
    ap.add_argument("--layer-arg", action="append", default=[], help="extra holoinject option (repeatable, e.g. --layer-arg=--synth-threshold=2)")
    ap.add_argument("--bin", default=os.path.join(os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target")), "release"))
    ap.add_argument("--cache", default=os.path.join(os.environ.get("XDG_CACHE_HOME", os.path.expanduser("~/.cache")), "holoinject", "traces"),
                    help="where apitrace recordings are kept")
    ap.add_argument("--out", default=os.path.join(ROOT, "scripts", "results"))
    ap.add_argument("--replot", metavar="TRADE_MD", help="only redraw OUT/trade.png (and trade-flip.png) from a table this script wrote")
    a = ap.parse_args()
    a.argv = sys.argv[1:]
    if a.quick:
        a.scenes, a.views, a.tiles, a.rounds = "cubes", "9,48", "210x280", 1
    a.layer_arg = [x for arg in a.layer_arg for x in (arg.split("=", 1) if arg.startswith("--") and "=" in arg else [arg])]
    return a


def counts_option(a):
    """The layer options that turn the counts on ([] when off), from `holoinject run --help`."""
    if a.counts is False:
        return []
    p = subprocess.run([os.path.join(a.bin, "holoinject"), "run", "--help"], capture_output=True, text=True)
    m = re.search(r"^\s*--gpu-counts(?: (\S+))?(?:\s{2,}|$)", p.stdout + p.stderr, re.M)
    if not m:
        if a.counts:
            sys.exit(f"bench-trade: --counts: {a.bin}/holoinject has no --gpu-counts (an older build?)")
        print("bench-trade: this holoinject has no --gpu-counts: no counts", file=sys.stderr)
        return []
    # A switch; should it take a value, on|off is the layer's spelling of switches.
    return ["--gpu-counts"] + (["on"] if m.group(1) and "on" in m.group(1).split("|") else [])


def flip_or_none():
    import trade_quilts
    flip = trade_quilts.flip_module()
    if flip is None:
        print("bench-trade: flip_evaluator missing (pip install --break-system-packages flip-evaluator): no FLIP",
              file=sys.stderr)
    return flip


def quilt_metrics_available():
    """numpy and PIL are there (the quilt metrics need them), else the metrics are off."""
    if all(importlib.util.find_spec(m) for m in ("numpy", "PIL")):
        return True
    print("bench-trade: numpy or PIL missing (apt-get install python3-numpy python3-pil): no quilt metrics",
          file=sys.stderr)
    return False


def cells(a):
    """(configs, {config: modes}) of the sweep, checked."""
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
    configs = [(s, n, t) for s in scenes for n in views for t in a.tiles.split(",")]
    return configs, {c: [m for m in modes if hybrid_k(m) is None or hybrid_k(m) < c[1]] for c in configs}


def progress(r, what, started):
    if "error" in r:
        print(f"{what} FAILED ({r['error']})", file=sys.stderr)
        return
    ps = f", PSNR {r['psnr_mean']:.1f}/{r['psnr_worst']:.1f} dB" if "psnr_mean" in r else ""
    cs = f", {r['draws']:.0f} draws submitted" if "draws" in r else ""
    cs += f", {r['fragments'] / 1e6:.2f} M fragments" if "fragments" in r else ""
    print(f"{what} {r['ms']:.0f} ms{ps}{cs}  ({time.time() - started:.0f} s)", file=sys.stderr)


def timed_rounds(configs, cell_modes, a, display):
    """{(scene, n, tile, mode): [run dicts]} of ROUNDS alternating rounds."""
    total = a.rounds * sum(len(v) for v in cell_modes.values())
    results, started, done = {}, time.time(), 0
    for rnd in range(a.rounds):
        for c in configs:
            ms = cell_modes[c]
            ms = ms[rnd % len(ms):] + ms[:rnd % len(ms)]  # rotate the order every round
            for mode in ms:
                done += 1
                scene, n, tile = c
                r = run_once(scene, mode, n, tile, a, display)
                results.setdefault((*c, mode), []).append(r)
                progress(r, f"[{done}/{total}] {c[0]} {mode} {quilt_of(c[1])} {c[2]}:", started)
    return results


def main():
    a = arguments()
    if a.replot:
        os.makedirs(a.out, exist_ok=True)
        plot(a.out, rows_of_table(a.replot))
        return
    for f in ["holoinject", "libholoinject.so"]:
        if not os.path.exists(os.path.join(a.bin, f)):
            sys.exit(f"bench-trade: {a.bin}/{f} missing: build first (cargo build --workspace --release) or pass --bin")
    configs, cell_modes = cells(a)
    a.counts_arg = counts_option(a)
    a.quilt_metrics = a.quilt_metrics and quilt_metrics_available()
    a.flip = flip_or_none() if a.quilt_metrics else None
    display, started, quilts = Display(), time.time(), {}
    try:
        results = timed_rounds(configs, cell_modes, a, display)
        if a.quilt_metrics:
            quilts = quilt_phase(configs, cell_modes, results, a, display)
    finally:
        display.stop()
    rows = summarise(configs, cell_modes, results, quilts)
    os.makedirs(a.out, exist_ok=True)
    write_table(a, rows, time.time() - started, quilt_frame(a))
    plot(a.out, rows)


if __name__ == "__main__":
    main()
