#!/usr/bin/env bash
# What the disparity record costs (issue 22): the layer's own frame-time median
# (`frame time: median … ms`, `--log info`, after 10 warm-up frames) of the same run with
# `--disparity-record on` and `off`, alternating, ROUNDS times each, on a shader sample app
# (`cubes`), a fixed-function one (`legacy`: its draws are recorded by drawing them again) and
# a real program's replay. Prints each run and the ratio of the medians of the medians.
# MODE exact measures what exact mode pays under auto-convergence (the centre view records).
# Usage: scripts/bench-record.sh [ROUNDS] [MODE]   (needs DISPLAY; OpenArena trace: TRACE=…)
set -euo pipefail
rounds=${1:-3}
mode=${2:-synth}
here=$(cd "$(dirname "$0")/.." && pwd)
bin=$here/target/release
trace=${TRACE:-}
median() { sort -g | awk '{a[NR]=$1} END {print (NR%2 ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2)}'; }
run() {  # label, record on|off, program args…
    local label=$1 rec=$2; shift 2
    "$bin/holoinject" run --log info --output quilt --mode "$mode" --disparity-record "$rec" "$@" 2>&1 \
        | sed -n 's/.*frame time: median \([0-9.]*\) ms.*/\1/p' | tail -1
}
bench() {  # name, args…
    local name=$1; shift
    local on=() off=()
    for _ in $(seq "$rounds"); do
        on+=("$(run "$name" on "$@")")
        off+=("$(run "$name" off "$@")")
    done
    local mon moff
    mon=$(printf '%s\n' "${on[@]}" | median)
    moff=$(printf '%s\n' "${off[@]}" | median)
    echo "$name ($mode): record on ${on[*]} ms (median $mon); off ${off[*]} ms (median $moff); on/off $(awk -v a="$mon" -v b="$moff" 'BEGIN {printf "%.3f", a/b}')"
}
bench cubes --quilt 5x3 --tile 420x560 --exit-after 60 -- "$bin/cubes" --backend osmesa --size 420x560 --frames 60
bench legacy --quilt 5x3 --tile 420x560 --exit-after 60 -- "$bin/legacy" --backend osmesa --size 420x560 --frames 60
if [ -n "$trace" ]; then
    bench "$(basename "$trace" .trace)" --quilt 3x3 --exit-after 60 -- glretrace "$trace"
fi
