#!/usr/bin/env bash
# The synthesised views' error per warp (issue 23): `--measure-error` (PSNR of the views a
# mode synthesises against an exact render of the same frame, rendered views left out: mean
# and worst view) of `synth` and `hybrid:3` with each warp, on the multi-view sample apps at
# 5x9 of 256x256, frame 6. LAYERS: "label=DIR …" to compare builds (default: this tree's);
# APPS: the sample apps (default: the nine below).
# Usage: scripts/warp-quality.sh [WARPS]   (WARPS default "rows gather"; needs no display)
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
warps=${1:-rows gather}
layers=${LAYERS:-this=$here/target/release}
echo "| program | layer | warp | synth mean / worst (dB) | hybrid:3 mean / worst (dB) |"
echo "|---|---|---|---|---|"
for app in ${APPS:-cubes asteroids model skybox bloom deferred framebuffers ssao shadowmap}; do
    for layer in $layers; do
        for warp in $warps; do
            row="| $app | ${layer%%=*} | $warp |"
            for mode in synth hybrid:3; do
                fig=$("${layer#*=}/holoinject" run --mode "$mode" --synth-warp "$warp" --output quilt \
                    --quilt 5x9 --tile 256x256 --log info --exit-after 6 --measure-error every:6 \
                    -- "$here/target/release/$app" --backend osmesa --size 256x256 --frames 6 2>&1 \
                    | sed -n 's/.*PSNR mean \([0-9.]*\) dB, worst \([0-9.]*\) dB.*/\1 \/ \2/p' | tail -1)
                row="$row ${fig:-n/a} |"
            done
            echo "$row"
        done
    done
done
