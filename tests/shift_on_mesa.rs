//! The injected GLSL, run on Mesa, against the f64 reference at the extremes of
//! `camera::precision::cases()` (tiny near planes, far 1e7 or none, reversed-Z, 1° and 170°
//! fields of view, a camera 1e6 from the origin).
//!
//! A real vertex shader (`gl_Position = mvp * pos`) is rewritten exactly as the link hook
//! does, compiled by Mesa (OSMesa, llvmpipe), and its `gl_Position` captured with transform
//! feedback, for the centre view and for the outermost of 48 views. Per case it reports, in
//! pixels of a 420-px tile:
//! - **shader**: the injected arithmetic alone: Mesa's shifted x/w against `x + k(w - c)`
//!   evaluated in f64 on Mesa's own unshifted clip coordinates;
//! - **total**: Mesa's shifted x/w against the exact f64 pipeline (app matrix and point in
//!   f64), i.e. what f32 costs the whole chain, the app's own transform included.
//!
//! The centre view must be bit-identical to the unrewritten shader.
//!
//! Run: `cargo test --release --test shift_on_mesa -- --nocapture`

mod mesa_common;

use holoapps::gl::{self, Gl};
use holoapps::platform::Profile;
use holoinject::camera::invert;
use holoinject::camera::precision::{Case, apply, cases, mul, point, rig_for};
use holoinject::camera::projection::classify;
use holoinject::shader::{Stage, VIEW_UNIFORM, ViewMode, analyse, rewrite};
use mesa_common::{capture, capture_program, mesa};
use std::ffi::CString;

const VERTEX: &str = "#version 330 core
uniform mat4 mvp;
layout(location = 0) in vec4 pos;
void main() {
    gl_Position = mvp * pos;
}
";
const TILE_HALF_WIDTH: f64 = 210.0;

/// Clip coordinates of `points` through `program` with `mvp` and, when the program was
/// rewritten, `holoinject_view = view`.
fn run(gl: &Gl, program: u32, mvp: &[f32; 16], view: Option<[f32; 4]>, points: &[[f32; 4]]) -> Vec<[f32; 4]> {
    // SAFETY (test): uniforms of our own program, bound on the current OSMesa context.
    unsafe {
        gl.UseProgram(program);
        gl.UniformMatrix4fv(
            gl.GetUniformLocation(program, c"mvp".as_ptr()),
            1,
            gl::FALSE,
            mvp.as_ptr(),
        );
        if let Some(v) = view {
            let name = CString::new(VIEW_UNIFORM).unwrap();
            let loc = gl.GetUniformLocation(program, name.as_ptr());
            assert!(loc >= 0, "{VIEW_UNIFORM} not found");
            gl.Uniform4f(loc, v[0], v[1], v[2], v[3]);
        }
    }
    let flat = capture(gl, program, points, 4);
    flat.chunks_exact(4).map(|p| [p[0], p[1], p[2], p[3]]).collect()
}

struct Measured {
    shader_px: f64,
    bound_px: f64,
    /// Points the far-plane rule treated as at infinity, and what that rule moved them by
    /// against the exact shift (`k·c/w`).
    at_far: usize,
    far_rule_px: f64,
    total_px: f64,
    /// Largest shift seen, to show the figures are not of a shift that does nothing.
    shift_px: f64,
}

/// The shader's far-plane test (`glsl-patches/view_shift.glsl`), evaluated on its f32 inputs.
/// (For infinite or unknown projections; finite and reversed-Z ones are tested exactly.)
const FAR_TOLERANCE: f64 = 1e-6;

fn measure(gl: &Gl, plain: u32, rewritten: u32, case: &Case) -> Measured {
    let m = mul(&case.p, &case.v);
    let m32 = m.map(|x| x as f32);
    let inv_v = invert(&case.v).unwrap();
    let world: Vec<[f64; 4]> = case.depths.iter().map(|&d| point(&inv_v, d)).collect();
    let points: Vec<[f32; 4]> = world.iter().map(|p| p.map(|x| x as f32)).collect();
    // The mode the layer sends for this matrix, and the far-plane test it makes the shader do.
    let view_mode = ViewMode::of(classify(&m32).as_ref());
    let mode = view_mode.as_uniform();
    let reversed = view_mode == ViewMode::PerspectiveReversedZ;
    let tolerance = match view_mode {
        ViewMode::Perspective | ViewMode::Unknown => FAR_TOLERANCE,
        _ => 0.0,
    };
    let rig = rig_for(&case.depths);

    // Centre view: bit-identical to the app's own shader.
    let c = rig.params(rig.centre() - 1 + rig.views % 2);
    let own = run(gl, plain, &m32, None, &points);
    let centre = run(gl, rewritten, &m32, Some([0.0, c.c, 0.0, mode]), &points);
    for (a, b) in own.iter().zip(&centre) {
        assert_eq!(
            a.map(f32::to_bits),
            b.map(f32::to_bits),
            "{}: centre view differs",
            case.name
        );
    }

    let v = rig.params(47);
    let shifted = run(gl, rewritten, &m32, Some([v.k, v.c, v.h, mode]), &points);
    let (k, cc, h) = (v.k as f64, v.c as f64, v.h as f64);
    let eps = f32::EPSILON as f64;
    let mut r = Measured {
        shader_px: 0.0,
        bound_px: 0.0,
        at_far: 0,
        far_rule_px: 0.0,
        total_px: 0.0,
        shift_px: 0.0,
    };
    for ((o, s), wp) in own.iter().zip(&shifted).zip(&world) {
        let (x, z, w) = (o[0] as f64, o[2] as f64, o[3] as f64);
        let got = s[0] as f64 / s[3] as f64;
        let far_z = if reversed { 0.0 } else { w };
        let at_far = (z - far_z).abs() <= tolerance * w.abs();
        let c_used = if at_far { 0.0 } else { cc };
        let want = (x + k * (w - c_used) + h * w) / w;
        r.shader_px = r.shader_px.max((got - want).abs() * TILE_HALF_WIDTH);
        // Five f32 roundings (w - c, k·(..), h·w and two sums), each within eps/2 of the
        // sizes involved, then the divide by w.
        let terms = x.abs() + k.abs() * (w.abs() + c_used.abs()) + h.abs() * w.abs();
        r.bound_px = r.bound_px.max(3.0 * eps * terms / w.abs() * TILE_HALF_WIDTH);
        if at_far {
            r.at_far += 1;
            r.far_rule_px = r.far_rule_px.max((k * cc / w).abs() * TILE_HALF_WIDTH);
        }
        let exact = apply(&m, *wp);
        let want64 = (exact[0] + k * (exact[3] - cc) + h * exact[3]) / exact[3];
        r.total_px = r.total_px.max((got - want64).abs() * TILE_HALF_WIDTH);
        r.shift_px = r.shift_px.max((got - x / w).abs() * TILE_HALF_WIDTH);
    }
    r
}

#[test]
fn injected_shift_on_mesa_matches_f64_at_the_extremes() {
    let mesa = mesa(Profile::Core33);
    let gl = &mesa.gl;
    let analysis = analyse(VERTEX, Stage::Vertex);
    let rewritten_src = rewrite(VERTEX, &analysis).expect("rewrite");
    let plain = capture_program(gl, VERTEX, "gl_Position");
    let rewritten = capture_program(gl, &rewritten_src, "gl_Position");
    println!(
        "| case | largest shift, view 47 (px) | shader arithmetic error (px) | its bound (px) | points taken as far plane | far-plane rule vs exact (px) | total f32 error (px) |"
    );
    println!("|---|---|---|---|---|---|---|");
    for case in cases() {
        let m = measure(gl, plain, rewritten, &case);
        println!(
            "| {} | {:.3e} | {:.2e} | {:.2e} | {} of {} | {:.2e} | {:.2e} |",
            case.name,
            m.shift_px,
            m.shader_px,
            m.bound_px,
            m.at_far,
            case.depths.len(),
            m.far_rule_px,
            m.total_px
        );
        assert!(m.shift_px > 1.0, "{}: the outer view is not shifted", case.name);
        assert!(
            m.shader_px <= m.bound_px,
            "{}: injected shift off by {} px (bound {} px)",
            case.name,
            m.shader_px,
            m.bound_px
        );
    }
}

/// The `glsl_compiles` fuzz target's promise, in every test run: each shader the sample apps
/// and the real programs of the tests compile (the fuzz seed corpus, collected by
/// `scripts/fuzz.sh seeds`) and each input fuzzing found, when Mesa compiles it, still
/// compiles after our rewrite — or the rewrite is refused and the app's text is used.
#[test]
fn rewrites_of_shaders_mesa_compiles_compile_too() {
    let mesa = mesa(Profile::Legacy);
    let gl = &mesa.gl;
    let root = env!("CARGO_MANIFEST_DIR");
    let mut files = vec![];
    for dir in ["tests/fuzz/seeds/glsl", "tests/fuzz/regressions/glsl_compiles"] {
        files.extend(
            std::fs::read_dir(format!("{root}/{dir}"))
                .unwrap()
                .map(|e| e.unwrap().path()),
        );
    }
    files.sort();
    let (mut compiled, mut rewritten, mut refused) = (0, 0, 0);
    for path in &files {
        let data = std::fs::read(path).unwrap();
        let Some((&sel, rest)) = data.split_first() else {
            continue;
        };
        let Ok(source) = std::str::from_utf8(rest) else {
            continue;
        };
        // The fuzz targets' stage byte.
        let (stage, kind) = match sel % 4 {
            0 => (Stage::Vertex, gl::VERTEX_SHADER),
            1 => (Stage::Geometry, gl::GEOMETRY_SHADER),
            2 => (Stage::TessEval, gl::TESS_EVALUATION_SHADER),
            _ => continue,
        };
        if holoapps::shader::compile_status(gl, kind, source).is_err() {
            continue;
        }
        compiled += 1;
        match rewrite(source, &analyse(source, stage)) {
            Ok(out) => {
                rewritten += 1;
                if let Err(log) = holoapps::shader::compile_status(gl, kind, &out) {
                    panic!("{}: Mesa compiles it but not its rewrite: {log}\n{out}", path.display());
                }
            }
            Err(_) => refused += 1,
        }
    }
    println!("{compiled} shaders compile on Mesa: {rewritten} rewritten (all compile), {refused} left as they are");
    assert!(rewritten >= 40, "only {rewritten} shaders rewritten: seeds missing?");
}
