//! `churn`: contexts destroyed and re-created in one share group, on headless EGL.
//!
//! A root context A, current without a surface, lives for the whole run and owns what
//! stays shared: a checker texture and the cube mesh. `--cycles N` times a context B is
//! created in A's share group, made current on its own pbuffer and renders `--frames`
//! frames: lit textured cubes into an FBO (colour texture + depth renderbuffer), then a
//! full-screen pass sampling that colour into framebuffer 0, `eglSwapBuffers` every frame.
//! B then deletes every shared object it created and is released and destroyed with its
//! pbuffer; its FBO and VAOs die with it, as per-context objects do. With
//! `--hand-over-target` B leaves its offscreen colour texture and depth renderbuffer alive
//! (a worker context rendering into a texture that outlives it), and A, made current after
//! each cycle, deletes them; with `--destroy-current` B is destroyed while still current
//! and only then released. With `--root-target` the root context, made current before
//! each cycle, creates B's offscreen colour texture (glGenTextures + glBindTexture +
//! glTexImage2D), so B renders into a texture it never bound before attaching it; with
//! `--reuse-name` that texture takes the name of a cube map made and deleted just before
//! (in the root with `--root-target`, else in B). At the end A counts the shared objects still alive
//! (names 1..=4096) and prints one line on stdout:
//! `objects textures=T buffers=B renderbuffers=R programs=P shaders=S samplers=M`.
//! A plain run prints the same line for any N, so anything a layer leaves behind in the
//! share group shows up as counts growing with N.
mod scene;

use holoapps::cli::{self, AppInfo, Backend, Options};
use holoapps::gl::{self, Gl};
use holoapps::image;
use holoapps::platform::{EglHandle, EglHeadlessDisplay, Profile};
use scene::{Root, Scene};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};

const APP: AppInfo = AppInfo {
    name: "churn",
    about: "contexts destroyed and re-created in one share group; counts the shared GL objects left

Headless EGL only (the default here). A root context lives for the whole run; each cycle
creates a context in its share group, renders --frames frames (0: 3) through an FBO on
its own pbuffer, deletes its objects (with --hand-over-target the root context deletes
the FBO's attachments) and is destroyed. At exit one line on stdout:
`objects textures=T buffers=B renderbuffers=R programs=P shaders=S samplers=M`.
--screenshot: the last frame of the last cycle. No --reference-quilt, --bench-quilt,
--timing or --debug-output.",
    default_convergence: 6.5,
    extra: &[(
        "cycles",
        "3",
        "contexts created, used and destroyed in turn (0 = until SIGINT/SIGTERM)",
    )],
    switches: &[
        (
            "hand-over-target",
            "the FBO's colour texture and depth renderbuffer outlive each context; the root deletes them",
        ),
        (
            "destroy-current",
            "destroy each context while it is still current, then release it (EGL defers the destruction)",
        ),
        (
            "root-target",
            "the root context creates each cycle's offscreen colour texture; the cycle's context attaches and renders into it",
        ),
        (
            "reuse-name",
            "the offscreen colour texture takes the name of a cube map created and deleted just before",
        ),
    ],
};

static STOP: AtomicBool = AtomicBool::new(false);

extern "C" fn on_signal(_: libc::c_int) {
    STOP.store(true, Ordering::SeqCst);
}

fn load_gl(d: &EglHeadlessDisplay) -> Result<Gl, String> {
    let gl = Gl::load_with(|name| d.get_proc_address(name));
    if !gl.GetString.is_loaded() || !gl.Clear.is_loaded() || !gl.GenSamplers.is_loaded() {
        return Err("GL 3.3 entry points could not be loaded".into());
    }
    Ok(gl)
}

fn check_gl_error(gl: &Gl, when: &str) {
    let e = unsafe { gl.GetError() };
    if e != gl::NO_ERROR {
        eprintln!("warning: GL error 0x{e:04X} {when}");
    }
}

/// Shared objects alive in the current context's share group, by probing names.
fn count_objects(gl: &Gl) -> String {
    let count = |is: &dyn Fn(u32) -> u8| (1..=4096).filter(|&n| is(n) == gl::TRUE).count();
    unsafe {
        format!(
            "objects textures={} buffers={} renderbuffers={} programs={} shaders={} samplers={}",
            count(&|n| gl.IsTexture(n)),
            count(&|n| gl.IsBuffer(n)),
            count(&|n| gl.IsRenderbuffer(n)),
            count(&|n| gl.IsProgram(n)),
            count(&|n| gl.IsShader(n)),
            count(&|n| gl.IsSampler(n)),
        )
    }
}

/// Cycle `n`: a context B created in the root's share group on its own pbuffer, its
/// frames (numbered on from the previous cycle's), its objects deleted, released and
/// destroyed with the pbuffer. Returns the offscreen target when it is handed over.
fn cycle(
    d: &EglHeadlessDisplay,
    gl: &Gl,
    root: (EglHandle, &Root),
    o: &Options,
    n: u64,
    last: bool,
) -> Result<Option<(u32, u32)>, String> {
    let hand_over = o.switches.contains("hand-over-target");
    let reuse_name = o.switches.contains("reuse-name");
    let frames = if o.frames == 0 { 3 } else { o.frames };
    let colour = match o.switches.contains("root-target") {
        true => Some(root_colour_target(d, gl, root.0, o.size, reuse_name)?),
        false => None,
    };
    let surface = d.create_pbuffer(o.size)?;
    let ctx = match d.create_context(Some(root.0)) {
        Ok(c) => c,
        Err(e) => {
            d.destroy_surface(surface);
            return Err(e);
        }
    };
    let result = (|| {
        d.make_current(Some((surface, ctx)))?;
        let scene = Scene::new(gl, root.1, (n, o.size), colour, reuse_name)?;
        for f in 0..frames {
            scene.render(gl, root.1, n * frames + f, o.size);
            if let Some(path) = o.screenshot.as_ref().filter(|_| last && f + 1 == frames) {
                let rgb = image::read_default_framebuffer(gl, o.size.0, o.size.1);
                image::write_png(path, o.size.0, o.size.1, &rgb)?;
            }
            d.swap_buffers(surface)?;
        }
        scene.delete(gl, hand_over);
        check_gl_error(gl, &format!("in cycle {n}"));
        Ok(hand_over.then_some(scene.target))
    })();
    if o.switches.contains("destroy-current") {
        d.destroy_context(ctx);
    }
    let released = d.make_current(None);
    if !o.switches.contains("destroy-current") {
        d.destroy_context(ctx);
    }
    d.destroy_surface(surface);
    released.and(result)
}

/// The root context creates the next cycle's offscreen colour texture.
fn root_colour_target(
    d: &EglHeadlessDisplay,
    gl: &Gl,
    root: EglHandle,
    size: (u32, u32),
    reuse_name: bool,
) -> Result<u32, String> {
    d.make_current_surfaceless(root)?;
    let colour = scene::colour_target(gl, (size.0 as i32, size.1 as i32), reuse_name);
    // Complete before the cycle's context attaches it.
    unsafe { gl.Finish() };
    d.make_current(None)?;
    Ok(colour)
}

/// The root context takes over what a cycle left it, and deletes it.
fn delete_handed_over(d: &EglHeadlessDisplay, gl: &Gl, root: EglHandle, target: (u32, u32)) -> Result<(), String> {
    d.make_current_surfaceless(root)?;
    unsafe {
        gl.DeleteTextures(1, &target.0);
        gl.DeleteRenderbuffers(1, &target.1);
    }
    d.make_current(None)
}

/// The root context's objects, the cycles, and the count (made current on the root).
fn churn(d: &EglHeadlessDisplay, root_ctx: EglHandle, o: &Options) -> Result<String, String> {
    let cycles = o.extra_u64("cycles")?;
    d.make_current_surfaceless(root_ctx)?;
    let gl = load_gl(d)?;
    let root = Root::new(&gl);
    unsafe { gl.Finish() };
    d.make_current(None)?;
    let more = |n| {
        if cycles == 0 {
            !STOP.load(Ordering::SeqCst)
        } else {
            n < cycles
        }
    };
    let mut n = 0;
    while more(n) {
        if let Some(target) = cycle(d, &gl, (root_ctx, &root), o, n, n + 1 == cycles)? {
            delete_handed_over(d, &gl, root_ctx, target)?;
        }
        n += 1;
    }
    d.make_current_surfaceless(root_ctx)?;
    let counts = count_objects(&gl);
    check_gl_error(&gl, "while counting objects");
    d.make_current(None)?;
    Ok(counts)
}

fn check_options(args: &[String], o: &Options) -> Result<(), String> {
    if args.iter().any(|a| a == "--backend") && o.backend != Backend::Egl {
        return Err("churn supports only --backend egl".into());
    }
    if o.quilt.is_some() || o.bench_quilt || o.timing || o.debug_output {
        return Err("churn does not support --reference-quilt, --bench-quilt, --timing or --debug-output".into());
    }
    Ok(())
}

fn run(args: &[String], o: &Options) -> Result<(), String> {
    check_options(args, o)?;
    let handler: extern "C" fn(libc::c_int) = on_signal;
    unsafe {
        libc::signal(libc::SIGINT, handler as libc::sighandler_t);
        libc::signal(libc::SIGTERM, handler as libc::sighandler_t);
    }
    let d = EglHeadlessDisplay::new(Profile::Core33)?;
    let root = d.create_context(None)?;
    let result = churn(&d, root, o);
    d.destroy_context(root);
    println!("{}", result?);
    Ok(())
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = cli::parse(&args, &APP).and_then(|o| match o {
        Some(o) => run(&args, &o),
        None => Ok(()),
    });
    holoapps::run::exit_code(result)
}
