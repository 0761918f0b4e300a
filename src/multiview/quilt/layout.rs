//! Where each view lives in the quilt (DESIGN §4): view `i` at column `i mod C`, row
//! `floor(i/C)` counted from the bottom (GL origin), and how the app's window coordinates map
//! into a tile.
//!
//! One exception while the layer draws: the centre view trades places with the view whose
//! tile starts at the quilt's storage origin (the top-left tile when the quilt is stored
//! top-down like a window, else the bottom-left one), so that the centre view is drawn at
//! the very pixel addresses the window has. Rasterisers snap vertices and interpolate from
//! the framebuffer's origin in floating point, so the same draw offset by a tile rounds
//! differently (llvmpipe, 3,000 smooth lines one tile right and up: 5,762 of 307,200 pixels
//! differ, 39 by more than one level). Whatever reads the quilt as a whole (dumps, the
//! weave, the quilt output) puts the two back (`swapped`).

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct QuiltLayout {
    pub cols: u32,
    pub rows: u32,
    pub tile_w: u32,
    pub tile_h: u32,
    /// The app's default framebuffer, whose coordinates the app draws in.
    pub window_w: u32,
    pub window_h: u32,
    /// The quilt's framebuffer stores rows top-down, as the window is stored.
    pub flipped: bool,
    /// Columns per side of the guard band's room (`guard`): beyond the tiles, to the right,
    /// a pair of strips per quilt row. 0: none.
    pub guard: u32,
}

/// Largest quilt edge we allocate when the tile size is derived from the window.
pub const MAX_QUILT_EDGE: u32 = 8192;
/// Largest quilt edge for tiles given explicitly (`--tile`): the common GL texture limit.
pub const MAX_EXPLICIT_QUILT_EDGE: u32 = 16384;

/// `tile` shrunk uniformly (aspect kept) so that `cols x rows` of it fit in `edge` pixels.
fn fit(tile: (u32, u32), cols: u32, rows: u32, edge: u32) -> (u32, u32) {
    let scale = (edge as f64 / (cols as f64 * tile.0.max(1) as f64))
        .min(edge as f64 / (rows as f64 * tile.1.max(1) as f64))
        .min(1.0);
    (
        ((tile.0 as f64 * scale) as u32).max(1),
        ((tile.1 as f64 * scale) as u32).max(1),
    )
}

impl QuiltLayout {
    /// Tiles default to the window size (so views are pixel-exact renders of the app's
    /// frame), shrunk uniformly when the quilt would exceed `MAX_QUILT_EDGE`; explicit tiles
    /// are shrunk only past `MAX_EXPLICIT_QUILT_EDGE`.
    pub fn new(quilt: (u32, u32), tile: Option<(u32, u32)>, window: (u32, u32)) -> QuiltLayout {
        let (cols, rows) = (quilt.0.max(1), quilt.1.max(1));
        let (tile_w, tile_h) = match tile {
            Some(t) => fit(t, cols, rows, MAX_EXPLICIT_QUILT_EDGE),
            None => fit(window, cols, rows, MAX_QUILT_EDGE),
        };
        QuiltLayout {
            cols,
            rows,
            tile_w,
            tile_h,
            window_w: window.0.max(1),
            window_h: window.1.max(1),
            flipped: false,
            guard: 0,
        }
    }

    /// This layout with room for guard bands up to `columns` wide (`guard`), as much of it
    /// as keeps the quilt's storage within `MAX_EXPLICIT_QUILT_EDGE`.
    pub fn with_guard(self, columns: u32) -> QuiltLayout {
        let room = MAX_EXPLICIT_QUILT_EDGE.saturating_sub(self.width()) / 2;
        QuiltLayout {
            guard: columns.min(room).min(self.tile_w),
            ..self
        }
    }

    /// The width of the quilt's storage: the tiles and the guard band's room.
    pub fn storage_width(&self) -> u32 {
        self.width() + 2 * self.guard
    }

    /// How many rendered views' guard bands the room holds (a pair of strips per row).
    pub fn guard_slots(&self) -> u32 {
        if self.guard == 0 { 0 } else { self.rows }
    }

    /// The two strips, `width` columns each (at most `guard`), of guard slot `slot`: beside
    /// the tiles, where the columns just left and right of a rendered view's tile are drawn.
    pub fn guard_strips(&self, slot: u32, width: u32) -> [[i32; 4]; 2] {
        let (x, y) = (self.width() as i32, (slot * self.tile_h) as i32);
        let (g, h) = (width.min(self.guard) as i32, self.tile_h as i32);
        [[x, y, g, h], [x + self.guard as i32, y, g, h]]
    }

    /// This layout in a framebuffer stored top-down (`flipped`) or bottom-up.
    pub fn stored(self, flipped: bool) -> QuiltLayout {
        QuiltLayout { flipped, ..self }
    }

    /// The view the app's own frame is compared with (the camera rig's centre).
    pub fn centre(&self) -> u32 {
        self.views() / 2
    }

    /// The two views whose tiles trade places (see the module notes), if they differ.
    pub fn swapped(&self) -> Option<(u32, u32)> {
        let first = if self.flipped { (self.rows - 1) * self.cols } else { 0 };
        (first != self.centre()).then_some((self.centre(), first))
    }

    /// Where view `i` is drawn: the grid cell (numbered like views) holding its tile.
    pub fn cell(&self, i: u32) -> u32 {
        match self.swapped() {
            Some((a, b)) if i == a => b,
            Some((a, b)) if i == b => a,
            _ => i,
        }
    }

    /// Lower-left corner of grid cell `cell`, as DESIGN §4 places view `cell`.
    pub fn cell_origin(&self, cell: u32) -> (i32, i32) {
        (
            ((cell % self.cols) * self.tile_w) as i32,
            ((cell / self.cols) * self.tile_h) as i32,
        )
    }

    pub fn views(&self) -> u32 {
        self.cols * self.rows
    }

    pub fn width(&self) -> u32 {
        self.cols * self.tile_w
    }

    pub fn height(&self) -> u32 {
        self.rows * self.tile_h
    }

    /// Lower-left corner of view `i`'s tile, where it is drawn.
    pub fn origin(&self, i: u32) -> (i32, i32) {
        self.cell_origin(self.cell(i))
    }

    /// True when tiles are the window's size, so window pixels map 1:1 into tiles.
    pub fn unscaled(&self) -> bool {
        self.tile_w == self.window_w && self.tile_h == self.window_h
    }

    /// A rectangle in window coordinates mapped into view `i`'s tile. Edges are mapped (not
    /// origin and size separately) so adjacent rectangles stay adjacent after rounding.
    pub fn map_rect(&self, i: u32, r: [i32; 4]) -> [i32; 4] {
        let (ox, oy) = self.origin(i);
        let sx = self.tile_w as f64 / self.window_w as f64;
        let sy = self.tile_h as f64 / self.window_h as f64;
        let (x0, y0) = ((r[0] as f64 * sx).round() as i32, (r[1] as f64 * sy).round() as i32);
        let (x1, y1) = (
            ((r[0] + r[2]) as f64 * sx).round() as i32,
            ((r[1] + r[3]) as f64 * sy).round() as i32,
        );
        [ox + x0, oy + y0, x1 - x0, y1 - y0]
    }

    /// The tile of view `i` as a rectangle.
    pub fn tile_rect(&self, i: u32) -> [i32; 4] {
        let (x, y) = self.origin(i);
        [x, y, self.tile_w as i32, self.tile_h as i32]
    }

    /// View aspect as written in quilt file names: `a{W/H}` with up to 4 decimals.
    pub fn aspect_label(&self) -> String {
        let a = format!("{:.4}", self.window_w as f64 / self.window_h as f64);
        a.trim_end_matches('0').trim_end_matches('.').to_string()
    }

    /// `qs{C}x{R}a{aspect}`, the Looking Glass quilt naming convention.
    pub fn file_tag(&self) -> String {
        format!("qs{}x{}a{}", self.cols, self.rows, self.aspect_label())
    }
}

/// Intersection of two rectangles (x, y, w, h); empty results have zero size.
pub fn intersect(a: [i32; 4], b: [i32; 4]) -> [i32; 4] {
    let x0 = a[0].max(b[0]);
    let y0 = a[1].max(b[1]);
    let x1 = (a[0] + a[2]).min(b[0] + b[2]);
    let y1 = (a[1] + a[3]).min(b[1] + b[3]);
    [x0, y0, (x1 - x0).max(0), (y1 - y0).max(0)]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn views_fill_rows_from_the_bottom() {
        let l = QuiltLayout::new((3, 2), Some((100, 50)), (200, 100));
        assert_eq!(l.cell_origin(0), (0, 0));
        assert_eq!(l.cell_origin(2), (200, 0));
        assert_eq!(l.cell_origin(3), (0, 50));
        assert_eq!((l.width(), l.height()), (300, 100));
    }

    #[test]
    fn window_rects_scale_into_tiles() {
        let l = QuiltLayout::new((3, 2), Some((100, 50)), (200, 100));
        assert_eq!(l.map_rect(4, [0, 0, 200, 100]), [100, 50, 100, 50]);
        assert_eq!(l.map_rect(1, [20, 10, 40, 20]), [110, 5, 20, 10]);
    }

    #[test]
    fn default_tiles_are_the_window_until_the_quilt_gets_too_big() {
        assert!(QuiltLayout::new((3, 3), None, (640, 480)).unscaled());
        let big = QuiltLayout::new((8, 6), None, (1920, 1080));
        assert!(big.width() <= MAX_QUILT_EDGE && big.height() <= MAX_QUILT_EDGE);
        let huge = QuiltLayout::new((8, 6), Some((16384, 16384)), (640, 480));
        assert!(huge.width() <= MAX_EXPLICIT_QUILT_EDGE && huge.height() <= MAX_EXPLICIT_QUILT_EDGE);
        assert_eq!(huge.tile_w, huge.tile_h);
        let many = QuiltLayout::new((1024, 1), None, (16384, 16384));
        assert!(many.width() <= MAX_QUILT_EDGE && many.tile_w >= 1);
        assert_eq!(big.file_tag(), "qs8x6a1.7778");
        assert_eq!(
            QuiltLayout::new((8, 6), Some((420, 560)), (420, 560)).aspect_label(),
            "0.75"
        );
    }

    #[test]
    fn the_centre_view_is_drawn_at_the_storage_origin() {
        let l = QuiltLayout::new((3, 2), Some((100, 50)), (200, 100));
        assert_eq!(l.swapped(), Some((3, 0)));
        assert_eq!((l.origin(3), l.origin(0), l.origin(1)), ((0, 0), (0, 50), (100, 0)));
        let top_down = l.stored(true);
        assert_eq!(top_down.swapped(), None);
        assert_eq!(top_down.origin(3), (0, 50));
        let wide = QuiltLayout::new((5, 1), None, (64, 48)).stored(true);
        assert_eq!(
            (wide.swapped(), wide.origin(2), wide.origin(0)),
            (Some((2, 0)), (0, 0), (128, 0))
        );
        assert_eq!(QuiltLayout::new((1, 1), None, (64, 48)).swapped(), None);
    }

    #[test]
    fn intersection() {
        assert_eq!(intersect([0, 0, 10, 10], [5, 5, 10, 10]), [5, 5, 5, 5]);
        assert_eq!(intersect([0, 0, 1, 1], [5, 5, 1, 1])[2], 0);
    }
}
