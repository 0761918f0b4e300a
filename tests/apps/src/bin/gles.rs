//! `gles`: OpenGL ES on EGL. ES 3.0 with `#version 300 es` shaders and a VAO
//! by default; `--es2` asks for an ES 2.0 context with `#version 100` shaders
//! (attribute/varying) and per-frame attribute setup, as ES 2 apps do without
//! OES_vertex_array_object. The camera reaches the shader only as one
//! combined `u_mvp` matrix, so the layer cannot see P on its own.
use holoapps::cli::{AppInfo, Backend, Options};
use holoapps::gl::{self, Gl};
use holoapps::math::{self, Mat4};
use holoapps::platform::Profile;
use holoapps::scene::{Scene, View, seconds};
use holoapps::shader;
use std::process::ExitCode;

const EYE: [f32; 3] = [0.0, 2.5, 6.0];
const CENTRE: [f32; 3] = [0.0, 0.0, 0.0];

const VS3: &str = r#"#version 300 es
layout (location = 0) in vec3 a_pos;
layout (location = 1) in vec3 a_normal;
uniform mat4 u_mvp;
uniform mat3 u_normal;
out vec3 v_normal;
void main() {
    v_normal = u_normal * a_normal;
    gl_Position = u_mvp * vec4(a_pos, 1.0);
}
"#;

const FS3: &str = r#"#version 300 es
precision mediump float;
in vec3 v_normal;
uniform vec3 u_colour;
out vec4 frag;
void main() {
    float d = max(dot(normalize(v_normal), normalize(vec3(0.4, 1.0, 0.6))), 0.0);
    frag = vec4(u_colour * (0.25 + 0.75 * d), 1.0);
}
"#;

const VS2: &str = r#"#version 100
attribute vec3 a_pos;
attribute vec3 a_normal;
uniform mat4 u_mvp;
uniform mat3 u_normal;
varying vec3 v_normal;
void main() {
    v_normal = u_normal * a_normal;
    gl_Position = u_mvp * vec4(a_pos, 1.0);
}
"#;

const FS2: &str = r#"#version 100
precision mediump float;
varying vec3 v_normal;
uniform vec3 u_colour;
void main() {
    float d = max(dot(normalize(v_normal), normalize(vec3(0.4, 1.0, 0.6))), 0.0);
    gl_FragColor = vec4(u_colour * (0.25 + 0.75 * d), 1.0);
}
"#;

/// Flat-shaded octahedron, CCW outside: 8 triangles of position + normal.
fn octahedron() -> Vec<f32> {
    let mut v = Vec::with_capacity(8 * 3 * 6);
    for sx in [-1.0f32, 1.0] {
        for sy in [-1.0f32, 1.0] {
            for sz in [-1.0f32, 1.0] {
                let (a, b, c) = ([sx, 0.0, 0.0], [0.0, sy, 0.0], [0.0, 0.0, sz]);
                // Odd sign parity flips the orientation of (a, b, c).
                let tri = if sx * sy * sz > 0.0 { [a, b, c] } else { [a, c, b] };
                let n = 1.0 / 3f32.sqrt();
                for p in tri {
                    v.extend_from_slice(&p);
                    v.extend_from_slice(&[sx * n, sy * n, sz * n]);
                }
            }
        }
    }
    v
}

/// Upper-left 3x3 of a rotation * uniform-scale model matrix: enough as the
/// normal matrix (the shader renormalises), and ES 1.00 has no inverse().
fn normal_matrix(m: &Mat4) -> [f32; 9] {
    [m[0], m[1], m[2], m[4], m[5], m[6], m[8], m[9], m[10]]
}

struct Gles {
    es2: bool,
    prog: u32,
    vbo: u32,
    /// ES 3 only; ES 2 re-specifies the attributes every frame instead.
    vao: u32,
    attr: [u32; 2],
    loc: [i32; 3],
}

impl Gles {
    fn new(gl: &Gl, es2: bool) -> Result<Self, String> {
        let (vs, fs) = if es2 { (VS2, FS2) } else { (VS3, FS3) };
        let prog = shader::program(gl, vs, fs)?;
        let loc = ["u_mvp", "u_normal", "u_colour"].map(|n| shader::uniform(gl, prog, n));
        let mut attr = [0u32; 2];
        for (a, name) in attr.iter_mut().zip([c"a_pos", c"a_normal"]) {
            let l = unsafe { gl.GetAttribLocation(prog, name.as_ptr()) };
            *a = u32::try_from(l).map_err(|_| format!("attribute {name:?} not found"))?;
        }
        let mut verts = shader::cube_vertices();
        verts.extend(octahedron());
        let (mut vbo, mut vao) = (0, 0);
        unsafe {
            gl.GenBuffers(1, &mut vbo);
            gl.BindBuffer(gl::ARRAY_BUFFER, vbo);
            let bytes = std::mem::size_of_val(verts.as_slice()) as isize;
            gl.BufferData(gl::ARRAY_BUFFER, bytes, verts.as_ptr().cast(), gl::STATIC_DRAW);
        }
        let mut g = Gles {
            es2,
            prog,
            vbo,
            vao,
            attr,
            loc,
        };
        if !es2 {
            unsafe {
                gl.GenVertexArrays(1, &mut vao);
                gl.BindVertexArray(vao);
            }
            g.vao = vao;
            g.attributes(gl);
            unsafe { gl.BindVertexArray(0) };
        }
        Ok(g)
    }

    fn attributes(&self, gl: &Gl) {
        unsafe {
            gl.BindBuffer(gl::ARRAY_BUFFER, self.vbo);
            for (k, a) in self.attr.into_iter().enumerate() {
                let offset = (k * 12) as *const std::ffi::c_void;
                gl.VertexAttribPointer(a, 3, gl::FLOAT, gl::FALSE, 24, offset);
                gl.EnableVertexAttribArray(a);
            }
        }
    }

    /// One draw: the app multiplies P * V * M itself and uploads only that.
    fn draw(&self, gl: &Gl, vp: &Mat4, m: &Mat4, colour: [f32; 3], first: i32, count: i32) {
        let mvp = math::mul(vp, m);
        unsafe {
            gl.UniformMatrix4fv(self.loc[0], 1, gl::FALSE, mvp.as_ptr());
            gl.UniformMatrix3fv(self.loc[1], 1, gl::FALSE, normal_matrix(m).as_ptr());
            gl.Uniform3f(self.loc[2], colour[0], colour[1], colour[2]);
            gl.DrawArrays(gl::TRIANGLES, first, count);
        }
    }
}

impl Scene for Gles {
    fn render(&mut self, gl: &Gl, frame: u64, v: &View) {
        let t = seconds(frame);
        let p = v.projection(math::perspective(50f32.to_radians(), v.aspect(), 0.1, 50.0));
        let vp = math::mul(&p, &math::look_at(EYE, CENTRE, [0.0, 1.0, 0.0]));
        unsafe {
            gl.Viewport(v.viewport[0], v.viewport[1], v.viewport[2], v.viewport[3]);
            gl.ClearColor(0.12, 0.1, 0.16, 1.0);
            gl.Enable(gl::DEPTH_TEST);
            gl.Enable(gl::CULL_FACE);
            gl.Clear(gl::COLOR_BUFFER_BIT | gl::DEPTH_BUFFER_BIT);
            gl.UseProgram(self.prog);
            if self.es2 {
                self.attributes(gl);
            } else {
                gl.BindVertexArray(self.vao);
            }
        }
        let (cube, octa) = ((0, 36), (36, 24));
        let floor = math::mul(&math::translate(0.0, -1.6, 0.0), &math::scale(10.0, 0.2, 10.0));
        self.draw(gl, &vp, &floor, [0.4, 0.42, 0.45], cube.0, cube.1);
        // A ring of alternating cubes and octahedra around a big octahedron.
        for k in 0..6 {
            let a = k as f32 * std::f32::consts::TAU / 6.0 + t * 0.4;
            let m = math::mul(
                &math::translate(3.0 * a.cos(), -0.6, 3.0 * a.sin()),
                &math::rotate(t * 1.5 + k as f32, [0.2, 1.0, 0.4]),
            );
            let c = [0.5 + 0.5 * (k as f32).cos(), 0.5 + 0.4 * (k as f32 * 2.0).sin(), 0.6];
            let (first, count) = if k % 2 == 0 { cube } else { octa };
            let s = if k % 2 == 0 { 1.0 } else { 0.7 };
            self.draw(gl, &vp, &math::mul(&m, &math::scale(s, s, s)), c, first, count);
        }
        let centre = math::mul(&math::translate(0.0, 0.3, 0.0), &math::rotate(-t, [0.0, 1.0, 0.0]));
        self.draw(
            gl,
            &vp,
            &math::mul(&centre, &math::scale(1.2, 1.2, 1.2)),
            [0.95, 0.8, 0.3],
            octa.0,
            octa.1,
        );
    }
}

/// ES contexts come from EGL only (see platform::create).
fn profile(o: &Options) -> Result<Profile, String> {
    if !matches!(o.backend, Backend::Egl | Backend::EglX11 | Backend::EglDevice) {
        return Err(format!(
            "gles runs on --backend egl, egl-x11 or egl-device only, not {:?}",
            o.backend
        ));
    }
    Ok(if o.switches.contains("es2") {
        Profile::Gles2
    } else {
        Profile::Gles3
    })
}

fn main() -> ExitCode {
    let info = AppInfo {
        name: "gles",
        about: "OpenGL ES 3.0 (or 2.0 with --es2) on EGL: lit spinning shapes, one combined u_mvp uniform",
        default_convergence: math::distance(EYE, CENTRE),
        extra: &[],
        switches: &[("es2", "ES 2.0 context and #version 100 shaders instead of ES 3.0")],
    };
    holoapps::run::main_with(
        &info,
        &profile,
        Box::new(|gl: &Gl, o: &Options| Ok(Box::new(Gles::new(gl, o.switches.contains("es2"))?) as Box<dyn Scene>)),
    )
}
