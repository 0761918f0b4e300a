//! Auto-convergence's depth read-back (`holoinject::gl::depth_copy`), run on Mesa: known
//! depths are cleared into regions of a framebuffer, copied by the layer's blit (in the
//! source's own format, resolving multisampled sources) and read back both ways — with
//! `glReadPixels` where desktop GL allows it, and through the RGBA8 packing pass that ES
//! contexts use — in desktop GL (OSMesa) and in OpenGL ES 3 (EGL, surfaceless). Every value
//! must come back to within a 24-bit step, and the layer must leave no GL error.
//!
//! Run: `cargo test --release --test depth_readback_on_mesa`

use holoapps::cli::Backend;
use holoapps::platform::{Platform, Profile, create};
use holoinject::gl::depth_copy::{self, DepthCopy, Restore};
use holoinject::gl::{self, Gl, GlInfo};

const SIZE: (i32, i32) = (64, 48);
/// Depths cleared into the four quadrants (bottom-left, bottom-right, top-left, top-right).
const DEPTHS: [f32; 4] = [0.25, 0.5, 0.999_999, 1.0];
/// How far a depth of `format` may come back from the value cleared: two steps of its
/// fixed-point format, or of the 24-bit packing (Mesa's clear rounds once, the read-back or
/// the packing once more).
fn step(format: gl::types::GLenum) -> f32 {
    if format == gl::DEPTH_COMPONENT16 {
        2.0 / 65_535.0
    } else {
        2.0 / 16_777_215.0
    }
}

struct Context {
    _platform: Box<dyn Platform>,
    gl: Gl,
    info: GlInfo,
}

fn context(backend: Backend, profile: Profile) -> Context {
    // This executable links the layer, which is live in it: keep it in pass-through.
    static PASS_THROUGH: std::sync::Once = std::sync::Once::new();
    // SAFETY: written once, before any GL call of this process.
    PASS_THROUGH.call_once(|| unsafe { std::env::set_var("HOLOINJECT_OUTPUT", "mono") });
    let platform = create(backend, (16, 16), profile).expect("Mesa context");
    let gl = Gl::load_with(|s| platform.get_proc_address(s));
    // SAFETY: a string query on the current context.
    let version = unsafe { std::ffi::CStr::from_ptr(gl.GetString(gl::VERSION).cast()) };
    let info = GlInfo::parse(&version.to_string_lossy());
    Context {
        _platform: platform,
        gl,
        info,
    }
}

/// A framebuffer with an RGBA8 colour and a `depth_format` renderbuffer of `samples`, its
/// quadrants cleared to `DEPTHS`; left bound.
fn scene_framebuffer(gl: &Gl, depth_format: gl::types::GLenum, samples: i32) -> u32 {
    let (mut fbo, mut rb) = (0, [0u32; 2]);
    let (w, h) = SIZE;
    // SAFETY: our own objects in the current context.
    unsafe {
        gl.GenFramebuffers(1, &mut fbo);
        gl.BindFramebuffer(gl::FRAMEBUFFER, fbo);
        gl.GenRenderbuffers(2, rb.as_mut_ptr());
        for (r, (format, point)) in rb
            .iter()
            .zip([(gl::RGBA8, gl::COLOR_ATTACHMENT0), (depth_format, gl::DEPTH_ATTACHMENT)])
        {
            gl.BindRenderbuffer(gl::RENDERBUFFER, *r);
            gl.RenderbufferStorageMultisample(gl::RENDERBUFFER, samples, format, w, h);
            gl.FramebufferRenderbuffer(gl::FRAMEBUFFER, point, gl::RENDERBUFFER, *r);
        }
        assert_eq!(gl.CheckFramebufferStatus(gl::FRAMEBUFFER), gl::FRAMEBUFFER_COMPLETE);
        gl.Enable(gl::SCISSOR_TEST);
        for (q, d) in DEPTHS.iter().enumerate() {
            let (x, y) = ((q as i32 % 2) * w / 2, (q as i32 / 2) * h / 2);
            gl.Scissor(x, y, w / 2, h / 2);
            gl.ClearDepthf(*d);
            gl.Clear(gl::DEPTH_BUFFER_BIT);
        }
        // Left on: the copy must not be clipped by the app's scissor.
        gl.Scissor(0, 0, 1, 1);
    }
    fbo
}

/// The expected depth at (x, y) of the copied rectangle `rect`.
fn expected(rect: [i32; 4], x: i32, y: i32) -> f32 {
    let (px, py) = (rect[0] + x, rect[1] + y);
    DEPTHS[(px * 2 / SIZE.0 + (py * 2 / SIZE.1) * 2) as usize]
}

fn check(what: &str, depths: &[f32], rect: [i32; 4], step: f32) {
    assert_eq!(depths.len(), (rect[2] * rect[3]) as usize, "{what}");
    for (i, &d) in depths.iter().enumerate() {
        let (x, y) = (i as i32 % rect[2], i as i32 / rect[2]);
        let e = expected(rect, x, y);
        assert!((d - e).abs() <= step, "{what}: depth {d} at ({x}, {y}), expected {e}");
    }
}

/// Copies a rectangle straddling all four quadrants and reads it back every way `ctx`
/// allows.
fn round_trip(ctx: &Context, depth_format: gl::types::GLenum, samples: i32) {
    let gl = &ctx.gl;
    let fbo = scene_framebuffer(gl, depth_format, samples);
    let rect = [8, 6, 40, 30];
    let mut copy = DepthCopy::default();
    let what = format!("{:?} format {depth_format:#x}, {samples} samples", ctx.info);
    let format = depth_copy::describe(gl, ctx.info, fbo).unwrap_or_else(|e| panic!("{what}: {e}"));
    assert_eq!(format.multisampled, samples > 0, "{what}");
    // What the app had bound (and its scissor test on): put back by the copy.
    let restore = Restore {
        draw_fbo: fbo,
        read_fbo: fbo,
        scissor: true,
    };
    copy.take(gl, ctx.info, (fbo, format), rect, restore);
    let step = step(depth_format);
    check(
        &format!("{what}, packed"),
        &copy.read_packed(gl, ctx.info).unwrap(),
        rect,
        step,
    );
    if !ctx.info.es {
        let read = copy.read(gl, ctx.info).unwrap();
        check(&format!("{what}, glReadPixels"), &read, rect, step);
        let packed = copy.read_packed(gl, ctx.info).unwrap();
        let worst = read.iter().zip(&packed).map(|(a, b)| (a - b).abs()).fold(0.0, f32::max);
        assert!(worst <= 1.0 / 16_777_215.0, "{what}: packing off by {worst}");
    }
    // SAFETY: an error query.
    assert_eq!(unsafe { gl.GetError() }, gl::NO_ERROR, "{what}: GL error");
    let (mut draw, mut read, mut read_buffer) = (0, 0, 0);
    // SAFETY: state queries.
    let scissor = unsafe {
        gl.GetIntegerv(gl::DRAW_FRAMEBUFFER_BINDING, &mut draw);
        gl.GetIntegerv(gl::READ_FRAMEBUFFER_BINDING, &mut read);
        gl.GetIntegerv(gl::READ_BUFFER, &mut read_buffer);
        gl.IsEnabled(gl::SCISSOR_TEST)
    };
    let state = (draw as u32, read as u32, read_buffer as u32, scissor);
    assert_eq!(
        state,
        (fbo, fbo, gl::COLOR_ATTACHMENT0, gl::TRUE),
        "{what}: state not put back"
    );
}

#[test]
fn desktop_depth_reads_back_exactly_both_ways() {
    let ctx = context(Backend::OsMesa, Profile::Core33);
    for format in [
        gl::DEPTH24_STENCIL8,
        gl::DEPTH_COMPONENT24,
        gl::DEPTH_COMPONENT32F,
        gl::DEPTH_COMPONENT16,
    ] {
        round_trip(&ctx, format, 0);
    }
    round_trip(&ctx, gl::DEPTH24_STENCIL8, 4);
}

#[test]
fn es_depth_reads_back_through_the_packing_pass() {
    let ctx = context(Backend::Egl, Profile::Gles3);
    assert!(ctx.info.es, "{:?}", ctx.info);
    for format in [gl::DEPTH24_STENCIL8, gl::DEPTH_COMPONENT32F] {
        round_trip(&ctx, format, 0);
    }
    round_trip(&ctx, gl::DEPTH24_STENCIL8, 4);
}
