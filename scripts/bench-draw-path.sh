#!/usr/bin/env bash
# The per-draw path under multiview, timed: asteroids (one glUniform + glDrawArrays per rock,
# thousands per frame) replayed into a QUILT quilt, with two builds of the layer in turn
# (A B A B …, ROUNDS times), each run reporting the median of its own frame times after
# warm-up; the figure is the ratio of the medians of those medians, t(B)/t(A), measured in
# one session (DESIGN §6). Typical use: A = a build of an older commit, B = this one.
#
# The window is small (256x192) so that the replayed draws, not llvmpipe's rasterisation of
# 48 tiles, dominate the frame.
#
#   scripts/bench-draw-path.sh LIB_A [LIB_B=target/release/libholoinject.so] \
#       [QUILT=8x6] [DRAWS=1000] [FRAMES=30] [ROUNDS=7]
set -euo pipefail
cd "$(dirname "$0")/.."
[ $# -ge 1 ] || { echo "usage: $0 LIB_A [LIB_B] [QUILT] [DRAWS] [FRAMES] [ROUNDS]" >&2; exit 2; }
lib_a=$(realpath "$1") lib_b=$(realpath "${2:-target/release/libholoinject.so}")
quilt=${3:-8x6} draws=${4:-1000} frames=${5:-30} rounds=${6:-7}
bin=target/release
[ -x "$bin/asteroids" ] || cargo build --workspace --release --locked -q
app=("$bin/asteroids" --backend egl --size 256x192 --draws "$draws" --frames "$frames" --timing)

median_ms() { grep -o 'median_frame_ms=[0-9.]*' | head -1 | cut -d= -f2; }
run() { HOLOINJECT_LIB=$1 "$bin/holoinject" run --quilt "$quilt" -- "${app[@]}" 2>&1 >/dev/null | median_ms; }
a=() b=()
for r in $(seq "$rounds"); do
  a+=("$(run "$lib_a")")
  b+=("$(run "$lib_b")")
  echo "round $r: A ${a[-1]} ms, B ${b[-1]} ms" >&2
done
/usr/bin/python3 - "${a[*]}" "${b[*]}" "$quilt" "$draws" "$frames" <<'PY'
import statistics, sys
a = [float(x) for x in sys.argv[1].split()]
b = [float(x) for x in sys.argv[2].split()]
ma, mb = statistics.median(a), statistics.median(b)
print(f"asteroids 256x192, {sys.argv[4]} draws/frame at {sys.argv[3]}, {sys.argv[5]} frames/run, {len(a)} runs each (EGL, llvmpipe)")
print(f"median frame time: A {ma:.3f} ms, B {mb:.3f} ms; t(B)/t(A) = {mb / ma:.4f}")
PY
