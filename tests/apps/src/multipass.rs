//! Shared parts of the multi-pass apps (framebuffers, shadowmap, deferred,
//! ssao, bloom, msaa): offscreen-target helpers, the full-screen quad, the
//! common scene, and `Output`, which decides where an app's last pass goes.
//!
//! Ground truth for a quilt view is "what the app would render if its camera
//! were view i's camera". So a quilt view runs the app's whole pipeline at the
//! app's window size (same targets, blur radii, texel offsets, noise tiling),
//! ends in a window-sized stand-in for the default framebuffer, and only then
//! is copied into its tile. A normal frame ends in the window itself.
use crate::gl::{self, Gl};
use crate::math::{self, Mat4};
use crate::scene::View;
use std::ffi::c_void;

pub const EYE: [f32; 3] = [0.0, 4.5, 10.0];
pub const CENTRE: [f32; 3] = [0.0, 0.6, 0.0];

/// The app's own perspective projection (before any shear) and view matrix.
pub fn camera(size: (i32, i32)) -> (Mat4, Mat4) {
    let aspect = size.0 as f32 / size.1 as f32;
    (
        math::perspective(45f32.to_radians(), aspect, 0.1, 60.0),
        math::look_at(EYE, CENTRE, [0.0, 1.0, 0.0]),
    )
}

/// The shared scene: a floor, a ring of spinning cubes of varied height, a
/// tilted cube floating in the middle and a row of pillars behind, so there is
/// depth range for parallax, shadows and occlusion. (model, colour) pairs.
pub fn objects(t: f32) -> Vec<(Mat4, [f32; 3])> {
    let mut v = vec![(
        math::mul(&math::translate(0.0, -0.05, 0.0), &math::scale(16.0, 0.1, 16.0)),
        [0.55, 0.55, 0.6],
    )];
    for k in 0..7 {
        let a = k as f32 / 7.0 * std::f32::consts::TAU;
        let h = 0.6 + 0.35 * ((k * 3) % 4) as f32;
        let m = math::mul(
            &math::translate(3.0 * a.sin(), h / 2.0, 3.0 * a.cos()),
            &math::rotate(t * (0.6 + 0.15 * k as f32) + a, [0.0, 1.0, 0.0]),
        );
        let hue = k as f32 / 7.0;
        let c = [
            0.5 + 0.5 * (hue * std::f32::consts::TAU).cos(),
            0.5 + 0.5 * (hue * std::f32::consts::TAU + 2.1).cos(),
            0.5 + 0.5 * (hue * std::f32::consts::TAU + 4.2).cos(),
        ];
        v.push((math::mul(&m, &math::scale(0.9, h, 0.9)), c));
    }
    let spin = math::mul(&math::translate(0.0, 1.6, 0.0), &math::rotate(t * 0.9, [1.0, 1.0, 0.3]));
    v.push((math::mul(&spin, &math::scale(1.3, 1.3, 1.3)), [0.95, 0.85, 0.3]));
    for k in 0..5 {
        let x = -5.0 + 2.5 * k as f32;
        let h = 2.0 + 0.6 * (k % 3) as f32;
        let m = math::mul(&math::translate(x, h / 2.0, -5.5), &math::scale(0.8, h, 0.8));
        v.push((m, [0.35, 0.5 + 0.1 * k as f32, 0.75]));
    }
    v
}

/// Creates a 2D texture (left bound), clamped to edge with `filter` both ways;
/// `data` is float pixel data (only the SSAO noise has any), None leaves it undefined.
pub fn texture(
    gl: &Gl,
    internal: u32,
    size: (i32, i32),
    format: u32,
    ty: u32,
    filter: u32,
    data: Option<&[f32]>,
) -> u32 {
    let mut t = 0;
    unsafe {
        gl.GenTextures(1, &mut t);
        gl.BindTexture(gl::TEXTURE_2D, t);
        let ptr = data.map_or(std::ptr::null(), |d| d.as_ptr().cast());
        gl.TexImage2D(gl::TEXTURE_2D, 0, internal as i32, size.0, size.1, 0, format, ty, ptr);
        gl.TexParameteri(gl::TEXTURE_2D, gl::TEXTURE_MIN_FILTER, filter as i32);
        gl.TexParameteri(gl::TEXTURE_2D, gl::TEXTURE_MAG_FILTER, filter as i32);
        gl.TexParameteri(gl::TEXTURE_2D, gl::TEXTURE_WRAP_S, gl::CLAMP_TO_EDGE as i32);
        gl.TexParameteri(gl::TEXTURE_2D, gl::TEXTURE_WRAP_T, gl::CLAMP_TO_EDGE as i32);
    }
    t
}

/// Renderbuffer storage; `samples` 0 means single-sampled.
pub fn renderbuffer(gl: &Gl, internal: u32, samples: i32, size: (i32, i32)) -> u32 {
    let mut rb = 0;
    unsafe {
        gl.GenRenderbuffers(1, &mut rb);
        gl.BindRenderbuffer(gl::RENDERBUFFER, rb);
        if samples > 0 {
            gl.RenderbufferStorageMultisample(gl::RENDERBUFFER, samples, internal, size.0, size.1);
        } else {
            gl.RenderbufferStorage(gl::RENDERBUFFER, internal, size.0, size.1);
        }
    }
    rb
}

#[derive(Clone, Copy)]
pub enum Attachment {
    Texture(u32),
    Renderbuffer(u32),
}

/// FBO with `colour` on COLOR_ATTACHMENT0.. (all enabled as draw buffers) and
/// an optional depth attachment; checked for completeness, left unbound.
pub fn framebuffer(gl: &Gl, what: &str, colour: &[Attachment], depth: Option<Attachment>) -> Result<u32, String> {
    let mut fbo = 0;
    unsafe {
        gl.GenFramebuffers(1, &mut fbo);
        gl.BindFramebuffer(gl::FRAMEBUFFER, fbo);
        let attach = |point, a| match a {
            Attachment::Texture(t) => gl.FramebufferTexture2D(gl::FRAMEBUFFER, point, gl::TEXTURE_2D, t, 0),
            Attachment::Renderbuffer(r) => gl.FramebufferRenderbuffer(gl::FRAMEBUFFER, point, gl::RENDERBUFFER, r),
        };
        for (i, a) in colour.iter().enumerate() {
            attach(gl::COLOR_ATTACHMENT0 + i as u32, *a);
        }
        if let Some(d) = depth {
            attach(gl::DEPTH_ATTACHMENT, d);
        }
        if colour.is_empty() {
            // Depth-only: without this the FBO is incomplete (draw/read buffer checks).
            gl.DrawBuffer(gl::NONE);
            gl.ReadBuffer(gl::NONE);
        } else {
            let bufs: Vec<u32> = (0..colour.len() as u32).map(|i| gl::COLOR_ATTACHMENT0 + i).collect();
            gl.DrawBuffers(bufs.len() as i32, bufs.as_ptr());
        }
        let status = gl.CheckFramebufferStatus(gl::FRAMEBUFFER);
        gl.BindFramebuffer(gl::FRAMEBUFFER, 0);
        if status != gl::FRAMEBUFFER_COMPLETE {
            return Err(format!("{what} framebuffer incomplete (0x{status:04X})"));
        }
    }
    Ok(fbo)
}

/// World-space scene vertex shader shared by the forward and G-buffer passes:
/// the camera reaches it as LearnOpenGL's `projection`/`view`/`model`.
pub const SCENE_VS: &str = r#"#version 330 core
layout (location = 0) in vec3 aPos;
layout (location = 1) in vec3 aNormal;
uniform mat4 projection;
uniform mat4 view;
uniform mat4 model;
out vec3 FragPos;
out vec3 Normal;
void main() {
    vec4 world = model * vec4(aPos, 1.0);
    FragPos = world.xyz;
    Normal = mat3(transpose(inverse(model))) * aNormal;
    gl_Position = projection * view * world;
}
"#;

/// Vertex shader of every full-screen pass: NDC quad, no projection at all,
/// so these passes are view-independent.
pub const QUAD_VS: &str = r#"#version 330 core
layout (location = 0) in vec2 aPos;
layout (location = 1) in vec2 aUV;
out vec2 UV;
void main() {
    UV = aUV;
    gl_Position = vec4(aPos, 0.0, 1.0);
}
"#;

/// LearnOpenGL's full-screen quad: a 4-vertex triangle strip, pos (0) + uv (1).
pub fn quad_vao(gl: &Gl) -> u32 {
    quad(gl).0
}

/// The same quad as `(VAO, VBO)`, for apps that delete what they create.
pub fn quad(gl: &Gl) -> (u32, u32) {
    let verts: [f32; 16] = [
        -1.0, 1.0, 0.0, 1.0, -1.0, -1.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0, 1.0, -1.0, 1.0, 0.0,
    ];
    let (mut vao, mut vbo) = (0, 0);
    unsafe {
        gl.GenVertexArrays(1, &mut vao);
        gl.BindVertexArray(vao);
        gl.GenBuffers(1, &mut vbo);
        gl.BindBuffer(gl::ARRAY_BUFFER, vbo);
        gl.BufferData(gl::ARRAY_BUFFER, 64, verts.as_ptr().cast(), gl::STATIC_DRAW);
        gl.VertexAttribPointer(0, 2, gl::FLOAT, gl::FALSE, 16, std::ptr::null());
        gl.EnableVertexAttribArray(0);
        gl.VertexAttribPointer(1, 2, gl::FLOAT, gl::FALSE, 16, 8 as *const c_void);
        gl.EnableVertexAttribArray(1);
        gl.BindVertexArray(0);
    }
    (vao, vbo)
}

pub fn draw_quad(gl: &Gl, vao: u32) {
    unsafe {
        gl.BindVertexArray(vao);
        gl.DrawArrays(gl::TRIANGLE_STRIP, 0, 4);
    }
}

/// Draws every object of the scene with the bound cube VAO, setting `model`
/// and (if the program has one) the colour uniform per draw.
pub fn draw_objects(gl: &Gl, objs: &[(Mat4, [f32; 3])], model: i32, colour: i32) {
    for (m, c) in objs {
        set_mat4(gl, model, m);
        set_vec3(gl, colour, *c);
        unsafe { gl.DrawArrays(gl::TRIANGLES, 0, 36) };
    }
}

pub fn set_mat4(gl: &Gl, loc: i32, m: &Mat4) {
    unsafe { gl.UniformMatrix4fv(loc, 1, gl::FALSE, m.as_ptr()) };
}

pub fn set_vec3(gl: &Gl, loc: i32, v: [f32; 3]) {
    unsafe { gl.Uniform3f(loc, v[0], v[1], v[2]) };
}

/// Binds `tex` to texture unit `unit` and points sampler `loc` at it.
pub fn bind_texture(gl: &Gl, unit: u32, tex: u32, loc: i32) {
    unsafe {
        gl.ActiveTexture(gl::TEXTURE0 + unit);
        gl.BindTexture(gl::TEXTURE_2D, tex);
        gl.Uniform1i(loc, unit as i32);
    }
}

/// Where the last pass of a frame or quilt view goes (see the module docs).
pub struct Output {
    size: (i32, i32),
    /// Window-sized stand-in for the default framebuffer (FBO, colour, depth);
    /// created on the first quilt view so normal runs never see it.
    standin: Option<(u32, u32, u32)>,
    /// Framebuffer the runner had bound: the window (0) or the quilt FBO.
    outer: u32,
    scissor: bool,
}

impl Output {
    pub fn new(size: (u32, u32)) -> Output {
        Output {
            size: (size.0 as i32, size.1 as i32),
            standin: None,
            outer: 0,
            scissor: false,
        }
    }

    /// The app's window size: every offscreen target and pass uses it.
    pub fn size(&self) -> (i32, i32) {
        self.size
    }

    /// Start of a frame or view. Turns the runner's tile scissor off, which
    /// would otherwise clip the window-sized passes, and returns the
    /// framebuffer the last pass must draw to ("framebuffer 0" of the app).
    pub fn begin(&mut self, gl: &Gl, v: &View) -> u32 {
        unsafe {
            let mut outer = 0;
            gl.GetIntegerv(gl::DRAW_FRAMEBUFFER_BINDING, &mut outer);
            self.outer = outer as u32;
            self.scissor = gl.IsEnabled(gl::SCISSOR_TEST) == gl::TRUE;
            gl.Disable(gl::SCISSOR_TEST);
        }
        if v.shear.is_none() {
            return self.outer;
        }
        if self.standin.is_none() {
            self.standin = Some(self.create_standin(gl).unwrap_or_else(|e| {
                eprintln!("error: {e}");
                std::process::exit(1)
            }));
        }
        self.standin.unwrap().0
    }

    fn create_standin(&self, gl: &Gl) -> Result<(u32, u32, u32), String> {
        // Same formats as the window's FBConfig (RGBA8, D24S8).
        let colour = renderbuffer(gl, gl::RGBA8, 0, self.size);
        let depth = renderbuffer(gl, gl::DEPTH24_STENCIL8, 0, self.size);
        let fbo = framebuffer(gl, "stand-in", &[Attachment::Renderbuffer(colour)], None)?;
        unsafe {
            gl.BindFramebuffer(gl::FRAMEBUFFER, fbo);
            gl.FramebufferRenderbuffer(gl::FRAMEBUFFER, gl::DEPTH_STENCIL_ATTACHMENT, gl::RENDERBUFFER, depth);
            gl.BindFramebuffer(gl::FRAMEBUFFER, 0);
        }
        Ok((fbo, colour, depth))
    }

    /// End of a frame or view: a quilt view's image is copied into its tile
    /// (scaled if the tile size differs from the window); the runner's
    /// framebuffer and scissor are restored.
    pub fn end(&self, gl: &Gl, v: &View) {
        unsafe {
            if self.scissor {
                gl.Enable(gl::SCISSOR_TEST);
                gl.Scissor(v.viewport[0], v.viewport[1], v.viewport[2], v.viewport[3]);
            }
            if let (Some((fbo, _, _)), Some(_)) = (self.standin, v.shear) {
                gl.BindFramebuffer(gl::READ_FRAMEBUFFER, fbo);
                gl.BindFramebuffer(gl::DRAW_FRAMEBUFFER, self.outer);
                let [x, y, w, h] = v.viewport;
                let same = (w, h) == self.size;
                let filter = if same { gl::NEAREST } else { gl::LINEAR };
                let (sw, sh) = self.size;
                gl.BlitFramebuffer(0, 0, sw, sh, x, y, x + w, y + h, gl::COLOR_BUFFER_BIT, filter);
            }
            gl.BindFramebuffer(gl::FRAMEBUFFER, self.outer);
        }
    }
}
