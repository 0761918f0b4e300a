//! Shared main loop: CLI, back-end, frame loop, screenshot and depth read-back, quilt, timing.
use crate::cli::{self, AppInfo, Options};
use crate::gl::{self, Gl};
use crate::platform::{self, Platform, Profile};
use crate::scene::{Scene, View};
use crate::{image, quilt};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

static STOP: AtomicBool = AtomicBool::new(false);

extern "C" fn on_signal(_: libc::c_int) {
    STOP.store(true, Ordering::SeqCst);
}

/// With --frames 0 the app runs until killed; exit cleanly on SIGINT/SIGTERM
/// so `finish` (e.g. the asteroids timing line) still runs.
fn install_signal_handlers() {
    let handler: extern "C" fn(libc::c_int) = on_signal;
    unsafe {
        libc::signal(libc::SIGINT, handler as libc::sighandler_t);
        libc::signal(libc::SIGTERM, handler as libc::sighandler_t);
    }
}

pub type MakeScene = dyn FnOnce(&Gl, &Options) -> Result<Box<dyn Scene>, String>;

/// Entry point for every app binary with a fixed context profile.
pub fn main(app: &AppInfo, profile: Profile, make: Box<MakeScene>) -> ExitCode {
    main_with(app, &|_| Ok(profile), make)
}

/// Entry point for apps whose profile depends on their flags (`gles --es2`),
/// or that refuse some back-ends.
pub fn main_with(
    app: &AppInfo,
    profile: &dyn Fn(&Options) -> Result<Profile, String>,
    make: Box<MakeScene>,
) -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = cli::parse(&args, app).and_then(|o| match o {
        Some(o) => run(&o, profile(&o)?, make),
        None => Ok(()),
    });
    exit_code(result)
}

/// An app's exit: 0, or 1 with its one-line error on stderr.
pub fn exit_code(result: Result<(), String>) -> ExitCode {
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(1)
        }
    }
}

fn load_gl(p: &dyn Platform) -> Result<Gl, String> {
    let gl = Gl::load_with(|name| p.get_proc_address(name));
    if !gl.GetString.is_loaded() || !gl.Clear.is_loaded() {
        return Err(format!("{}: basic GL entry points could not be loaded", p.describe()));
    }
    if std::env::var_os("HOLOAPPS_VERBOSE").is_some() {
        let s = |e| unsafe {
            std::ffi::CStr::from_ptr(gl.GetString(e).cast())
                .to_string_lossy()
                .into_owned()
        };
        let (mut d, mut st) = (0, 0);
        unsafe {
            gl.GetFramebufferAttachmentParameteriv(
                gl::FRAMEBUFFER,
                gl::DEPTH,
                gl::FRAMEBUFFER_ATTACHMENT_DEPTH_SIZE,
                &mut d,
            );
            gl.GetFramebufferAttachmentParameteriv(
                gl::FRAMEBUFFER,
                gl::STENCIL,
                gl::FRAMEBUFFER_ATTACHMENT_STENCIL_SIZE,
                &mut st,
            );
        }
        eprintln!(
            "{}: {} / {} (depth {d}, stencil {st})",
            p.describe(),
            s(gl::RENDERER),
            s(gl::VERSION)
        );
    }
    Ok(gl)
}

fn check_gl_error(gl: &Gl, when: &str) {
    let e = unsafe { gl.GetError() };
    if e != gl::NO_ERROR {
        eprintln!("warning: GL error 0x{e:04X} {when}");
    }
}

fn run(o: &Options, profile: Profile, make: Box<MakeScene>) -> Result<(), String> {
    let config = platform::WindowConfig {
        samples: o.samples,
        alpha: o.alpha,
    };
    let mut plat = platform::create_with(o.backend, o.size, profile, config)?;
    let gl = load_gl(plat.as_ref())?;
    if o.srgb {
        if profile.is_es() {
            return Err("--srgb needs desktop GL".into());
        }
        unsafe { gl.Enable(gl::FRAMEBUFFER_SRGB) };
    }
    if o.debug_output {
        crate::debug_output::enable(&gl)?;
    }
    if o.depth_out.is_some() || o.reference_depth_out.is_some() {
        image::check_depth_readable(&gl)?;
    }
    let mut scene = make(&gl, o)?;
    install_signal_handlers();
    let (w, h) = plat.size();
    let normal = View {
        viewport: [0, 0, w as i32, h as i32],
        shear: None,
    };
    // Reference mode needs a frame to take the quilt of, even with --frames 0.
    let captures = o.quilt.is_some() || o.screenshot.is_some() || o.depth_out.is_some();
    let last = match (o.frames, captures) {
        (0, true) => Some(0),
        (0, false) => None,
        (n, _) => Some(n - 1),
    };
    let mut times = Vec::new();
    let mut frame = 0u64;
    let bench = if o.bench_quilt {
        Some(quilt::BenchQuilt::new(&gl, o)?)
    } else {
        None
    };
    while !STOP.load(Ordering::SeqCst) && last.is_none_or(|l| frame <= l) {
        let start = Instant::now();
        // What the scene shows: time stops at `--freeze`.
        let shown = o.shown(frame);
        match &bench {
            Some(b) => b.frame(&gl, scene.as_mut(), shown, o, (w, h)),
            None => scene.render(&gl, shown, &normal),
        }
        let mut elapsed = start.elapsed();
        if frame == 0 {
            check_gl_error(&gl, "after the first frame");
        }
        if Some(frame) == last {
            capture_default_framebuffer(&gl, o, (w, h))?;
            if o.quilt.is_some() && bench.is_none() {
                quilt::render(&gl, scene.as_mut(), shown, o)?;
                check_gl_error(&gl, "after the quilt pass");
            }
        }
        let start = Instant::now();
        plat.end_frame();
        elapsed += start.elapsed();
        times.push(elapsed.as_secs_f64() * 1000.0);
        frame += 1;
    }
    if o.timing {
        print_timing(o, &times);
    }
    if o.debug_output {
        crate::debug_output::report();
    }
    scene.finish(&times);
    Ok(())
}

/// `--screenshot` and `--depth-out`: the last frame's default framebuffer, read before the
/// frame ends (after the swap the back buffer's content is undefined).
fn capture_default_framebuffer(gl: &Gl, o: &Options, (w, h): (u32, u32)) -> Result<(), String> {
    if let Some(path) = &o.screenshot {
        image::write_png(path, w, h, &image::read_default_framebuffer(gl, w, h))?;
    }
    if let Some(path) = &o.depth_out {
        image::write_f32(path, &image::read_default_depth(gl, w, h)?)?;
        check_gl_error(gl, "after reading depth");
    }
    Ok(())
}

/// `--timing`: median CPU wall time per frame (render + end of frame), after 10 warm-up
/// frames; llvmpipe renders synchronously, so this is the frame's full cost.
fn print_timing(o: &Options, frame_ms: &[f64]) {
    let mut ms: Vec<f64> = frame_ms.iter().skip(10).copied().collect();
    ms.sort_by(f64::total_cmp);
    let median = if ms.is_empty() { 0.0 } else { ms[ms.len() / 2] };
    let mode = if o.bench_quilt { "reference-quilt" } else { "normal" };
    eprintln!(
        "timing: mode={mode} frames={} median_frame_ms={median:.3}",
        frame_ms.len()
    );
}
