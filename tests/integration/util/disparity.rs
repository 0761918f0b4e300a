//! Block agreement of a fast mode's quilt with exact's quilt of the same frame: the measure of
//! `scripts/disparity_blocks.py` (`agreement`), ported so that tests need no Python. Read that
//! module's doc for the definitions; in short: the centre tile is cut into 16x16 blocks, a
//! block is textured when the standard deviation of its luminance (Rec. 601) reaches
//! `texture` levels, its shift in a view is the integer offset in ±`max` px minimising the SSD
//! of RGB (offsets that leave the tile are not tried; ties go to the smallest |offset|, the
//! negative one first), distinct when at most `DISTINCT` times the mean SSD and not at the end
//! of the search, unique when no other valley more than `AGREE_PX` away comes within
//! 1/`UNIQUE` of it. A block is matched when exact's shift is distinct and unique in both
//! outermost views, and agrees when the fast mode shows it distinctly there too, within
//! `AGREE_PX` of exact's, in both.

use super::image::{Image, tile};

const BLOCK: u32 = 16;
pub const AGREE_PX: i32 = 2;
const DISTINCT: f64 = 0.5;
const UNIQUE: f64 = 0.7;
const LUMA: [f64; 3] = [0.299, 0.587, 0.114];

/// What `agreement` measured (the fields of the script's dict of the same names).
#[derive(Debug, Clone)]
pub struct Agreement {
    pub blocks: usize,
    pub textured: usize,
    pub matched: usize,
    pub not_found: usize,
    /// Matched blocks that agree, in % (NaN when none matched).
    pub agree_pct: f64,
    /// Textured blocks that agree (matched or not), in % of the textured ones.
    pub agree_pct_textured: f64,
    /// Median and 95th percentile of |shift_exact - shift_fast| (px), both outer views pooled.
    pub median_d: f64,
    pub p95_d: f64,
    /// 10th and 90th percentile of exact's shifts in the rightmost view (matched blocks).
    pub exact_p10_p90: (f64, f64),
    /// The fast mode's shifts there, of the matched blocks it shows distinctly.
    pub fast_p10_p90: (f64, f64),
}

fn px(t: &Image, x: u32, y: u32) -> [f64; 3] {
    let i = ((y * t.width + x) * 3) as usize;
    [t.rgb[i] as f64, t.rgb[i + 1] as f64, t.rgb[i + 2] as f64]
}

/// Luminance standard deviation of block (bx, by).
fn luma_std(t: &Image, bx: u32, by: u32) -> f64 {
    let (mut s, mut s2) = (0.0, 0.0);
    for y in by * BLOCK..(by + 1) * BLOCK {
        for x in bx * BLOCK..(bx + 1) * BLOCK {
            let p = px(t, x, y);
            let l = p[0] * LUMA[0] + p[1] * LUMA[1] + p[2] * LUMA[2];
            s += l;
            s2 += l * l;
        }
    }
    let n = f64::from(BLOCK * BLOCK);
    (s2 / n - (s / n).powi(2)).max(0.0).sqrt()
}

/// One block's match: (shift, distinct, unique).
fn match_block(centre: &Image, view: &Image, bx: u32, by: u32, max: i32) -> (i32, bool, bool) {
    let shifts: Vec<i32> = (-max..=max).collect();
    let (x0, y0) = ((bx * BLOCK) as i32, by * BLOCK);
    let ssd: Vec<f64> = shifts
        .iter()
        .map(|&dx| {
            if x0 + dx < 0 || x0 + dx + BLOCK as i32 > view.width as i32 {
                return f64::INFINITY;
            }
            let mut e = 0.0;
            for y in y0..y0 + BLOCK {
                for x in 0..BLOCK {
                    let (a, b) = (px(centre, x0 as u32 + x, y), px(view, (x0 + dx) as u32 + x, y));
                    e += (0..3).map(|c| (a[c] - b[c]).powi(2)).sum::<f64>();
                }
            }
            e
        })
        .collect();
    // Smallest SSD; ties to the smallest |shift|, the negative one first (numpy's stable sort).
    let mut order: Vec<usize> = (0..shifts.len()).collect();
    order.sort_by_key(|&k| shifts[k].abs());
    let k = order
        .iter()
        .copied()
        .fold(order[0], |b, k| if ssd[k] < ssd[b] { k } else { b });
    let (best, shift) = (ssd[k], shifts[k]);
    let finite: Vec<f64> = ssd.iter().copied().filter(|e| e.is_finite()).collect();
    let mean = finite.iter().sum::<f64>() / finite.len().max(1) as f64;
    let distinct = best <= DISTINCT * mean && shift.abs() < max && finite.len() > 2;
    let at = |i: isize| {
        if i < 0 || i as usize >= ssd.len() {
            f64::INFINITY
        } else {
            ssd[i as usize]
        }
    };
    let other = (0..ssd.len())
        .filter(|&i| {
            let e = ssd[i];
            e.is_finite() && e <= at(i as isize - 1) && e <= at(i as isize + 1) && (shifts[i] - shift).abs() > AGREE_PX
        })
        .map(|i| ssd[i])
        .fold(f64::INFINITY, f64::min);
    (shift, distinct, best <= UNIQUE * other)
}

fn percentile(v: &mut [f64], q: f64) -> f64 {
    // numpy's default (linear) percentile.
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let r = (v.len() - 1) as f64 * q / 100.0;
    let (lo, hi) = (r.floor() as usize, r.ceil() as usize);
    v[lo] + (v[hi] - v[lo]) * (r - lo as f64)
}

/// The agreement of quilt `fast` with quilt `exact` (both `cols`x`rows`, same layout) over
/// their outermost views, view 0 and view N-1, against the centre view N/2.
pub fn agreement(exact: &Image, fast: &Image, (cols, rows): (u32, u32), texture: f64, max: i32) -> Agreement {
    let n = cols * rows;
    let te: Vec<Image> = [n / 2, 0, n - 1].iter().map(|&i| tile(exact, cols, rows, i)).collect();
    let ts: Vec<Image> = [n / 2, 0, n - 1].iter().map(|&i| tile(fast, cols, rows, i)).collect();
    let (bw, bh) = (te[0].width / BLOCK, te[0].height / BLOCK);
    let (mut textured, mut matched, mut not_found, mut agree_m, mut agree_t) = (0, 0, 0, 0, 0);
    let (mut diffs, mut exact_right, mut fast_right) = (Vec::new(), Vec::new(), Vec::new());
    for by in 0..bh {
        for bx in 0..bw {
            if luma_std(&te[0], bx, by) < texture {
                continue;
            }
            textured += 1;
            let (mut m, mut found, mut agree, mut d) = (true, true, true, Vec::new());
            let (mut right_e, mut right_s) = (None, None);
            for v in [1, 2] {
                let (se, de, ue) = match_block(&te[0], &te[v], bx, by, max);
                let (ss, ds, _) = match_block(&ts[0], &ts[v], bx, by, max);
                m &= de && ue;
                found &= ds;
                d.push(f64::from((se - ss).abs()));
                agree &= (se - ss).abs() <= AGREE_PX;
                if v == 2 {
                    right_e = Some(f64::from(se));
                    right_s = ds.then_some(f64::from(ss));
                }
            }
            let agree = agree && found;
            if m {
                exact_right.extend(right_e);
                fast_right.extend(right_s);
                matched += 1;
                agree_m += usize::from(agree);
                not_found += usize::from(!found);
                if found {
                    diffs.extend(d);
                }
            }
            agree_t += usize::from(agree);
        }
    }
    let pct = |a: usize, of: usize| {
        if of == 0 {
            f64::NAN
        } else {
            100.0 * a as f64 / of as f64
        }
    };
    Agreement {
        blocks: (bw * bh) as usize,
        textured,
        matched,
        not_found,
        agree_pct: pct(agree_m, matched),
        agree_pct_textured: pct(agree_t, textured),
        median_d: percentile(&mut diffs.clone(), 50.0),
        p95_d: percentile(&mut diffs, 95.0),
        exact_p10_p90: (percentile(&mut exact_right, 10.0), percentile(&mut exact_right, 90.0)),
        fast_p10_p90: (percentile(&mut fast_right, 10.0), percentile(&mut fast_right, 90.0)),
    }
}
