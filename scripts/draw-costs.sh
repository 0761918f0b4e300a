#!/usr/bin/env bash
# What a draw costs the layer, counted rather than timed: share-group locks, GL state queries
# and heap allocations per draw, while the layer replays every draw into an 8x6 quilt. Builds
# the layer with the `draw-costs` feature (into target/draw-costs, leaving the normal build
# alone) and runs one sample app per common case:
#   asteroids     shader draws to framebuffer 0 (thousands per frame, a glUniform each)
#   legacy        fixed-function draws (matrix stack, immediate mode, display lists)
#   framebuffers  draws into the app's own framebuffers, shadowed per view
#
#   scripts/draw-costs.sh [QUILT=8x6] [FRAMES=20]
set -euo pipefail
cd "$(dirname "$0")/.."
quilt=${1:-8x6} frames=${2:-20}
cargo build --workspace --release --locked -q
CARGO_TARGET_DIR=target/draw-costs cargo build --release --locked -q --features draw-costs --lib
lib=$PWD/target/draw-costs/release/libholoinject.so
bin=target/release
for app in "asteroids --draws 2000" legacy framebuffers; do
  set -- $app
  line=$(HOLOINJECT_LIB=$lib "$bin/holoinject" run --quilt "$quilt" --log info --exit-after "$frames" -- \
    "$bin/$1" --backend egl --size 640x480 "${@:2}" 2>&1 >/dev/null | grep -o 'draw costs: .*' || true)
  echo "$1: ${line:-no draw-costs line (the layer did not replay)}"
done
