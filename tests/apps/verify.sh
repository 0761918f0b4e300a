#!/bin/bash
# usage: tests/apps/verify.sh [BINDIR]  (default target/release)
# Every app x {glx,egl,osmesa}: screenshot + 3x3 quilt check, determinism.
# TOL = allowed centre-tile edge pixels (see README).
BIN=${1:-target/release}; HERE=$(dirname "$0"); TOL=${TOL:-16}; D=/tmp/v; mkdir -p $D; fail=0
for app in cubes legacy asteroids; do for be in glx egl osmesa; do
  pre=""; [ $be = glx ] && pre="xvfb-run -a -s '-screen 0 1280x1024x24'"
  run() { eval $pre $BIN/$app --backend $be "$@"; }
  run --frames 5 --screenshot $D/$app-$be.png --reference-quilt 3x3 --out $D/$app-$be-q.png 2>$D/err || { echo "FAIL run $app $be: $(cat $D/err)"; fail=1; continue; }
  run --frames 5 --screenshot $D/$app-$be-plain.png 2>/dev/null
  cmp -s $D/$app-$be.png $D/$app-$be-plain.png || { echo "FAIL: quilt run changed screenshot $app $be"; fail=1; }
  r=$(python3 $HERE/check_quilt.py $D/$app-$be.png $D/$app-$be-q.png 3 3 $TOL 2>&1) || { echo "FAIL quilt $app $be: $r"; fail=1; }
  run --frames 3 --screenshot $D/d1.png --reference-quilt 3x3 --out $D/dq1.png 2>/dev/null; run --frames 3 --screenshot $D/d2.png --reference-quilt 3x3 --out $D/dq2.png 2>/dev/null; cmp -s $D/dq1.png $D/dq2.png || { echo "FAIL quilt determinism $app $be"; fail=1; }
  cmp -s $D/d1.png $D/d2.png || { echo "FAIL determinism $app $be"; fail=1; }
  echo "$app $be: $(echo "$r" | tail -1)"
done; done
exit $fail
