//! `--overlay`: the live values drawn into the presented image for two seconds after each
//! change, as MangoHud draws its HUD. The text is rasterised on the CPU with an 8x8 bitmap
//! font (`font8x8`, doubled) into a small texture, uploaded only when the text changes,
//! and blitted into the top-left corner of what is presented; the app's unpack state and
//! bindings are put back (`compose::present` holds the guard for the rest).

use crate::gl::*;

/// Glyphs are doubled in windows at least this wide.
const DOUBLE_FROM: u32 = 800;
const PAD: usize = 6;
const MARGIN: i32 = 8;
const INK: [u8; 4] = [255, 255, 255, 255];
const CHANGED: [u8; 4] = [255, 214, 64, 255];
const PAPER: [u8; 4] = [20, 20, 24, 255];

#[derive(Default)]
pub struct Overlay {
    pub texture: u32,
    pub fbo: u32,
    size: (usize, usize),
    drawn: Vec<String>,
    scale: usize,
    /// What to show this frame (empty: nothing).
    pub lines: Vec<String>,
}

/// `lines` as a bottom-up RGBA image of `scale`d 8x8 glyphs; a line starting with `>` is
/// the changed value.
pub fn rasterise(lines: &[String], scale: usize) -> (usize, usize, Vec<u8>) {
    let (cell, line_h) = (8 * scale, 8 * scale + 2);
    let cols = lines.iter().map(|l| l.chars().count()).max().unwrap_or(0);
    let (w, h) = (cols * cell + 2 * PAD, lines.len() * line_h + 2 * PAD);
    let mut rgba: Vec<u8> = PAPER.iter().copied().cycle().take(w * h * 4).collect();
    for (row, line) in lines.iter().enumerate() {
        let ink = if line.starts_with('>') { CHANGED } else { INK };
        for (gx, gy) in inked(line) {
            for (sy, sx) in (0..scale).flat_map(|a| (0..scale).map(move |b| (a, b))) {
                let x = PAD + gx * scale + sx;
                let y_top = PAD + row * line_h + gy * scale + sy;
                let at = ((h - 1 - y_top) * w + x) * 4;
                rgba[at..at + 4].copy_from_slice(&ink);
            }
        }
    }
    (w, h, rgba)
}

/// The inked pixels of `text` in 8x8 glyphs (`font8x8`), as (x, y from the top) of an
/// unscaled line.
pub fn inked(text: &str) -> impl Iterator<Item = (usize, usize)> + '_ {
    text.chars().enumerate().flat_map(|(col, ch)| {
        let glyph = font8x8::legacy::BASIC_LEGACY
            .get(ch as usize)
            .copied()
            .unwrap_or_default();
        (0..8).flat_map(move |gy| {
            (0..8)
                .filter(move |gx| glyph[gy] & (1 << gx) != 0)
                .map(move |gx| (col * 8 + gx, gy))
        })
    })
}

impl Overlay {
    /// Blits the current lines into `dest` (a framebuffer of `window` pixels) at its
    /// top-left corner. The caller's guard restores framebuffers and texture unit 0.
    pub fn draw(&mut self, gl: &Gl, dest: u32, window: (u32, u32)) -> Result<(), String> {
        if self.lines.is_empty() {
            return Ok(());
        }
        let scale = if window.0 >= DOUBLE_FROM { 2 } else { 1 };
        if self.drawn != self.lines || self.scale != scale {
            self.upload(gl, scale)?;
        }
        let (w, h) = (self.size.0 as i32, self.size.1 as i32);
        let (ww, wh) = (window.0 as i32, window.1 as i32);
        let (cw, ch) = (w.min(ww - MARGIN).max(0), h.min(wh - MARGIN).max(0));
        // SAFETY: our framebuffer read, the presented image drawn; bindings restored by the
        // caller's guard; the rectangles are clipped to both.
        unsafe {
            gl.BindFramebuffer(READ_FRAMEBUFFER, self.fbo);
            gl.BindFramebuffer(DRAW_FRAMEBUFFER, dest);
            gl.ReadBuffer(COLOR_ATTACHMENT0);
            let top = wh - MARGIN;
            gl.BlitFramebuffer(
                0,
                h - ch,
                cw,
                h,
                MARGIN,
                top - ch,
                MARGIN + cw,
                top,
                COLOR_BUFFER_BIT,
                NEAREST,
            );
        }
        Ok(())
    }

    fn upload(&mut self, gl: &Gl, scale: usize) -> Result<(), String> {
        let (w, h, rgba) = rasterise(&self.lines, scale);
        let unpack = crate::gl::unpack::UnpackState::neutral(gl);
        // SAFETY: our texture on unit 0 (restored by the caller's guard) filled from a local
        // buffer of w*h RGBA8 pixels, with tight unpacking and no unpack buffer.
        unsafe {
            if self.texture == 0 {
                gl.GenTextures(1, &mut self.texture);
                gl.GenFramebuffers(1, &mut self.fbo);
            }
            gl.BindTexture(TEXTURE_2D, self.texture);
            gl.TexParameteri(TEXTURE_2D, TEXTURE_MIN_FILTER, NEAREST as i32);
            gl.TexParameteri(TEXTURE_2D, TEXTURE_MAG_FILTER, NEAREST as i32);
            gl.TexParameteri(TEXTURE_2D, TEXTURE_MAX_LEVEL, 0);
            let (wi, hi) = (w as i32, h as i32);
            gl.TexImage2D(
                TEXTURE_2D,
                0,
                RGBA8 as i32,
                wi,
                hi,
                0,
                RGBA,
                UNSIGNED_BYTE,
                rgba.as_ptr().cast(),
            );
            gl.BindFramebuffer(READ_FRAMEBUFFER, self.fbo);
            gl.FramebufferTexture2D(READ_FRAMEBUFFER, COLOR_ATTACHMENT0, TEXTURE_2D, self.texture, 0);
        }
        unpack.restore(gl);
        self.size = (w, h);
        self.drawn = self.lines.clone();
        self.scale = scale;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_is_inked_and_the_changed_line_stands_out() {
        let (w, h, rgba) = rasterise(&["> A".into(), "  I".into()], 2);
        assert_eq!((w, h), (3 * 16 + 2 * PAD, 2 * 18 + 2 * PAD));
        let count = |c: [u8; 4]| rgba.chunks(4).filter(|p| *p == c).count();
        assert!(count(CHANGED) > 0 && count(INK) > 0);
        // The first line is at the top of the image, which is the end of a bottom-up buffer.
        let top_half = &rgba[rgba.len() / 2..];
        assert!(top_half.chunks(4).any(|p| p == CHANGED));
        assert!(!top_half.chunks(4).any(|p| p == INK));
    }
}
