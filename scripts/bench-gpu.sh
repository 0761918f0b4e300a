#!/bin/bash
# One command for a GPU machine (issue 23): the speed/accuracy trade of exact, synth and
# hybrid:4 for the six sample apps at 48 views (8x6) of 420x560, with the layer's GPU counts,
# headless on an EGL device (no X server, no window system), in at most about 8 minutes.
#
#   scripts/bench-gpu.sh [--out FILE] [--frames N] [--rounds N] [--scenes a,b] [--budget S]
#                        [--quilt-metrics]
#
# Writes the machine (GL renderer, CPU, date, git revision), the table and the counts into
# one Markdown file (default ./bench-gpu-HOST-DATE.md) and prints it. Builds the binaries if
# they are missing. A software renderer (llvmpipe here) gets 20 frames and one round, a GPU
# 40 frames and 3 rounds. A scene still running when the budget is spent is cut, and the
# file says so. --quilt-metrics adds bench-trade's FLIP and disparity error: CPU work of
# about 2 minutes per scene, more than the budget allows.
set -euo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BIN=${CARGO_TARGET_DIR:-$ROOT/target}/release
# Cheap scenes first: time they leave over goes to the expensive ones at the end.
SCENES=cubes,asteroids,framebuffers,deferred,bloom,ssao
APPS="cubes asteroids framebuffers deferred bloom ssao"
OUT=bench-gpu-$(hostname)-$(date +%Y-%m-%d-%H%M).md
BUDGET=470 # s for everything, build included; the last run may overrun by its kill grace
FRAMES="" ROUNDS="" METRICS=--no-quilt-metrics
START=$SECONDS

die() { echo "bench-gpu: $*" >&2; exit 1; }

while [ $# -gt 0 ]; do
    case $1 in
        --out) OUT=$2; shift 2 ;;
        --frames) FRAMES=$2; shift 2 ;;
        --rounds) ROUNDS=$2; shift 2 ;;
        --scenes) SCENES=$2; shift 2 ;;
        --budget) BUDGET=$2; shift 2 ;;
        --quilt-metrics) METRICS=--quilt-metrics; shift ;;
        -h|--help) sed -n '2,14p' "$0" | cut -c3-; exit 0 ;;
        *) die "unknown option $1 (see --help)" ;;
    esac
done

# No window system: whatever the shell has, the runs must not find an X or Wayland server.
unset DISPLAY WAYLAND_DISPLAY

# The first python3 with the modules bench-trade.py and its plot use (pyenv shims may hide them).
python_with_modules() {
    for py in python3 /usr/bin/python3; do
        if command -v "$py" >/dev/null && "$py" -c 'import numpy, PIL, matplotlib' 2>/dev/null; then
            echo "$py"; return
        fi
    done
    die "no python3 with numpy, PIL and matplotlib (apt-get install python3-numpy python3-pil python3-matplotlib)"
}

check_prerequisites() {
    command -v timeout >/dev/null || die "timeout (coreutils) missing"
    PY=$(python_with_modules)
    local f missing=""
    for f in holoinject libholoinject.so $APPS; do
        [ -e "$BIN/$f" ] || missing+=" $f"
    done
    if [ -n "$missing" ]; then
        command -v cargo >/dev/null || die "$BIN lacks$missing and there is no cargo to build it"
        echo "bench-gpu: building ($BIN lacks$missing)" >&2
        (cd "$ROOT" && cargo build --release --workspace --locked) >&2
    fi
    local help
    help=$("$PY" "$ROOT/scripts/bench-trade.py" --help)
    for f in --backend --counts --quilt-metrics; do
        grep -q -- "$f" <<<"$help" || die "scripts/bench-trade.py has no $f option (older checkout?)"
    done
}

# The sample apps' own view of the device: "egl-device (device 0 of 1: software, pbuffer):
# llvmpipe (...) / 4.5 (Core Profile) Mesa 22.3.6 (depth 24, stencil 8)".
renderer() {
    local out
    out=$(HOLOAPPS_VERBOSE=1 "$BIN/cubes" --backend egl-device --size 64x64 --frames 1 2>&1 >/dev/null) ||
        die "no usable EGL device: cubes --backend egl-device said: ${out##*$'\n'}"
    grep -m1 '^egl-device' <<<"$out" || die "cubes --backend egl-device named no device (HOLOAPPS_VERBOSE)"
}

machine() {
    local rev dirty=""
    rev=$(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo "?")
    [ -z "$(git -C "$ROOT" status --porcelain 2>/dev/null)" ] || dirty=" + local changes"
    echo "- GL: $RENDERER"
    if command -v nvidia-smi >/dev/null; then
        echo "- GPU: $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader | head -1)"
    fi
    echo "- CPU: $(lscpu | sed -n 's/^Model name: *//p' | head -1), $(nproc) cores"
    echo "- OS: $(. /etc/os-release && echo "$PRETTY_NAME"), kernel $(uname -r)"
    echo "- date: $(date -u '+%Y-%m-%d %H:%M UTC'), host $(hostname), revision $rev$dirty"
}

# A software renderer is 10-100 times slower: 20 frames is 9 timed after the layer's 10
# warm-up frames (frames 10 and 20 are the measured ones), and one round fits 8 minutes on 2
# cores (4 minutes here). 12 frames timed two, the one after a measured frame among them:
# synth read 194 ms a frame on cubes and 335 on deferred where 20 frames read 93 and 106.
pick_counts() {
    if grep -qiE 'llvmpipe|softpipe|swrast|software' <<<"$RENDERER"; then
        FRAMES=${FRAMES:-20} ROUNDS=${ROUNDS:-1}
    else
        FRAMES=${FRAMES:-40} ROUNDS=${ROUNDS:-3}
    fi
}

# Ends bench-trade and the program it runs (which it starts in a session of its own, so
# signalling bench-trade's group would leave it running).
stop_scene() {
    local py=$1 child
    for child in $(pgrep -P "$py" || true); do
        kill -TERM -- "-$child" 2>/dev/null || kill -TERM "$child" 2>/dev/null || true
    done
    kill -TERM "$py" 2>/dev/null || true
}

# One scene with `$1` seconds at most; its results go to $WORK/$scene/.
run_scene() {
    local scene=$2 seconds=$1 end py
    end=$((SECONDS + seconds))
    "$PY" "$ROOT/scripts/bench-trade.py" --scenes "$scene" --views 48 --tiles 420x560 \
        --modes exact,synth,hybrid:4 --rounds "$ROUNDS" --frames "$FRAMES" --timeout "$seconds" \
        --backend egl-device --counts "$METRICS" --bin "$BIN" --out "$WORK/$scene" \
        >"$WORK/$scene.out" 2>"$WORK/$scene.err" &
    py=$!
    CURRENT=$py
    while kill -0 "$py" 2>/dev/null; do
        if [ $SECONDS -ge $end ]; then
            stop_scene "$py"
            echo "$scene" >>"$WORK/cut"
            break
        fi
        sleep 1
    done
    wait "$py" || echo "$scene: bench-trade exit status $?" >>"$WORK/failed"
    CURRENT=""
}

# Each scene may use what is left, less 30 s kept for every scene after it, so one slow scene
# cannot starve the rest.
run_all() {
    local scene left n
    n=$(tr ',' '\n' <<<"$SCENES" | grep -c .)
    for scene in ${SCENES//,/ }; do
        n=$((n - 1))
        left=$((BUDGET - (SECONDS - START) - 30 * n))
        if [ $left -lt 10 ]; then
            echo "$scene" >>"$WORK/cut"
            continue
        fi
        echo "bench-gpu: $scene ($left s at most)" >&2
        run_scene "$left" "$scene"
        grep -h '^\[' "$WORK/$scene.err" >&2 || true
    done
}

# The scenes' Markdown (bench-trade's table, the counts) as one document: each table once,
# with the rows of every scene; then what was cut or failed.
report() {
    "$PY" - "$@" <<'PY'
import os, re, sys
work, scenes = sys.argv[1], sys.argv[2:]
def lines(p):
    return open(p).read().splitlines() if os.path.exists(p) else []
def blocks(doc):
    out, i = [], 0
    while i < len(doc):
        if doc[i].startswith("|") and i + 1 < len(doc) and doc[i + 1].startswith("|-"):
            j = i + 2
            while j < len(doc) and doc[j].startswith("|"):
                j += 1
            out.append((doc[i], doc[i + 1], doc[i + 2:j]))
            i = j
        else:
            out.append(doc[i])
            i += 1
    return out
docs = {}
for s in scenes:
    d = os.path.join(work, s)
    mds = sorted(f for f in os.listdir(d) if f.endswith(".md")) if os.path.isdir(d) else []
    if mds:
        docs[s] = blocks([l for f in mds for l in lines(os.path.join(d, f)) + [""]])
rows = {}
for doc in docs.values():
    for b in doc:
        if isinstance(b, tuple):
            rows.setdefault(b[0], []).extend(b[2])
first = next(iter(docs.values()), [])
for b in first:
    if isinstance(b, tuple):
        print("\n".join([b[0], b[1], *rows[b[0]]]))
    else:  # the first scene's words stand for all; the time is given above
        print(re.sub(r" Took \d+ min\.", "", b).replace(f"--scenes {next(iter(docs))} ", "--scenes SCENE "))
# Other scenes' notes under the table (the legend is every scene's, printed once).
notes = [b for doc in list(docs.values())[1:] for b in doc if isinstance(b, str) and b.startswith("- ")]
notes = [n for n in dict.fromkeys(notes) if n not in first]
if notes:
    print("\n".join(notes))
if not docs:
    print("No scene finished: no table.")
cut, failed = lines(os.path.join(work, "cut")), lines(os.path.join(work, "failed"))
for s in cut:
    done = [l for l in lines(os.path.join(work, s + ".err")) if l.startswith("[")]
    print(f"\n**{s} was cut by the time limit**" + (": runs done before:" if done else ": not started."))
    print("\n".join(f"    {l}" for l in done))
for f in failed:
    if f.split(":")[0] not in cut:
        err = [l for l in lines(os.path.join(work, f.split(":")[0] + ".err")) if l.strip()][-3:]
        print(f"\n**{f}**\n" + "\n".join(f"    {l}" for l in err))
PY
}

CURRENT=""
WORK=$(mktemp -d)
trap '[ -z "$CURRENT" ] || stop_scene "$CURRENT"; rm -rf "$WORK"' EXIT
trap 'exit 130' INT TERM

check_prerequisites
RENDERER=$(renderer)
pick_counts
echo "bench-gpu: $RENDERER; $FRAMES frames, $ROUNDS round(s), at most $BUDGET s" >&2
run_all
{
    echo "# bench-gpu: speed/accuracy trade and GPU counts, 48 views (8x6) of 420x560"
    echo
    machine
    echo "- runs: scripts/bench-trade.py --views 48 --tiles 420x560 --modes exact,synth,hybrid:4"
    echo "  --backend egl-device --counts $METRICS --frames $FRAMES --rounds $ROUNDS, one scene at a time;"
    echo "  $((SECONDS - START)) s in all (budget $BUDGET s)"
    echo
    report "$WORK" ${SCENES//,/ }
} >"$OUT"
cat "$OUT"
echo "bench-gpu: written to $OUT" >&2
