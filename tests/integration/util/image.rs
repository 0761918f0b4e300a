//! Images (RGB8, top-down) and the measures the tests take of them.

use std::path::Path;

pub struct Image {
    pub width: u32,
    pub height: u32,
    /// RGB8, top-down.
    pub rgb: Vec<u8>,
}

impl Image {
    /// The pixel at column `x`, row `y` (from the top), if the image has one there.
    pub fn pixel(&self, x: u32, y: u32) -> Option<&[u8]> {
        let i = ((y * self.width + x) * 3) as usize;
        (x < self.width && y < self.height).then(|| &self.rgb[i..i + 3])
    }
}

pub fn read_png(path: &Path) -> Image {
    let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut dec = png::Decoder::new(std::io::BufReader::new(file));
    dec.set_transformations(png::Transformations::EXPAND | png::Transformations::STRIP_16);
    let mut reader = dec.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    let channels = info.color_type.samples();
    let rgb = buf[..info.buffer_size()]
        .chunks_exact(channels)
        .flat_map(|p| if channels < 3 { [p[0]; 3] } else { [p[0], p[1], p[2]] })
        .collect();
    Image {
        width: info.width,
        height: info.height,
        rgb,
    }
}

pub fn save(img: &Image, path: &Path) {
    holoinject::output::png::write_rgb(path, img.width, img.height, &img.rgb)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
}

/// True when the image is not one flat colour (a blank frame would make "identical" trivial).
pub fn has_content(path: &Path) -> bool {
    let img = read_png(path);
    let first = &img.rgb[..3];
    img.rgb.chunks(3).any(|p| p != first)
}

/// Per-tile PSNR (dB, 8-bit RGB) between two quilts of `cols`x`rows` tiles, in view order
/// (view 0 bottom-left). Identical tiles report `f64::INFINITY`.
pub fn tile_psnr(a: &Image, b: &Image, cols: u32, rows: u32) -> Vec<f64> {
    assert_eq!((a.width, a.height), (b.width, b.height), "quilt sizes differ");
    let (tw, th) = (a.width / cols, a.height / rows);
    (0..cols * rows)
        .map(|i| {
            let (col, row) = (i % cols, i / cols);
            let y0 = a.height - (row + 1) * th;
            let mut se = 0.0f64;
            for y in y0..y0 + th {
                let start = ((y * a.width + col * tw) * 3) as usize;
                let end = start + (tw * 3) as usize;
                se += a.rgb[start..end]
                    .iter()
                    .zip(&b.rgb[start..end])
                    .map(|(&x, &y)| (x as f64 - y as f64).powi(2))
                    .sum::<f64>();
            }
            let mse = se / (tw * th * 3) as f64;
            if mse == 0.0 {
                f64::INFINITY
            } else {
                10.0 * (255.0f64 * 255.0 / mse).log10()
            }
        })
        .collect()
}

/// Tile `i` of a quilt as its own image.
pub fn tile(q: &Image, cols: u32, rows: u32, i: u32) -> Image {
    let (tw, th) = (q.width / cols, q.height / rows);
    let (col, row) = (i % cols, i / cols);
    let y0 = q.height - (row + 1) * th;
    let mut rgb = Vec::with_capacity((tw * th * 3) as usize);
    for y in y0..y0 + th {
        let start = ((y * q.width + col * tw) * 3) as usize;
        rgb.extend_from_slice(&q.rgb[start..start + (tw * 3) as usize]);
    }
    Image {
        width: tw,
        height: th,
        rgb,
    }
}

/// Mean horizontal shift (pixels) that best aligns `b` onto `a`, searched in ±`max` px.
pub fn horizontal_shift(a: &Image, b: &Image, max: i32) -> i32 {
    let err = |dx: i32| -> f64 {
        let mut e = 0.0;
        for y in (0..a.height).step_by(2) {
            for x in max..(a.width as i32 - max) {
                let ia = ((y * a.width) as i32 + x) as usize * 3;
                let ib = ((y * b.width) as i32 + x + dx) as usize * 3;
                e += (0..3)
                    .map(|c| (a.rgb[ia + c] as f64 - b.rgb[ib + c] as f64).abs())
                    .sum::<f64>();
            }
        }
        e
    };
    (-max..=max).min_by(|&p, &q| err(p).total_cmp(&err(q))).unwrap()
}
