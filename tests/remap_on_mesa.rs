//! The comfort remap's GLSL twin (`glsl-patches/depth_remap.glsl`), run on Mesa (OSMesa,
//! llvmpipe), against `camera::comfort::DepthRemap::apply` in f64:
//! - the bare function over disparities from -inf to +inf (values captured with transform
//!   feedback);
//! - the injected view shift with the remap on, exactly as the link hook rewrites a vertex
//!   shader, for the outermost of 48 views at eye distances from 1e-30 to 1e7: the disparity
//!   it produces must be `R(S·(1 - c/w)) + focus` px, and the centre view must stay
//!   bit-identical to the app's own shader.
//!
//! Run: `cargo test --release --test remap_on_mesa -- --nocapture`

use holoapps::gl::{self, Gl};
use holoapps::platform::{Platform, Profile, create};
use holoinject::camera::comfort::{DepthRemap, GLSL, REMAP_OFF};
use holoinject::shader::{REMAP_UNIFORM, Stage, VIEW_UNIFORM, ViewMode, analyse, rewrite};
use std::ffi::CString;

const VERTEX: &str = "#version 330 core
layout(location = 0) in vec4 pos;
void main() {
    gl_Position = pos;
}
";
const TILE_W: f64 = 420.0;

struct Mesa {
    _platform: Box<dyn Platform>,
    gl: Gl,
}

fn mesa() -> Mesa {
    // The layer linked into this test binary stays in pass-through (see shift_on_mesa.rs).
    static PASS_THROUGH: std::sync::Once = std::sync::Once::new();
    // SAFETY: written once, before the first GL call reads the settings.
    PASS_THROUGH.call_once(|| unsafe { std::env::set_var("HOLOINJECT_OUTPUT", "mono") });
    let platform = create(holoapps::cli::Backend::OsMesa, (16, 16), Profile::Core33).expect("OSMesa context");
    let gl = Gl::load_with(|s| platform.get_proc_address(s));
    Mesa {
        _platform: platform,
        gl,
    }
}

/// A vertex-only program capturing `varying` with transform feedback.
fn capture_program(gl: &Gl, vertex: &str, varying: &str) -> u32 {
    holoapps::shader::compile_status(gl, gl::VERTEX_SHADER, vertex).unwrap_or_else(|e| panic!("{e}\n{vertex}"));
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

fn set4(gl: &Gl, program: u32, name: &str, v: [f32; 4]) {
    let c = CString::new(name).unwrap();
    // SAFETY (test): a uniform of the bound program.
    unsafe {
        let loc = gl.GetUniformLocation(program, c.as_ptr());
        assert!(loc >= 0, "{name} not found");
        gl.Uniform4f(loc, v[0], v[1], v[2], v[3]);
    }
}

/// `components` floats per point of what `program` captures for `points`.
fn run(gl: &Gl, program: u32, points: &[[f32; 4]], components: usize) -> Vec<f32> {
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

fn remap() -> DepthRemap {
    DepthRemap::new(30.0, 40.0, 90.0, 120.0).unwrap()
}

#[test]
fn glsl_remap_matches_f64() {
    let mesa = mesa();
    let gl = &mesa.gl;
    let src = format!(
        "#version 330 core\n{GLSL}layout(location = 0) in vec4 pos;\nuniform vec4 r;\nout float y;\n\
         void main() {{ y = holoinject_remap(pos.x, r); gl_Position = vec4(0.0); }}\n"
    );
    let program = capture_program(gl, &src, "y");
    let r = remap();
    let mut xs: Vec<f32> = (-2000..=2000).map(|k| k as f32 * 0.25).collect();
    xs.extend([
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::MAX,
        -f32::MAX,
        1e30,
        -1e30,
        -30.0,
        40.0,
    ]);
    let points: Vec<[f32; 4]> = xs.iter().map(|&x| [x, 0.0, 0.0, 1.0]).collect();
    // SAFETY (test): binding our program to set its uniform.
    unsafe { gl.UseProgram(program) };
    set4(gl, program, "r", r.uniform());
    let got = run(gl, program, &points, 1);
    let mut worst: f64 = 0.0;
    for (&x, &y) in xs.iter().zip(&got) {
        let want = r.apply(x as f64);
        assert!(y.is_finite(), "R({x}) = {y} on Mesa");
        // f32 rounding of a handful of operations on values up to the asymptote's size.
        let err = (y as f64 - want).abs();
        worst = worst.max(err);
        assert!(
            err <= 8.0 * f32::EPSILON as f64 * want.abs().max(120.0),
            "R({x}): Mesa {y}, f64 {want}"
        );
    }
    println!("remap on Mesa vs f64: worst {worst:.2e} px over {} inputs", xs.len());
    // Off (r = 0): the identity, bit for bit.
    set4(gl, program, "r", REMAP_OFF);
    let off = run(gl, program, &points, 1);
    assert!(xs.iter().zip(&off).all(|(x, y)| x.to_bits() == y.to_bits()));
}

#[test]
fn injected_shift_with_remap_gives_the_remapped_disparity() {
    let mesa = mesa();
    let gl = &mesa.gl;
    let plain = capture_program(gl, VERTEX, "gl_Position");
    let rewritten = capture_program(
        gl,
        &rewrite(VERTEX, &analyse(VERTEX, Stage::Vertex)).unwrap(),
        "gl_Position",
    );
    let (s, c, f) = (0.45f64, 5.0f64, 0.01f64);
    let px_per_parallax = s * TILE_W / 2.0;
    let r = remap();
    let comfort = r.scaled(px_per_parallax).unwrap().uniform();
    // Clip-space points (x, 0, 0, w) at eye distances w: z = 0 is never the far plane.
    let ws: Vec<f64> = (0..=200).map(|k| 10f64.powf(-2.0 + 9.0 * k as f64 / 200.0)).collect();
    let mut points: Vec<[f32; 4]> = ws.iter().map(|&w| [(0.3 * w) as f32, 0.1, 0.0, w as f32]).collect();
    points.push([0.0, 0.0, 0.0, 1e-30]);
    let mode = ViewMode::PerspectiveFiniteFar.as_uniform();
    let own = run(gl, plain, &points, 4);
    // SAFETY (test): binding our program to set its uniforms.
    unsafe { gl.UseProgram(rewritten) };
    set4(gl, rewritten, REMAP_UNIFORM, comfort);
    set4(gl, rewritten, VIEW_UNIFORM, [0.0, c as f32, 0.0, mode]);
    let centre = run(gl, rewritten, &points, 4);
    assert!(
        own.iter().zip(&centre).all(|(a, b)| a.to_bits() == b.to_bits()),
        "centre view differs"
    );
    // The outermost view (u = 1): k = s, h = f.
    set4(gl, rewritten, VIEW_UNIFORM, [s as f32, c as f32, f as f32, mode]);
    let outer = run(gl, rewritten, &points, 4);
    let (mut worst, mut largest): (f64, f64) = (0.0, 0.0);
    for (k, &w) in ws.iter().enumerate() {
        let (x0, x1, w32) = (own[4 * k] as f64, outer[4 * k] as f64, outer[4 * k + 3] as f64);
        assert_eq!(
            outer[4 * k + 1..4 * k + 4],
            own[4 * k + 1..4 * k + 4],
            "y, z or w changed"
        );
        let got = (x1 - x0) / w32 * TILE_W / 2.0;
        let want = r.apply(px_per_parallax * (1.0 - c / w)) + f * TILE_W / 2.0;
        worst = worst.max((got - want).abs());
        largest = largest.max(want.abs());
    }
    println!("remapped disparity on Mesa vs f64: worst {worst:.2e} px (disparities up to {largest:.1} px)");
    // f32 on coordinates of size 0.3 w plus the shift: a few ulps of the largest term, in px.
    assert!(worst < 0.01, "remapped shift off by {worst} px");
    // Nearest points: within 3 px of -D_F = -90 px (shifted by the focus, +2.1 px).
    assert!(largest > 85.0, "the test does not reach the front asymptote");
    let tiny = &outer[outer.len() - 4..];
    assert!(tiny.iter().all(|v| v.is_finite()), "w = 1e-30 gave {tiny:?}");
}
