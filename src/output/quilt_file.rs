//! Quilts read back from files, for `holoinject quilt` and the tests: a PNG (any 8 or 16-bit
//! colour type, as other tools write them), or one frame of a video decoded by `ffmpeg`
//! (frame `n` counted from 0, as ffmpeg's `select` filter counts).

use std::path::Path;
use std::process::{Command, Stdio};

/// An RGB8 image, rows top-down.
pub struct RgbImage {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<u8>,
}

/// Reads `path`: a PNG, else a video's frame `frame` (the first when `None`).
pub fn load(path: &Path, frame: Option<u64>) -> Result<RgbImage, String> {
    let is_png = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    if is_png {
        if frame.is_some_and(|f| f > 0) {
            return Err(format!("{}: a PNG has one frame", path.display()));
        }
        let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
        decode_png(&bytes).map_err(|e| format!("{}: {e}", path.display()))
    } else {
        video_frame(path, frame.unwrap_or(0))
    }
}

pub fn decode_png(bytes: &[u8]) -> Result<RgbImage, String> {
    let mut dec = png::Decoder::new(std::io::Cursor::new(bytes));
    dec.set_transformations(png::Transformations::EXPAND | png::Transformations::STRIP_16);
    let mut reader = dec.read_info().map_err(|e| format!("not a readable PNG: {e}"))?;
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).map_err(|e| format!("PNG data: {e}"))?;
    let channels = info.color_type.samples();
    let rgb = buf[..info.buffer_size()]
        .chunks_exact(channels)
        .flat_map(|p| if channels < 3 { [p[0]; 3] } else { [p[0], p[1], p[2]] })
        .collect();
    Ok(RgbImage {
        width: info.width,
        height: info.height,
        rgb,
    })
}

/// Frame `n` of a video, decoded by ffmpeg into a PNG on its stdout.
fn video_frame(path: &Path, n: u64) -> Result<RgbImage, String> {
    if !path.is_file() {
        return Err(format!("{}: no such file", path.display()));
    }
    let ffmpeg = super::encoder::find_ffmpeg()?;
    let out = Command::new(ffmpeg)
        .args(["-hide_banner", "-loglevel", "error", "-i"])
        .arg(path)
        .args(["-vf", &format!("select=eq(n\\,{n})"), "-frames:v", "1"])
        .args(["-f", "image2pipe", "-c:v", "png", "-"])
        .stdin(Stdio::null())
        .output()
        .map_err(|e| format!("ffmpeg: {e}"))?;
    if !out.status.success() {
        let why = String::from_utf8_lossy(&out.stderr);
        return Err(format!("{}: ffmpeg cannot decode it: {}", path.display(), why.trim()));
    }
    if out.stdout.is_empty() {
        return Err(format!("{}: has no frame {n}", path.display()));
    }
    decode_png(&out.stdout).map_err(|e| format!("{} frame {n}: {e}", path.display()))
}
