//! Save-and-restore of the GL state the layer touches behind the app's back.
//!
//! A [`StateGuard`] records each piece of state as it is asked for and puts everything back,
//! in reverse order, when dropped. Only state that exists in the context's version is
//! queried, so the guard itself never raises a GL error the app could later observe.

use super::GlInfo;
use super::*;

enum Saved {
    Framebuffers {
        draw: u32,
        read: u32,
    },
    Viewport([i32; 4]),
    Scissor([i32; 4]),
    Cap(GLenum, bool),
    Program(u32),
    VertexArray(u32),
    ActiveTexture(u32),
    Texture2d(u32),
    Sampler0(u32),
    Renderbuffer(u32),
    ColorMask([u8; 4]),
    DepthMask(u8),
    PolygonMode(i32),
    MatrixMode(i32),
    DepthFunc(u32),
    DepthRange([f64; 2]),
    /// Source and destination factors (RGB, alpha), then the equations (RGB, alpha).
    Blend([i32; 6]),
    /// Per face (front, back): function, reference, value mask, fail, depth-fail, pass ops,
    /// write mask.
    Stencil([[i32; 7]; 2]),
    Sampler(u32, u32),
    /// (unit, target, name)
    Texture(u32, GLenum, u32),
    /// (target, name) of a non-indexed buffer binding.
    Buffer(GLenum, u32),
    /// (target, index, name, start, size) of an indexed buffer binding.
    IndexedBuffer(GLenum, u32, u32, i64, i64),
    /// (unit, name, level, layered, layer, access, format) of an image unit.
    Image(u32, u32, i32, u8, i32, GLenum, GLenum),
}

pub struct StateGuard<'a> {
    gl: &'a Gl,
    pub info: GlInfo,
    saved: Vec<Saved>,
}

pub fn get_i(gl: &Gl, pname: GLenum) -> i32 {
    crate::log::costs::gl_query();
    let mut v = 0;
    // SAFETY: single-value query into a local.
    unsafe { gl.GetIntegerv(pname, &mut v) };
    v
}

pub fn get_i4(gl: &Gl, pname: GLenum) -> [i32; 4] {
    crate::log::costs::gl_query();
    let mut v = [0; 4];
    // SAFETY: four-value query into a local array.
    unsafe { gl.GetIntegerv(pname, v.as_mut_ptr()) };
    v
}

impl<'a> StateGuard<'a> {
    pub fn new(gl: &'a Gl, info: GlInfo) -> Self {
        StateGuard {
            gl,
            info,
            saved: Vec::with_capacity(16),
        }
    }

    pub fn framebuffers(mut self) -> Self {
        let (draw, read) = (
            get_i(self.gl, DRAW_FRAMEBUFFER_BINDING) as u32,
            get_i(self.gl, READ_FRAMEBUFFER_BINDING) as u32,
        );
        self.saved.push(Saved::Framebuffers { draw, read });
        self
    }

    pub fn viewport(mut self) -> Self {
        self.saved.push(Saved::Viewport(get_i4(self.gl, VIEWPORT)));
        self
    }

    pub fn scissor(mut self) -> Self {
        self.saved.push(Saved::Scissor(get_i4(self.gl, SCISSOR_BOX)));
        self.caps(&[SCISSOR_TEST])
    }

    pub fn caps(mut self, caps: &[GLenum]) -> Self {
        for &cap in caps {
            // SAFETY: querying an enable flag valid in this context.
            let on = unsafe { self.gl.IsEnabled(cap) } != 0;
            self.saved.push(Saved::Cap(cap, on));
        }
        self
    }

    /// Everything a full-screen pass of ours changes: program, vertex array, texture unit 0,
    /// sampler, renderbuffer, masks and the fixed-function toggles that would alter it.
    pub fn for_pass(mut self) -> Self {
        let gl = self.gl;
        self.saved.push(Saved::Program(get_i(gl, CURRENT_PROGRAM) as u32));
        if self.info.has_gl3_features() {
            self.saved
                .push(Saved::VertexArray(get_i(gl, VERTEX_ARRAY_BINDING) as u32));
        }
        self.saved.push(Saved::ActiveTexture(get_i(gl, ACTIVE_TEXTURE) as u32));
        // SAFETY: selecting unit 0 so its bindings can be read; restored by the guard.
        unsafe { gl.ActiveTexture(TEXTURE0) };
        self.saved.push(Saved::Texture2d(get_i(gl, TEXTURE_BINDING_2D) as u32));
        if self.info.has_samplers() {
            self.saved.push(Saved::Sampler0(get_i(gl, SAMPLER_BINDING) as u32));
        }
        self.saved
            .push(Saved::Renderbuffer(get_i(gl, RENDERBUFFER_BINDING) as u32));
        let mut mask = [0u8; 4];
        // SAFETY: four-boolean query into a local array.
        unsafe { gl.GetBooleanv(COLOR_WRITEMASK, mask.as_mut_ptr()) };
        self.saved.push(Saved::ColorMask(mask));
        let mut depth = 0u8;
        // SAFETY: one-boolean query into a local.
        unsafe { gl.GetBooleanv(DEPTH_WRITEMASK, &mut depth) };
        self.saved.push(Saved::DepthMask(depth));
        if !self.info.es {
            let mut modes = [0i32; 2];
            // SAFETY: GL_POLYGON_MODE answers two integers (desktop GL only, checked above).
            unsafe { gl.GetIntegerv(POLYGON_MODE, modes.as_mut_ptr()) };
            self.saved.push(Saved::PolygonMode(modes[0]));
        }
        let mut caps = vec![BLEND, DEPTH_TEST, STENCIL_TEST, CULL_FACE, DITHER, SCISSOR_TEST];
        if self.info.has_gl3_features() {
            caps.push(RASTERIZER_DISCARD);
        }
        if !self.info.es {
            caps.extend([FRAMEBUFFER_SRGB, COLOR_LOGIC_OP, MULTISAMPLE]);
        }
        if compatibility(gl, self.info) {
            caps.push(ALPHA_TEST);
        }
        self.caps(&caps).viewport()
    }

    pub fn depth_range(mut self) -> Self {
        let mut r = [0.0f64; 2];
        if self.info.es {
            let mut f = [0.0f32; 2];
            // SAFETY: two floats into a local array (ES has no glGetDoublev).
            unsafe { self.gl.GetFloatv(DEPTH_RANGE, f.as_mut_ptr()) };
            r = f.map(f64::from);
        } else {
            // SAFETY: two doubles into a local array.
            unsafe { self.gl.GetDoublev(DEPTH_RANGE, r.as_mut_ptr()) };
        }
        self.saved.push(Saved::DepthRange(r));
        self
    }

    /// The depth test's function (a pass writing depth sets `GL_ALWAYS`).
    pub fn depth_func(mut self) -> Self {
        self.saved.push(Saved::DepthFunc(get_i(self.gl, DEPTH_FUNC) as u32));
        self
    }

    /// The blend factors and equations (a pass that blends sets its own).
    pub fn blend_func(mut self) -> Self {
        let names = [
            BLEND_SRC_RGB,
            BLEND_DST_RGB,
            BLEND_SRC_ALPHA,
            BLEND_DST_ALPHA,
            BLEND_EQUATION_RGB,
            BLEND_EQUATION_ALPHA,
        ];
        self.saved.push(Saved::Blend(names.map(|n| get_i(self.gl, n))));
        self
    }

    /// The stencil test's functions, operations and write masks, both faces.
    pub fn stencil(mut self) -> Self {
        let front = [
            STENCIL_FUNC,
            STENCIL_REF,
            STENCIL_VALUE_MASK,
            STENCIL_FAIL,
            STENCIL_PASS_DEPTH_FAIL,
            STENCIL_PASS_DEPTH_PASS,
            STENCIL_WRITEMASK,
        ];
        let back = [
            STENCIL_BACK_FUNC,
            STENCIL_BACK_REF,
            STENCIL_BACK_VALUE_MASK,
            STENCIL_BACK_FAIL,
            STENCIL_BACK_PASS_DEPTH_FAIL,
            STENCIL_BACK_PASS_DEPTH_PASS,
            STENCIL_BACK_WRITEMASK,
        ];
        let gl = self.gl;
        self.saved.push(Saved::Stencil([
            front.map(|n| get_i(gl, n)),
            back.map(|n| get_i(gl, n)),
        ]));
        self
    }

    /// The `target` binding (`binding` names its query) of texture units `units`; the active
    /// unit must be saved first (`for_pass` does).
    pub fn textures(mut self, target: GLenum, binding: GLenum, units: std::ops::Range<u32>) -> Self {
        for unit in units {
            // SAFETY: selecting a unit to read its binding; the active unit is restored.
            unsafe { self.gl.ActiveTexture(TEXTURE0 + unit) };
            self.saved
                .push(Saved::Texture(unit, target, get_i(self.gl, binding) as u32));
        }
        self
    }

    /// Sampler objects bound to texture units `units`; the active unit must be saved first.
    pub fn samplers(mut self, units: std::ops::Range<u32>) -> Self {
        for unit in units {
            // SAFETY: selecting a unit to read its sampler; the active unit is restored.
            unsafe { self.gl.ActiveTexture(TEXTURE0 + unit) };
            self.saved
                .push(Saved::Sampler(unit, get_i(self.gl, SAMPLER_BINDING) as u32));
        }
        self
    }

    pub fn buffer(mut self, target: GLenum, binding: GLenum) -> Self {
        self.saved.push(Saved::Buffer(target, get_i(self.gl, binding) as u32));
        self
    }

    /// Indexed bindings `indices` of `target` (a storage or uniform buffer), with the generic
    /// binding that binding an index also changes.
    pub fn indexed_buffers(
        mut self,
        target: GLenum,
        binding: GLenum,
        start: GLenum,
        size: GLenum,
        indices: std::ops::Range<u32>,
    ) -> Self {
        self = self.buffer(target, binding);
        for i in indices {
            let (mut name, mut from, mut len) = (0i32, 0i64, 0i64);
            // SAFETY: indexed queries into locals.
            unsafe {
                self.gl.GetIntegeri_v(binding, i, &mut name);
                self.gl.GetInteger64i_v(start, i, &mut from);
                self.gl.GetInteger64i_v(size, i, &mut len);
            }
            self.saved.push(Saved::IndexedBuffer(target, i, name as u32, from, len));
        }
        self
    }

    /// Image units `units` (GL 4.2), as `glBindImageTexture` sets them.
    pub fn images(mut self, units: std::ops::Range<u32>) -> Self {
        for u in units {
            let at = |pname| {
                let mut v = 0i32;
                // SAFETY: an indexed integer query into a local.
                unsafe { self.gl.GetIntegeri_v(pname, u, &mut v) };
                v
            };
            self.saved.push(Saved::Image(
                u,
                at(IMAGE_BINDING_NAME) as u32,
                at(IMAGE_BINDING_LEVEL),
                at(IMAGE_BINDING_LAYERED) as u8,
                at(IMAGE_BINDING_LAYER),
                at(IMAGE_BINDING_ACCESS) as GLenum,
                at(IMAGE_BINDING_FORMAT) as GLenum,
            ));
        }
        self
    }

    pub fn matrix_mode(mut self) -> Self {
        self.saved.push(Saved::MatrixMode(get_i(self.gl, MATRIX_MODE)));
        self
    }

    fn restore(&self, s: &Saved) {
        let gl = self.gl;
        // SAFETY: every value restored was read from this same current context.
        unsafe {
            match *s {
                Saved::Framebuffers { draw, read } => {
                    gl.BindFramebuffer(DRAW_FRAMEBUFFER, draw);
                    gl.BindFramebuffer(READ_FRAMEBUFFER, read);
                }
                Saved::Viewport(v) => gl.Viewport(v[0], v[1], v[2], v[3]),
                Saved::Scissor(v) => gl.Scissor(v[0], v[1], v[2], v[3]),
                Saved::Cap(cap, true) => gl.Enable(cap),
                Saved::Cap(cap, false) => gl.Disable(cap),
                Saved::Program(p) => gl.UseProgram(p),
                Saved::VertexArray(v) => gl.BindVertexArray(v),
                Saved::ActiveTexture(t) => gl.ActiveTexture(t),
                Saved::Texture2d(t) => gl.BindTexture(TEXTURE_2D, t),
                Saved::Sampler0(s) => gl.BindSampler(0, s),
                Saved::Renderbuffer(r) => gl.BindRenderbuffer(RENDERBUFFER, r),
                Saved::ColorMask(m) => gl.ColorMask(m[0], m[1], m[2], m[3]),
                Saved::DepthMask(d) => gl.DepthMask(d),
                Saved::DepthFunc(f) => gl.DepthFunc(f),
                Saved::PolygonMode(m) => gl.PolygonMode(FRONT_AND_BACK, m as u32),
                Saved::MatrixMode(m) => gl.MatrixMode(m as u32),
                Saved::DepthRange(r) => set_depth_range(gl, self.info, r),
                Saved::Stencil(faces) => {
                    for (face, s) in [FRONT, BACK].into_iter().zip(faces) {
                        gl.StencilFuncSeparate(face, s[0] as u32, s[1], s[2] as u32);
                        gl.StencilOpSeparate(face, s[3] as u32, s[4] as u32, s[5] as u32);
                        gl.StencilMaskSeparate(face, s[6] as u32);
                    }
                }
                Saved::Blend(b) => {
                    gl.BlendFuncSeparate(b[0] as u32, b[1] as u32, b[2] as u32, b[3] as u32);
                    gl.BlendEquationSeparate(b[4] as u32, b[5] as u32);
                }
                Saved::Sampler(unit, name) => gl.BindSampler(unit, name),
                Saved::Texture(unit, target, name) => {
                    gl.ActiveTexture(TEXTURE0 + unit);
                    gl.BindTexture(target, name);
                }
                Saved::Buffer(target, name) => gl.BindBuffer(target, name),
                Saved::IndexedBuffer(target, i, name, _, 0) => gl.BindBufferBase(target, i, name),
                Saved::IndexedBuffer(target, i, name, start, size) => {
                    gl.BindBufferRange(target, i, name, start as isize, size as isize)
                }
                Saved::Image(u, name, level, layered, layer, access, format) => {
                    gl.BindImageTexture(u, name, level, layered, layer, access, format)
                }
            }
        }
    }
}

impl Drop for StateGuard<'_> {
    fn drop(&mut self) {
        for s in self.saved.iter().rev() {
            self.restore(s);
        }
    }
}

/// `glDepthRange`, or `glDepthRangef` on ES (which has only that one).
pub fn set_depth_range(gl: &Gl, info: GlInfo, [near, far]: [f64; 2]) {
    // SAFETY: plain state setters of the current context.
    unsafe {
        if info.es {
            gl.DepthRangef(near as f32, far as f32);
        } else {
            gl.DepthRange(near, far);
        }
    }
}

/// Fixed-function state a full-screen pass of ours must not inherit from the app (the caller
/// holds a `StateGuard::for_pass` that puts it all back).
/// A context with the fixed-function per-fragment state (desktop before 3.1, or a 3.2+
/// compatibility profile): there the alpha test applies to our passes' output too.
pub fn compatibility(gl: &Gl, info: GlInfo) -> bool {
    !info.es
        && (!info.at_least(3, 1)
            || info.at_least(3, 2) && get_i(gl, CONTEXT_PROFILE_MASK) as u32 & CONTEXT_COMPATIBILITY_PROFILE_BIT != 0)
}

pub fn neutral_pass_state(gl: &Gl, info: GlInfo) {
    let mut off = vec![BLEND, DEPTH_TEST, STENCIL_TEST, CULL_FACE, SCISSOR_TEST, DITHER];
    // A fixed-function game's alpha test (foliage: GL_GREATER 0.5) left on at the swap would
    // discard every fragment of a pass whose output has no alpha of 1 (found on Minetest).
    if compatibility(gl, info) {
        off.push(ALPHA_TEST);
    }
    if info.es || info.at_least(3, 0) {
        off.push(RASTERIZER_DISCARD);
    }
    if !info.es {
        off.extend([FRAMEBUFFER_SRGB, COLOR_LOGIC_OP]);
    }
    // SAFETY: toggles and masks valid in this context, restored by the caller's guard.
    unsafe {
        for cap in off {
            gl.Disable(cap);
        }
        gl.ColorMask(TRUE, TRUE, TRUE, TRUE);
        if !info.es {
            gl.PolygonMode(FRONT_AND_BACK, FILL);
        }
        if info.es && info.at_least(3, 0) || !info.es && info.at_least(3, 3) {
            gl.BindSampler(0, 0);
        }
    }
}
