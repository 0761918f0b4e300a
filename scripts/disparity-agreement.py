#!/usr/bin/python3
"""Disparity agreement of `--mode synth` with `--mode exact` (issue 22, DESIGN §6), and the
PSNR of the views `synth` and `hybrid:3` synthesise against exact, over sample apps and real
programs.

Per program the quilt of one frame is dumped under `--mode exact`, `--mode synth` and
`--mode hybrid:3`, same quilt, tile, depthiness and convergence (how programs are run:
scripts/disparity_programs.py). Per program (the definitions: scripts/disparity_blocks.py):
- block agreement: textured 16x16 blocks of the centre view, their horizontal shift in the
  outermost views in exact and in synth; agree % = matched blocks within 2 px in both views,
  median and 95th percentile of |shift_exact - shift_synth|;
- PSNR (dB, per tile) of each view a mode synthesises against exact's: synth all but the
  centre view N/2, hybrid:K all but its K evenly spaced rendered ones; mean and worst;
- whether synth's centre tile is exact's bit for bit.

Convergence (--convergence): `exact-auto` (default) runs exact once with auto-convergence,
takes the estimate it logs at `--log info` ("auto-convergence: scene at C": the layer logs its
first estimate per framebuffer, before smoothing; the last line wins) and passes
`--convergence C` to all three measured runs. When exact logs none (no depth written: the
layer falls back to sqrt(near*far)) all three run with auto. `auto`: all three on auto, each
mode's own logged estimate in the CSV. A number: that, for all.

    scripts/disparity-agreement.py                      # every program, 5x3 quilt, 256x192 tiles
    scripts/disparity-agreement.py --programs cubes,glmark2-jellyfish@30 --keep /tmp/q
    scripts/disparity-agreement.py --layer /path/to/other/build/release --out /tmp/after
    scripts/disparity-agreement.py --recompute /tmp/q --texture 12   # kept quilts, other thresholds

Programs are named as --list shows; NAME@F looks at frame F instead of the default, NAME@P% at P
percent of a recording's frames. A recording pins what frame F shows, but a new recording
(another --cache, another machine) may show another moment of a scene that animates by the
wall clock: compare builds on the same recordings.

Nothing is built: the layer (holoinject + libholoinject.so) comes from --layer, the sample apps
from --apps (default: the --layer directory). Writes OUT/disparity-agreement.md and .csv and
prints the table. Needs python3 with numpy and PIL (Debian python3-numpy, python3-pil),
apitrace, Xvfb when DISPLAY is unset, and the programs.
"""
import argparse, csv, json, math, os, re, shutil, subprocess, sys, tempfile, time

sys.dont_write_bytecode = True  # no __pycache__ beside the scripts for the two modules below
from disparity_blocks import AGREE_PX, DISTINCT, UNIQUE, IDENTICAL_DB, metrics, spaced
from disparity_programs import (PROGRAMS, DEFAULT_PROGRAMS, STAYS_EXACT, Display, command, frame_text, log,
                                parse_frame, run_layer)

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


# ---------------------------------------------------------------------------------- one program

def measure(name, spec, frame, a, display, work):
    """Runs one program in the three modes and measures its quilts: a result dict."""
    r = {"program": name, "frame": frame_text(frame), "notes": []}
    t0 = time.time()
    pdir = os.path.join(work, name)
    os.makedirs(pdir, exist_ok=True)
    try:
        prog, env, r["record_s"], frame = command(name, spec, frame, a, display, pdir)
        if r["frame"].endswith("%"):
            r["notes"].append(f"frame {frame} = {r['frame']} of the recording")
        r["frame"] = str(frame)
        runs = run_modes(r, prog, env, frame, a, pdir)
    except (RuntimeError, OSError) as e:
        r["error"] = str(e)
        r["seconds"] = time.time() - t0
        return r
    if spec.get("note"):
        r["notes"].append(spec["note"])
    note_modes(r, runs, a)
    hk = f"hybrid:{a.hybrid_k}"
    r["quilts"] = {"exact": runs["exact"]["quilt"], "synth": runs["synth"]["quilt"], "hybrid": runs[hk]["quilt"]}
    r["seconds"] = time.time() - t0
    r["notes_run"] = list(r["notes"])
    return evaluate(r, a)


def run_modes(r, prog, env, frame, a, pdir):
    """The runs of one program, by key (exact-auto, exact, synth, hybrid:K), at the
    convergence --convergence asks for (recorded in `r`)."""
    runs = {}

    def go(key, mode, conv):
        d = os.path.join(pdir, key.replace(":", "-"))
        shutil.rmtree(d, ignore_errors=True)
        runs[key] = x = run_layer(a, prog, env, mode, conv, frame, d)
        if "error" in x:
            raise RuntimeError(x["error"])
        return x

    hk = f"hybrid:{a.hybrid_k}"
    c = None
    if a.convergence in ("exact-auto", "auto"):
        probe = go("exact-auto", "exact", "auto")
        c = r["c_exact_auto"] = probe.get("scene_at")
        if a.convergence == "auto" or c is None:
            r["convergence"] = "auto"
            r["c_source"] = "auto in every mode" + ("" if c is not None else " (no estimate logged: no depth seen, fallback sqrt(near*far))")
            runs["exact"] = probe
            r["c_synth_auto"] = go("synth", "synth", "auto").get("scene_at")
            r["c_hybrid_auto"] = go(hk, hk, "auto").get("scene_at")
            return runs
        r["convergence"], r["c_source"] = f"{c:g}", f"exact's auto estimate (framebuffer {probe['scene_fbo']})"
    else:
        r["convergence"], r["c_source"] = a.convergence, "given"
    for key in ("exact", "synth", hk):
        go(key, key, r["convergence"])
    return runs


def note_modes(r, runs, a):
    """What the layer said about the fast modes: stayed exact (and why), no synthesis, warnings."""
    for key in ("synth", f"hybrid:{a.hybrid_k}"):
        x = runs[key]
        if x.get("stays_exact"):
            why = re.search(r"holoinject: warn: (.*every view is rendered exactly[^\n]*)", x["stderr"])
            r["notes"].append(f"{key} stayed exact: {why.group(1) if why else 'the layer says so'}")
            r["stays_exact"] = True
        elif "rendered" not in x:
            r["notes"].append(f"{key}: the layer announced no synthesis (no `synthesis: K of N views rendered` line)")
    warns = sorted({w for x in runs.values() for w in x.get("warnings", []) if STAYS_EXACT not in w})
    if warns:
        r["notes"].append(f"{len(warns)} layer warning(s), e.g. {warns[0][:160]}")


def evaluate(r, a):
    """The metrics of one program's kept quilts, into `r`."""
    cols, rows = (int(x) for x in a.quilt.split("x"))
    q = r["quilts"]
    try:
        r.update(metrics(q["exact"], q["synth"], q["hybrid"], cols, rows, a.texture, a.max_shift, a.hybrid_k))
    except Exception as e:  # a broken PNG, a quilt of another size
        r["error"] = f"metrics: {e}"
        return r
    if not r["centre_identical"]:
        r["notes"].append(f"synth's centre view differs from exact's in {r['centre_diff_pixels']} pixels "
                          f"(up to {r['centre_diff_max']} levels)")
    if r.get("synth_black_views"):
        r["notes"].append(f"synth left {len(r['synth_black_views'])} of its synthesised views black (exact's are not)")
    if r.get("hybrid_black_views"):
        r["notes"].append(f"hybrid:{a.hybrid_k} left {len(r['hybrid_black_views'])} of its synthesised views black")
    if not r["hybrid_rendered_identical"]:
        r["notes"].append(f"hybrid:{a.hybrid_k}'s rendered views are not all identical to exact's")
    return r


SETTINGS = ["quilt", "tile", "hybrid_k", "depthiness", "convergence", "layer"]


def keep_run(a, work, r):
    """What `--recompute` needs of one program, beside its quilts."""
    with open(os.path.join(work, r["program"], "run.json"), "w") as f:
        json.dump({**r, "settings": {k: getattr(a, k) for k in SETTINGS}}, f, indent=1)


def recompute(a):
    """Results of an earlier sweep's kept quilts (--keep DIR), measured again (other thresholds)."""
    results = []
    for name in PROGRAMS:
        path = os.path.join(a.recompute, name, "run.json")
        if not os.path.exists(path):
            continue
        with open(path) as f:
            r = json.load(f)
        for k, v in r.pop("settings").items():
            setattr(a, k, v)
        r["notes"] = list(r.get("notes_run", r.get("notes", [])))
        results.append(evaluate(r, a) if "quilts" in r else r)
    if not results:
        sys.exit(f"disparity-agreement: no */run.json under {a.recompute} (a directory given to --keep)")
    return results


# ---------------------------------------------------------------------------------- output

def f1(x, nd=1):
    return "–" if x is None or (isinstance(x, float) and math.isnan(x)) else f"{x:.{nd}f}"


def psnr_cell(p):
    if not p:
        return "–"
    fmt = lambda v: "∞" if v >= IDENTICAL_DB else f"{v:.1f}"
    return f"{fmt(p[0])} / {fmt(p[1])}"


def table_row(r):
    name = f"{r['program']} @{r['frame']}"
    if "error" in r:
        return f"| {name} | failed: {r['error'][:140]} | | | | | | | |"
    centre = "yes" if r["centre_identical"] else "no"
    if r.get("stays_exact"):
        return f"| {name} † | {r['textured']} ({r['matched']}) | n/a | n/a | n/a | n/a | n/a | {centre} | {r['convergence']} |"
    nf = f" ({r['not_found_in_synth']} not found)" if r["not_found_in_synth"] else ""
    return (f"| {name} | {r['textured']} ({r['matched']}) | {f1(r['agree_pct'])}{nf} | {f1(r['median_d'])} | "
            f"{f1(r['p95_d'])} | {psnr_cell(r['synth_psnr'])} | {psnr_cell(r.get('hybrid_psnr'))} | {centre} | "
            f"{r['convergence']} |")


def header(a, elapsed, recording):
    """The paragraphs above the table: what ran, and what each column means."""
    n = math.prod(int(x) for x in a.quilt.split("x"))
    rev = subprocess.run(["git", "-C", ROOT, "describe", "--always", "--dirty"], capture_output=True, text=True).stdout.strip()
    depth = f"`--depthiness {a.depthiness}`" if a.depthiness else \
        f"default depthiness (4 px between neighbouring views at infinity: s = 4(N-1)/W = {4 * (n - 1) / int(a.tile.split('x')[0]):.4g})"
    conv = {"exact-auto": "`--convergence C` with C the auto-convergence estimate an exact run of the same program "
                          "logs (`auto-convergence: scene at C`, the layer's first estimate per framebuffer, unsmoothed); "
                          "`auto` for all three where exact logs none",
            "auto": "`--convergence auto` in every mode (each mode's logged estimate in the CSV)"}.get(
        a.convergence, f"`--convergence {a.convergence}`")
    took = (f"The whole sweep took {elapsed / 60:.1f} min ({recording / 60:.1f} min of it recording traces not yet cached)."
            if elapsed is not None else f"Measured again from the quilts kept in `{a.recompute}`.")
    k = a.hybrid_k
    return [
        "# Disparity agreement of synth with exact",
        "",
        f"`scripts/disparity-agreement.py` (tree at {rev}, {time.strftime('%Y-%m-%d')}); layer from `{a.layer}`; "
        f"Mesa llvmpipe, {os.cpu_count()} cores shared with other work. Quilt {a.quilt} ({n} views, centre view {n // 2}), "
        f"tiles {a.tile}, `--output quilt --preset none`, {depth}; convergence: {conv}. Sample apps on OSMesa "
        f"(`--backend osmesa --size {a.tile} --frames F`), real programs replayed from apitrace recordings "
        f"(`holoinject run … -- glretrace|eglretrace TRACE`), f3d run directly with a VTK interaction log. {took}",
        "",
        "Command: `" + " ".join(["scripts/disparity-agreement.py", *a.argv]) + "`",
        "",
        f"- **textured blocks (matched)**: 16x16 blocks of the centre view whose luminance (Rec. 601) has a standard "
        f"deviation ≥ {a.texture:g} levels; in brackets those whose best shift in exact is distinct and unique in both "
        f"outermost views (best SSD ≤ {DISTINCT} × the mean over the shifts tried, not at ±{a.max_shift} px; no other "
        f"local minimum more than {AGREE_PX} px away within 1/{UNIQUE} of it: periodic texture is left out).",
        f"- **agree %**: matched blocks found in views 0 and {n - 1} at shifts (integer, ±{a.max_shift} px, SSD of RGB) "
        f"within {AGREE_PX} px of exact's in both; a block synth shows nowhere distinctly (same test as exact's) is not "
        f"found and disagrees (\"k not found\"). **median/p95 |Δ|** (px): |shift_exact − shift_synth| over the matched "
        f"blocks synth finds, both outermost views pooled. Issue 22's bar: agree ≥ 90 %.",
        f"- **PSNR** (dB, mean / worst view) of the views each mode synthesises against exact's same view: synth all but "
        f"view {n // 2}; hybrid:{k} all but views {', '.join(map(str, spaced(k, n)))}. ∞: identical.",
        "- **centre identical**: synth's centre tile equals exact's bit for bit. **C**: the convergence passed.",
        "- †: the fast modes stayed exact for this program (the layer says why, see the notes): nothing synthesised to measure.",
        "- program @F: the frame compared (sample apps: `--frames F`; replays: the F-th swap of the recording).",
        "",
        f"| program | textured blocks (matched) | agree % | median \\|Δ\\| | p95 \\|Δ\\| | synth PSNR mean / worst | "
        f"hybrid:{k} PSNR mean / worst | centre identical | C |",
        "|---|---|---|---|---|---|---|---|---|",
    ]


def write_markdown(a, results, elapsed, recording):
    lines = header(a, elapsed, recording) + [table_row(r) for r in results]
    ok = [r for r in results if "error" not in r and not r.get("stays_exact") and not math.isnan(r["agree_pct"])]
    if ok:
        passing = [r for r in ok if r["agree_pct"] >= 90]
        below = ", ".join("%s (%.1f %%)" % (r["program"], r["agree_pct"]) for r in ok if r["agree_pct"] < 90)
        lines += ["", f"{len(passing)} of {len(ok)} measured programs reach 90 % agreement" + (f"; below: {below}." if below else ".")]
    notes = [f"- {r['program']} (frame {r['frame']}): {'; '.join(r['notes'])}" for r in results if r.get("notes")]
    if notes:
        lines += ["", "Notes:", *notes]
    text = "\n".join(lines) + "\n"
    with open(os.path.join(a.out, "disparity-agreement.md"), "w") as f:
        f.write(text)
    return text


CSV_FIELDS = [
    "program", "frame", "status", "convergence", "c_source", "c_exact_auto", "c_synth_auto", "c_hybrid_auto",
    "blocks", "textured", "matched", "not_found_in_synth", "agree_pct", "agree_pct_textured", "median_d", "p95_d",
    "exact_shift_p10", "exact_shift_p90", "synth_psnr_mean", "synth_psnr_worst", "synth_worst_view",
    "synth_identical_views", "synth_black_views", "hybrid_psnr_mean", "hybrid_psnr_worst", "hybrid_worst_view",
    "hybrid_rendered_identical", "hybrid_black_views", "centre_identical", "centre_diff_pixels", "centre_diff_max",
    "stays_exact", "seconds", "record_s", "notes",
]


def csv_row(r):
    row = {**r, "status": r.get("error", "ok"), "notes": "; ".join(r.get("notes", []))}
    for key, names in [("exact_shift_p10_p90", ["exact_shift_p10", "exact_shift_p90"]),
                       ("synth_psnr", ["synth_psnr_mean", "synth_psnr_worst", "synth_worst_view"]),
                       ("hybrid_psnr", ["hybrid_psnr_mean", "hybrid_psnr_worst", "hybrid_worst_view"])]:
        if r.get(key):
            row.update(zip(names, r[key]))
    cell = lambda v: f"{v:.3f}" if isinstance(v, float) else " ".join(map(str, v)) if isinstance(v, list) else v
    return [cell(row.get(x, "")) for x in CSV_FIELDS]


def write_outputs(a, results, elapsed, recording):
    os.makedirs(a.out, exist_ok=True)
    text = write_markdown(a, results, elapsed, recording)
    with open(os.path.join(a.out, "disparity-agreement.csv"), "w", newline="") as f:
        wr = csv.writer(f)
        wr.writerow(CSV_FIELDS)
        wr.writerows(csv_row(r) for r in results)
    print(text)


# ---------------------------------------------------------------------------------- main

def arguments():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], epilog="Programs: " + ", ".join(PROGRAMS))
    ap.add_argument("--programs", default=",".join(DEFAULT_PROGRAMS), help="comma-separated NAME, NAME@FRAME or NAME@P%% (default: all)")
    ap.add_argument("--quilt", default="5x3", help="CxR (default 5x3)")
    ap.add_argument("--tile", default="256x192", help="WxH (default 256x192; also the sample apps' and recordings' window)")
    ap.add_argument("--depthiness", help="--depthiness S for every run (default: the layer's default)")
    ap.add_argument("--convergence", default="exact-auto", help="exact-auto (default) | auto | C")
    ap.add_argument("--hybrid-k", type=int, default=3, help="K of the hybrid mode measured (default 3)")
    ap.add_argument("--texture", type=float, default=8.0, help="luminance std (8-bit levels) a block needs (default 8)")
    ap.add_argument("--max-shift", type=int, default=64, help="shift search range ± px (default 64)")
    ap.add_argument("--layer", default=os.path.join(os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target")), "release"),
                    help="directory with holoinject and libholoinject.so (default target/release)")
    ap.add_argument("--apps", help="directory with the sample apps (default: --layer)")
    ap.add_argument("--cache", default=os.path.join(os.environ.get("XDG_CACHE_HOME", os.path.expanduser("~/.cache")), "holoinject", "traces"),
                    help="where apitrace recordings are kept")
    ap.add_argument("--out", default=os.path.join(ROOT, "scripts", "results"), help="where the .md and .csv go")
    ap.add_argument("--keep", metavar="DIR", help="keep the quilt PNGs in DIR (default: a temporary directory, removed)")
    ap.add_argument("--recompute", metavar="DIR", help="no runs: measure the quilts an earlier sweep kept in DIR (--keep) again")
    ap.add_argument("--timeout", type=int, default=240, help="seconds before a run counts as failed (default 240)")
    ap.add_argument("--list", action="store_true", help="list the programs and exit")
    a = ap.parse_args()
    a.argv = sys.argv[1:]
    return a


def programs_to_run(a):
    todo = []
    for p in filter(None, a.programs.split(",")):
        name, _, fr = p.partition("@")
        if name not in PROGRAMS:
            sys.exit(f"disparity-agreement: unknown program {name} (--list)")
        todo.append((name, parse_frame(fr) if fr else PROGRAMS[name]["frame"]))
    return todo


def progress(i, total, r, started):
    what = f"[{i}/{total}] {r['program']} frame {r['frame']}:"
    if "error" in r:
        log(f"{what} FAILED ({r['error']})  ({time.time() - started:.0f} s)")
        return
    log(f"{what} {r['textured']} textured ({r['matched']} matched), agree {f1(r['agree_pct'])} %, "
        f"|Δ| median {f1(r['median_d'])} p95 {f1(r['p95_d'])}, synth {psnr_cell(r['synth_psnr'])} dB, "
        f"hybrid {psnr_cell(r.get('hybrid_psnr'))} dB, centre {'=' if r['centre_identical'] else '≠'}, "
        f"C {r['convergence']}  ({r['seconds']:.0f} s, {time.time() - started:.0f} s total)")


def main():
    a = arguments()
    if a.list:
        for k, v in PROGRAMS.items():
            print(f"{k:22} {v['kind']:6} frame {frame_text(v['frame'])}")
        return
    if a.recompute:
        write_outputs(a, recompute(a), None, 0.0)
        return
    a.layer, a.apps = os.path.abspath(a.layer), os.path.abspath(a.apps or a.layer)
    for f in ["holoinject", "libholoinject.so"]:
        if not os.path.exists(os.path.join(a.layer, f)):
            sys.exit(f"disparity-agreement: {a.layer}/{f} missing: build first (cargo build --release --workspace) or pass --layer")
    if not re.fullmatch(r"\d+x\d+", a.quilt) or not re.fullmatch(r"\d+x\d+", a.tile):
        sys.exit("disparity-agreement: --quilt and --tile are CxR and WxH")
    todo = programs_to_run(a)
    work = a.keep or tempfile.mkdtemp(prefix="disparity-agreement-")
    display, results, started = Display(), [], time.time()
    try:
        for i, (name, frame) in enumerate(todo):
            r = measure(name, PROGRAMS[name], frame, a, display, work)
            results.append(r)
            keep_run(a, work, r)
            progress(i + 1, len(todo), r, started)
    finally:
        display.stop()
        if not a.keep:
            shutil.rmtree(work, ignore_errors=True)
    write_outputs(a, results, time.time() - started, sum(r.get("record_s", 0.0) for r in results))


if __name__ == "__main__":
    main()
