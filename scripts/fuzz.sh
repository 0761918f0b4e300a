#!/usr/bin/env bash
# cargo fuzz targets (tests/fuzz), outside CI's default path: they need the nightly toolchain
# and run for as long as they are given.
#
#   scripts/fuzz.sh seeds                 collect the seed corpus: every shader the sample
#                                         apps and the real programs of the tests compile
#   scripts/fuzz.sh run TARGET SECONDS    fuzz one target (glsl_rewrite, glsl_compiles,
#                                         visual_json, app_preset) for SECONDS
#   scripts/fuzz.sh all SECONDS           every target, one after the other
#
# Each run appends a line to scripts/results/fuzz-log.md (target, seconds, executions,
# corpus size, crashes). Runs go on past a finding (libFuzzer fork mode); every crash or hang
# is written to tests/fuzz/artifacts/TARGET/; copy it into tests/fuzz/regressions/ (run by
# `cargo test`) once it is fixed.
set -euo pipefail
cd "$(dirname "$0")/.."
# No sanitizer: the targets are safe Rust, and under ASan the binary exports our dlsym
# interposer to its own runtime, which crashes at start-up.
fuzz=(cargo +nightly fuzz)
seeds=tests/fuzz/seeds
work=target/fuzz-corpus

collect_seeds() {
  command -v xvfb-run >/dev/null || { echo "fuzz.sh: run scripts/setup-debian.sh first" >&2; exit 2; }
  cargo build --workspace --release --locked -q
  local cap; cap=$(mktemp -d)
  local n=0
  run_captured() {  # Mesa writes every linked program to MESA_SHADER_CAPTURE_PATH as .shader_test
    n=$((n + 1)); mkdir -p "$cap/$n"
    MESA_SHADER_CAPTURE_PATH="$cap/$n" timeout -k 5 60 "$@" >/dev/null 2>&1 || true
  }
  for app in cubes legacy asteroids model skybox compat120 framebuffers shadowmap deferred ssao bloom msaa; do
    run_captured target/release/$app --backend osmesa --frames 3
  done
  run_captured target/release/gles --backend egl --frames 3
  run_captured target/release/gles --backend egl --es2 --frames 3
  run_captured xvfb-run -a es2gears_x11 -info
  for scene in build texture shading:shading=phong shading:shading=blinn-phong-inf bump:bump-render=normals \
               pulsar shadow terrain refract effect2d desktop ideas jellyfish conditionals function loop buffer; do
    run_captured xvfb-run -a glmark2 --off-screen -b "$scene:duration=0.2"
  done
  rm -rf "$seeds/glsl"; mkdir -p "$seeds/glsl" "$seeds/visual_json" "$seeds/app_preset"
  /usr/bin/python3 - "$cap" "$seeds/glsl" tests/shaders <<'PY'
import hashlib, os, re, sys
cap, out, corpus = sys.argv[1:4]
# First byte selects the stage in both GLSL targets: 0 vertex, 1 geometry, 2 tess-eval, 3 fragment.
stage = {"vertex": 0, "geometry": 1, "tessellation evaluation": 2, "fragment": 3}
ext = {"vert": 0, "geom": 1, "tese": 2, "frag": 3}
seen = set()
def keep(sel, text):
    data = bytes([sel]) + text.encode()
    h = hashlib.sha1(data).hexdigest()[:16]
    if h not in seen:
        seen.add(h)
        open(os.path.join(out, h), "wb").write(data)
for root, _, files in os.walk(cap):
    for f in files:
        parts = re.split(r"^\[(.*?) shader\]\n", open(os.path.join(root, f)).read(), flags=re.M)
        for name, body in zip(parts[1::2], parts[2::2]):
            if name in stage:
                keep(stage[name], body.split("\n[", 1)[0] if "\n[require]" in body else body)
for f in sorted(os.listdir(corpus)):
    e = f.rsplit(".", 1)[-1]
    keep(ext.get(e, 0), open(os.path.join(corpus, f)).read())
print(f"fuzz.sh: {len(seen)} GLSL seeds in {out}", file=sys.stderr)
PY
  rm -rf "$cap"
  cp presets/*.toml "$seeds/app_preset/" 2>/dev/null || true
}

run_target() {
  local target=$1 secs=$2
  local artifacts=tests/fuzz/artifacts/$target/
  local seed_dir=$seeds/$target
  case $target in glsl_rewrite|glsl_compiles) seed_dir=$seeds/glsl ;; esac
  mkdir -p "$work/$target" "$artifacts" scripts/results
  [[ -s scripts/results/fuzz-log.md ]] || printf '%s\n' '# cargo fuzz runs (scripts/fuzz.sh)' '' \
    '| when (UTC) | target | ran | executions | corpus | crash files |' '|---|---|---|---|---|---|' \
    > scripts/results/fuzz-log.md
  local log; log=$(mktemp)
  local start; start=$(date +%s)
  local status=0
  "${fuzz[@]}" run --fuzz-dir tests/fuzz -O -a -s none "$target" "$work/$target" "$seed_dir" -- \
      -max_total_time="$secs" -max_len=65536 -timeout=20 -rss_limit_mb=4096 \
      -fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1 \
      -artifact_prefix="$artifacts" -print_final_stats=1 2>&1 | tee "$log" | grep -E '^(#[0-9]+: cov|==|.*panicked|INFO: fuzzed)' >&2 \
      || status=$?
  local took=$(( $(date +%s) - start ))
  local execs corpus crashes
  # Fork mode (it goes on past a finding) reports progress as `#EXECUTIONS: cov: …`.
  execs=$(grep -o '^#[0-9]*: cov' "$log" | tail -1 | tr -dc '0-9' || true)
  corpus=$(find "$work/$target" -type f | wc -l)
  crashes=$(find "$artifacts" -type f | wc -l)
  printf '| %s | %s | %s s | %s | %s | %s |\n' "$(date -u +%F\ %H:%M)" "$target" "$took" "${execs:-?}" \
    "$corpus" "$crashes" >> scripts/results/fuzz-log.md
  rm -f "$log"
  echo "fuzz.sh: $target ran ${took}s, ${execs:-?} executions, corpus $corpus, crash files $crashes" >&2
  return 0
}

case ${1:-} in
  seeds) collect_seeds ;;
  run) [[ $# -eq 3 ]] || { echo "usage: scripts/fuzz.sh run TARGET SECONDS" >&2; exit 2; }; run_target "$2" "$3" ;;
  all) [[ $# -eq 2 ]] || { echo "usage: scripts/fuzz.sh all SECONDS" >&2; exit 2; }
       for t in glsl_rewrite glsl_compiles visual_json app_preset; do run_target "$t" "$2"; done ;;
  *) sed -n '2,14p' "$0" >&2; exit 2 ;;
esac
