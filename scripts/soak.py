#!/usr/bin/python3
"""Soak run: does anything pile up over a long run under the layer?

Replays an apitrace of a multi-pass glmark2 scene (`terrain`: a chain of FBOs with mipmaps,
the scene in its own FBO, a blur, a composite; or `refract`) under the layer at a 3x3 quilt
for FRAMES frames, glretrace looping over the trace's last frame (`--loop`). Every 100
frames the layer logs how many GL objects of its own are alive (`hook::census`); at that
moment the script reads the replay's resident memory (VmRSS in /proc/PID/status; llvmpipe
keeps textures in process memory, so a leaked image shows there too).

Prints a Markdown table (frame, RSS MiB, layer GL objects) on stdout and fails (status 1)
if, after warm-up (frame WARM_UP to the last), RSS grows by more than RSS_GROWTH percent or
the object count grows at all.

The trace is recorded on first use (glmark2 at SIZE for a few seconds), and cut after its
last swap: glmark2's teardown follows it, and looping over teardown calls would replay
deletions instead of a frame.

    scripts/soak.py [--scene terrain|refract] [--frames 2000] [--size 200x150]
                    [--warm-up 500] [--rss-growth 5] [--trace PATH] [--out FILE]

Needs an X display (re-runs itself under xvfb-run when there is none), apitrace, glretrace,
glmark2, and the built launcher (`$CARGO_TARGET_DIR` or `target`, release profile).
"""
import argparse, os, re, shutil, subprocess, sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TARGET = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
LAUNCHER = os.path.join(TARGET, "release", "holoinject")
CENSUS = re.compile(r"layer GL objects at frame (\d+): (.*), total (\d+)")
SCENES = {"terrain": "terrain:duration=3", "refract": "refract:duration=2"}


def fail(msg):
    sys.exit(f"soak: {msg}")


def record(trace, scene, size):
    """glmark2's scene recorded, then cut after its last swap."""
    os.makedirs(os.path.dirname(trace), exist_ok=True)
    raw = trace + ".raw"
    # apitrace's signal handler in the traced program has been seen to hang under load.
    cmd = ["timeout", "-k", "5", "90", "apitrace", "trace", "--api", "gl", "-o", raw,
           "glmark2", "-s", size, "-b", SCENES[scene]]
    subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    if not os.path.exists(raw) or os.path.getsize(raw) < 1000:
        fail(f"apitrace recorded nothing: {' '.join(cmd)}")
    dump = subprocess.run(["apitrace", "dump", raw], capture_output=True, text=True).stdout
    swaps = [int(m.group(1)) for m in re.finditer(r"^(\d+) glXSwapBuffers", dump, re.M)]
    if not swaps:
        fail(f"no swap in {raw}")
    subprocess.run(["apitrace", "trim", f"--calls=0-{swaps[-1]}", "-o", trace, raw],
                   check=True, stdout=subprocess.DEVNULL)
    os.remove(raw)


def rss_mib(pid):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
    fail(f"no VmRSS for pid {pid}")


def soak(trace, frames, quilt):
    """(frame, RSS MiB, objects, breakdown) every 100 frames, and the layer's warnings."""
    cmd = [LAUNCHER, "run", "--quilt", quilt, "--log", "info", "--exit-after", str(frames),
           "--", "glretrace", f"--loop={frames}", trace]
    # The launcher execs the program: its pid is the replay's.
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    samples, complaints = [], []
    for line in p.stderr:
        m = CENSUS.search(line)
        if m:
            samples.append((int(m.group(1)), rss_mib(p.pid), int(m.group(3)), m.group(2)))
            print(f"soak: frame {samples[-1][0]}: {samples[-1][1]:.1f} MiB, {samples[-1][2]} objects",
                  file=sys.stderr, flush=True)
        elif "holoinject: error" in line or "holoinject: warn" in line:
            complaints.append(line.rstrip())
    if p.wait() != 0:
        fail(f"the replay failed (status {p.returncode}): {' '.join(cmd)}")
    if not samples or samples[-1][0] != frames:
        fail(f"the layer's census stopped at frame {samples[-1][0] if samples else 0} of {frames}")
    return samples, complaints


def table(samples, scene, size, quilt):
    rows = [f"Soak: glmark2 `{scene}` at {size}, {quilt} quilt, glretrace looping its last frame.",
            "",
            "| frame | RSS MiB | layer GL objects | textures, renderbuffers, framebuffers, programs, vertex arrays, display lists |",
            "|---:|---:|---:|---|"]
    for frame, rss, total, detail in samples:
        counts = ", ".join(re.findall(r"\d+", detail.split("(")[0]))
        rows.append(f"| {frame} | {rss:.1f} | {total} | {counts} |")
    return "\n".join(rows)


def verdict(samples, warm_up, rss_limit):
    after = [s for s in samples if s[0] >= warm_up]
    if len(after) < 2:
        fail(f"too few samples after frame {warm_up}")
    base, last = after[0], after[-1]
    growth = (last[1] - base[1]) / base[1] * 100
    most = max(s[2] for s in after)
    problems = []
    if growth > rss_limit:
        problems.append(f"RSS grew {growth:.1f}% from frame {base[0]} to {last[0]} (limit {rss_limit}%)")
    if most > base[2]:
        problems.append(f"layer GL objects grew from {base[2]} at frame {base[0]} to {most}")
    summary = (f"frames {base[0]}-{last[0]}: RSS {base[1]:.1f} -> {last[1]:.1f} MiB ({growth:+.1f}%), "
               f"layer GL objects {base[2]} -> {last[2]} (max {most})")
    return summary, problems


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", choices=sorted(SCENES), default="terrain")
    ap.add_argument("--frames", type=int, default=2000)
    ap.add_argument("--size", default="200x150", help="glmark2 window when recording")
    ap.add_argument("--quilt", default="3x3")
    ap.add_argument("--warm-up", type=int, default=500)
    ap.add_argument("--rss-growth", type=float, default=5.0, help="percent allowed after warm-up")
    ap.add_argument("--trace", help="default: TARGET/soak/glmark2-SCENE-SIZE.trace")
    ap.add_argument("--out", help="also write the table and verdict to this file")
    a = ap.parse_args()
    if a.frames % 100 or a.frames <= a.warm_up:
        fail("--frames must be a multiple of 100 (the layer's census period) beyond --warm-up")
    if not os.environ.get("DISPLAY"):
        xvfb = ["xvfb-run", "-a", "-s", "-screen 0 1280x1024x24 -noreset"]
        os.execvp("xvfb-run", xvfb + [sys.executable, *sys.argv])
    for tool in ["apitrace", "glretrace", "glmark2"]:
        if not shutil.which(tool):
            fail(f"{tool} not found (scripts/setup-debian.sh)")
    if not os.access(LAUNCHER, os.X_OK):
        fail(f"{LAUNCHER} missing: cargo build --workspace --release --locked")
    os.environ["ALSOFT_DRIVERS"] = "null"
    trace = a.trace or os.path.join(TARGET, "soak", f"glmark2-{a.scene}-{a.size}.trace")
    if not os.path.exists(trace):
        record(trace, a.scene, a.size)
    samples, complaints = soak(trace, a.frames, a.quilt)
    summary, problems = verdict(samples, a.warm_up, a.rss_growth)
    report = "\n".join([table(samples, a.scene, a.size, a.quilt), "", summary, *complaints])
    print(report)
    if a.out:
        with open(a.out, "w") as f:
            f.write(report + "\n")
    if problems:
        fail("; ".join(problems))


if __name__ == "__main__":
    main()
