#!/bin/bash
# usage: tests/apps/verify.sh [BINDIR]  (default target/release)
# Every app x its back-ends: screenshot + 3x3 quilt check, determinism.
# ONLY="app1 app2" restricts the run to those apps.
# TOL = allowed centre-tile edge pixels (see README).
BIN=${1:-target/release}; HERE=$(dirname "$0"); TOL=${TOL:-16}; D=/tmp/v; mkdir -p $D; fail=0
# app, LSB (centre-tile +-LSB differences not counted, see check_quilt.py),
# back-ends, extra flags. gles has no GLX/OSMesa path (ES comes from EGL).
CASES="cubes 0 glx,egl,osmesa
legacy 0 glx,egl,osmesa
asteroids 0 glx,egl,osmesa
model 1 glx,egl,osmesa
skybox 1 glx,egl,osmesa
compat120 0 glx,egl,osmesa
gles 0 egl,egl-x11
gles 0 egl,egl-x11 --es2
framebuffers 1 glx,egl,osmesa
shadowmap 1 glx,egl,osmesa
deferred 1 glx,egl,osmesa
ssao 1 glx,egl,osmesa
bloom 1 glx,egl,osmesa
msaa 1 glx,egl,osmesa
msaa 1 glx,egl,osmesa --blit-to-default"
# fd 3: xvfb-run would otherwise eat the case list from stdin.
while read -r -u 3 app lsb bes extra; do
  [ -n "$ONLY" ] && [[ " $ONLY " != *" $app "* ]] && continue
  for be in ${bes//,/ }; do
  tag=$app$(echo $extra | tr -d ' '); pre=""
  [ $be = glx ] || [ $be = egl-x11 ] && pre="xvfb-run -a -s '-screen 0 1280x1024x24'"
  run() { eval $pre $BIN/$app --backend $be $extra "$@" </dev/null; }
  run --frames 5 --screenshot $D/$tag-$be.png --reference-quilt 3x3 --out $D/$tag-$be-q.png 2>$D/err || { echo "FAIL run $tag $be: $(cat $D/err)"; fail=1; continue; }
  run --frames 5 --screenshot $D/$tag-$be-plain.png 2>/dev/null
  cmp -s $D/$tag-$be.png $D/$tag-$be-plain.png || { echo "FAIL: quilt run changed screenshot $tag $be"; fail=1; }
  r=$(python3 $HERE/check_quilt.py $D/$tag-$be.png $D/$tag-$be-q.png 3 3 $TOL $lsb 2>&1) || { echo "FAIL quilt $tag $be: $r"; fail=1; }
  run --frames 3 --screenshot $D/d1.png --reference-quilt 3x3 --out $D/dq1.png 2>/dev/null; run --frames 3 --screenshot $D/d2.png --reference-quilt 3x3 --out $D/dq2.png 2>/dev/null; cmp -s $D/dq1.png $D/dq2.png || { echo "FAIL quilt determinism $tag $be"; fail=1; }
  cmp -s $D/d1.png $D/d2.png || { echo "FAIL determinism $tag $be"; fail=1; }
  echo "$tag $be: $(echo "$r" | tail -1)"
done; done 3<<< "$CASES"
exit $fail
