"""What scripts/disparity-agreement.py measures in two quilts of the same frame (DESIGN §6):
where exact and a fast mode put each textured block of the centre view in the outermost
views, and how close the views a mode synthesises are to exact's.

Blocks. The centre tile is cut into 16x16 blocks; a block is *textured* when the standard
deviation of its luminance (Rec. 601 luma of the 8-bit RGB) reaches a threshold. Its shift in
a view is the integer horizontal offset in [-max, +max] px minimising the sum of squared RGB
differences (offsets that put the block outside the tile are not tried; ties go to the
smallest |offset|). The minimum is *distinct* when it is at most DISTINCT times the mean over
the offsets tried and not at the end of the search (flat content, or a horizontal edge, has no
shift to find), and *unique* when no other valley of the SSD curve (a local minimum more than
AGREE_PX px away) comes within 1/UNIQUE of it (periodic texture — a checkerboard floor, a
plate of studs — matches at several offsets, and its "shift" is an alias).

A block is *matched* when its exact minimum is distinct and unique in both outermost views,
and it *agrees* when the fast mode shows it distinctly there too (else it is "not found") at
shifts within AGREE_PX px of exact's, in both views.
"""
import math

import numpy as np
from PIL import Image

BLOCK = 16
AGREE_PX = 2
DISTINCT = 0.5
UNIQUE = 0.7
IDENTICAL_DB = 100.0
LUMA = np.array([0.299, 0.587, 0.114], dtype=np.float32)


def load_tiles(path, cols, rows):
    """The quilt's views as float32 arrays (H, W, 3): view i at column i % cols, row i // cols
    from the bottom (DESIGN §4; the PNG is top-down)."""
    img = np.asarray(Image.open(path).convert("RGB"), dtype=np.float32)
    th, tw = img.shape[0] // rows, img.shape[1] // cols
    tiles = []
    for i in range(cols * rows):
        c, r = i % cols, rows - 1 - i // cols
        tiles.append(img[r * th:(r + 1) * th, c * tw:(c + 1) * tw])
    return tiles


def luma_std(tile):
    """Standard deviation of luminance per block, shape (rows of blocks, columns of blocks)."""
    y = tile @ LUMA
    by, bx = tile.shape[0] // BLOCK, tile.shape[1] // BLOCK
    return y[:by * BLOCK, :bx * BLOCK].reshape(by, BLOCK, bx, BLOCK).std(axis=(1, 3))


def block_ssd(centre, view, shifts):
    """SSD[k, by, bx] of each centre block against `view` moved by shifts[k] (the block's
    content found shifts[k] px to the right); inf where the block would leave the tile."""
    h, w, _ = centre.shape
    by, bx = h // BLOCK, w // BLOCK
    m = int(np.abs(shifts).max())
    pad = np.full((h, w + 2 * m, 3), np.nan, dtype=np.float32)
    pad[:, m:m + w] = view
    c = centre[:by * BLOCK, :bx * BLOCK]
    out = np.empty((len(shifts), by, bx), dtype=np.float64)
    for k, dx in enumerate(shifts):
        d = ((c - pad[:by * BLOCK, m + dx:m + dx + bx * BLOCK]) ** 2).sum(axis=2)
        out[k] = d.reshape(by, BLOCK, bx, BLOCK).sum(axis=(1, 3))
    out[np.isnan(out)] = np.inf
    return out


def match(centre, view, max_shift, ssd_of=None):
    """Per block of `centre`: (shift in `view`, distinct?, unique?), as the module says;
    `ssd_of` computes the SSDs as `block_ssd` does (a faster equivalent may be given)."""
    shifts = np.arange(-max_shift, max_shift + 1)
    ssd = (ssd_of or block_ssd)(centre, view, shifts)
    order = np.argsort(np.abs(shifts), kind="stable")
    k = order[ssd[order].argmin(axis=0)]
    best = np.take_along_axis(ssd, k[None], 0)[0]
    finite = np.isfinite(ssd)
    mean = np.where(finite, ssd, 0).sum(axis=0) / np.maximum(finite.sum(axis=0), 1)
    shift = shifts[k]
    distinct = (best <= DISTINCT * mean) & (np.abs(shift) < max_shift) & (finite.sum(axis=0) > 2)
    p = np.pad(ssd, ((1, 1), (0, 0), (0, 0)), constant_values=np.inf)
    valley = (ssd <= p[:-2]) & (ssd <= p[2:]) & finite
    elsewhere = np.abs(shifts[:, None, None] - shift[None]) > AGREE_PX
    unique = best <= UNIQUE * np.where(valley & elsewhere, ssd, np.inf).min(axis=0)
    return shift, distinct, unique


def agreement(te, ts, texture, max_shift):
    """Block agreement of quilt `ts` with quilt `te` (lists of tiles), over the outermost views."""
    n, centre = len(te), len(te) // 2
    std = luma_std(te[centre])
    textured = std >= texture
    matched, found, agree = textured.copy(), np.ones_like(textured), np.ones_like(textured)
    diffs, exact_right = [], None
    for v in (0, n - 1):
        se, de, ue = match(te[centre], te[v], max_shift)
        ss, ds, _ = match(ts[centre], ts[v], max_shift)
        matched &= de & ue
        found &= ds
        diffs.append(np.abs(se - ss))
        agree &= diffs[-1] <= AGREE_PX
        exact_right = se
    agree &= found
    both = matched & found
    pooled = np.concatenate([d[both] for d in diffs]).astype(float)
    sh = exact_right[matched].astype(float)
    pct = lambda m: 100.0 * agree[m].mean() if m.any() else float("nan")
    return {
        "blocks": int(std.size), "textured": int(textured.sum()), "matched": int(matched.sum()),
        "not_found_in_synth": int((matched & ~found).sum()),
        "agree_pct": pct(matched), "agree_pct_textured": pct(textured),
        "median_d": float(np.median(pooled)) if pooled.size else float("nan"),
        "p95_d": float(np.percentile(pooled, 95)) if pooled.size else float("nan"),
        # Does exact show depth at all: the spread of its shifts in the right-most view.
        "exact_shift_p10_p90": (float(np.percentile(sh, 10)), float(np.percentile(sh, 90))) if sh.size else None,
    }


def psnr(a, b):
    mse = float(((a - b) ** 2).mean())
    return IDENTICAL_DB if mse == 0 else min(IDENTICAL_DB, 10 * math.log10(255.0 ** 2 / mse))


def spaced(k, n):
    """K evenly spaced views of n including both ends (src/multiview/plan.rs `spaced`)."""
    k = max(1, min(k, n))
    if k == 1:
        return [n // 2]
    return sorted({int(math.floor(j * (n - 1) / (k - 1) + 0.5)) for j in range(k)})


def synthesised(te, tm, rendered):
    """PSNR (mean, worst, worst view) of the views of `tm` not in `rendered` against exact's,
    and which of them are black where exact's are not."""
    made = [i for i in range(len(te)) if i not in rendered]
    p = [psnr(te[i], tm[i]) for i in made]
    black = [i for i in made if tm[i].max() == 0 and te[i].max() > 0]
    if not p:
        return None, black, 0
    return (float(np.mean(p)), float(min(p)), made[int(np.argmin(p))]), black, sum(x >= IDENTICAL_DB for x in p)


def metrics(exact, synth, hybrid, cols, rows, texture, max_shift, hybrid_k):
    """Every figure of one program from its three quilts (PNG paths)."""
    te, ts, th = (load_tiles(q, cols, rows) for q in (exact, synth, hybrid))
    centre = cols * rows // 2
    r = {"centre_identical": bool(np.array_equal(te[centre], ts[centre])),
         "centre_diff_pixels": int((te[centre] != ts[centre]).any(axis=2).sum()),
         "centre_diff_max": int(np.abs(te[centre] - ts[centre]).max())}
    r.update(agreement(te, ts, texture, max_shift))
    r["synth_psnr"], r["synth_black_views"], r["synth_identical_views"] = synthesised(te, ts, [centre])
    rendered = spaced(hybrid_k, cols * rows)
    r["hybrid_psnr"], r["hybrid_black_views"], _ = synthesised(te, th, rendered)
    r["hybrid_rendered"] = rendered
    r["hybrid_rendered_identical"] = all(np.array_equal(te[i], th[i]) for i in rendered)
    return r
