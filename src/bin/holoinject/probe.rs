//! `holoinject __probe glx|egl|osmesa [--draw OUT.png]`: doctor's tiny GL program, run as a
//! child (a driver that crashes takes only the probe down). It prints what the context offers,
//! one `key value` line each (`version`, `glsl`, `renderer`, `ext`); with `--draw` (OSMesa)
//! it renders two frames of a small perspective scene (three quads at three depths, so views
//! differ by parallax) and writes the last one as a PNG. Under the layer the same run makes a
//! quilt, which doctor compares with this pass-through image.

use super::probe_context::{self, Probe};
use holoinject::gl::{self, Gl};
use std::ffi::{CStr, OsString};

const SIZE: (u32, u32) = (96, 96);

pub fn run(args: &[OsString]) -> Result<(), String> {
    let backend = args.first().and_then(|a| a.to_str()).unwrap_or("");
    let draw = match (args.get(1).and_then(|a| a.to_str()), args.get(2)) {
        (Some("--draw"), Some(out)) => Some(std::path::PathBuf::from(out)),
        _ => None,
    };
    let probe = match backend {
        "glx" => probe_context::glx()?,
        "egl" => probe_context::egl()?,
        "osmesa" => probe_context::osmesa(SIZE)?,
        other => return Err(format!("__probe: unknown back-end `{other}`")),
    };
    let gl = Gl::load_with(|name| (probe.get_proc)(name));
    describe(&gl);
    if let Some(out) = draw {
        draw_scene(&gl, &probe, &out)?;
    }
    Ok(())
}

fn string(gl: &Gl, name: gl::GLenum) -> String {
    // SAFETY: glGetString returns a static NUL-terminated string or null.
    let p = unsafe { gl.GetString(name) };
    if p.is_null() {
        return String::new();
    }
    // SAFETY: non-null, NUL-terminated, owned by GL.
    unsafe { CStr::from_ptr(p.cast()) }.to_string_lossy().into_owned()
}

fn describe(gl: &Gl) {
    println!("version {}", string(gl, gl::VERSION));
    println!("glsl {}", string(gl, gl::SHADING_LANGUAGE_VERSION));
    println!("renderer {}", string(gl, gl::RENDERER));
    let mut n = 0;
    // SAFETY: a single-integer query, then indexed strings below the count.
    unsafe { gl.GetIntegerv(gl::NUM_EXTENSIONS, &mut n) };
    for i in 0..n.max(0) as u32 {
        // SAFETY: `i` is below NUM_EXTENSIONS.
        let p = unsafe { gl.GetStringi(gl::EXTENSIONS, i) };
        if !p.is_null() {
            // SAFETY: non-null, NUL-terminated, owned by GL.
            println!("ext {}", unsafe { CStr::from_ptr(p.cast()) }.to_string_lossy());
        }
    }
}

const VS: &str = "#version 330 core\nuniform mat4 u_mvp;\nlayout(location = 0) in vec3 pos;\n\
    layout(location = 1) in vec3 col;\nout vec3 c;\nvoid main() { c = col; gl_Position = u_mvp * vec4(pos, 1.0); }\n";
const FS: &str = "#version 330 core\nin vec3 c;\nout vec4 o;\nvoid main() { o = vec4(c, 1.0); }\n";

/// Three quads (x, y, z, r, g, b per vertex) at depths 3, 5 and 9 in front of the camera.
fn quads() -> Vec<f32> {
    let quad = |x: f32, z: f32, s: f32, rgb: [f32; 3]| -> Vec<f32> {
        [
            (-1.0, -1.0),
            (1.0, -1.0),
            (1.0, 1.0),
            (-1.0, -1.0),
            (1.0, 1.0),
            (-1.0, 1.0),
        ]
        .iter()
        .flat_map(|&(u, v)| [x + u * s, v * s, -z, rgb[0], rgb[1], rgb[2]])
        .collect()
    };
    let mut v = quad(0.0, 9.0, 3.0, [0.2, 0.3, 0.8]);
    v.extend(quad(-0.8, 5.0, 0.9, [0.9, 0.6, 0.1]));
    v.extend(quad(0.6, 3.0, 0.4, [0.1, 0.8, 0.3]));
    v
}

/// OpenGL's perspective matrix (column-major), 60° vertical, square, near 1, far 20.
fn projection() -> [f32; 16] {
    let f = 1.0 / (30f32.to_radians()).tan();
    let (n, far) = (1.0, 20.0);
    let mut m = [0.0; 16];
    (m[0], m[5], m[11]) = (f, f, -1.0);
    m[10] = (far + n) / (n - far);
    m[14] = 2.0 * far * n / (n - far);
    m
}

fn compile(gl: &Gl, kind: gl::GLenum, src: &str) -> u32 {
    // SAFETY: a shader of ours from one NUL-free source string with its length.
    unsafe {
        let s = gl.CreateShader(kind);
        gl.ShaderSource(s, 1, &src.as_ptr().cast(), &(src.len() as i32));
        gl.CompileShader(s);
        s
    }
}

fn draw_scene(gl: &Gl, probe: &Probe, out: &std::path::Path) -> Result<(), String> {
    let vertices = quads();
    // SAFETY: our own objects in our own context; the buffer outlives the upload; the
    // attribute layout matches `quads` (6 floats per vertex).
    unsafe {
        let program = gl.CreateProgram();
        gl.AttachShader(program, compile(gl, gl::VERTEX_SHADER, VS));
        gl.AttachShader(program, compile(gl, gl::FRAGMENT_SHADER, FS));
        gl.LinkProgram(program);
        let (mut vao, mut vbo) = (0, 0);
        gl.GenVertexArrays(1, &mut vao);
        gl.BindVertexArray(vao);
        gl.GenBuffers(1, &mut vbo);
        gl.BindBuffer(gl::ARRAY_BUFFER, vbo);
        let bytes = (vertices.len() * 4) as isize;
        gl.BufferData(gl::ARRAY_BUFFER, bytes, vertices.as_ptr().cast(), gl::STATIC_DRAW);
        gl.VertexAttribPointer(0, 3, gl::FLOAT, gl::FALSE, 24, std::ptr::null());
        gl.VertexAttribPointer(1, 3, gl::FLOAT, gl::FALSE, 24, 12 as *const _);
        gl.EnableVertexAttribArray(0);
        gl.EnableVertexAttribArray(1);
        gl.UseProgram(program);
        gl.UniformMatrix4fv(
            gl.GetUniformLocation(program, c"u_mvp".as_ptr()),
            1,
            gl::FALSE,
            projection().as_ptr(),
        );
        gl.Enable(gl::DEPTH_TEST);
        gl.Viewport(0, 0, probe.size.0 as i32, probe.size.1 as i32);
        for _frame in 0..2 {
            gl.ClearColor(0.05, 0.05, 0.05, 1.0);
            gl.Clear(gl::COLOR_BUFFER_BIT | gl::DEPTH_BUFFER_BIT);
            gl.DrawArrays(gl::TRIANGLES, 0, (vertices.len() / 6) as i32);
            // OSMesa's frame boundary, as the layer sees it.
            gl.Finish();
        }
    }
    let (w, h) = probe.size;
    let mut rgba = vec![0u8; w as usize * h as usize * 4];
    // SAFETY: reading the w*h RGBA8 frame just drawn into a buffer of that size (alignment 4
    // suits RGBA8 rows).
    unsafe {
        gl.ReadPixels(
            0,
            0,
            w as i32,
            h as i32,
            gl::RGBA,
            gl::UNSIGNED_BYTE,
            rgba.as_mut_ptr().cast(),
        )
    };
    let rgb = holoinject::output::png::rgba_bottom_up_to_rgb_top_down(&rgba, w, h);
    holoinject::output::png::write_rgb(out, probe.size.0, probe.size.1, &rgb)
}
