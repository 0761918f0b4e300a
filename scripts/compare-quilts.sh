#!/usr/bin/env bash
# Dumps the quilts of every sample app (OSMesa, deterministic: frame numbers are scenes) in
# exact, synth and hybrid:3 with the launcher and layer of BUILD (default target/release), so
# that a restructuring can be checked bit for bit against an earlier build:
#
#   scripts/compare-quilts.sh dump OUT [BUILD]     # writes OUT/APP-MODE.png
#   scripts/compare-quilts.sh diff A B             # cmp of every quilt; exits 1 on a difference
set -euo pipefail
cd "$(dirname "$0")/.."
apps=(asteroids bloom compat120 cubes deferred framebuffers legacy lines model msaa shadowmap skybox ssao)
modes=(exact synth hybrid:3)
case "${1:-}" in
dump)
  out=$2 build=${3:-target/release}
  mkdir -p "$out"
  for app in "${apps[@]}"; do
    for mode in "${modes[@]}"; do
      tmp=$(mktemp -d)
      "$build/holoinject" run \
        --quilt 3x3 --tile 160x120 --mode "$mode" --dump "$tmp" --dump-frames 3 --exit-after 3 \
        -- target/release/"$app" --backend osmesa --size 320x240 --frames 3 >/dev/null 2>&1 || true
      q=$(ls "$tmp"/f000003_qs*.png 2>/dev/null | head -1)
      if [ -n "$q" ]; then cp "$q" "$out/$app-${mode/:/}.png"; else echo "no quilt: $app $mode" >&2; fi
      rm -rf "$tmp"
    done
  done ;;
diff)
  status=0
  for f in "$2"/*.png; do
    g="$3/$(basename "$f")"
    if ! cmp -s "$f" "$g"; then echo "differs: $(basename "$f")"; status=1; fi
  done
  echo "compared $(ls "$2"/*.png | wc -l) quilts"
  exit $status ;;
*) echo "usage: $0 dump OUT [BUILD] | diff A B" >&2; exit 2 ;;
esac
