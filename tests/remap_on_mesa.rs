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

mod mesa_common;

use holoapps::gl::Gl;
use holoapps::platform::Profile;
use holoinject::camera::comfort::{DepthRemap, GLSL, REMAP_OFF};
use holoinject::shader::{REMAP_UNIFORM, Stage, VIEW_UNIFORM, ViewMode, analyse, rewrite};
use mesa_common::{capture, capture_program, mesa};
use std::ffi::CString;

const VERTEX: &str = "#version 330 core
layout(location = 0) in vec4 pos;
void main() {
    gl_Position = pos;
}
";
const TILE_W: f64 = 420.0;

fn set4(gl: &Gl, program: u32, name: &str, v: [f32; 4]) {
    let c = CString::new(name).unwrap();
    // SAFETY (test): a uniform of the bound program.
    unsafe {
        let loc = gl.GetUniformLocation(program, c.as_ptr());
        assert!(loc >= 0, "{name} not found");
        gl.Uniform4f(loc, v[0], v[1], v[2], v[3]);
    }
}

fn remap() -> DepthRemap {
    DepthRemap::new(30.0, 40.0, 90.0, 120.0).unwrap()
}

#[test]
fn glsl_remap_matches_f64() {
    let mesa = mesa(Profile::Core33);
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
    let got = capture(gl, program, &points, 1);
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
    let off = capture(gl, program, &points, 1);
    assert!(xs.iter().zip(&off).all(|(x, y)| x.to_bits() == y.to_bits()));
}

#[test]
fn injected_shift_with_remap_gives_the_remapped_disparity() {
    let mesa = mesa(Profile::Core33);
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
    let own = capture(gl, plain, &points, 4);
    // SAFETY (test): binding our program to set its uniforms.
    unsafe { gl.UseProgram(rewritten) };
    set4(gl, rewritten, REMAP_UNIFORM, comfort);
    set4(gl, rewritten, VIEW_UNIFORM, [0.0, c as f32, 0.0, mode]);
    let centre = capture(gl, rewritten, &points, 4);
    assert!(
        own.iter().zip(&centre).all(|(a, b)| a.to_bits() == b.to_bits()),
        "centre view differs"
    );
    // The outermost view (u = 1): k = s, h = f.
    set4(gl, rewritten, VIEW_UNIFORM, [s as f32, c as f32, f as f32, mode]);
    let outer = capture(gl, rewritten, &points, 4);
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
