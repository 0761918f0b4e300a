#!/usr/bin/python3
"""`--fbo-scale window` against `tile` (the default since 1e0b054, issue 24), measured against
the truth: a view shown in a WxH tile should be what the program itself draws at WxH.

Quality: each program at 800x600 under the layer as a 3x3 quilt of 256x192 tiles, per scale;
the centre view (view 4) of frame F against the program run plainly at 256x192, frame F: PSNR
(RGB; "identical" when bit-equal) and FLIP (flip_evaluator, LDR, mean). Sample apps animate by
frame (F = 3; `--screenshot` is the truth). glmark2 animates by the wall clock, so each scene
is recorded with apitrace under the tests' steady clock (tests/integration/real_programs/
steady_clock.c) at 800x600 and at 256x192, frame F = 12 of both being one moment; the truth is
`glretrace -s` of the small trace, the layer replays the large one. Traces are cached in
~/.cache/holoinject/traces (fbo-truth-*).
Frame time: each program at 800x600 as a 5x9 quilt of 256x256 tiles, `--exit-after 30`, the
layer's `frame time: median X ms` line; runs alternate window, tile, window, ... (--rounds each).
Fall-backs: the `tile` runs' `framebuffer N: layers at the program's size (REASON)` lines, by
cause; `framebuffers --texel-fetch` (a texelFetch fall-back) is measured for quality too.

    scripts/fbo-scale-truth.py [--rounds 3] [--programs bloom,glmark2-terrain] [--no-timing]

Nothing is built (binaries from $CARGO_TARGET_DIR/release, else target/release); glmark2 needs
$DISPLAY. Writes scripts/results/fbo-scale-truth.md (--out) and prints it.
"""
import argparse, datetime, glob, os, platform, re, shlex, statistics, subprocess, sys, tempfile, time

sys.dont_write_bytecode = True
from disparity_blocks import load_tiles, psnr
from trade_quilts import flip_module, flip_of

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.path.join(os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target")), "release")
CACHE = os.path.expanduser("~/.cache/holoinject/traces")
CLOCK_SRC = os.path.join(ROOT, "tests/integration/real_programs/steady_clock.c")
# Runs the rest with $0 appended to LD_PRELOAD: apitrace sets LD_PRELOAD for what it starts.
PRELOAD_TOO = 'LD_PRELOAD="$LD_PRELOAD:$0" exec "$@"'
WINDOW, TILE = "800x600", "256x192"
TIMED_QUILT, TIMED_TILE, TIMED_FRAMES = "5x9", "256x256", 30
SAMPLE_FRAME, GLMARK2_FRAME, TRACE_FRAMES = 3, 12, 36
SAMPLE_APPS = ["framebuffers", "bloom", "deferred", "ssao"]
# glmark2 scenes whose passes go through framebuffers sized from the window: terrain (its scene
# and tilt-shift blur at the window's size) and refract (a distance map at twice the window's).
GLMARK2 = {"glmark2-terrain": "terrain", "glmark2-refract": "refract"}
TEXEL_FETCH = "framebuffers --texel-fetch"
FRAME_TIME = re.compile(r"frame time: median ([0-9.]+) ms over (\d+) frames")
FALLBACK = re.compile(r"framebuffer (\d+): layers at the program's size \((.*)\)$")


def sh(argv, limit=3600):
    """Runs argv; returns its stderr (+ stdout). Fails loudly: a number from a failed run is no number."""
    p = subprocess.run(["timeout", "-k", "5", str(limit), *argv], capture_output=True, text=True,
                       env={**os.environ, "ALSOFT_DRIVERS": "null"}, stdin=subprocess.DEVNULL)
    if p.returncode != 0:
        raise RuntimeError(f"{shlex.join(argv)} exited {p.returncode}:\n{p.stderr[-3000:]}")
    return p.stderr + p.stdout


def steady_clock(work):
    lib = os.path.join(work, "steady_clock.so")
    sh(["cc", "-shared", "-fPIC", "-O2", "-o", lib, CLOCK_SRC, "-ldl"])
    return lib


def frames_in(trace):
    out = subprocess.run(["apitrace", "info", trace], capture_output=True, text=True).stdout
    m = re.search(r'"FramesCount":\s*(\d+)', out)
    return int(m.group(1)) if m else 0


def record(scene, size, clock):
    """The steady-clock trace of glmark2 `scene` at `size`, recorded into the cache once. A loaded
    machine can spend a short recording starting: then four times as long."""
    trace = os.path.join(CACHE, f"fbo-truth-{scene}-{size}-{TRACE_FRAMES}.trace")
    if os.path.exists(trace) and frames_in(trace) >= TRACE_FRAMES:
        return trace
    os.makedirs(CACHE, exist_ok=True)
    prog = ["glmark2", "-s", size, "-b", f"{scene}:nframes={TRACE_FRAMES}"]
    for limit in (120, 480):
        log(f"recording {shlex.join(prog)} under the steady clock (at most {limit} s)")
        subprocess.run(["timeout", "-k", "5", str(limit), "apitrace", "trace", "--api", "gl", "-o", trace + ".part",
                        "sh", "-c", PRELOAD_TOO, clock, *prog], capture_output=True, stdin=subprocess.DEVNULL)
        if frames_in(trace + ".part") >= TRACE_FRAMES:
            os.replace(trace + ".part", trace)
            return trace
    raise RuntimeError(f"apitrace recorded {frames_in(trace + '.part')} < {TRACE_FRAMES} frames of {scene} at {size}")


class Program:
    """One program of the measurement: how to run it at a size, and its truth at the tile's size."""

    def __init__(self, name, clock):
        self.name, self.clock = name, clock
        self.app, *self.extra = name.split()
        self.frame = GLMARK2_FRAME if self.app in GLMARK2 else SAMPLE_FRAME
        self.traces = {}

    def trace(self, size):
        if size not in self.traces:
            self.traces[size] = record(GLMARK2[self.app], size, self.clock)
        return self.traces[size]

    def argv(self, size, frames):
        if self.app in GLMARK2:
            return ["glretrace", self.trace(size)]
        return [os.path.join(BIN, self.app), "--backend", "osmesa", "--size", size, "--frames", str(frames),
                *self.extra]

    def truth(self, work):
        png = os.path.join(work, f"{self.slug()}-truth.png")
        if self.app in GLMARK2:
            snaps = os.path.join(work, f"{self.slug()}-plain") + "/"
            os.makedirs(snaps, exist_ok=True)
            sh(["glretrace", "--call-nos=false", "-s", snaps, self.trace(TILE)])
            os.replace(f"{snaps}{self.frame - 1:010}.png", png)
        else:
            sh([*self.argv(TILE, self.frame), "--screenshot", png])
        return png

    def slug(self):
        return self.name.replace(" --", "-")


def under_layer(options, argv):
    cmd = [os.path.join(BIN, "holoinject"), "run", "--preset", "none", "--log", "info", *options, "--", *argv]
    return sh(cmd)


def quality_options(scale, dump, frame):
    return ["--output", "quilt", "--quilt", "3x3", "--tile", TILE, "--fbo-scale", scale,
            "--dump", dump, "--dump-frames", str(frame), "--exit-after", str(frame)]


def timed_options(scale):
    return ["--output", "quilt", "--quilt", TIMED_QUILT, "--tile", TIMED_TILE, "--fbo-scale", scale,
            "--exit-after", str(TIMED_FRAMES)]


def centre_metrics(truth_png, quilt_png, flip):
    """(PSNR, FLIP) of the 3x3 quilt's centre view against the truth; PSNR None when bit-equal
    (disparity_blocks.psnr caps at 100 dB, which one differing level already reaches)."""
    truth = load_tiles(truth_png, 1, 1)[0]
    centre = load_tiles(quilt_png, 3, 3)[4]
    same = truth.shape == centre.shape and (truth == centre).all()
    return (None if same else psnr(truth, centre)), (flip_of(flip, truth, centre) if flip else None)


def quality(prog, scales, work, flip, logs):
    truth = prog.truth(work)
    row = {}
    for scale in scales:
        dump = os.path.join(work, f"{prog.slug()}-{scale}")
        logs.append((prog.name, scale, under_layer(quality_options(scale, dump, prog.frame), prog.argv(WINDOW, 3))))
        (quilt,) = glob.glob(os.path.join(dump, f"f{prog.frame:06}_qs3x3a*.png"))
        row[scale] = centre_metrics(truth, quilt, flip)
        log(f"{prog.name} {scale}: centre PSNR {fmt_db(row[scale][0])} dB, FLIP {fmt_flip(row[scale][1])}")
    return row


def timing(prog, rounds, logs):
    """{scale: [per-run median ms]}, runs alternating window, tile, window, ..."""
    times = {"window": [], "tile": []}
    for r in range(rounds):
        for scale in times:
            t0 = time.time()
            out = under_layer(timed_options(scale), prog.argv(WINDOW, TIMED_FRAMES + 10))
            logs.append((prog.name, scale, out))
            times[scale].append(float(FRAME_TIME.search(out).group(1)))
            log(f"{prog.name} {scale} round {r + 1}: {times[scale][-1]:.0f} ms/frame ({time.time() - t0:.0f} s)")
    return times


def fallbacks(logs):
    """{cause: {(program, framebuffer, reason)}} from the `tile` runs' logs."""
    found = {}
    for name, scale, out in logs:
        for line in out.splitlines() if scale == "tile" else []:
            m = FALLBACK.search(line)
            if m:
                reason = m.group(2)
                cause = "a size of its own" if reason.endswith("a size of its own") else reason.split(" reads ")[-1]
                found.setdefault(cause, set()).add((name, int(m.group(1)), reason))
    return found


def fmt_db(v):
    return "identical" if v is None else f"{v:.2f}"


def fmt_flip(v):
    return "n/a" if v is None else f"{v:.4f}"


def quality_table(rows):
    cmd = shlex.join(["holoinject", "run", "--preset", "none", "--log", "info",
                      *quality_options("SCALE", "DIR", "F"), "--", "PROGRAM@800x600"])
    out = ["## Centre view against the program at 256x192", "", f"`{cmd}`", "",
           "Truth: sample apps `APP --backend osmesa --size 256x192 --frames 3 --screenshot T.png` (F = 3); "
           f"glmark2 `glretrace -s DIR/ fbo-truth-SCENE-256x192-{TRACE_FRAMES}.trace`, frame {GLMARK2_FRAME} "
           f"(the layer replays fbo-truth-SCENE-800x600-{TRACE_FRAMES}.trace). PSNR in dB (RGB), FLIP mean "
           "(LDR; 0 = same).", "",
           "| program | window PSNR | tile PSNR | window FLIP | tile FLIP |", "|---|---|---|---|---|"]
    for name, row in rows.items():
        (wp, wf), (tp, tf) = row["window"], row["tile"]
        out.append(f"| {name} | {fmt_db(wp)} | {fmt_db(tp)} | {fmt_flip(wf)} | {fmt_flip(tf)} |")
    return out


def timing_table(times):
    cmd = shlex.join(["holoinject", "run", "--preset", "none", "--log", "info", *timed_options("SCALE"),
                      "--", "PROGRAM@800x600"])
    out = ["## Frame time, 5x9 quilt of 256x256 tiles, window 800x600", "", f"`{cmd}`", "",
           "Sample apps with `--frames 40`; glmark2 replays its 800x600 trace. Median of the runs' medians "
           "(frames 11-30 of each run); runs alternate window, tile, window, ...", "",
           "| program | window ms (runs) | tile ms (runs) | window / tile |", "|---|---|---|---|"]
    for name, t in times.items():
        w, s = statistics.median(t["window"]), statistics.median(t["tile"])
        runs = lambda v: ", ".join(f"{x:.0f}" for x in v)
        out.append(f"| {name} | {w:.0f} ({runs(t['window'])}) | {s:.0f} ({runs(t['tile'])}) | {w / s:.2f} |")
    return out


def fallback_table(found):
    out = ["## Fall-backs to the program's size under `tile`", "",
           "From the `--log info` lines `framebuffer N: layers at the program's size (REASON)` of every "
           "`tile` run above (3x3 of 256x192 and 5x9 of 256x256).", "",
           "| cause | program: framebuffer (reason) |", "|---|---|"]
    for cause, hits in sorted(found.items()):
        cells = "; ".join(f"{p}: {fbo} ({reason})" for p, fbo, reason in sorted(hits))
        out.append(f"| {cause} | {cells} |")
    return out if found else out + ["| (none) | |"]


def machine():
    renderer = re.search(r"OpenGL renderer string: (.*)", sh(["glxinfo", "-B"]))
    cpu = re.search(r"model name\s*: (.*)", open("/proc/cpuinfo").read())
    rev = subprocess.run(["git", "-C", ROOT, "describe", "--always", "--dirty"], capture_output=True, text=True)
    return [f"Date: {datetime.datetime.now():%Y-%m-%d %H:%M}; git {rev.stdout.strip()}; "
            f"{platform.platform()}; {cpu.group(1) if cpu else '?'}, {os.cpu_count()} cores; "
            f"{renderer.group(1) if renderer else '?'}; load average at start {os.getloadavg()[0]:.1f}."]


def log(msg):
    print(f"fbo-scale-truth: {msg}", file=sys.stderr, flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rounds", type=int, default=3, help="timed runs of each scale per program")
    ap.add_argument("--programs", default=",".join(SAMPLE_APPS + list(GLMARK2)))
    ap.add_argument("--no-timing", action="store_true")
    ap.add_argument("--out", default=os.path.join(ROOT, "scripts/results/fbo-scale-truth.md"))
    a = ap.parse_args()
    head = machine()
    t0, flip = time.time(), flip_module()
    with tempfile.TemporaryDirectory(prefix="fbo-truth-") as work:
        clock, logs = steady_clock(work), []
        progs = [Program(n, clock) for n in a.programs.split(",")]
        rows = {p.name: quality(p, ["window", "tile"], work, flip, logs) for p in progs}
        if "framebuffers" in a.programs.split(","):
            rows[TEXEL_FETCH] = quality(Program(TEXEL_FETCH, clock), ["window", "tile"], work, flip, logs)
        times = {} if a.no_timing else {p.name: timing(p, a.rounds, logs) for p in progs}
    lines = ["# `--fbo-scale window` and `tile` against the program at tile size", "",
             "Made by `scripts/fbo-scale-truth.py " + shlex.join(sys.argv[1:]) + "`.", "", *head, ""]
    lines += quality_table(rows) + [""] + (timing_table(times) + [""] if times else [])
    lines += fallback_table(fallbacks(logs)) + ["", f"Wall time {time.time() - t0:.0f} s; load average at "
                                                    f"the end {os.getloadavg()[0]:.1f}."]
    os.makedirs(os.path.dirname(a.out), exist_ok=True)
    with open(a.out, "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
