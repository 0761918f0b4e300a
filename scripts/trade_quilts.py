"""What scripts/bench-trade.py measures in two quilts of the same frame, exact's and a fast
mode's (DESIGN §6): FLIP and PSNR of the views the mode synthesised, and their disparity error.

Synthesised views are the views the mode does not render, derived from the mode as the layer's
view plan does (src/multiview/fast/plan.rs): `synth` and `synth:pixel` render the centre view
N/2, `hybrid:K[:pixel]` K evenly spaced views including both ends. The views a mode renders
are exact's and do not count, whatever they hold (when they are not bit-identical to exact's,
the caller says so).

- FLIP: NVIDIA's reference implementation (`flip_evaluator`, LDR, its default 67 pixels per
  degree) of each synthesised tile against exact's same tile, as 8-bit sRGB; the mean of its
  per-pixel error map. Mean over the synthesised views, and the worst (largest) view.
- PSNR: per tile over RGB, as the layer's `--measure-error` computes it (identical tiles count
  as 100 dB), to check these quilts against the layer's own in-process measurement.
- Disparity error: the textured 16x16 blocks of exact's centre view (disparity_blocks.py:
  Rec. 601 luminance std >= TEXTURE levels) are searched for in view i of exact and of the
  mode (integer horizontal shift minimising the SSD of RGB, disparity_blocks.match). A block
  counts in view i when exact's minimum there is distinct and unique (flat and periodic content
  has no shift to compare); the error is |shift_exact - shift_mode| in tile px, pooled over
  the blocks and synthesised views; blocks the mode shows nowhere distinctly are "not found"
  and counted apart. The search in view i reaches max(MIN_SHIFT, per_view * |i - N/2|) px:
  the default depthiness puts infinity 4 px further per view, so 8 px per view also covers
  content up to three times nearer than the convergence plane.
"""
import math

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view

import disparity_blocks
from disparity_blocks import BLOCK, load_tiles, luma_std, psnr, spaced

TEXTURE = 8.0
MIN_SHIFT = 16


def rendered_views(mode, n):
    """The views `mode` renders (ascending), or None when the mode does not fix them (`auto`
    picks K per frame)."""
    m = mode.partition("+")[0]
    if m == "exact":
        return list(range(n))
    if m in ("synth", "synth:pixel"):
        return [n // 2]
    if m.startswith("hybrid:"):
        return spaced(int(m.split(":")[1]), n)
    return None


def flip_module():
    """NVIDIA's FLIP (pip package flip-evaluator), or None when it is not installed."""
    try:
        import flip_evaluator
        return flip_evaluator
    except ImportError:
        return None


def flip_of(flip, ref, test):
    """Mean FLIP of one tile (float 0..255 RGB arrays) against its reference."""
    _, mean, _ = flip.evaluate(ref / 255.0, test / 255.0, "LDR", applyMagma=False)
    return float(mean)


def per_view(te, tm, views, fn):
    """(mean, worst value, worst view) of fn over `views`; worst = the largest fn."""
    vals = [fn(te[i], tm[i]) for i in views]
    k = int(np.argmax(vals))
    return float(np.mean(vals)), float(vals[k]), views[k]


def block_ssd(centre, view, shifts):
    """disparity_blocks.block_ssd computed as |block|^2 - 2 block.window + |window|^2, the
    cross terms of a row of blocks against every window of the view's strip in one matrix
    product: some 40 times faster for the hundreds of shifts of 48 views. In float64, where
    8-bit sums are exact (block_ssd's float32 rounds above 2^24)."""
    h, w, _ = centre.shape
    by, bx = h // BLOCK, w // BLOCK
    pos = np.arange(bx)[None, :] * BLOCK + shifts[:, None]  # window start of (shift, block)
    valid = (pos >= 0) & (pos <= w - BLOCK)  # offsets that leave the tile are not tried
    pos = np.clip(pos, 0, w - BLOCK)
    cols = np.arange(bx)[None, :]
    out = np.empty((len(shifts), by, bx), dtype=np.float64)
    for r in range(by):
        rows = slice(r * BLOCK, (r + 1) * BLOCK)
        blocks = centre[rows, :bx * BLOCK].astype(np.float64).reshape(BLOCK, bx, BLOCK, 3)
        blocks = blocks.transpose(1, 0, 2, 3).reshape(bx, -1)
        # (y, start, channel, x) -> (start, y, x, channel): the blocks' element order.
        win = sliding_window_view(view[rows].astype(np.float64), BLOCK, axis=1)
        win = win.transpose(1, 0, 3, 2).reshape(w - BLOCK + 1, -1)
        cross = blocks @ win.T
        ssd = (blocks ** 2).sum(1)[cols] - 2 * cross[cols, pos] + (win ** 2).sum(1)[pos]
        out[:, r] = np.where(valid, np.maximum(ssd, 0), np.inf)
    return out


def match(centre, view, max_shift):
    """disparity_blocks.match on this module's block_ssd."""
    return disparity_blocks.match(centre, view, max_shift, ssd_of=block_ssd)


class ExactShifts:
    """Shifts of exact's centre blocks in exact's views, kept per (quilt, view): every mode of a
    scene/N/tile is compared with the same exact quilt."""

    def __init__(self):
        self.done = {}

    def get(self, path, te, view, reach):
        key = (path, view, reach)
        if key not in self.done:
            self.done[key] = match(te[len(te) // 2], te[view], reach)
        return self.done[key]


def reach(view, centre, width, per_view_px):
    """Search range (px) in `view`: grows with the view's distance from the centre; a block
    cannot move further than the tile is wide."""
    return int(min(width - 16, max(MIN_SHIFT, math.ceil(per_view_px * abs(view - centre)))))


def disparity_error(exact_path, te, tm, views, per_view_px, cache):
    """{'disp_median', 'disp_p95', 'disp_blocks', 'disp_not_found'} over `views` (module doc)."""
    centre = len(te) // 2
    textured = luma_std(te[centre]) >= TEXTURE
    diffs, counted, lost = [], 0, 0
    for i in views:
        r = reach(i, centre, te[0].shape[1], per_view_px)
        se, de, ue = cache.get(exact_path, te, i, r)
        sm, dm, _ = match(te[centre], tm[i], r)
        ok = textured & de & ue
        counted += int(ok.sum())
        lost += int((ok & ~dm).sum())
        diffs.append(np.abs(se - sm)[ok & dm].astype(float))
    pooled = np.concatenate(diffs) if diffs else np.zeros(0)
    out = {"disp_blocks": counted, "disp_not_found": lost}
    if pooled.size:
        out["disp_median"], out["disp_p95"] = float(np.median(pooled)), float(np.percentile(pooled, 95))
    return out


def compare(exact_path, mode_path, cols, rows, rendered, per_view_px, cache, flip):
    """Every figure of one mode's quilt against exact's quilt of the same frame."""
    te, tm = load_tiles(exact_path, cols, rows), load_tiles(mode_path, cols, rows)
    views = [i for i in range(len(te)) if i not in rendered]
    r = {"synth_views": views,
         "rendered_identical": all(np.array_equal(te[i], tm[i]) for i in rendered)}
    if not views:
        return r
    # PSNR's "worst" is the smallest: negate to share per_view's largest-is-worst.
    m, w, v = per_view(te, tm, views, lambda a, b: -psnr(a, b))
    r["q_psnr_mean"], r["q_psnr_worst"], r["q_psnr_worst_view"] = -m, -w, v
    if flip is not None:
        r["flip_mean"], r["flip_worst"], r["flip_worst_view"] = per_view(te, tm, views, lambda a, b: flip_of(flip, a, b))
    r.update(disparity_error(exact_path, te, tm, views, per_view_px, cache))
    return r
