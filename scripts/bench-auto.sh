#!/bin/bash
# `--mode auto` against the faster of its two ends, per scene: exact, synth and auto with a
# budget no K can meet (so auto must settle on the fastest K), alternated, ROUNDS times each;
# prints the layer's own frame-time medians (after its 10 warm-up frames).
#
#   SCENES="cubes asteroids framebuffers bloom" QUILT=6x4 TILE=420x560 FRAMES=50 ROUNDS=2 \
#       scripts/bench-auto.sh
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
export PATH="$root/target/release:$PATH"
SCENES=${SCENES:-"cubes asteroids framebuffers bloom"}
QUILT=${QUILT:-6x4}
TILE=${TILE:-420x560}
FRAMES=${FRAMES:-50}
ROUNDS=${ROUNDS:-2}
echo "| scene | round | exact ms | synth ms | auto ms | auto / faster end |"
echo "|---|---|---|---|---|---|"
for scene in $SCENES; do
  for r in $(seq "$ROUNDS"); do
    declare -A ms=()
    for mode in exact synth auto; do
      extra=()
      [ "$mode" = auto ] && extra=(--frame-budget 1)
      out=$(holoinject run --mode "$mode" "${extra[@]}" --output quilt --quilt "$QUILT" --tile "$TILE" \
        --log info --exit-after "$FRAMES" -- "$scene" --backend osmesa --size "$TILE" --frames "$FRAMES" 2>&1)
      ms[$mode]=$(grep -o 'frame time: median [0-9.]*' <<<"$out" | awk '{print $4}')
      [ -n "${ms[$mode]}" ] || { echo "bench-auto: no frame time from $scene under $mode" >&2; exit 1; }
    done
    ratio=$(awk -v a="${ms[auto]}" -v e="${ms[exact]}" -v s="${ms[synth]}" 'BEGIN { b = e < s ? e : s; printf "%.2f", a / b }')
    echo "| $scene | $r | ${ms[exact]} | ${ms[synth]} | ${ms[auto]} | $ratio |"
  done
done
