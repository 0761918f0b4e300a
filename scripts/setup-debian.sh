#!/usr/bin/env bash
# Installs what building, the demo and the tests need on Debian 12 (bookworm): Mesa (GLX, EGL,
# OSMesa; llvmpipe renders without a GPU), Xvfb, the real GL programs the tests run
# (mesa-utils, glmark2, chromium-bsu, extremetuxracer: a sky box around the eye, openarena: a
# first-person weapon in id Tech 3's depth-range hack, minetest: a voxel game through Irrlicht,
# shaders on and off, f3d: a VTK viewer, xscreensaver's GL hacks), apitrace (deterministic
# replays), hyperfine (benchmarks), python3-pip (NVIDIA's FLIP from PyPI for bench-trade), ffmpeg (--record, holoinject quilt of a video) and xdotool
# (the live-control hotkey test, driving Extreme Tux Racer's menus), wine64 and mingw-w64
# (a Direct3D 9 program built for Windows, drawn by Wine's wined3d through OpenGL).
set -euo pipefail

packages=(
  xvfb xauth
  libgl1-mesa-dri libglx-mesa0 libegl-mesa0 libgl-dev libegl-dev libgles-dev libx11-dev libosmesa6-dev
  mesa-utils mesa-utils-bin glmark2-x11 glmark2-es2-x11
  apitrace apitrace-tracers chromium-bsu extremetuxracer openarena f3d xscreensaver-gl
  glslang-tools hyperfine python3-numpy python3-matplotlib python3-pil python3-pip
  ffmpeg minetest
  xdotool
  wine64 gcc-mingw-w64-x86-64
)

sudo=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "setup: need root or sudo to install packages" >&2; exit 1; }
  sudo="sudo"
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}" >&2
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
# NVIDIA's FLIP for scripts/bench-trade.py is on PyPI only; the tests do not need it, so a
# failure (no python3-pip, no network) only warns.
/usr/bin/python3 -c 'import flip_evaluator' 2>/dev/null || $sudo /usr/bin/python3 -m pip install -q --break-system-packages flip-evaluator >/dev/null 2>&1 || echo "setup: warning: pip could not install flip-evaluator (python3-pip installed?): scripts/bench-trade.py reports no FLIP" >&2

if ! command -v cargo >/dev/null; then
  echo "setup: Rust is missing: install it with rustup (https://rustup.rs); Debian's cargo is too old for edition 2024" >&2
  exit 1
fi
# scripts/test.sh runs clippy and rustfmt before the tests.
if ! cargo clippy --version >/dev/null 2>&1 || ! cargo fmt --version >/dev/null 2>&1; then
  if ! command -v rustup >/dev/null; then
    echo "setup: cargo clippy or cargo fmt is missing and there is no rustup to add them: install your toolchain's clippy and rustfmt" >&2
    exit 1
  fi
  echo "setup: adding the clippy and rustfmt components" >&2
  rustup component add clippy rustfmt
fi
echo "setup: ok ($(cargo --version))" >&2
