//! One row of one target: the scan itself, and the pixels and settings it reads and writes
//! (laid out as the shader's storage).

/// A source pixel as `synth_pack.comp` stores it.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct SrcPixel {
    pub color: u32,
    pub depth: f32,
    pub parallax: f32,
}

/// A warped pixel as the resolve pass reads it: colour, and the depth's bits with the marks.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct OutPixel {
    pub color: u32,
    pub depth: u32,
}

pub(super) const HOLE: u32 = 0x8000_0000;
pub(super) const SECOND: u32 = 0x4000_0000;

/// The uniforms of synth_rows.comp.
#[derive(Clone, Copy, Debug)]
pub struct Settings {
    /// Pixels per unit of parallax, and of focus.
    pub px: (f32, f32),
    pub threshold: f32,
    pub reversed: bool,
    pub far_bias: f32,
    pub count_holes: bool,
    pub second_fills_holes: bool,
    /// Source columns beyond each side of the target row (the guard band): a source row is
    /// `width + 2 guard` pixels, its pixel `i` at target column `i - guard`.
    pub guard: usize,
}

/// One target: camera offsets from (second, preferred) source, their layers, and whether
/// there are two.
#[derive(Clone, Copy, Debug)]
pub struct TargetParams {
    pub du: [f32; 2],
    pub src: [usize; 2],
    pub two: bool,
}

/// One source pixel where it lands (see `land` in the shader).
#[derive(Clone, Copy)]
pub(super) struct Landed {
    pub(super) x: f32,
    pub(super) d: f32,
    pub(super) color: u32,
    pub(super) z: f32,
    pub(super) ok: bool,
}

/// `v.ceil() as i64`, without the library call that `ceil` is on baseline x86-64 (no SSE4.1):
/// it was a sixth of `over_holes`' time on asteroids.
pub(super) fn ceil(v: f32) -> i64 {
    let i = v as i64;
    if (i as f32) < v { i.saturating_add(1) } else { i }
}

/// Clamped to [0, 1], NaN to 0 (as llvmpipe's clamp returns the other operand).
fn unit(v: f32) -> f32 {
    if v > 0.0 { v.min(1.0) } else { 0.0 }
}

/// `mix` of two RGBA8 colours, two channels per multiply, rounded to nearest with the weight
/// in 1/256 steps (the shader's float mix and rounding: within one step of it).
fn mix_color(a: u32, b: u32, w: f32) -> u32 {
    if w <= 0.0 {
        return a;
    }
    if w >= 1.0 {
        return b;
    }
    // SAFETY: w is in (0, 1) here, so the value is in (0.5, 256.5): no saturation needed.
    let wb: u32 = unsafe { (w * 256.0 + 0.5).to_int_unchecked() };
    let wa = 256 - wb;
    const M: u32 = 0x00ff_00ff;
    let rb = ((a & M) * wa + (b & M) * wb + 0x0080_0080) >> 8 & M;
    let ga = ((a >> 8 & M) * wa + (b >> 8 & M) * wb + 0x0080_0080) & !M;
    rb | ga
}

fn mix(a: f32, b: f32, w: f32) -> f32 {
    if w <= 0.0 {
        a
    } else if w >= 1.0 {
        b
    } else {
        a * (1.0 - w) + b * w
    }
}

/// One row of one target being made.
pub(super) struct Row<'a> {
    pub(super) out: &'a mut [OutPixel],
    pub(super) width: usize,
    pub(super) s: &'a Settings,
    pub(super) first_scan: bool,
    pub(super) second: bool,
}

impl Row<'_> {
    fn nearer(&self, a: f32, b: f32) -> bool {
        if self.s.reversed { a >= b } else { a <= b }
    }

    pub(super) fn run<'s>(
        &mut self,
        t: &TargetParams,
        lands: &mut Lands,
        source: impl Fn(usize) -> &'s [SrcPixel],
    ) -> u64 {
        let [second, preferred] = t.src;
        if self.s.second_fills_holes {
            self.scan(lands, source(preferred), t.du[1]);
            self.first_scan = false;
            self.second = t.two;
            if t.two {
                self.scan(lands, source(second), t.du[0]);
            }
            self.row_done(t.two)
        } else {
            if t.two {
                self.scan(lands, source(second), t.du[0]);
                self.first_scan = false;
            }
            self.scan(lands, source(preferred), t.du[1]);
            self.row_done(false)
        }
    }

    fn put(&mut self, x: usize, color: u32, z: f32, hole: bool) {
        let o = &mut self.out[x];
        if self.first_scan {
            *o = OutPixel {
                color,
                depth: z.to_bits() | if hole { HOLE } else { 0 },
            };
            return;
        }
        let e = o.depth;
        let was = f32::from_bits(e & !(HOLE | SECOND));
        let nearer = if self.s.reversed { z >= was } else { z <= was };
        let write = if !self.second {
            nearer
        } else if e & HOLE != 0 {
            !hole || nearer
        } else {
            e & SECOND != 0 && !hole && nearer
        };
        if write {
            let mark = if hole {
                HOLE
            } else if self.second {
                SECOND
            } else {
                0
            };
            *o = OutPixel {
                color,
                depth: z.to_bits() | mark,
            };
        }
    }

    fn row_done(&mut self, marked: bool) -> u64 {
        if !marked && !self.s.count_holes {
            return 0;
        }
        let mut n = 0;
        for o in self.out.iter_mut() {
            o.depth &= !SECOND;
            n += u64::from(o.depth >> 31);
        }
        if self.s.count_holes { n } else { 0 }
    }

    pub(super) fn emit(&mut self, x: usize, a: &Landed, b: &Landed, edge_a: bool, edge_b: bool, dir: f32) {
        let c = x as f32 + 0.5;
        let thr = self.s.threshold;
        let border = edge_a || !a.ok || edge_b || !b.ok;
        let mut hole = false;
        let w = if border {
            let use_a = edge_b || !b.ok;
            let (landed, ok) = if use_a { (a.x, a.ok) } else { (b.x, b.ok) };
            hole = !ok || (c - landed).abs() >= 0.5;
            if use_a { 0.0 } else { 1.0 }
        } else if c >= b.x {
            1.0
        } else if (b.d - a.d).abs() <= thr {
            unit((c - a.x) / (b.x - a.x))
        } else if c < a.x + 0.5 {
            0.0
        } else if c >= b.x - 0.5 {
            1.0
        } else {
            hole = true;
            if self.nearer(b.z, a.z) { 0.0 } else { 1.0 }
        };
        let color = mix_color(a.color, b.color, w);
        let mut z = mix(a.z, b.z, w);
        if hole && !border {
            z = (z + self.s.far_bias).clamp(0.0, 1.0);
        }
        let at = if dir > 0.0 { x } else { self.width - 1 - x };
        self.put(at, color, z, hole);
    }

    #[inline]
    #[allow(clippy::too_many_arguments)]
    pub(super) fn over_holes(&mut self, a: &Landed, b: &Landed, cont: bool, c: f32, (h0, h1): (f32, f32), dir: f32) {
        let lo = if cont { a.x.min(b.x) } else { b.x - 0.5 };
        let hi = if cont { a.x.max(b.x) } else { b.x + 0.5 };
        let x0 = ceil(lo.max(h0) - 0.5).max(0);
        let x1 = ceil(hi.min((h1 + 0.5).min(c)) - 0.5).min(self.width as i64);
        if x0 >= x1 {
            return;
        }
        let was = self.first_scan;
        self.first_scan = false;
        for x in x0..x1 {
            let w = if cont {
                unit((x as f32 + 0.5 - a.x) / (b.x - a.x))
            } else {
                1.0
            };
            let x = x as usize;
            let at = if dir > 0.0 { x } else { self.width - 1 - x };
            self.put(at, mix_color(a.color, b.color, w), mix(a.z, b.z, w), false);
        }
        self.first_scan = was;
    }

    /// The target row from one source row: the merge of the source walk and the target walk
    /// in occlusion order, as `scan` in the shader (whose comments say why it is right).
    /// The shader takes one step of either walk per iteration so that SIMD lanes stay in step;
    /// here the source walk runs ahead in an inner loop over landing points made beforehand
    /// (`Lands`), and a target pixel inside a piece (the common case: no edge, no hole) takes
    /// a short path: the same steps in the same order, and each pixel the same value as
    /// `emit` gives it (tested against the shader's order).
    pub(super) fn scan(&mut self, lands: &mut Lands, row: &[SrcPixel], du: f32) {
        let (k, f) = (du * self.s.px.0, du * self.s.px.1);
        // The band's columns this target can see (`band_used`), the rest left out of the walk.
        let g = band_used(k, f, self.s.guard);
        let row = &row[self.s.guard - g..][..self.width + 2 * g];
        // Scanned in the direction nearer pixels move.
        if k > 0.0 {
            self.scan_towards::<true>(lands, row, (k, f), g);
        } else {
            self.scan_towards::<false>(lands, row, (k, f), g);
        }
    }

    pub(super) fn scan_towards<const MIRRORED: bool>(
        &mut self,
        lands: &mut Lands,
        row: &[SrcPixel],
        (k, f): (f32, f32),
        guard: usize,
    ) {
        let (width, thr) = (self.width, self.s.threshold);
        // The source row, guard band included (mirrored, its columns still sit `guard` left
        // of the target's: the band is as wide on both sides).
        let sw = width + 2 * guard;
        let dir = if MIRRORED { -1.0 } else { 1.0 };
        let row = &row[..sw];
        let src = |i: usize| if MIRRORED { &row[sw - 1 - i] } else { &row[i] };
        lands.make(sw, src, (dir * k, dir * f), thr, guard);
        let (xs, ds, reach) = (&lands.x[..sw], &lands.d[..sw], &lands.reach[..sw]);
        let landed = |i: usize| {
            let p = src(i);
            Landed {
                x: xs[i],
                d: ds[i],
                color: p.color,
                z: p.depth,
                ok: xs[i] > OFF_ROW,
            }
        };
        let mut t = 0usize;
        let (mut h0, mut h1) = (1.0e30f32, -1.0e30f32);
        let mut front = -1.0e30f32;
        let mut x = 0;
        while x < width {
            let c = x as f32 + 0.5;
            while t < sw && reach[t] <= c {
                let bx = xs[t];
                if t > 0 && bx + 0.5 > h0 && bx < front - 0.5 && bx > OFF_ROW && xs[t - 1] > OFF_ROW {
                    let (a, b) = (landed(t - 1), landed(t));
                    if a.x.min(b.x) < h1 + 0.5 {
                        self.over_holes(&a, &b, (b.d - a.d).abs() <= thr, c, (h0, h1), dir);
                    }
                }
                front = front.max(bx);
                t += 1;
            }
            let at = |x: usize| if MIRRORED { width - 1 - x } else { x };
            if t > 0 && t < sw {
                let (ax, bx) = (xs[t - 1], xs[t]);
                let on_row = ax > OFF_ROW && bx > OFF_ROW;
                let (pa, pb) = (src(t - 1), src(t));
                if c < bx && on_row && (ds[t] - ds[t - 1]).abs() <= thr {
                    // Inside a piece: `emit`'s interpolation, nothing marked.
                    let w = unit((c - ax) / (bx - ax));
                    self.put(
                        at(x),
                        mix_color(pa.color, pb.color, w),
                        mix(pa.depth, pb.depth, w),
                        false,
                    );
                    x += 1;
                    continue;
                }
                if on_row && c >= ax + 0.5 && c < bx - 0.5 {
                    // A gap between the two sides of a depth edge (`emit`'s hole): every target
                    // pixel up to the far side's half pixel takes the farther side, pushed back.
                    // The source walk stays: the far side reaches beyond the gap.
                    let far = if self.nearer(pb.depth, pa.depth) { pa } else { pb };
                    let z = (far.depth + self.s.far_bias).clamp(0.0, 1.0);
                    h0 = h0.min(c);
                    while x < width && x as f32 + 0.5 < bx - 0.5 {
                        self.put(at(x), far.color, z, true);
                        x += 1;
                    }
                    h1 = x as f32 - 0.5;
                    continue;
                }
            }
            let (a, b) = (landed(t.saturating_sub(1)), landed(t.min(sw - 1)));
            self.emit(x, &a, &b, t == 0, t >= sw, dir);
            x += 1;
        }
    }
}

/// The guard band's columns (of `guard`) a scan moving pixels by `k p + f` can bring into the
/// row: what moves in from beyond the edge at parallax -1 (half the convergence distance) to 1
/// (infinity), and one more for the piece it ends. Fewer band columns, less of a walk: a
/// target next to its source scans none of a band made for the outermost one.
pub(super) fn band_used(k: f32, f: f32, guard: usize) -> usize {
    if guard == 0 {
        return 0;
    }
    let reach = f.abs().max((k + f).abs()).max((f - k).abs());
    // All of it past its width, and for shifts not finite (the shader's int() of either is
    // undefined, and max() of a NaN either operand).
    if !(k.abs() < 1.0e30 && f.abs() < 1.0e30 && reach < guard as f32) {
        return guard;
    }
    (ceil(reach) as usize + 1).min(guard)
}

/// Where a pixel that lands off the row is put (`land` in the shader): below every target
/// pixel, so that the walk passes it at once.
const OFF_ROW_X: f32 = -1.0e30;
/// Every landing point above this is on the row.
const OFF_ROW: f32 = -1.0e29;

/// Where each pixel of a source row lands in the target, in scan order (`land` in the
/// shader), and how far it reaches: the point beyond which the target walk has passed it
/// (half a pixel more at a depth edge, where it keeps its own half pixel). Kept per thread.
#[derive(Default)]
pub(super) struct Lands {
    x: Vec<f32>,
    d: Vec<f32>,
    reach: Vec<f32>,
}

impl Lands {
    /// `k`, `f`: the shift per unit of parallax and the constant shift, signed for the scan;
    /// source pixel `i` sits at target column `i - guard`.
    fn make<'r>(
        &mut self,
        width: usize,
        src: impl Fn(usize) -> &'r SrcPixel,
        (k, f): (f32, f32),
        thr: f32,
        guard: usize,
    ) {
        self.x.resize(width, 0.0);
        self.d.resize(width, 0.0);
        self.reach.resize(width, 0.0);
        let (xs, ds) = (&mut self.x[..width], &mut self.d[..width]);
        for i in 0..width {
            let d = k * src(i).parallax + f;
            let x = (i as isize - guard as isize) as f32 + 0.5 + d;
            xs[i] = if x.abs() < 1.0e6 { x } else { OFF_ROW_X };
            ds[i] = d;
        }
        let reach = &mut self.reach[..width];
        for (i, r) in reach[..width - 1].iter_mut().enumerate() {
            let edge = xs[i + 1] <= OFF_ROW || (ds[i + 1] - ds[i]).abs() > thr;
            *r = xs[i] + if edge { 0.5 } else { 0.0 };
        }
        reach[width - 1] = xs[width - 1] + 0.5;
    }
}
