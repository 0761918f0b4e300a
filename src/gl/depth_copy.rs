//! A copy of one rectangle of a framebuffer's depth, taken when the caller decides and read
//! back later as window depth values (0..1).
//!
//! Taking the copy is a GPU blit into a depth texture of ours, so taking it in the middle of
//! a frame — before the app overwrites the depth — makes nobody wait; the read-back comes at
//! the swap. Desktop GL reads the texture's depth with `glReadPixels`. OpenGL ES cannot read
//! depth back at all, so there a small pass draws the texture into an RGBA8 target, each
//! depth packed into 24 bits (`glsl-patches/depth_pack.frag`), and that is read back like
//! any colour.
//!
//! A depth blit between two different formats is an error, so the copy takes the source's
//! own format, read from its depth attachment beforehand (`describe`: depth bits, float or
//! normalised, stencil bits in the same image). The same blit resolves a multisampled
//! source. The copy itself asks GL nothing, so that it can be taken in the middle of a draw
//! call at no more cost than the blit.

use super::GlInfo;
use super::guard::StateGuard;
use super::*;

const FULLSCREEN_VERT: &str = include_str!("../../glsl-patches/fullscreen.vert");
const DEPTH_PACK_FRAG: &str = include_str!("../../glsl-patches/depth_pack.frag");

/// Our depth texture (and the framebuffer it is attached to) holding the last copy.
#[derive(Default)]
pub struct DepthCopy {
    fbo: u32,
    texture: u32,
    format: GLenum,
    size: (i32, i32),
    /// Where in our texture the last copy lies, and its size.
    origin: (i32, i32),
    copied: (i32, i32),
    /// `RG32F` beside the depth (colour attachment 0), when a disparity record is read back
    /// with rows left out (`read_record`): the same rows of it.
    record: u32,
    /// ES only: the RGBA8 target and program of the packing pass.
    pack: PackPass,
}

#[derive(Default)]
struct PackPass {
    fbo: u32,
    color: u32,
    size: (i32, i32),
    vao: u32,
    program: Option<Result<u32, String>>,
}

fn attachment_iv(gl: &Gl, point: GLenum, pname: GLenum) -> i32 {
    let mut v = 0;
    // SAFETY: a single-integer query on the bound read framebuffer.
    unsafe { gl.GetFramebufferAttachmentParameteriv(READ_FRAMEBUFFER, point, pname, &mut v) };
    v
}

/// What a depth copy needs to know of its source, asked of GL ahead of the copy.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SourceFormat {
    pub format: GLenum,
    pub multisampled: bool,
}

/// The state `DepthCopy::take` leaves behind.
#[derive(Clone, Copy, Debug)]
pub struct Restore {
    pub draw_fbo: u32,
    pub read_fbo: u32,
    pub scissor: bool,
}

/// The depth format and sampling of framebuffer `fbo`, which must exist; state restored.
pub fn describe(gl: &Gl, info: GlInfo, fbo: u32) -> Result<SourceFormat, String> {
    let _guard = StateGuard::new(gl, info).framebuffers();
    // SAFETY: binding an existing framebuffer for the queries; the guard restores bindings.
    unsafe {
        gl.BindFramebuffer(READ_FRAMEBUFFER, fbo);
        gl.BindFramebuffer(DRAW_FRAMEBUFFER, fbo);
    }
    if attachment_iv(gl, DEPTH_ATTACHMENT, FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE) as GLenum == NONE {
        return Err("it has no depth buffer".into());
    }
    let bits = attachment_iv(gl, DEPTH_ATTACHMENT, FRAMEBUFFER_ATTACHMENT_DEPTH_SIZE);
    let float = attachment_iv(gl, DEPTH_ATTACHMENT, FRAMEBUFFER_ATTACHMENT_COMPONENT_TYPE) as GLenum == FLOAT;
    let stencil = attachment_iv(gl, DEPTH_ATTACHMENT, FRAMEBUFFER_ATTACHMENT_STENCIL_SIZE);
    let format = super::format::sized_depth_format(bits, float, stencil)
        .ok_or_else(|| format!("its depth format ({bits} bits) is not copied"))?;
    // SAFETY: a completeness query on the bound framebuffer.
    if unsafe { gl.CheckFramebufferStatus(READ_FRAMEBUFFER) } != FRAMEBUFFER_COMPLETE {
        return Err("it is incomplete".into());
    }
    let multisampled = super::guard::get_i(gl, SAMPLE_BUFFERS) > 0;
    Ok(SourceFormat { format, multisampled })
}

/// Whether framebuffer object `fbo` (not 0) exists, is complete, and has a colour and a
/// depth attachment: what a scene is drawn into (a depth-only target is a shadow map).
pub fn is_scene_target(gl: &Gl, info: GlInfo, fbo: u32) -> bool {
    // SAFETY: a query on a name, binding nothing.
    if unsafe { gl.IsFramebuffer(fbo) } == 0 {
        return false;
    }
    let _guard = StateGuard::new(gl, info).framebuffers();
    // SAFETY: the framebuffer exists; the guard puts the app's binding back.
    unsafe { gl.BindFramebuffer(READ_FRAMEBUFFER, fbo) };
    let kind = |p| attachment_iv(gl, p, FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE) as GLenum != NONE;
    // SAFETY: as above.
    let complete = unsafe { gl.CheckFramebufferStatus(READ_FRAMEBUFFER) } == FRAMEBUFFER_COMPLETE;
    // Every context has at least four colour attachment points.
    complete && kind(DEPTH_ATTACHMENT) && (0..4).any(|i| kind(COLOR_ATTACHMENT0 + i))
}

/// A 2D texture of ours with `format` storage, sampled texel by texel (nearest); left bound on
/// the active unit, which the caller's guard restores.
pub fn storage(gl: &Gl, format: GLenum, (w, h): (i32, i32)) -> u32 {
    let mut t = 0;
    // SAFETY: our own texture, bound on the active unit; the caller's guard restores it.
    unsafe {
        gl.GenTextures(1, &mut t);
        gl.BindTexture(TEXTURE_2D, t);
        gl.TexStorage2D(TEXTURE_2D, 1, format, w, h);
        gl.TexParameteri(TEXTURE_2D, TEXTURE_MIN_FILTER, NEAREST as i32);
        gl.TexParameteri(TEXTURE_2D, TEXTURE_MAG_FILTER, NEAREST as i32);
    }
    t
}

/// Rows a copy of `h` rows keeps when it takes every `step`-th: a NEAREST blit onto this
/// many rows takes the source rows nearest `(i + 1/2)·h/rows`, the same for any two
/// rectangles of one height, so a depth copy and a record read (`DepthCopy::read_record`)
/// keep the same pixels.
pub fn rows_of(h: i32, step: i32) -> i32 {
    let step = step.max(1);
    (h.max(1) + step - 1) / step
}

/// A framebuffer of ours with `texture` at `point`, bound for drawing.
fn framebuffer(gl: &Gl, fbo: &mut u32, point: GLenum, texture: u32) {
    // SAFETY: our own framebuffer; the caller's guard restores the bindings.
    unsafe {
        if *fbo == 0 {
            gl.GenFramebuffers(1, fbo);
        }
        gl.BindFramebuffer(DRAW_FRAMEBUFFER, *fbo);
        gl.FramebufferTexture2D(DRAW_FRAMEBUFFER, point, TEXTURE_2D, texture, 0);
    }
}

impl DepthCopy {
    /// Copies the depth of `rect` (x, y, w, h) of framebuffer `source`, described by
    /// `describe`, into our texture. Asks GL nothing and allocates nothing (it may run in a
    /// draw call), except when our texture must change; `restore` is the state to leave:
    /// the draw and read framebuffer bindings and whether the scissor test is on.
    pub fn take(&mut self, gl: &Gl, info: GlInfo, source: (u32, SourceFormat), rect: [i32; 4], restore: Restore) {
        self.take_rows(gl, info, source, rect, restore, 1);
    }

    /// `take`, of every `step`-th row only (the rows `rows_of` picks) where the source is
    /// single-sampled and not ES (a multisampled source resolves only onto an equal
    /// rectangle; ES reads through the packing pass): what is read back for statistics.
    pub fn take_rows(
        &mut self,
        gl: &Gl,
        info: GlInfo,
        source: (u32, SourceFormat),
        rect: [i32; 4],
        restore: Restore,
        step: i32,
    ) {
        let [x, y, w, h] = rect.map(|v| v.clamp(0, 16384));
        let (fbo, SourceFormat { format, multisampled }) = source;
        let rows = if multisampled || info.es { h } else { rows_of(h, step) };
        // ES resolves a multisampled source only onto the same coordinates: the copy then
        // keeps the rectangle where it was.
        self.origin = if info.es && multisampled { (x, y) } else { (0, 0) };
        let size = ((self.origin.0 + w).max(1), (self.origin.1 + rows).max(1));
        if (format, size) != (self.format, self.size) {
            self.resize(gl, info, format, size);
        }
        let (ox, oy) = self.origin;
        // SAFETY: a depth blit between framebuffers of one format (the source's), equal
        // rectangles when multisampled (so it resolves; else rows may be left out, NEAREST),
        // nothing clipping it; the caller's state put back after.
        unsafe {
            gl.BindFramebuffer(READ_FRAMEBUFFER, fbo);
            gl.BindFramebuffer(DRAW_FRAMEBUFFER, self.fbo);
            if restore.scissor {
                gl.Disable(SCISSOR_TEST);
            }
            gl.BlitFramebuffer(x, y, x + w, y + h, ox, oy, ox + w, oy + rows, DEPTH_BUFFER_BIT, NEAREST);
            if restore.scissor {
                gl.Enable(SCISSOR_TEST);
            }
            gl.BindFramebuffer(DRAW_FRAMEBUFFER, restore.draw_fbo);
            gl.BindFramebuffer(READ_FRAMEBUFFER, restore.read_fbo);
        }
        self.copied = (w, rows);
    }

    fn resize(&mut self, gl: &Gl, info: GlInfo, format: GLenum, size: (i32, i32)) {
        let _guard = StateGuard::new(gl, info).for_pass();
        // SAFETY: our own textures, replaced (the record's made again when wanted).
        unsafe { gl.DeleteTextures(2, [self.texture, self.record].as_ptr()) };
        self.record = 0;
        self.texture = storage(gl, format, size);
        let point = if matches!(format, DEPTH24_STENCIL8 | DEPTH32F_STENCIL8) {
            DEPTH_STENCIL_ATTACHMENT
        } else {
            DEPTH_ATTACHMENT
        };
        framebuffer(gl, &mut self.fbo, point, self.texture);
        // SAFETY: a depth-only framebuffer of ours draws and reads no colour (bound for
        // reading too: the read buffer is the read binding's; the record's old texture let
        // go); the caller rebinds.
        unsafe {
            gl.FramebufferTexture2D(DRAW_FRAMEBUFFER, COLOR_ATTACHMENT0, TEXTURE_2D, 0, 0);
            gl.DrawBuffers(1, &NONE);
            gl.BindFramebuffer(READ_FRAMEBUFFER, self.fbo);
            gl.ReadBuffer(NONE);
        }
        (self.format, self.size) = (format, size);
    }

    /// Window depths (0..1, rows bottom-up) of the last copy.
    pub fn read(&mut self, gl: &Gl, info: GlInfo) -> Result<Vec<f32>, String> {
        if self.fbo == 0 {
            return Err("nothing copied".into());
        }
        if info.es {
            return self.read_packed(gl, info);
        }
        Ok(super::readback::read_depth(gl, info, self.fbo, self.copied_rect()))
    }

    /// `read` through the packing pass, as ES has to (any GL 3.3 or ES 3 context can).
    pub fn read_packed(&mut self, gl: &Gl, info: GlInfo) -> Result<Vec<f32>, String> {
        if self.fbo == 0 {
            return Err("nothing copied".into());
        }
        self.pack.draw(gl, info, self.texture, self.size)?;
        let source = super::readback::Source::Fbo(self.pack.fbo);
        let rgba = super::readback::read_rgba(gl, info, source, self.copied_rect())?;
        Ok(rgba.chunks_exact(4).map(unpack).collect())
    }

    /// Our depth texture and where in it the last copy lies (x, y, w, h).
    pub fn copied(&self) -> (u32, [i32; 4]) {
        (self.texture, self.copied_rect())
    }

    fn copied_rect(&self) -> [i32; 4] {
        [self.origin.0, self.origin.1, self.copied.0, self.copied.1]
    }

    /// Deletes every object of ours (for a copy made for one use).
    pub fn delete(&self, gl: &Gl) {
        let program = self.pack.program.as_ref().and_then(|p| p.as_ref().ok().copied());
        // SAFETY: deleting only objects this copy created; zero names are ignored by GL.
        unsafe {
            gl.DeleteFramebuffers(2, [self.fbo, self.pack.fbo].as_ptr());
            gl.DeleteTextures(3, [self.texture, self.pack.color, self.record].as_ptr());
            if self.pack.vao != 0 {
                gl.DeleteVertexArrays(1, &self.pack.vao);
            }
            if let Some(p) = program {
                gl.DeleteProgram(p);
            }
        }
    }

    /// How many framebuffers and vertex arrays of ours (per context) exist.
    pub fn context_objects(&self) -> (usize, usize) {
        let fbos = [self.fbo, self.pack.fbo].iter().filter(|&&f| f != 0).count();
        (fbos, usize::from(self.pack.vao != 0))
    }

    /// The disparity record (`RG32F` pairs, rows bottom-up) of `rect` of framebuffer `fbo`,
    /// which holds the same pixels as the last copy: the rows it kept. State restored.
    pub fn read_record(&mut self, gl: &Gl, info: GlInfo, fbo: u32, rect: [i32; 4]) -> Vec<f32> {
        let (w, rows) = self.copied;
        if rows == rect[3] || self.fbo == 0 || self.origin != (0, 0) {
            return super::readback::read_rg(gl, info, fbo, rect);
        }
        let _guard = StateGuard::new(gl, info)
            .framebuffers()
            .for_pass()
            .caps(&[SCISSOR_TEST]);
        // SAFETY: our own texture and framebuffer; the bindings and the scissor test are
        // restored by the guard. A NEAREST blit onto `rows` rows keeps the rows the depth
        // copy kept (`rows_of`).
        unsafe {
            if self.record == 0 {
                self.record = storage(gl, RG32F, self.size);
                gl.BindFramebuffer(DRAW_FRAMEBUFFER, self.fbo);
                gl.FramebufferTexture2D(DRAW_FRAMEBUFFER, COLOR_ATTACHMENT0, TEXTURE_2D, self.record, 0);
                gl.DrawBuffers(1, &COLOR_ATTACHMENT0);
                gl.BindFramebuffer(READ_FRAMEBUFFER, self.fbo);
                gl.ReadBuffer(COLOR_ATTACHMENT0);
            }
            gl.Disable(SCISSOR_TEST);
            gl.BindFramebuffer(READ_FRAMEBUFFER, fbo);
            gl.BindFramebuffer(DRAW_FRAMEBUFFER, self.fbo);
            let [x, y, rw, rh] = rect;
            gl.BlitFramebuffer(x, y, x + rw, y + rh, 0, 0, w, rows, COLOR_BUFFER_BIT, NEAREST);
        }
        super::readback::read_rg(gl, info, self.fbo, [0, 0, w, rows])
    }

    /// Textures and programs of ours, which the share group holds.
    pub fn shared_objects(&self) -> ([u32; 3], Option<u32>) {
        let program = self.pack.program.as_ref().and_then(|p| p.as_ref().ok().copied());
        ([self.texture, self.pack.color, self.record], program)
    }
}

/// A depth packed by `depth_pack.frag`.
pub fn unpack(p: &[u8]) -> f32 {
    let v = (u32::from(p[0]) << 16) | (u32::from(p[1]) << 8) | u32::from(p[2]);
    (f64::from(v) / 16_777_215.0) as f32
}

impl PackPass {
    /// Draws `depth` (a depth texture of `size`) packed into our RGBA8 target.
    fn draw(&mut self, gl: &Gl, info: GlInfo, depth: u32, size: (i32, i32)) -> Result<(), String> {
        let _guard = StateGuard::new(gl, info).framebuffers().for_pass();
        let program = self
            .program
            .get_or_insert_with(|| super::program::link(gl, info, FULLSCREEN_VERT, DEPTH_PACK_FRAG))
            .clone()
            .map_err(|e| format!("depth pack pass: {e}"))?;
        if self.size != size {
            // SAFETY: our own texture, replaced.
            unsafe { gl.DeleteTextures(1, &self.color) };
            self.color = storage(gl, RGBA8, size);
            self.size = size;
        }
        framebuffer(gl, &mut self.fbo, COLOR_ATTACHMENT0, self.color);
        super::guard::neutral_pass_state(gl, info);
        // SAFETY: our program, vertex array and textures; the guard restores the app's.
        unsafe {
            if self.vao == 0 {
                gl.GenVertexArrays(1, &mut self.vao);
            }
            gl.DrawBuffers(1, &COLOR_ATTACHMENT0);
            gl.Viewport(0, 0, size.0, size.1);
            gl.UseProgram(program);
            gl.Uniform1i(gl.GetUniformLocation(program, c"depth".as_ptr()), 0);
            gl.ActiveTexture(TEXTURE0);
            gl.BindTexture(TEXTURE_2D, depth);
            gl.BindVertexArray(self.vao);
            gl.DrawArrays(TRIANGLES, 0, 3);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn packed_depth_unpacks_to_24_bits() {
        assert_eq!(unpack(&[255, 255, 255, 255]), 1.0);
        assert_eq!(unpack(&[0, 0, 0, 255]), 0.0);
        let d = 0.987_654_3f64;
        let v = (d * 16_777_215.0).round() as u32;
        let p = [(v >> 16) as u8, (v >> 8) as u8, v as u8, 255];
        assert!((f64::from(unpack(&p)) - d).abs() < 1e-7);
    }
}
