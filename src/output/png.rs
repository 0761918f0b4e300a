//! PNG files as the project writes them: 8-bit RGB, top-down rows.

use std::io::BufWriter;
use std::path::Path;

pub fn write_rgb(path: &Path, width: u32, height: u32, rgb: &[u8]) -> Result<(), String> {
    let file = std::fs::File::create(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut enc = ::png::Encoder::new(BufWriter::new(file), width, height);
    enc.set_color(::png::ColorType::Rgb);
    enc.set_depth(::png::BitDepth::Eight);
    enc.set_compression(::png::Compression::Fast);
    let mut w = enc.write_header().map_err(|e| format!("{}: {e}", path.display()))?;
    w.write_image_data(rgb).map_err(|e| format!("{}: {e}", path.display()))
}

/// GL rows are bottom-up RGBA; PNG rows are top-down RGB.
pub fn rgba_bottom_up_to_rgb_top_down(rgba: &[u8], width: u32, height: u32) -> Vec<u8> {
    let (w, h) = (width as usize, height as usize);
    let mut out = Vec::with_capacity(w * h * 3);
    for row in (0..h).rev() {
        for px in rgba[row * w * 4..(row + 1) * w * 4].chunks_exact(4) {
            out.extend_from_slice(&px[..3]);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    #[test]
    fn flips_rows_and_drops_alpha() {
        let rgba = [1, 2, 3, 9, 4, 5, 6, 9, /* row 1 */ 7, 8, 9, 9, 10, 11, 12, 9];
        let rgb = super::rgba_bottom_up_to_rgb_top_down(&rgba, 2, 2);
        assert_eq!(rgb, vec![7, 8, 9, 10, 11, 12, 1, 2, 3, 4, 5, 6]);
    }
}
