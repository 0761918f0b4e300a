//! `skybox`: GL 3.3 core cube-map skybox drawn last with `gl_Position =
//! pos.xyww` and GL_LEQUAL (LearnOpenGL style), behind a few lit cubes. The
//! layer treats such far-plane geometry as lying at infinity, so the reference
//! quilt draws the skybox with `View::projection_at_infinity`.
use holoapps::cli::{AppInfo, Options};
use holoapps::gl::{self, Gl};
use holoapps::math::{self, Mat4};
use holoapps::platform::Profile;
use holoapps::scene::{Scene, View, seconds};
use holoapps::shader;
use std::process::ExitCode;

/// The camera orbits the origin at this radius and height.
const ORBIT: f32 = 6.0;
const HEIGHT: f32 = 2.0;
const FACE: i32 = 128;

const OBJ_VS: &str = r#"#version 330 core
layout (location = 0) in vec3 aPos;
layout (location = 1) in vec3 aNormal;
uniform mat4 projection;
uniform mat4 view;
uniform mat4 model;
out vec3 Normal;
out vec3 FragPos;
void main() {
    FragPos = vec3(model * vec4(aPos, 1.0));
    Normal = mat3(model) * aNormal;
    gl_Position = projection * view * vec4(FragPos, 1.0);
}
"#;

const OBJ_FS: &str = r#"#version 330 core
in vec3 Normal;
in vec3 FragPos;
uniform vec3 colour;
uniform vec3 viewPos;
out vec4 FragColor;
void main() {
    vec3 n = normalize(Normal);
    vec3 l = normalize(vec3(0.5, 1.0, 0.3));
    vec3 h = normalize(l + normalize(viewPos - FragPos));
    float diff = max(dot(n, l), 0.0);
    float spec = pow(max(dot(n, h), 0.0), 32.0);
    FragColor = vec4(colour * (0.25 + 0.75 * diff) + vec3(0.4) * spec, 1.0);
}
"#;

const SKY_VS: &str = r#"#version 330 core
layout (location = 0) in vec3 aPos;
uniform mat4 projection;
uniform mat4 view;
out vec3 TexCoords;
void main() {
    TexCoords = aPos;
    // Rotation only: the sky stays put when the camera moves.
    vec4 pos = projection * mat4(mat3(view)) * vec4(aPos, 1.0);
    gl_Position = pos.xyww;
}
"#;

const SKY_FS: &str = r#"#version 330 core
in vec3 TexCoords;
uniform samplerCube skybox;
out vec4 FragColor;
void main() {
    FragColor = texture(skybox, TexCoords);
}
"#;

/// One cube-map face: its own hue, a vertical gradient and a grid, so that
/// every face and its motion between views are easy to tell apart.
fn face_pixels(face: usize) -> Vec<u8> {
    const HUES: [[f32; 3]; 6] = [
        [0.9, 0.3, 0.25],  // +X
        [0.2, 0.8, 0.85],  // -X
        [0.6, 0.8, 1.0],   // +Y
        [0.45, 0.35, 0.2], // -Y
        [0.3, 0.85, 0.35], // +Z
        [0.65, 0.35, 0.9], // -Z
    ];
    let mut px = Vec::with_capacity((FACE * FACE * 4) as usize);
    for y in 0..FACE {
        for x in 0..FACE {
            let g = 0.45 + 0.55 * y as f32 / (FACE - 1) as f32;
            let line = x % 16 == 0 || y % 16 == 0;
            let dot = (x - FACE / 2).pow(2) + (y - FACE / 2).pow(2) < 30;
            for c in HUES[face] {
                let v = if dot {
                    1.0
                } else if line {
                    0.15
                } else {
                    c * g
                };
                px.push((255.0 * v) as u8);
            }
            px.push(255);
        }
    }
    px
}

struct Skybox {
    obj: u32,
    sky: u32,
    vao: u32,
    cubemap: u32,
    obj_loc: [i32; 5],
    sky_loc: [i32; 3],
}

fn eye(t: f32) -> [f32; 3] {
    let a = 0.25 * t + 0.3;
    [ORBIT * a.sin(), HEIGHT, ORBIT * a.cos()]
}

impl Skybox {
    fn new(gl: &Gl) -> Result<Self, String> {
        let obj = shader::program(gl, OBJ_VS, OBJ_FS)?;
        let sky = shader::program(gl, SKY_VS, SKY_FS)?;
        let obj_loc = ["projection", "view", "model", "colour", "viewPos"].map(|n| shader::uniform(gl, obj, n));
        let sky_loc = ["projection", "view", "skybox"].map(|n| shader::uniform(gl, sky, n));
        // The same unit cube serves the objects and (position only) the sky.
        let vao = shader::pos_normal_vao(gl, &shader::cube_vertices());
        let mut cubemap = 0;
        unsafe {
            gl.GenTextures(1, &mut cubemap);
            gl.BindTexture(gl::TEXTURE_CUBE_MAP, cubemap);
            for f in 0..6 {
                let px = face_pixels(f);
                let target = gl::TEXTURE_CUBE_MAP_POSITIVE_X + f as u32;
                let rgba = gl::RGBA as i32;
                gl.TexImage2D(
                    target,
                    0,
                    rgba,
                    FACE,
                    FACE,
                    0,
                    gl::RGBA,
                    gl::UNSIGNED_BYTE,
                    px.as_ptr().cast(),
                );
            }
            for (p, v) in [
                (gl::TEXTURE_MIN_FILTER, gl::LINEAR),
                (gl::TEXTURE_MAG_FILTER, gl::LINEAR),
                (gl::TEXTURE_WRAP_S, gl::CLAMP_TO_EDGE),
                (gl::TEXTURE_WRAP_T, gl::CLAMP_TO_EDGE),
                (gl::TEXTURE_WRAP_R, gl::CLAMP_TO_EDGE),
            ] {
                gl.TexParameteri(gl::TEXTURE_CUBE_MAP, p, v as i32);
            }
            gl.Enable(gl::TEXTURE_CUBE_MAP_SEAMLESS);
        }
        Ok(Skybox {
            obj,
            sky,
            vao,
            cubemap,
            obj_loc,
            sky_loc,
        })
    }

    fn draw_objects(&self, gl: &Gl, p: &Mat4, view: &Mat4, eye: [f32; 3], t: f32) {
        let l = &self.obj_loc;
        unsafe {
            gl.UseProgram(self.obj);
            gl.UniformMatrix4fv(l[0], 1, gl::FALSE, p.as_ptr());
            gl.UniformMatrix4fv(l[1], 1, gl::FALSE, view.as_ptr());
            gl.Uniform3f(l[4], eye[0], eye[1], eye[2]);
        }
        // Three cubes at different depths plus a pedestal slab.
        let cubes = [
            ([0.0, 0.0, 0.0], 1.6, [0.9, 0.75, 0.3]),
            ([2.2, 0.4, -1.8], 1.0, [0.3, 0.6, 0.95]),
            ([-2.0, -0.2, 1.5], 0.8, [0.95, 0.4, 0.5]),
        ];
        for (k, (pos, size, colour)) in cubes.into_iter().enumerate() {
            let m = math::mul(
                &math::translate(pos[0], pos[1], pos[2]),
                &math::rotate(t * (0.6 + 0.3 * k as f32) + k as f32, [0.3, 1.0, 0.2]),
            );
            self.draw(gl, &math::mul(&m, &math::scale(size, size, size)), colour);
        }
        let slab = math::mul(&math::translate(0.0, -1.5, 0.0), &math::scale(7.0, 0.2, 7.0));
        self.draw(gl, &slab, [0.5, 0.5, 0.55]);
    }

    fn draw(&self, gl: &Gl, m: &Mat4, c: [f32; 3]) {
        unsafe {
            gl.UniformMatrix4fv(self.obj_loc[2], 1, gl::FALSE, m.as_ptr());
            gl.Uniform3f(self.obj_loc[3], c[0], c[1], c[2]);
            gl.DrawArrays(gl::TRIANGLES, 0, 36);
        }
    }
}

impl Scene for Skybox {
    fn render(&mut self, gl: &Gl, frame: u64, v: &View) {
        let t = seconds(frame);
        let p = math::perspective(60f32.to_radians(), v.aspect(), 0.1, 100.0);
        let eye = eye(t);
        let view = math::look_at(eye, [0.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        unsafe {
            gl.Viewport(v.viewport[0], v.viewport[1], v.viewport[2], v.viewport[3]);
            gl.ClearColor(0.0, 0.0, 0.0, 1.0);
            gl.Enable(gl::DEPTH_TEST);
            gl.DepthFunc(gl::LESS);
            gl.Enable(gl::CULL_FACE);
            gl.Clear(gl::COLOR_BUFFER_BIT | gl::DEPTH_BUFFER_BIT);
            gl.BindVertexArray(self.vao);
        }
        self.draw_objects(gl, &v.projection(p), &view, eye, t);
        // Sky last: its depth is exactly 1.0, which only LEQUAL lets through,
        // and only where no object was drawn.
        let sky_p = v.projection_at_infinity(p);
        unsafe {
            gl.DepthFunc(gl::LEQUAL);
            gl.Disable(gl::CULL_FACE); // seen from inside
            gl.UseProgram(self.sky);
            gl.UniformMatrix4fv(self.sky_loc[0], 1, gl::FALSE, sky_p.as_ptr());
            gl.UniformMatrix4fv(self.sky_loc[1], 1, gl::FALSE, view.as_ptr());
            gl.ActiveTexture(gl::TEXTURE0);
            gl.BindTexture(gl::TEXTURE_CUBE_MAP, self.cubemap);
            gl.Uniform1i(self.sky_loc[2], 0);
            gl.DrawArrays(gl::TRIANGLES, 0, 36);
            gl.DepthFunc(gl::LESS);
        }
    }
}

fn main() -> ExitCode {
    let info = AppInfo {
        name: "skybox",
        about: "GL 3.3 core cube-map skybox (pos.xyww, GL_LEQUAL) behind lit cubes",
        default_convergence: (ORBIT * ORBIT + HEIGHT * HEIGHT).sqrt(),
        extra: &[],
        switches: &[],
    };
    holoapps::run::main(
        &info,
        Profile::Core33,
        Box::new(|gl: &Gl, _: &Options| Ok(Box::new(Skybox::new(gl)?) as Box<dyn Scene>)),
    )
}
