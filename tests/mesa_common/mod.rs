//! What the tests that run the injected GLSL on Mesa in their own process share
//! (`remap_on_mesa.rs`, `shift_on_mesa.rs`): an OSMesa context with the layer kept in
//! pass-through, and vertex programs whose outputs come back through transform feedback.
//! The layer's rewrite is judged by numbers Mesa computes, not by pixels: transform feedback
//! returns the clip coordinates the rasteriser would get, bit for bit, for any points the
//! test chooses, without a framebuffer in the way.

use holoapps::gl::{self, Gl};
use holoapps::platform::{Platform, Profile, create};
use std::ffi::CString;

pub struct Mesa {
    _platform: Box<dyn Platform>,
    pub gl: Gl,
}

/// A 16x16 OSMesa context of `profile`, current on this thread.
pub fn mesa(profile: Profile) -> Mesa {
    // A test executable linking the holoinject rlib exports its hooks (and `dlsym`), so the
    // layer is live in this process: keep it in pass-through, as the shaders here are
    // rewritten and driven by hand.
    static PASS_THROUGH: std::sync::Once = std::sync::Once::new();
    // SAFETY: the layer reads its settings on its first GL call, after this; every test
    // writes the same value under the Once.
    PASS_THROUGH.call_once(|| unsafe { std::env::set_var("HOLOINJECT_OUTPUT", "mono") });
    let platform = create(holoapps::cli::Backend::OsMesa, (16, 16), profile).expect("OSMesa context");
    let gl = Gl::load_with(|s| platform.get_proc_address(s));
    Mesa {
        _platform: platform,
        gl,
    }
}

/// A vertex-only program capturing `varying` with transform feedback.
pub fn capture_program(gl: &Gl, vertex: &str, varying: &str) -> u32 {
    holoapps::shader::compile_status(gl, gl::VERTEX_SHADER, vertex)
        .unwrap_or_else(|e| panic!("Mesa refused: {e}\n{vertex}"));
    // SAFETY (test): plain GL calls on the current OSMesa context.
    unsafe {
        let s = gl.CreateShader(gl::VERTEX_SHADER);
        let c = CString::new(vertex).unwrap();
        gl.ShaderSource(s, 1, &c.as_ptr(), std::ptr::null());
        gl.CompileShader(s);
        let p = gl.CreateProgram();
        gl.AttachShader(p, s);
        let v = CString::new(varying).unwrap();
        gl.TransformFeedbackVaryings(p, 1, &v.as_ptr(), gl::INTERLEAVED_ATTRIBS);
        gl.LinkProgram(p);
        let mut ok = 0;
        gl.GetProgramiv(p, gl::LINK_STATUS, &mut ok);
        assert_eq!(ok, 1, "link failed");
        gl.DeleteShader(s);
        p
    }
}

/// `components` floats per point of what `program` (its uniforms set) captures for `points`.
pub fn capture(gl: &Gl, program: u32, points: &[[f32; 4]], components: usize) -> Vec<f32> {
    // SAFETY (test): our buffers and a rasterizer-discarded point draw.
    unsafe {
        gl.UseProgram(program);
        let (mut vao, mut vbo, mut tfb) = (0, 0, 0);
        gl.GenVertexArrays(1, &mut vao);
        gl.BindVertexArray(vao);
        gl.GenBuffers(1, &mut vbo);
        gl.BindBuffer(gl::ARRAY_BUFFER, vbo);
        let bytes = std::mem::size_of_val(points) as isize;
        gl.BufferData(gl::ARRAY_BUFFER, bytes, points.as_ptr().cast(), gl::STATIC_DRAW);
        gl.VertexAttribPointer(0, 4, gl::FLOAT, gl::FALSE, 0, std::ptr::null());
        gl.EnableVertexAttribArray(0);
        gl.GenBuffers(1, &mut tfb);
        let out_bytes = (points.len() * components * 4) as isize;
        gl.BindBuffer(gl::TRANSFORM_FEEDBACK_BUFFER, tfb);
        gl.BufferData(
            gl::TRANSFORM_FEEDBACK_BUFFER,
            out_bytes,
            std::ptr::null(),
            gl::STATIC_READ,
        );
        gl.BindBufferBase(gl::TRANSFORM_FEEDBACK_BUFFER, 0, tfb);
        gl.Enable(gl::RASTERIZER_DISCARD);
        gl.BeginTransformFeedback(gl::POINTS);
        gl.DrawArrays(gl::POINTS, 0, points.len() as i32);
        gl.EndTransformFeedback();
        gl.Disable(gl::RASTERIZER_DISCARD);
        let mut out = vec![0f32; points.len() * components];
        gl.GetBufferSubData(gl::TRANSFORM_FEEDBACK_BUFFER, 0, out_bytes, out.as_mut_ptr().cast());
        assert_eq!(gl.GetError(), gl::NO_ERROR);
        gl.DeleteBuffers(1, &vbo);
        gl.DeleteBuffers(1, &tfb);
        gl.DeleteVertexArrays(1, &vao);
        out
    }
}
