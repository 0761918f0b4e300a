//! `twothreads`: two GL 3.3 core contexts in one share group, each current on
//! its own thread with its own pbuffer. Context A creates a checker texture,
//! context B samples the same texture name after a barrier.
use holoapps::gl::{self, Gl};
use holoapps::image;
use holoapps::math::{self, Mat4};
use holoapps::platform::{EglHandle, EglHeadlessDisplay, Profile};
use holoapps::scene::seconds;
use holoapps::shader;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use std::sync::{Arc, Barrier};

const HELP: &str = "twothreads - two GL 3.3 core contexts in one share group, each on its own thread

USAGE: twothreads [OPTIONS]

Headless EGL only (EGL_PLATFORM_SURFACELESS_MESA, one pbuffer per context).
Context A (thread 1) creates a 64x64 checker texture; context B (created with A
as share context, thread 2) samples the same texture name after a barrier.
Each thread renders its own scene and calls eglSwapBuffers on its own surface
every frame. --reference-quilt is not supported.

  --backend egl          the only back-end (default egl)
  --size WxH             size of each pbuffer (default 320x240)
  --frames N             frames per thread, then exit (default 0 = until killed)
  --screenshot PREFIX    write PREFIX-a.png and PREFIX-b.png (last frame of each thread)
  --help                 this text
";

static STOP: AtomicBool = AtomicBool::new(false);

extern "C" fn on_signal(_: libc::c_int) {
    STOP.store(true, Ordering::SeqCst);
}

const FS: &str = r#"#version 330 core
in vec3 Normal;
in vec2 Uv;
uniform sampler2D tex;
uniform vec3 tint;
uniform vec3 lightDir;
out vec4 FragColor;
void main() {
    float diff = max(dot(normalize(Normal), normalize(lightDir)), 0.0);
    vec3 c = texture(tex, Uv).rgb * tint;
    FragColor = vec4((0.25 + 0.75 * diff) * c, 1.0);
}
"#;

struct Opts {
    size: (u32, u32),
    frames: u64,
    screenshot: Option<PathBuf>,
}

fn parse_args(args: &[String]) -> Result<Option<Opts>, String> {
    let mut o = Opts {
        size: (320, 240),
        frames: 0,
        screenshot: None,
    };
    let mut it = args.iter();
    while let Some(flag) = it.next() {
        if flag == "--help" || flag == "-h" {
            print!("{HELP}");
            return Ok(None);
        }
        let val = it.next().ok_or_else(|| format!("{flag} needs a value"))?;
        match flag.as_str() {
            "--backend" if val == "egl" => {}
            "--backend" => return Err(format!("twothreads supports only --backend egl (got '{val}')")),
            "--size" => {
                let bad = || format!("--size: expected WxH with integers in 1..=16384, got '{val}'");
                let (w, h) = val.split_once(['x', 'X']).ok_or_else(bad)?;
                let (w, h) = (
                    w.parse::<u32>().map_err(|_| bad())?,
                    h.parse::<u32>().map_err(|_| bad())?,
                );
                if w == 0 || h == 0 || w > 16384 || h > 16384 {
                    return Err(bad());
                }
                o.size = (w, h);
            }
            "--frames" => o.frames = val.parse().map_err(|_| format!("--frames: invalid number '{val}'"))?,
            "--screenshot" => o.screenshot = Some(val.into()),
            "--reference-quilt" => return Err("twothreads does not support --reference-quilt".into()),
            f => return Err(format!("unknown option '{f}' (see --help)")),
        }
    }
    Ok(Some(o))
}

/// Which thread / context a scene belongs to.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Side {
    A,
    B,
}

impl Side {
    fn letter(self) -> &'static str {
        match self {
            Side::A => "a",
            Side::B => "b",
        }
    }
}

/// Two-colour 64x64 checker (8x8 texels a square), RGBA8, NEAREST, no mipmaps.
fn checker_texture(gl: &Gl) -> u32 {
    let mut px = Vec::with_capacity(64 * 64 * 4);
    for y in 0..64 {
        for x in 0..64 {
            let c: [u8; 4] = if ((x / 8) + (y / 8)) % 2 == 0 {
                [240, 200, 60, 255]
            } else {
                [40, 90, 200, 255]
            };
            px.extend_from_slice(&c);
        }
    }
    let mut tex = 0;
    unsafe {
        gl.GenTextures(1, &mut tex);
        gl.BindTexture(gl::TEXTURE_2D, tex);
        gl.PixelStorei(gl::UNPACK_ALIGNMENT, 1);
        gl.TexImage2D(
            gl::TEXTURE_2D,
            0,
            gl::RGBA8 as i32,
            64,
            64,
            0,
            gl::RGBA,
            gl::UNSIGNED_BYTE,
            px.as_ptr().cast(),
        );
        gl.TexParameteri(gl::TEXTURE_2D, gl::TEXTURE_MIN_FILTER, gl::NEAREST as i32);
        gl.TexParameteri(gl::TEXTURE_2D, gl::TEXTURE_MAG_FILTER, gl::NEAREST as i32);
        gl.TexParameteri(gl::TEXTURE_2D, gl::TEXTURE_WRAP_S, gl::REPEAT as i32);
        gl.TexParameteri(gl::TEXTURE_2D, gl::TEXTURE_WRAP_T, gl::REPEAT as i32);
        gl.BindTexture(gl::TEXTURE_2D, 0);
    }
    tex
}

/// Per-context objects (programs and VAOs are not shared; the texture is).
struct Scene {
    side: Side,
    prog: u32,
    vao: u32,
    tex: u32,
    loc: [i32; 6],
}

impl Scene {
    fn new(gl: &Gl, side: Side, tex: u32) -> Result<Self, String> {
        let prog = shader::program(gl, shader::TEXTURED_CUBE_VS, FS)?;
        let loc = ["projection", "view", "model", "tint", "lightDir", "tex"].map(|n| shader::uniform(gl, prog, n));
        let vao = shader::pos_normal_vao(gl, &shader::cube_vertices());
        Ok(Scene {
            side,
            prog,
            vao,
            tex,
            loc,
        })
    }

    /// (model, tint) of each cube at time t: A has three cubes in a row,
    /// B five cubes on a turning ring around a tall pillar.
    fn cubes(&self, t: f32) -> Vec<(Mat4, [f32; 3])> {
        let mut v = Vec::new();
        match self.side {
            Side::A => {
                for i in 0..3 {
                    let x = (i - 1) as f32 * 1.8;
                    let a = t * (0.6 + 0.3 * i as f32) + i as f32;
                    let m = math::mul(&math::translate(x, 0.0, 0.0), &math::rotate(a, [0.3, 1.0, 0.2]));
                    let tint = [[1.0, 0.7, 0.7], [0.7, 1.0, 0.7], [0.7, 0.7, 1.0]][i as usize];
                    v.push((m, tint));
                }
            }
            Side::B => {
                let pillar = math::scale(0.6, 2.4, 0.6);
                v.push((math::mul(&math::rotate(-t, [0.0, 1.0, 0.0]), &pillar), [1.0, 1.0, 1.0]));
                for i in 0..5 {
                    let phi = t * 0.8 + i as f32 * std::f32::consts::TAU / 5.0;
                    let m = math::mul(
                        &math::translate(2.2 * phi.cos(), 0.3 * (i as f32 - 2.0), 2.2 * phi.sin()),
                        &math::rotate(t * 1.5 + i as f32, [1.0, 0.5, 0.0]),
                    );
                    let m = math::mul(&m, &math::scale(0.7, 0.7, 0.7));
                    v.push((m, [0.5 + 0.1 * i as f32, 0.9, 1.0 - 0.1 * i as f32]));
                }
            }
        }
        v
    }

    fn render(&self, gl: &Gl, frame: u64, size: (u32, u32)) {
        let t = seconds(frame);
        let (eye, clear, light) = match self.side {
            Side::A => ([0.0, 2.5, 6.0], [0.1, 0.12, 0.18], [0.4, 1.0, 0.6]),
            Side::B => ([4.5, 3.0, 4.5], [0.2, 0.1, 0.12], [-0.5, 1.0, 0.3]),
        };
        let p = math::perspective(45f32.to_radians(), size.0 as f32 / size.1 as f32, 0.1, 100.0);
        let view = math::look_at(eye, [0.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        unsafe {
            gl.Viewport(0, 0, size.0 as i32, size.1 as i32);
            gl.ClearColor(clear[0], clear[1], clear[2], 1.0);
            gl.Enable(gl::DEPTH_TEST);
            gl.Enable(gl::CULL_FACE);
            gl.Clear(gl::COLOR_BUFFER_BIT | gl::DEPTH_BUFFER_BIT);
            gl.UseProgram(self.prog);
            gl.UniformMatrix4fv(self.loc[0], 1, gl::FALSE, p.as_ptr());
            gl.UniformMatrix4fv(self.loc[1], 1, gl::FALSE, view.as_ptr());
            gl.Uniform3f(self.loc[4], light[0], light[1], light[2]);
            gl.Uniform1i(self.loc[5], 0);
            gl.ActiveTexture(gl::TEXTURE0);
            gl.BindTexture(gl::TEXTURE_2D, self.tex);
            gl.BindVertexArray(self.vao);
            for (m, tint) in self.cubes(t) {
                gl.UniformMatrix4fv(self.loc[2], 1, gl::FALSE, m.as_ptr());
                gl.Uniform3f(self.loc[3], tint[0], tint[1], tint[2]);
                gl.DrawArrays(gl::TRIANGLES, 0, 36);
            }
        }
    }
}

fn load_gl(d: &EglHeadlessDisplay) -> Result<Gl, String> {
    let gl = Gl::load_with(|name| d.get_proc_address(name));
    if !gl.GetString.is_loaded() || !gl.Clear.is_loaded() {
        return Err("basic GL entry points could not be loaded".into());
    }
    Ok(gl)
}

struct Shared {
    disp: EglHeadlessDisplay,
    /// Texture name created by A; 0 when A failed before the barrier.
    tex: AtomicU32,
    barrier: Barrier,
}

/// One thread's whole life: make current, (A) create the texture, barrier,
/// render the frames, screenshot, release.
fn thread_main(sh: &Shared, side: Side, surface: EglHandle, ctx: EglHandle, o: &Opts) -> Result<(), String> {
    let d = &sh.disp;
    let setup = (|| {
        d.make_current(Some((surface, ctx)))?;
        let gl = load_gl(d)?;
        if side == Side::A {
            let tex = checker_texture(&gl);
            // The texture must be complete before the other context samples it.
            unsafe { gl.Finish() };
            sh.tex.store(tex, Ordering::SeqCst);
        }
        Ok::<Gl, String>(gl)
    })();
    // Both threads always reach the barrier, so a failure cannot deadlock.
    sh.barrier.wait();
    let gl = setup?;
    let tex = sh.tex.load(Ordering::SeqCst);
    if tex == 0 {
        d.make_current(None)?;
        return Err("context A could not create the shared texture".into());
    }
    if side == Side::B && unsafe { gl.IsTexture(tex) } == gl::FALSE {
        d.make_current(None)?;
        return Err(format!("texture {tex} of context A is not visible in context B"));
    }
    let scene = Scene::new(&gl, side, tex)?;
    let last = match (o.frames, o.screenshot.is_some()) {
        (0, true) => Some(0),
        (0, false) => None,
        (n, _) => Some(n - 1),
    };
    let mut frame = 0u64;
    while !STOP.load(Ordering::SeqCst) && last.is_none_or(|l| frame <= l) {
        scene.render(&gl, frame, o.size);
        if frame == 0 {
            let e = unsafe { gl.GetError() };
            if e != gl::NO_ERROR {
                eprintln!(
                    "warning: GL error 0x{e:04X} after the first frame (context {})",
                    side.letter()
                );
            }
        }
        if Some(frame) == last
            && let Some(prefix) = &o.screenshot
        {
            let mut name = prefix.as_os_str().to_owned();
            name.push(format!("-{}.png", side.letter()));
            let rgb = image::read_default_framebuffer(&gl, o.size.0, o.size.1);
            image::write_png(&PathBuf::from(name), o.size.0, o.size.1, &rgb)?;
        }
        d.swap_buffers(surface)?;
        frame += 1;
    }
    unsafe { gl.Finish() };
    d.make_current(None)
}

fn run(o: Opts) -> Result<(), String> {
    let disp = EglHeadlessDisplay::new(Profile::Core33)?;
    let surf_a = disp.create_pbuffer(o.size)?;
    let surf_b = disp.create_pbuffer(o.size)?;
    let ctx_a = disp.create_context(None)?;
    let ctx_b = disp.create_context(Some(ctx_a))?;
    let handler: extern "C" fn(libc::c_int) = on_signal;
    unsafe {
        libc::signal(libc::SIGINT, handler as libc::sighandler_t);
        libc::signal(libc::SIGTERM, handler as libc::sighandler_t);
    }
    let sh = Arc::new(Shared {
        disp,
        tex: AtomicU32::new(0),
        barrier: Barrier::new(2),
    });
    let o = Arc::new(o);
    let spawn = |side: Side, surface, ctx| {
        let (sh, o) = (Arc::clone(&sh), Arc::clone(&o));
        std::thread::Builder::new()
            .name(format!("twothreads-{}", side.letter()))
            .spawn(move || thread_main(&sh, side, surface, ctx, &o))
            .map_err(|e| format!("cannot spawn a thread: {e}"))
    };
    let ta = spawn(Side::A, surf_a, ctx_a)?;
    let tb = spawn(Side::B, surf_b, ctx_b)?;
    let join = |t: std::thread::JoinHandle<Result<(), String>>, side: Side| {
        t.join()
            .unwrap_or_else(|_| Err(format!("thread {} panicked", side.letter())))
    };
    let (ra, rb) = (join(ta, Side::A), join(tb, Side::B));
    sh.disp.destroy_context(ctx_b);
    sh.disp.destroy_context(ctx_a);
    sh.disp.destroy_surface(surf_b);
    sh.disp.destroy_surface(surf_a);
    ra.map_err(|e| format!("thread a: {e}"))?;
    rb.map_err(|e| format!("thread b: {e}"))
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = parse_args(&args).and_then(|o| match o {
        Some(o) => run(o),
        None => Ok(()),
    });
    holoapps::run::exit_code(result)
}
