#!/usr/bin/env bash
# Pass-through overhead (DESIGN §6): t(preloaded, --output mono) / t(plain) on `asteroids`,
# thousands of small draw calls per frame, headless EGL. Runs alternate plain / preloaded
# ROUNDS times in one session; each run reports the median of its own per-frame times
# (after 10 warm-up frames); the figure is the ratio of the medians of those medians.
#
#   scripts/bench-passthrough.sh [DRAWS=5000] [FRAMES=300] [ROUNDS=5]
set -euo pipefail
cd "$(dirname "$0")/.."
draws=${1:-5000} frames=${2:-300} rounds=${3:-5}
cargo build --workspace --release --locked -q
bin=target/release
app=("$bin/asteroids" --backend egl --size 640x480 --draws "$draws" --frames "$frames")

median_ms() { grep -o 'median_frame_ms=[0-9.]*' | cut -d= -f2; }
plain=() injected=()
for r in $(seq "$rounds"); do
  plain+=("$("${app[@]}" 2>&1 >/dev/null | median_ms)")
  injected+=("$("$bin/holoinject" run --output mono -- "${app[@]}" 2>&1 >/dev/null | median_ms)")
  echo "round $r: plain ${plain[-1]} ms, preloaded ${injected[-1]} ms" >&2
done
/usr/bin/python3 - "${plain[*]}" "${injected[*]}" "$draws" "$frames" <<'PY'
import statistics, sys
plain = [float(x) for x in sys.argv[1].split()]
inj = [float(x) for x in sys.argv[2].split()]
p, i = statistics.median(plain), statistics.median(inj)
print(f"asteroids, {sys.argv[3]} draws/frame, {sys.argv[4]} frames/run, {len(plain)} runs each (EGL, llvmpipe)")
print(f"median frame time: plain {p:.3f} ms, preloaded --output mono {i:.3f} ms")
print(f"pass-through overhead t(preloaded)/t(plain) = {i / p:.4f}")
PY
