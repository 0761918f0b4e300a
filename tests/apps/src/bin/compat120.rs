//! `compat120`: GLSL 1.20 on a compatibility context. The shaders read the
//! built-in matrices (`ftransform()`, `gl_ModelViewProjectionMatrix`,
//! `gl_NormalMatrix`) that glFrustum/glRotate/glTranslate set, and geometry
//! comes from client-side vertex arrays and from a VBO through
//! glVertexPointer/glNormalPointer. A glOrtho HUD is drawn with a second
//! `#version 120` program and must stay unshifted in every view.
use holoapps::cli::{AppInfo, Options};
use holoapps::gl::{self, Gl};
use holoapps::platform::Profile;
use holoapps::scene::{Scene, View, seconds};
use holoapps::shader;
use std::ffi::c_void;
use std::process::ExitCode;

/// Camera 4 up and 10 back, pitched down to look at (0, LOOK_Y, 0), the
/// middle of the objects.
const EYE_Y: f32 = 4.0;
const EYE_Z: f32 = 10.0;
const LOOK_Y: f32 = 1.0;
/// Interleaved position + normal: 6 floats a vertex.
const STRIDE: i32 = 24;

const SCENE_VS: &str = r#"#version 120
varying vec3 normal;
varying vec3 eyePos;
void main() {
    normal = normalize(gl_NormalMatrix * gl_Normal);
    eyePos = vec3(gl_ModelViewMatrix * gl_Vertex);
    gl_FrontColor = gl_Color;
    gl_Position = ftransform();
}
"#;

const SCENE_FS: &str = r#"#version 120
varying vec3 normal;
varying vec3 eyePos;
uniform vec3 lightDir; // eye space
void main() {
    vec3 n = normalize(normal);
    vec3 l = normalize(lightDir);
    vec3 h = normalize(l - normalize(eyePos));
    float diff = max(dot(n, l), 0.0);
    float spec = pow(max(dot(n, h), 0.0), 24.0);
    gl_FragColor = vec4(gl_Color.rgb * (0.25 + 0.75 * diff) + vec3(0.35 * spec), 1.0);
}
"#;

const HUD_VS: &str = r#"#version 120
void main() {
    gl_Position = gl_ModelViewProjectionMatrix * gl_Vertex;
}
"#;

const HUD_FS: &str = r#"#version 120
uniform vec4 colour;
void main() {
    gl_FragColor = colour;
}
"#;

/// Torus (major radius 1, minor 0.35) as triangles with position + normal.
fn torus() -> Vec<f32> {
    let (rings, sides) = (48, 16);
    let tau = std::f32::consts::TAU;
    let vertex = |i: usize, j: usize| {
        let (su, cu) = (i as f32 / rings as f32 * tau).sin_cos();
        let (sv, cv) = (j as f32 / sides as f32 * tau).sin_cos();
        let n = [cu * cv, sv, su * cv];
        let p = [cu * (1.0 + 0.35 * cv), 0.35 * sv, su * (1.0 + 0.35 * cv)];
        [p[0], p[1], p[2], n[0], n[1], n[2]]
    };
    let mut v = Vec::new();
    for i in 0..rings {
        for j in 0..sides {
            let q = [vertex(i, j), vertex(i, j + 1), vertex(i + 1, j + 1), vertex(i + 1, j)];
            for k in [0, 1, 2, 0, 2, 3] {
                v.extend_from_slice(&q[k]);
            }
        }
    }
    v
}

struct Compat {
    scene: u32,
    hud: u32,
    light_loc: i32,
    colour_loc: i32,
    /// Client-side arrays: cube (36 vertices) then floor (6).
    client: Vec<f32>,
    torus_vbo: u32,
    torus_count: i32,
}

impl Compat {
    fn new(gl: &Gl) -> Result<Self, String> {
        let scene = shader::program(gl, SCENE_VS, SCENE_FS)?;
        let hud = shader::program(gl, HUD_VS, HUD_FS)?;
        let mut client = shader::cube_vertices();
        for (x, z) in [
            (-8.0, 8.0),
            (8.0, 8.0),
            (8.0, -8.0),
            (-8.0, 8.0),
            (8.0, -8.0),
            (-8.0, -8.0),
        ] {
            client.extend_from_slice(&[x, 0.0, z, 0.0, 1.0, 0.0]);
        }
        let t = torus();
        let mut torus_vbo = 0;
        unsafe {
            gl.GenBuffers(1, &mut torus_vbo);
            gl.BindBuffer(gl::ARRAY_BUFFER, torus_vbo);
            let bytes = std::mem::size_of_val(t.as_slice()) as isize;
            gl.BufferData(gl::ARRAY_BUFFER, bytes, t.as_ptr().cast(), gl::STATIC_DRAW);
            gl.BindBuffer(gl::ARRAY_BUFFER, 0);
        }
        Ok(Compat {
            scene,
            hud,
            light_loc: shader::uniform(gl, scene, "lightDir"),
            colour_loc: shader::uniform(gl, hud, "colour"),
            client,
            torus_vbo,
            torus_count: (t.len() / 6) as i32,
        })
    }

    /// glFrustum like a 45-degree gluPerspective; the reference quilt swaps
    /// in the sheared matrix read back from GL_PROJECTION_MATRIX.
    unsafe fn projection(gl: &Gl, v: &View) {
        let top = 0.1 * 22.5f32.to_radians().tan();
        let right = top * v.aspect();
        unsafe {
            gl.MatrixMode(gl::PROJECTION);
            gl.LoadIdentity();
            gl.Frustum(-right as f64, right as f64, -top as f64, top as f64, 0.1, 100.0);
            if v.shear.is_some() {
                let mut p = [0f32; 16];
                gl.GetFloatv(gl::PROJECTION_MATRIX, p.as_mut_ptr());
                gl.LoadMatrixf(v.projection(p).as_ptr());
            }
            gl.MatrixMode(gl::MODELVIEW);
            gl.LoadIdentity();
            gl.Rotatef((EYE_Y - LOOK_Y).atan2(EYE_Z).to_degrees(), 1.0, 0.0, 0.0);
            gl.Translatef(0.0, -EYE_Y, -EYE_Z);
        }
    }

    /// Points glVertexPointer/glNormalPointer at interleaved client memory
    /// (`base` = null and a VBO bound means offsets into that VBO).
    unsafe fn arrays(gl: &Gl, base: *const f32) {
        unsafe {
            gl.VertexPointer(3, gl::FLOAT, STRIDE, base.cast());
            gl.NormalPointer(gl::FLOAT, STRIDE, base.wrapping_add(3).cast::<c_void>());
        }
    }

    unsafe fn world(&self, gl: &Gl, t: f32) {
        unsafe {
            gl.UseProgram(self.scene);
            // Light fixed in eye space, up and to the right of the camera.
            gl.Uniform3f(self.light_loc, 0.4, 0.8, 0.5);
            gl.EnableClientState(gl::VERTEX_ARRAY);
            gl.EnableClientState(gl::NORMAL_ARRAY);
            // Floor and cubes straight from client memory.
            gl.BindBuffer(gl::ARRAY_BUFFER, 0);
            Self::arrays(gl, self.client.as_ptr());
            gl.Color3f(0.45, 0.5, 0.45);
            gl.DrawArrays(gl::TRIANGLES, 36, 6);
            for k in 0..5 {
                let a = k as f32 * 72.0 + t * 20.0;
                gl.PushMatrix();
                gl.Rotatef(a, 0.0, 1.0, 0.0);
                gl.Translatef(3.5, 0.6 + 0.3 * k as f32, 0.0);
                gl.Rotatef(t * 60.0 + k as f32 * 30.0, 1.0, 1.0, 0.0);
                gl.Scalef(1.2, 1.2, 1.2);
                let c = [
                    [0.9, 0.3, 0.3],
                    [0.3, 0.9, 0.4],
                    [0.3, 0.5, 0.95],
                    [0.95, 0.85, 0.3],
                    [0.8, 0.4, 0.9],
                ][k];
                gl.Color3f(c[0], c[1], c[2]);
                gl.DrawArrays(gl::TRIANGLES, 0, 36);
                gl.PopMatrix();
            }
            // Torus in the middle from the VBO.
            gl.BindBuffer(gl::ARRAY_BUFFER, self.torus_vbo);
            Self::arrays(gl, std::ptr::null());
            gl.PushMatrix();
            gl.Translatef(0.0, 1.2, 0.0);
            gl.Rotatef(t * 45.0, 0.0, 1.0, 0.0);
            gl.Rotatef(60.0, 1.0, 0.0, 0.0);
            gl.Scalef(1.4, 1.4, 1.4);
            gl.Color3f(0.95, 0.6, 0.25);
            gl.DrawArrays(gl::TRIANGLES, 0, self.torus_count);
            gl.PopMatrix();
            gl.BindBuffer(gl::ARRAY_BUFFER, 0);
            gl.DisableClientState(gl::NORMAL_ARRAY);
        }
    }

    /// Screen-space bars (pixels) through glOrtho and the HUD program.
    unsafe fn hud(&self, gl: &Gl, v: &View, t: f32) {
        let (w, h) = v.size();
        let mut rects: Vec<([f32; 4], [f32; 4])> = (0..3)
            .map(|k| {
                let len = (0.15 + 0.2 * (t * (k + 1) as f32).sin().abs()) * w;
                let y = h - 22.0 - k as f32 * 16.0;
                (
                    [10.0, y, 10.0 + len, y + 10.0],
                    [[0.9, 0.2, 0.2, 1.0], [0.2, 0.8, 0.2, 1.0], [0.2, 0.4, 0.9, 1.0]][k],
                )
            })
            .collect();
        rects.push(([w - 40.0, 10.0, w - 10.0, 40.0], [1.0; 4]));
        unsafe {
            gl.Disable(gl::DEPTH_TEST);
            gl.MatrixMode(gl::PROJECTION);
            gl.LoadIdentity();
            gl.Ortho(0.0, w as f64, 0.0, h as f64, -1.0, 1.0);
            gl.MatrixMode(gl::MODELVIEW);
            gl.LoadIdentity();
            gl.UseProgram(self.hud);
            for (r, c) in rects {
                let quad = [r[0], r[1], r[2], r[1], r[2], r[3], r[0], r[3]];
                gl.Uniform4f(self.colour_loc, c[0], c[1], c[2], c[3]);
                gl.VertexPointer(2, gl::FLOAT, 0, quad.as_ptr().cast());
                gl.DrawArrays(gl::TRIANGLE_FAN, 0, 4);
            }
            gl.DisableClientState(gl::VERTEX_ARRAY);
            gl.UseProgram(0);
        }
    }
}

impl Scene for Compat {
    fn render(&mut self, gl: &Gl, frame: u64, v: &View) {
        let t = seconds(frame);
        unsafe {
            gl.Viewport(v.viewport[0], v.viewport[1], v.viewport[2], v.viewport[3]);
            gl.ClearColor(0.15, 0.17, 0.22, 1.0);
            gl.Enable(gl::DEPTH_TEST);
            gl.Enable(gl::CULL_FACE);
            gl.Clear(gl::COLOR_BUFFER_BIT | gl::DEPTH_BUFFER_BIT);
            Self::projection(gl, v);
            self.world(gl, t);
            gl.Disable(gl::CULL_FACE);
            self.hud(gl, v, t);
        }
    }
}

fn main() -> ExitCode {
    let info = AppInfo {
        name: "compat120",
        about: "GLSL 1.20 compat: ftransform/gl_ModelViewProjectionMatrix, glFrustum, client arrays + VBO, glOrtho HUD",
        default_convergence: ((EYE_Y - LOOK_Y).powi(2) + EYE_Z * EYE_Z).sqrt(),
        extra: &[],
        switches: &[],
    };
    holoapps::run::main(
        &info,
        Profile::Legacy,
        Box::new(|gl: &Gl, _: &Options| Ok(Box::new(Compat::new(gl)?) as Box<dyn Scene>)),
    )
}
