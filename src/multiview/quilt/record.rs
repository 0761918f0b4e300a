//! The disparity record's storage and draw state (DESIGN §5, "One disparity per pixel"; the
//! shader side is `shader::record`).
//!
//! The scene target's rendered views get a companion colour attachment at draw buffer
//! `RECORD_BUFFER`: a `RG32F` texture the size of the quilt when the camera draws to
//! framebuffer 0, or an array with a layer per view beside a shadowed framebuffer's layers.
//! Programs with the record write `(p, 1)` there; every other draw into the target (fixed
//! function, programs the layer could not edit) broadcasts its colour to all draw buffers, so
//! for those the record's blend is set to `ZERO, ZERO`: `(0, 0)`, "not recorded", and the
//! readers fall back to depth there. Programs that write it blend with `SRC_ALPHA,
//! ONE_MINUS_SRC_ALPHA` when the app blends, with the coverage step of the shader as alpha,
//! so "what the viewer sees" decides: the nearest opaque surface through the depth test, a
//! translucent one where it contributes at all.
//!
//! The textures and framebuffers are ours. The draw-buffer list of our view framebuffers
//! gains `RECORD_BUFFER` for each recorded draw only; the quilt's keeps it from a recorded draw
//! until something else writes the quilt (an unrecorded draw, a clear, a blit, the warp, the
//! frame's end: `release_bound`), because a change of draw buffers costs a software
//! rasteriser a flush, and per tile the record's write mask says which views record. So
//! clears, blits and every other draw never reach the record, and buffer 7's blend state and
//! mask are put back to buffer 0's (the app's) after each recorded draw. A draw into the target that is not seen through the
//! camera (a HUD, a full-screen pass) is not recorded at all: the scene's record stays.
//! The record is cleared to "not recorded" after the frame is presented (the comfort pass is
//! its last reader).

use crate::gl::guard::get_i;
use crate::gl::*;
use crate::shader::record::RECORD_BUFFER;

const POINT: GLenum = COLOR_ATTACHMENT0 + RECORD_BUFFER;

/// A record texture: a 2D texture (`layers == 0`) or a 2D array.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RecordImage {
    pub texture: u32,
    pub size: (i32, i32),
    pub layers: i32,
}

#[derive(Debug, Default)]
pub struct DisparityRecord {
    /// Beside the quilt (the camera draws to framebuffer 0).
    pub quilt: Option<RecordImage>,
    /// Beside the shadow of the app's framebuffer `.0`.
    pub shadow: Option<(u32, RecordImage)>,
    /// A framebuffer of ours per view reading its record (`read_fbo`).
    read: Vec<(u32, RecordImage, i32)>,
    /// Buffer 7's blend state was changed for the current draw.
    blend_changed: bool,
    /// What this frame wrote of the quilt's record and of the shadow's.
    dirty: (Dirty, Dirty),
}

/// What a frame wrote of a record.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
enum Dirty {
    #[default]
    Clean,
    View(u32),
    All,
}

fn image(gl: &Gl, size: (i32, i32), layers: i32) -> RecordImage {
    let mut t = 0;
    let target = if layers == 0 { TEXTURE_2D } else { TEXTURE_2D_ARRAY };
    // SAFETY: a texture of ours, created with DSA (no binding changed).
    unsafe {
        gl.CreateTextures(target, 1, &mut t);
        if layers == 0 {
            gl.TextureStorage2D(t, 1, RG32F, size.0.max(1), size.1.max(1));
        } else {
            gl.TextureStorage3D(t, 1, RG32F, size.0.max(1), size.1.max(1), layers);
        }
        gl.TextureParameteri(t, TEXTURE_MIN_FILTER, NEAREST as i32);
        gl.TextureParameteri(t, TEXTURE_MAG_FILTER, NEAREST as i32);
        let zero = [0f32; 2];
        gl.ClearTexImage(t, 0, RG, FLOAT, zero.as_ptr().cast());
    }
    RecordImage {
        texture: t,
        size,
        layers,
    }
}

impl DisparityRecord {
    /// The quilt's record, made (or remade) for a quilt of `size`.
    pub fn quilt_image(&mut self, gl: &Gl, size: (i32, i32)) -> RecordImage {
        match self.quilt {
            Some(r) if r.size == size => r,
            old => {
                if let Some(o) = old {
                    self.forget(gl, o.texture);
                }
                let r = image(gl, size, 0);
                self.quilt = Some(r);
                r
            }
        }
    }

    /// The record beside the shadow of the app's `fbo`, `views` layers of `size`.
    pub fn shadow_image(&mut self, gl: &Gl, fbo: u32, size: (i32, i32), views: i32) -> RecordImage {
        match self.shadow {
            Some((f, r)) if f == fbo && r.size == size && r.layers == views => r,
            old => {
                if let Some((_, o)) = old {
                    self.forget(gl, o.texture);
                }
                let r = image(gl, size, views);
                self.shadow = Some((fbo, r));
                r
            }
        }
    }

    fn forget(&mut self, gl: &Gl, texture: u32) {
        for (fbo, img, _) in self.read.iter_mut() {
            if img.texture == texture {
                // SAFETY: our own framebuffer; its attachment is going away.
                unsafe { gl.NamedFramebufferTexture(*fbo, COLOR_ATTACHMENT0, 0, 0) };
                *img = RecordImage::default();
            }
        }
        // SAFETY: our own texture; every framebuffer of ours detached it above or is a view
        // framebuffer that re-attaches before its next draw.
        unsafe { gl.DeleteTextures(1, &texture) };
    }

    /// Attaches `img` (layer `layer` of an array) to the bound draw framebuffer (ours: the
    /// quilt or a view framebuffer) and puts `RECORD_BUFFER` in its draw-buffer list for the
    /// draw; `release_bound` takes it out again, so that blits into the quilt (ours, the
    /// app's) and everything drawn outside a recorded draw never reach the record.
    pub fn attach_bound(gl: &Gl, img: RecordImage, layer: i32) {
        let mut name = 0;
        let mut at_layer = 0;
        // SAFETY: queries and attachment on our own framebuffer, bound by the caller.
        unsafe {
            gl.GetFramebufferAttachmentParameteriv(
                DRAW_FRAMEBUFFER,
                POINT,
                FRAMEBUFFER_ATTACHMENT_OBJECT_NAME,
                &mut name,
            );
            if name as u32 == img.texture && img.layers > 0 {
                gl.GetFramebufferAttachmentParameteriv(
                    DRAW_FRAMEBUFFER,
                    POINT,
                    FRAMEBUFFER_ATTACHMENT_TEXTURE_LAYER,
                    &mut at_layer,
                );
            }
            if name as u32 != img.texture || at_layer != layer {
                if img.layers == 0 {
                    gl.FramebufferTexture2D(DRAW_FRAMEBUFFER, POINT, TEXTURE_2D, img.texture, 0);
                } else {
                    gl.FramebufferTextureLayer(DRAW_FRAMEBUFFER, POINT, img.texture, 0, layer);
                }
            }
            if get_i(gl, DRAW_BUFFER0 + RECORD_BUFFER) as GLenum != POINT {
                let mut bufs = [NONE; RECORD_BUFFER as usize + 1];
                for (i, b) in bufs.iter_mut().enumerate().take(RECORD_BUFFER as usize) {
                    *b = get_i(gl, DRAW_BUFFER0 + i as u32) as GLenum;
                }
                bufs[RECORD_BUFFER as usize] = POINT;
                gl.DrawBuffers(bufs.len() as i32, bufs.as_ptr());
            }
        }
    }

    /// Takes `RECORD_BUFFER` out of the bound draw framebuffer's list after a recorded draw.
    pub fn release_bound(gl: &Gl) {
        // SAFETY: our own framebuffer, bound by the caller; only the record's slot changes.
        unsafe {
            if get_i(gl, DRAW_BUFFER0 + RECORD_BUFFER) as GLenum == POINT {
                let mut bufs = [NONE; RECORD_BUFFER as usize];
                for (i, b) in bufs.iter_mut().enumerate() {
                    *b = get_i(gl, DRAW_BUFFER0 + i as u32) as GLenum;
                }
                let n = bufs.iter().rposition(|&b| b != NONE).map_or(1, |i| i + 1);
                gl.DrawBuffers(n as i32, bufs.as_ptr());
            }
        }
    }

    /// The record's write mask: `on` when the app's colour writes are on and this view
    /// records (a colour-masked pass, a stencil shadow volume, leaves no record).
    pub fn mask(gl: &Gl, on: bool) {
        let b = if on { TRUE } else { FALSE };
        // SAFETY: the write mask of the record's draw buffer alone.
        unsafe { gl.ColorMaski(RECORD_BUFFER, b, b, b, b) };
    }

    /// The app's colour write mask (buffer 0's red), which the record follows.
    pub fn app_writes_colour(gl: &Gl) -> bool {
        let mut m = [0u8; 4];
        // SAFETY: a four-boolean query into a local.
        unsafe { gl.GetBooleanv(COLOR_WRITEMASK, m.as_mut_ptr()) };
        m[0] != 0
    }

    /// `release_bound` on the quilt's framebuffer `fbo`, whatever is bound: before our own
    /// passes write the quilt (the warp, the frame's end).
    pub fn release_quilt(gl: &Gl, fbo: Option<u32>) {
        let Some(fbo) = fbo else { return };
        let bound = get_i(gl, DRAW_FRAMEBUFFER_BINDING) as u32;
        // SAFETY: our framebuffer bound for the query and put back.
        unsafe { gl.BindFramebuffer(DRAW_FRAMEBUFFER, fbo) };
        Self::release_bound(gl);
        // SAFETY: as above.
        unsafe { gl.BindFramebuffer(DRAW_FRAMEBUFFER, bound) };
    }

    /// Before a draw into a recording target: the record's blend for what this draw writes
    /// there (`records`: its fragment shader writes the record; `blending`: the app blends).
    pub fn before_draw(&mut self, gl: &Gl, records: bool, blending: bool) {
        // SAFETY: per-buffer blend state of the record's draw buffer, put back by `after_draw`.
        unsafe {
            if records && !blending {
                return;
            }
            gl.Enablei(BLEND, RECORD_BUFFER);
            gl.BlendEquationi(RECORD_BUFFER, FUNC_ADD);
            if records {
                gl.BlendFunci(RECORD_BUFFER, SRC_ALPHA, ONE_MINUS_SRC_ALPHA);
            } else {
                gl.BlendFunci(RECORD_BUFFER, ZERO, ZERO);
            }
        }
        self.blend_changed = true;
    }

    /// Buffer 7's blend state back to buffer 0's (what the app set for all buffers).
    pub fn after_draw(&mut self, gl: &Gl) {
        if !std::mem::take(&mut self.blend_changed) {
            return;
        }
        let at0 = |p| {
            let mut v = 0;
            // SAFETY: an indexed integer query into a local.
            unsafe { gl.GetIntegeri_v(p, 0, &mut v) };
            v as GLenum
        };
        let (sr, dr, sa, da) = (
            at0(BLEND_SRC_RGB),
            at0(BLEND_DST_RGB),
            at0(BLEND_SRC_ALPHA),
            at0(BLEND_DST_ALPHA),
        );
        let (er, ea) = (at0(BLEND_EQUATION_RGB), at0(BLEND_EQUATION_ALPHA));
        // SAFETY: buffer 7's blend state set to buffer 0's.
        unsafe {
            gl.BlendFuncSeparatei(RECORD_BUFFER, sr, dr, sa, da);
            gl.BlendEquationSeparatei(RECORD_BUFFER, er, ea);
            if gl.IsEnabledi(BLEND, 0) == 0 {
                gl.Disablei(BLEND, RECORD_BUFFER);
            }
        }
    }

    /// A framebuffer of ours whose colour attachment 0 (its read buffer) is `img`'s layer
    /// `layer`, one per view `slot`, for the readers' blits; `flipped`: stored top-down as
    /// the quilt is (`GL_MESA_framebuffer_flip_y`), so the quilt's rectangles address it.
    pub fn read_fbo(&mut self, gl: &Gl, slot: usize, img: RecordImage, layer: i32, flipped: bool) -> u32 {
        while self.read.len() <= slot {
            let mut f = 0;
            // SAFETY: a framebuffer of ours, created with DSA.
            unsafe {
                gl.CreateFramebuffers(1, &mut f);
                gl.NamedFramebufferReadBuffer(f, COLOR_ATTACHMENT0);
            }
            self.read.push((f, RecordImage::default(), -1));
        }
        let (fbo, held, held_layer) = &mut self.read[slot];
        let layer_flip = layer | (flipped as i32) << 30;
        if *held != img || *held_layer != layer_flip {
            // SAFETY: our framebuffer and texture.
            unsafe {
                if img.layers == 0 {
                    gl.NamedFramebufferTexture(*fbo, COLOR_ATTACHMENT0, img.texture, 0);
                } else {
                    gl.NamedFramebufferTextureLayer(*fbo, COLOR_ATTACHMENT0, img.texture, 0, layer);
                }
            }
            if gl.NamedFramebufferParameteri.is_loaded() {
                // SAFETY: a parameter of our own framebuffer (the extension is the quilt's).
                unsafe {
                    gl.NamedFramebufferParameteri(*fbo, super::window_format::FRAMEBUFFER_FLIP_Y_MESA, flipped as i32)
                };
            }
            (*held, *held_layer) = (img, layer_flip);
        }
        *fbo
    }

    /// A recorded draw into the quilt (`shadow`: into the shadow) wrote view `only`, or every
    /// view: what the frame's clear must reach.
    pub fn mark(&mut self, shadow: bool, only: Option<u32>) {
        let d = if shadow { &mut self.dirty.1 } else { &mut self.dirty.0 };
        *d = match (*d, only) {
            (Dirty::Clean, Some(v)) => Dirty::View(v),
            (Dirty::View(w), Some(v)) if w == v => Dirty::View(v),
            _ => Dirty::All,
        };
    }

    /// Every record back to "not recorded", for the next frame: only what the frame wrote
    /// (exact mode records one view; a quilt-sized clear is most of what it would cost).
    pub fn clear(&mut self, gl: &Gl, layout: Option<super::layout::QuiltLayout>) {
        let zero = [0f32; 2];
        let (quilt, shadow) = std::mem::take(&mut self.dirty);
        let images = [(self.quilt, quilt), (self.shadow.map(|(_, r)| r), shadow)];
        for (img, dirty) in images {
            let Some(img) = img else { continue };
            let ptr = zero.as_ptr().cast();
            // SAFETY: our own texture, a region inside it.
            unsafe {
                match (dirty, layout) {
                    (Dirty::Clean, _) => {}
                    (Dirty::View(v), Some(l)) if img.layers == 0 => {
                        let [x, y, w, h] = l.tile_rect(v);
                        // Stored top-down like the quilt when it is.
                        let y = if l.flipped { img.size.1 - y - h } else { y };
                        gl.ClearTexSubImage(img.texture, 0, x, y.max(0), 0, w, h, 1, RG, FLOAT, ptr);
                    }
                    (Dirty::View(v), _) if (v as i32) < img.layers => {
                        let (w, h) = img.size;
                        gl.ClearTexSubImage(img.texture, 0, 0, 0, v as i32, w, h, 1, RG, FLOAT, ptr);
                    }
                    _ => gl.ClearTexImage(img.texture, 0, RG, FLOAT, ptr),
                }
            }
        }
    }

    pub fn textures(&self) -> Vec<u32> {
        self.quilt
            .iter()
            .chain(self.shadow.iter().map(|(_, r)| r))
            .map(|r| r.texture)
            .collect()
    }
}

/// The read framebuffer and rectangle of rendered view `r`'s record, when the scene target
/// records (`depth_fbo`: where its depth is read from, the quilt or a view framebuffer).
pub fn source(gl: &Gl, mv: &mut crate::multiview::Multiview, r: u32, quilt_rect: [i32; 4]) -> Option<(u32, [i32; 4])> {
    if !(mv.settings.disparity_record && mv.record_supported) {
        return None;
    }
    match mv.scene.tracker.target? {
        0 => {
            let img = mv.record.quilt?;
            let flipped = mv.layout().is_some_and(|l| l.flipped);
            Some((mv.record.read_fbo(gl, r as usize, img, 0, flipped), quilt_rect))
        }
        fbo => {
            let (f, img) = mv.record.shadow?;
            let s = mv.shadows.get(&fbo).filter(|s| !s.stale && f == fbo)?;
            (s.size == img.size).then_some(())?;
            Some((
                mv.record.read_fbo(gl, r as usize, img, r as i32, false),
                [0, 0, img.size.0, img.size.1],
            ))
        }
    }
}
