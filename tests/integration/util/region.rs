//! Where one object of a frame moves between the views of a quilt, by masked block matching,
//! and whether a fast mode (`--mode synth`, `hybrid:K`) moves it as `--mode exact` does.
//!
//! The object is given as a mask of the centre view (which pixels are the object: how each
//! test finds it is its own business). The centre view is cut into 16x16 blocks; a block
//! belongs to the object when most of its pixels do. Its shift in a view is the integer
//! offset in ±`max` px minimising the sum of squared RGB differences over the block's object
//! pixels only (the background around the object moves otherwise and must not pull the
//! match): the same measure as scripts/disparity_blocks.py, restricted to the mask. A shift
//! is trusted in exact's quilt only when it is distinct (at most `DISTINCT` times the mean
//! error over the offsets tried, and not at the end of the search) and unique (no other
//! valley of the error curve more than 2 px away within 1/`UNIQUE` of it), in both
//! outermost views: flat metal or repeated texture has no shift to compare.

use super::image::{Image, tile};

const BLOCK: u32 = 16;
/// A block is the object's when at least this share of its pixels are.
const COVER: f64 = 0.75;
/// Best error at most this share of the mean error over the offsets tried.
const DISTINCT: f64 = 0.5;
/// No other valley (more than `VALLEY_PX` away) within 1/UNIQUE of the best.
const UNIQUE: f64 = 0.7;
const VALLEY_PX: i32 = 2;

/// A mask over an image of `width`x`height`, row-major, top-down.
pub struct Mask {
    pub width: u32,
    pub height: u32,
    pub bits: Vec<bool>,
}

impl Mask {
    /// Pixels where `a` and `b` differ by more than `threshold` levels in some channel.
    pub fn differing(a: &Image, b: &Image, threshold: u8) -> Mask {
        assert_eq!(
            (a.width, a.height),
            (b.width, b.height),
            "the two frames differ in size"
        );
        let bits = a
            .rgb
            .chunks(3)
            .zip(b.rgb.chunks(3))
            .map(|(p, q)| p.iter().zip(q).any(|(x, y)| x.abs_diff(*y) > threshold))
            .collect();
        Mask {
            width: a.width,
            height: a.height,
            bits,
        }
    }

    pub fn at(&self, x: u32, y: u32) -> bool {
        self.bits[(y * self.width + x) as usize]
    }

    pub fn count(&self) -> usize {
        self.bits.iter().filter(|&&b| b).count()
    }

    /// The smallest rectangle holding every masked pixel: (x0, y0, x1, y1), ends exclusive.
    pub fn bounds(&self) -> Option<(u32, u32, u32, u32)> {
        let mut r: Option<(u32, u32, u32, u32)> = None;
        for y in 0..self.height {
            for x in 0..self.width {
                if self.at(x, y) {
                    let (x0, y0, x1, y1) = r.unwrap_or((x, y, x + 1, y + 1));
                    r = Some((x0.min(x), y0.min(y), x1.max(x + 1), y1.max(y + 1)));
                }
            }
        }
        r
    }

    /// The top-left corners of the blocks that are the object's (at least 75 % masked).
    pub fn blocks(&self) -> Vec<(u32, u32)> {
        let mut out = Vec::new();
        for y0 in (0..=self.height - BLOCK).step_by(BLOCK as usize) {
            for x0 in (0..=self.width - BLOCK).step_by(BLOCK as usize) {
                let n = (y0..y0 + BLOCK)
                    .flat_map(|y| (x0..x0 + BLOCK).map(move |x| (x, y)))
                    .filter(|&(x, y)| self.at(x, y))
                    .count();
                if n as f64 >= COVER * f64::from(BLOCK * BLOCK) {
                    out.push((x0, y0));
                }
            }
        }
        out
    }
}

/// One block's shift in one view: the best integer offset (the block's content found that
/// many px to the right), and whether it is distinct and unique.
#[derive(Clone, Copy, Debug)]
pub struct Match {
    pub shift: i32,
    pub distinct: bool,
    pub unique: bool,
}

/// The shift of the object's pixels of block (x0, y0) of `centre` in `view`, searched in
/// ±`max` px (offsets that put the block outside the tile are not tried).
pub fn masked_shift(centre: &Image, view: &Image, mask: &Mask, (x0, y0): (u32, u32), max: i32) -> Match {
    let w = centre.width as i32;
    let px = |img: &Image, x: u32, y: u32| {
        let i = ((y * img.width + x) * 3) as usize;
        [img.rgb[i], img.rgb[i + 1], img.rgb[i + 2]].map(f64::from)
    };
    let errors: Vec<Option<f64>> = (-max..=max)
        .map(|dx| {
            if (x0 as i32 + dx) < 0 || x0 as i32 + dx + BLOCK as i32 > w {
                return None;
            }
            let mut e = 0.0;
            for y in y0..y0 + BLOCK {
                for x in x0..x0 + BLOCK {
                    if mask.at(x, y) {
                        let (a, b) = (px(centre, x, y), px(view, (x as i32 + dx) as u32, y));
                        e += (0..3).map(|c| (a[c] - b[c]).powi(2)).sum::<f64>();
                    }
                }
            }
            Some(e)
        })
        .collect();
    let tried: Vec<f64> = errors.iter().flatten().copied().collect();
    // Ties go to the smallest |offset|, as in scripts/disparity_blocks.py.
    let (best, e0) = errors
        .iter()
        .enumerate()
        .filter_map(|(k, e)| Some((k, (*e)?)))
        .min_by(|a, b| {
            let off = |k: usize| (k as i32 - max).abs();
            a.1.total_cmp(&b.1).then(off(a.0).cmp(&off(b.0)))
        })
        .expect("no offset tried");
    let shift = best as i32 - max;
    let mean = tried.iter().sum::<f64>() / tried.len() as f64;
    let distinct = tried.len() > 2 && shift.abs() < max && e0 <= DISTINCT * mean;
    let valley = |k: usize| {
        let e = errors[k].unwrap_or(f64::INFINITY);
        let l = if k > 0 {
            errors[k - 1].unwrap_or(f64::INFINITY)
        } else {
            f64::INFINITY
        };
        let r = errors.get(k + 1).copied().flatten().unwrap_or(f64::INFINITY);
        errors[k].is_some() && e <= l && e <= r
    };
    let rival = (0..errors.len())
        .filter(|&k| (k as i32 - best as i32).abs() > VALLEY_PX && valley(k))
        .filter_map(|k| errors[k])
        .fold(f64::INFINITY, f64::min);
    Match {
        shift,
        distinct,
        unique: e0 <= UNIQUE * rival,
    }
}

/// One object block in the outermost views, exact against a fast mode.
#[derive(Debug)]
pub struct BlockPair {
    pub at: (u32, u32),
    /// Exact's shift in the first and last view.
    pub exact: [i32; 2],
    /// The fast mode's, `None` where it shows the block nowhere distinctly.
    pub fast: [Option<i32>; 2],
}

impl BlockPair {
    /// The fast mode's shift is within `px` of exact's in both outermost views.
    pub fn agrees(&self, px: i32) -> bool {
        self.exact
            .iter()
            .zip(&self.fast)
            .all(|(e, f)| f.is_some_and(|f| (f - e).abs() <= px))
    }

    /// |fast - exact|, the larger of the two views (`None`: not found in one of them).
    pub fn error(&self) -> Option<i32> {
        let d: Option<Vec<i32>> = self
            .exact
            .iter()
            .zip(&self.fast)
            .map(|(e, f)| Some((f.as_ref()? - e).abs()))
            .collect();
        d?.into_iter().max()
    }
}

/// What `compare_outer_views` found: the object's blocks, those exact shows with a
/// trustworthy shift in both outermost views, and each of those against the fast mode.
pub struct RegionDisparity {
    pub blocks: usize,
    pub matched: Vec<BlockPair>,
}

impl RegionDisparity {
    pub fn agreeing(&self, px: i32) -> usize {
        self.matched.iter().filter(|b| b.agrees(px)).count()
    }

    pub fn share_agreeing(&self, px: i32) -> f64 {
        self.agreeing(px) as f64 / self.matched.len().max(1) as f64
    }

    /// Median over the matched blocks of exact's shift (first or last view) and of the
    /// fast mode's (blocks it shows nowhere left out).
    pub fn medians(&self, view: usize) -> (f64, f64) {
        let mut e: Vec<f64> = self.matched.iter().map(|b| f64::from(b.exact[view])).collect();
        let mut f: Vec<f64> = self
            .matched
            .iter()
            .filter_map(|b| b.fast[view].map(f64::from))
            .collect();
        e.sort_by(f64::total_cmp);
        f.sort_by(f64::total_cmp);
        (super::quantile(&e, 0.5), super::quantile(&f, 0.5))
    }

    /// The largest |exact shift| over the matched blocks, both views.
    pub fn largest_exact(&self) -> i32 {
        self.matched
            .iter()
            .flat_map(|b| b.exact.map(i32::abs))
            .max()
            .unwrap_or(0)
    }

    /// A one-line summary for reports and assertion messages.
    pub fn summary(&self, fast: &str) -> String {
        let ((e0, f0), (e1, f1)) = (self.medians(0), self.medians(1));
        let mut errs: Vec<f64> = self
            .matched
            .iter()
            .map(|b| b.error().map_or(f64::INFINITY, f64::from))
            .collect();
        errs.sort_by(f64::total_cmp);
        let missing = self.matched.iter().filter(|b| b.error().is_none()).count();
        format!(
            "{} blocks, {} with a trustworthy exact shift; {} of them ({:.0} %) within 1 px in {fast}; \
             median shift first/last view: exact {e0:+.0}/{e1:+.0} px, {fast} {f0:+.0}/{f1:+.0} px; \
             |{fast} - exact| median {:.0} px, 90th percentile {:.0} px{}",
            self.blocks,
            self.matched.len(),
            self.agreeing(1),
            100.0 * self.share_agreeing(1),
            super::quantile(&errs, 0.5),
            super::quantile(&errs, 0.9),
            if missing > 0 {
                format!(", {missing} not found in {fast}")
            } else {
                String::new()
            }
        )
    }
}

/// The object's blocks (`mask`, of the centre view) in the first and last views of two quilts
/// of `grid` views, exact and a fast mode, each against its own centre view, searched in
/// ±`max` px.
pub fn compare_outer_views(exact: &Image, fast: &Image, grid: (u32, u32), mask: &Mask, max: i32) -> RegionDisparity {
    let n = grid.0 * grid.1;
    let views = |q: &Image| [n / 2, 0, n - 1].map(|i| tile(q, grid.0, grid.1, i));
    let ([ec, e0, e1], [fc, f0, f1]) = (views(exact), views(fast));
    let blocks = mask.blocks();
    let mut matched = Vec::new();
    for &at in &blocks {
        let ex = [&e0, &e1].map(|v| masked_shift(&ec, v, mask, at, max));
        if !ex.iter().all(|m| m.distinct && m.unique) {
            continue;
        }
        let fa = [&f0, &f1].map(|v| masked_shift(&fc, v, mask, at, max));
        matched.push(BlockPair {
            at,
            exact: ex.map(|m| m.shift),
            fast: fa.map(|m| m.distinct.then_some(m.shift)),
        });
    }
    RegionDisparity {
        blocks: blocks.len(),
        matched,
    }
}

/// PSNR (dB, 8-bit RGB) of `b` against `a` inside the rectangle (x0, y0, x1, y1), ends
/// exclusive; `f64::INFINITY` when identical there.
pub fn psnr_in(a: &Image, b: &Image, (x0, y0, x1, y1): (u32, u32, u32, u32)) -> f64 {
    let mut se = 0.0;
    for y in y0..y1 {
        for x in x0..x1 {
            let i = ((y * a.width + x) * 3) as usize;
            se += (0..3)
                .map(|c| (f64::from(a.rgb[i + c]) - f64::from(b.rgb[i + c])).powi(2))
                .sum::<f64>();
        }
    }
    let mse = se / f64::from((x1 - x0) * (y1 - y0) * 3);
    if mse == 0.0 {
        f64::INFINITY
    } else {
        10.0 * (255.0f64 * 255.0 / mse).log10()
    }
}

/// What a viewer sees of an object that a fast mode shifts by `fast` px between the centre
/// and the rightmost view where exact shifts it by `exact` px (negative: in front of the
/// screen, as a nearer camera on the right sees it further left).
pub fn seen_depth(object: &str, mode: &str, exact: f64, fast: f64) -> String {
    let relation = match (exact < 0.0, fast < 0.0) {
        (true, true) if fast < exact => "further out of the screen (nearer) than exact shows it",
        (true, true) => "less far out of the screen than exact shows it (flattened)",
        (false, false) if fast > exact => "deeper behind the screen than exact shows it",
        (false, false) => "closer to the screen plane than exact shows it (flattened)",
        (true, false) => "behind the screen where exact shows it in front",
        (false, true) => "in front of the screen where exact shows it behind",
    };
    format!(
        "in --mode {mode} a viewer sees {object} {relation}: it shifts {fast:+.0} px from the centre \
         to the rightmost view where exact shifts it {exact:+.0} px (median over its blocks; negative \
         is in front of the screen)"
    )
}
