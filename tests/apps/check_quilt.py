#!/usr/bin/env python3
"""Check a reference quilt against a screenshot of the same frame.

usage: check_quilt.py SCREENSHOT QUILT COLS ROWS [MAX_DIFF_PX [MAX_LSB]]
The centre tile (odd COLS*ROWS) must equal the screenshot except for at most
MAX_DIFF_PX edge pixels (default 0), and the outermost views must differ from
it (horizontal parallax). Pixels whose channels all differ by at most MAX_LSB
(default 0) are reported but not counted. Needs pillow+numpy.

Why a tolerance exists at all: Mesa stores window-system framebuffers Y-flipped
(different edge rule / rounding) and a tile's viewport offset changes float
rounding of window coordinates, so an FBO tile can differ from the window at a
handful of edge pixels where depths tie. The same offset changes the float
rounding of interpolated varyings, which smooth shading and texture filtering
turn into scattered +-1 LSB differences (model, skybox): hence MAX_LSB.
The quilt itself is deterministic.
"""
import sys

import numpy as np
from PIL import Image


def tile(q, i, cols, rows, tw, th):
    # Row 0 of views is at the bottom of the GL image = bottom of the PNG.
    x, y = i % cols, i // cols
    top = (rows - 1 - y) * th
    return q[top:top + th, x * tw:(x + 1) * tw]


def main():
    shot = np.asarray(Image.open(sys.argv[1]).convert("RGB")).astype(int)
    quilt = np.asarray(Image.open(sys.argv[2]).convert("RGB")).astype(int)
    cols, rows = int(sys.argv[3]), int(sys.argv[4])
    th, tw = shot.shape[:2]
    assert quilt.shape[:2] == (rows * th, cols * tw), f"quilt shape {quilt.shape}"
    n = cols * rows
    assert len(np.unique(shot.reshape(-1, 3), axis=0)) > 8, "screenshot is nearly uniform"
    max_px = int(sys.argv[5]) if len(sys.argv) > 5 else 0
    max_lsb = int(sys.argv[6]) if len(sys.argv) > 6 else 0
    centre = tile(quilt, n // 2, cols, rows, tw, th)
    diff = np.abs(centre - shot).max(axis=2)
    bad = np.count_nonzero(diff > max_lsb)
    small = np.count_nonzero((diff > 0) & (diff <= max_lsb))
    print(f"centre tile vs screenshot: {bad} px differ" + (f" (+{small} px by <= {max_lsb} LSB)" if small else ""))
    assert bad <= max_px, f"centre tile != screenshot: {bad} px differ (> {max_px})"
    for i in (0, n - 1):
        d = np.count_nonzero(np.abs(tile(quilt, i, cols, rows, tw, th) - shot).any(axis=2))
        assert d > 100, f"view {i} shows no parallax ({d} px differ)"
        print(f"view {i}: {d} px differ from centre")
    state = "identical" if bad == 0 else f"{bad} edge px off"
    if small:
        state += f", {small} px off by <= {max_lsb} LSB"
    print(f"ok: centre tile {state}, side views differ")


if __name__ == "__main__":
    main()
