#!/usr/bin/env bash
# Checks formatting and lints (clippy, warnings as errors), builds everything (layer, launcher,
# sample apps) and runs every test headless: unit tests, launcher tests, sample apps on GLX
# (Xvfb), EGL and OSMesa, and real Debian programs.
set -euo pipefail
cd "$(dirname "$0")/.."
export ALSOFT_DRIVERS=null
cargo fmt --all --check
cargo clippy --workspace --release --locked -- -D warnings
# The layering of DESIGN §2: the module graph must stay acyclic.
scripts/module-graph.sh >/dev/null
# The same one level down: no cycle between files, nor between a module's sub-modules.
python3 scripts/file-graph.py >/dev/null
cargo build --workspace --release --locked
# -noreset: Xvfb otherwise resets whenever its last client disconnects, and a GLX test
# starting during that reset fails with "cannot open X display" (seen in CI).
xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" cargo test --workspace --release --locked -- --test-threads=2
