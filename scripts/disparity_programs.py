"""The programs scripts/disparity-agreement.py measures, and how one is run under the layer.

Sample apps run on headless OSMesa with `--frames F`: frame F is one moment of their scene on
any machine. Real programs animate by the wall clock: each is recorded once with `apitrace
trace` (on the caller's X server or an Xvfb of our own) and replayed by glretrace/eglretrace
under the layer, so every mode sees the same frames. f3d shows a static model: it runs directly
with a VTK interaction log that renders one frame per event.
"""
import math, os, re, shutil, signal, subprocess, sys, time

XS = "/usr/libexec/xscreensaver"

# name -> spec. kind app: a sample app (argv[0] in --apps) on OSMesa, window = one tile.
# kind trace: recorded with `apitrace trace --api API` (argv; {W}, {H}, {n} filled in) for at
# most `seconds`, replayed by `retrace`. kind f3d: run directly with a VTK event log.
PROGRAMS = {}


def _app(name, argv, frame=10):
    PROGRAMS[name] = {"kind": "app", "argv": argv, "frame": frame}


def _trace(name, argv, frame, seconds, api="gl", note=""):
    PROGRAMS[name] = {"kind": "trace", "argv": argv, "frame": frame, "seconds": seconds, "api": api,
                      "retrace": "eglretrace" if api == "egl" else "glretrace", "note": note}


for _a in ["cubes", "asteroids", "model", "legacy"]:
    _app(_a, [_a])
_app("legacy-sky", ["legacy", "--sky"])
for _a in ["skybox", "bloom", "deferred", "framebuffers", "ssao", "shadowmap", "compat120", "msaa", "lines"]:
    _app(_a, [_a])
_GLMARK2 = {  # scene options, frame looked at
    "build": ("build:use-vbo=true", 12),
    "texture": ("texture", 60),
    "shading": ("shading:shading=phong", 12),
    "bump": ("bump:bump-render=normals", 12),
    "refract": ("refract", 12),
    "terrain": ("terrain", 6),
    "jellyfish": ("jellyfish", 30),
    "shadow": ("shadow", 12),
    "desktop": ("desktop", 8),
}
for _s, (_b, _f) in _GLMARK2.items():
    _trace(f"glmark2-{_s}", ["glmark2", "-s", "{W}x{H}", "-b", _b + ":nframes={n}"], _f, 120)
# ideas lights its scene up along its wall-clock duration (speed=duration): recorded for 1.5 s
# of its own time and seen a quarter of the way through (the lit table, the lamp).
_trace("glmark2-ideas", ["glmark2", "-s", "{W}x{H}", "-b", "ideas:duration=1.5"], 0.25, 120)
_trace("glxgears", ["glxgears", "-geometry", "{W}x{H}"], 30, 3)
_trace("es2gears", ["es2gears_x11"], 30, 3, api="egl", note="its own 300x300 window")
_trace("chromium-bsu", ["/usr/games/chromium-bsu", "-w", "-v", "0", "-na"], 60, 6, note="512x384 window; its menu (nothing plays the game in the recording)")
# OpenArena (ioquake3's opengl2 renderer): the first-person weapon is drawn inside
# glDepthRange(0, 0.3), id Tech 3's depth hack (tests/integration/real_programs/weapon.rs).
# Its own settings in a fresh HOME (~/.openarena), no sound, no 2D HUD; the game quits itself
# 80 frames after loading oa_dm1 (66 frames in all, the map on screen from frame 31).
_OA = {"cl_renderer": "opengl2", "r_mode": "-1", "r_customwidth": "{W}", "r_customheight": "{H}",
       "r_fullscreen": "0", "s_initsound": "0", "com_introplayed": "1", "sv_pure": "0", "cg_draw2D": "0",
       "con_notifytime": "0"}
_trace("openarena", ["sh", "-c", 'HOME=$(mktemp -d) exec /usr/games/openarena "$@"', "openarena",
                     *[x for k, v in _OA.items() for x in ("+set", k, v)], "+devmap", "oa_dm1", "+wait", "80", "+quit"],
       56, 60, note="the weapon is drawn inside glDepthRange(0, 0.3); HUD off")
# Neverball (SDL2, fixed-function GL): a level's floor and walls run off every side of the
# window, what the guard band is for (scripts/guard-band.py). Its settings in a fresh HOME, no
# sound; the level loads and the camera flies in (frames 20 on: the floor under the ball).
_NB_RC = "fullscreen 0\nwidth {W}\nheight {H}\nsound_volume 0\nmusic_volume 0\n"
_trace("neverball", ["sh", "-c", 'export HOME=$(mktemp -d); mkdir -p "$HOME/.neverball"; printf "' + _NB_RC
                     + '" > "$HOME/.neverball/neverballrc"; exec /usr/games/neverball "$@"', "neverball",
                     "-l", "map-easy/coins.sol"], 60, 8, note="level map-easy/coins, as it loads")
for _h, _f in [("engine", 20), ("moebiusgears", 30), ("topblock", 10), ("pipes", 60)]:
    # xscreensaver 6 draws through EGL (desktop GL API).
    _trace(f"xss-{_h}", [f"{XS}/{_h}", "-geometry", "{W}x{H}"], _f, 4, api="egl")
PROGRAMS["f3d"] = {"kind": "f3d", "ssao": False, "frame": 10}
PROGRAMS["f3d-ssao"] = {"kind": "f3d", "ssao": True, "frame": 10}
DEFAULT_PROGRAMS = list(PROGRAMS)

SCENE_AT = re.compile(r"auto-convergence: scene at ([0-9.eE+-]+) \(near ([0-9.eE+-]+), far ([0-9.eE+-]+|inf)\) "
                      r"from framebuffer (\d+)")
RENDERED = re.compile(r"synthesis: (\d+) of (\d+) views rendered")
STAYS_EXACT = "every view is rendered exactly"


def parse_frame(text):
    """A frame number (from 1), or P% of a recording's frames (a float)."""
    if text.endswith("%"):
        return float(text[:-1]) / 100.0
    return int(text)


def frame_text(frame):
    return f"{frame * 100:g}%" if isinstance(frame, float) else str(frame)


def log(msg):
    print(f"disparity-agreement: {msg}", file=sys.stderr, flush=True)


class Display:
    """DISPLAY for programs with windows: the caller's, or an Xvfb of our own (stopped at exit)."""

    def __init__(self):
        self.proc = None
        self.display = os.environ.get("DISPLAY")

    def get(self):
        if self.display:
            return self.display
        if not shutil.which("Xvfb"):
            raise RuntimeError("no DISPLAY and no Xvfb (apt-get install xvfb)")
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
        log(f"started Xvfb on {self.display} (pid {self.proc.pid})")
        return self.display

    def stop(self):
        if self.proc:
            self.proc.terminate()
            try:
                self.proc.wait(5)
            except subprocess.TimeoutExpired:
                self.proc.kill()


def frames_in(trace, retrace, display):
    p = subprocess.run(["timeout", "-k", "5", "300", retrace, "-b", trace], capture_output=True, text=True,
                       env={**os.environ, "DISPLAY": display})
    m = re.search(r"Rendered (\d+) frames", p.stdout + p.stderr)
    return int(m.group(1)) if m else -1


def record(name, spec, frame, a, display):
    """(trace, frames it holds, seconds spent recording) of real program `name` at this tile
    size, recorded into --cache the first time. `frame` is a frame number or a fraction of the
    recording (for scenes whose story is spread over their wall-clock duration)."""
    w, h = a.tile.split("x")
    fixed = any("{n}" in x for x in spec["argv"])
    if fixed and isinstance(frame, float):
        raise RuntimeError(f"{name} runs a fixed number of frames: give a frame number, not a fraction")
    need = frame if isinstance(frame, int) else 4
    n = need + 10
    trace = os.path.join(a.cache, f"agree-{name}-{a.tile}" + (f"-{n}" if fixed else "") + ".trace")
    got = cached_frames(trace, spec, display)
    if got >= need:
        return trace, got, 0.0
    argv = [x.replace("{W}", w).replace("{H}", h).replace("{n}", str(n)) for x in spec["argv"]]
    for tool in (argv[0], "apitrace"):
        if not shutil.which(tool):
            raise RuntimeError(f"{tool} is not installed")
    os.makedirs(a.cache, exist_ok=True)
    t0 = time.time()
    got = record_until(name, spec, argv, trace + ".part", need, display)
    os.replace(trace + ".part", trace)
    with open(trace + ".frames", "w") as f:
        f.write(str(got))
    return trace, got, time.time() - t0


def cached_frames(trace, spec, display):
    """Frames in a recording already made (-1: none), counted once and kept beside it."""
    if not os.path.exists(trace) or os.path.getsize(trace) <= 1000:
        return -1
    try:
        with open(trace + ".frames") as f:
            return int(f.read())
    except (OSError, ValueError):
        got = frames_in(trace, spec["retrace"], display)
        with open(trace + ".frames", "w") as f:
            f.write(str(got))
        return got


def record_until(name, spec, argv, tmp, need, display):
    """Records `argv` into `tmp` until it holds `need` frames: a program that runs until killed
    gets `seconds`, then four times as long (a loaded machine spends the time starting it).
    timeout signals the group; apitrace's handler has been seen to hang, hence the KILL 5 s later."""
    got = -1
    for limit in (spec["seconds"], spec["seconds"] * 4):
        log(f"recording {name} for at most {limit} s: {' '.join(argv)}")
        subprocess.run(["timeout", "-k", "5", str(limit), "apitrace", "trace", "--api", spec["api"], "-o", tmp, *argv],
                       env={**os.environ, "DISPLAY": display, "ALSOFT_DRIVERS": "null"},
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, stdin=subprocess.DEVNULL)
        if not os.path.exists(tmp) or os.path.getsize(tmp) < 1000:
            continue
        got = frames_in(tmp, spec["retrace"], display)
        log(f"{name}: {got} frames recorded")
        if got >= need:
            return got
    if got < 0:
        raise RuntimeError("apitrace recorded nothing")
    raise RuntimeError(f"the recording holds {got} < {need} frames")


OBJ_BOXES = [  # centre x, y, z, half size: boxes at different depths in front of and behind z = 0
    (-2.4, 0.0, -3.0, 0.6), (-1.2, -0.4, 0.5, 0.4), (0.0, 0.2, -1.5, 0.7), (1.3, -0.3, 1.2, 0.35),
    (2.5, 0.3, -2.2, 0.5), (-0.6, 0.9, 1.8, 0.3), (0.8, 1.0, -0.5, 0.4), (-1.8, -1.0, -1.0, 0.5),
    (1.9, -1.0, 0.0, 0.45), (0.1, -1.1, 2.2, 0.3),
]


def write_f3d_inputs(work, frames, w, h):
    """A small OBJ (ten boxes at different depths, each turned a little so their faces shade
    differently) and a VTK interaction log: the left button held while the mouse wiggles by a
    pixel, one rendered frame per event (the model barely turns)."""
    obj = os.path.join(work, "boxes.obj")
    events = os.path.join(work, "wiggle.log")
    lines, base = [], 0
    for k, (cx, cy, cz, s) in enumerate(OBJ_BOXES):
        a = 0.3 + 0.25 * k
        ca, sa = math.cos(a), math.sin(a)
        for i in range(8):
            dx, dy, dz = ((i >> 2) * 2 - 1) * s, (((i >> 1) & 1) * 2 - 1) * s, ((i & 1) * 2 - 1) * s
            lines.append(f"v {cx + ca * dx + sa * dz:.4f} {cy + dy:.4f} {cz - sa * dx + ca * dz:.4f}")
        for f in [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]:
            lines.append("f " + " ".join(str(base + i + 1) for i in f))
        base += 8
    with open(obj, "w") as f:
        f.write("\n".join(lines) + "\n")
    cx, cy = w // 2, h // 2
    ev = ["# StreamVersion 1.1", f"LeftButtonPressEvent {cx} {cy} 0 0 0 0 0"]
    ev += [f"MouseMoveEvent {cx - 1 + 2 * (i % 2)} {cy} 0 0 0 0 0" for i in range(frames)]
    ev.append(f"LeftButtonReleaseEvent {cx} {cy} 0 0 0 0 0")
    with open(events, "w") as f:
        f.write("\n".join(ev) + "\n")
    return obj, events


def command(name, spec, frame, a, display, work):
    """(argv, env, seconds spent recording, frame number) of program `name`."""
    w, h = a.tile.split("x")
    if isinstance(frame, float) and spec["kind"] != "trace":
        raise RuntimeError("only recordings take a frame as a fraction")
    if spec["kind"] == "app":
        exe = os.path.join(a.apps, spec["argv"][0])
        if not os.path.exists(exe):
            raise RuntimeError(f"{exe} missing")
        return [exe, *spec["argv"][1:], "--backend", "osmesa", "--size", a.tile, "--frames", str(frame)], {}, 0.0, frame
    d = display.get()
    if spec["kind"] == "trace":
        trace, count, spent = record(name, spec, frame, a, d)
        if isinstance(frame, float):
            frame = max(1, min(count, round(frame * count)))
        return [spec["retrace"], trace], {"DISPLAY": d}, spent, frame
    if spec["kind"] == "f3d":
        if not shutil.which("f3d"):
            raise RuntimeError("f3d is not installed")
        obj, events = write_f3d_inputs(work, frame + 10, int(w), int(h))
        argv = ["f3d", "--grid", "--resolution", f"{w},{h}", f"--interaction-test-play={events}", obj]
        if spec["ssao"]:
            argv.insert(1, "--ssao")
        return argv, {"DISPLAY": d}, 0.0, frame
    raise RuntimeError(f"unknown kind {spec['kind']}")


def run_layer(a, prog, env, mode, convergence, frame, dump, extra=()):
    """One run under the layer (`extra`: more of its options); returns {'quilt', 'stderr',
    'scene_at', 'rendered', ...} or {'error'}."""
    cmd = [os.path.join(a.layer, "holoinject"), "run", "--preset", "none", "--log", "info", "--output", "quilt",
           "--quilt", a.quilt, "--tile", a.tile, "--mode", mode, "--convergence", convergence,
           *(["--depthiness", a.depthiness] if a.depthiness else []), *extra,
           "--dump", dump, "--dump-frames", str(frame), "--exit-after", str(frame), "--", *prog]
    t0 = time.time()
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, stdin=subprocess.DEVNULL, text=True,
                         env={**os.environ, "ALSOFT_DRIVERS": "null", **env}, start_new_session=True)
    try:
        _, err = p.communicate(timeout=a.timeout)
    except subprocess.TimeoutExpired:
        # The launcher exec'd into the program, which leads its own session: end that group.
        os.killpg(p.pid, signal.SIGKILL)
        p.communicate()
        return {"error": f"{mode}: timed out after {a.timeout} s", "cmd": cmd}
    r = {"cmd": cmd, "stderr": err, "seconds": time.time() - t0}
    quilts = [f for f in os.listdir(dump) if f.startswith(f"f{frame:06}_qs")] if os.path.isdir(dump) else []
    if not quilts:
        tail = [l for l in err.splitlines() if "error" in l.lower() or "panic" in l.lower()][-2:]
        r["error"] = f"{mode}: status {p.returncode}, no quilt of frame {frame}" + (f" ({' | '.join(tail)})" if tail else "")
        return r
    r["quilt"] = os.path.join(dump, quilts[0])
    found = SCENE_AT.findall(err)
    if found:
        r["scene_at"] = float(found[-1][0])
        r["scene_fbo"] = int(found[-1][3])
    m = RENDERED.search(err)
    if m:
        r["rendered"] = (int(m.group(1)), int(m.group(2)))
    r["stays_exact"] = STAYS_EXACT in err
    r["warnings"] = [l for l in err.splitlines() if l.startswith("holoinject: warn") or l.startswith("holoinject: error")]
    return r
