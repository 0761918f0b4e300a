#!/usr/bin/env bash
# The main job on a bundled demo, headless: the `cubes` sample app (GL 3.3 core, EGL
# pbuffer, no X server needed) under holoinject for a Looking Glass Portrait. Writes the
# quilt (8x6 views of 420x560), the native lenticular image (1536x2048) and what the window
# showed, then prints where they are.
#
#   scripts/demo.sh [DEVICE=portrait] [OUT=out/demo]
set -euo pipefail
cd "$(dirname "$0")/.."
device=${1:-portrait} out=${2:-out/demo}
cargo build --workspace --release --locked -q
rm -rf "$out" && mkdir -p "$out"
target/release/holoinject run --device "$device" --log info \
  --dump "$out" --dump-frames 30 --exit-after 30 \
  -- target/release/cubes --backend egl --size 420x560 --frames 30 2>&1 | grep -E "quilt|exit-after" >&2
echo "wrote:"
for f in "$out"/f000030_*.png; do echo "  $f"; done
