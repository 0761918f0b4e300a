//! `cubes`: GL 3.3 core, LearnOpenGL-style lit cube grid (one draw per cube).
use holoapps::cli::{AppInfo, Options};
use holoapps::gl::{self, Gl};
use holoapps::math::{self, Mat4};
use holoapps::platform::Profile;
use holoapps::scene::{Scene, View, seconds};
use holoapps::shader;
use holoapps::weapon::{self, Weapon};
use std::process::ExitCode;

const EYE: [f32; 3] = [0.0, 9.0, 17.0];
const CENTRE: [f32; 3] = [0.0, 0.0, 0.0];
const GRID: i32 = 9;

const VS: &str = r#"#version 330 core
layout (location = 0) in vec3 aPos;
layout (location = 1) in vec3 aNormal;
uniform mat4 model;
uniform mat4 view;
uniform mat4 projection;
out vec3 Normal;
void main() {
    Normal = mat3(transpose(inverse(model))) * aNormal;
    gl_Position = projection * view * model * vec4(aPos, 1.0);
}
"#;

const FS: &str = r#"#version 330 core
in vec3 Normal;
uniform vec3 objectColor;
uniform vec3 lightDir;
out vec4 FragColor;
void main() {
    float diff = max(dot(normalize(Normal), normalize(lightDir)), 0.0);
    FragColor = vec4((0.25 + 0.75 * diff) * objectColor, 1.0);
}
"#;

struct Cubes {
    prog: u32,
    vao: u32,
    loc: [i32; 5],
    near: f32,
    far: Option<f32>,
    reversed: bool,
    /// Degrees per frame the camera orbits the centre (`--orbit`), and the cubes' spin
    /// speed factor (`--spin`).
    orbit: f32,
    spin: f32,
    weapon: Weapon,
}

impl Cubes {
    fn new(gl: &Gl) -> Result<Self, String> {
        let prog = shader::program(gl, VS, FS)?;
        let loc = ["projection", "view", "model", "objectColor", "lightDir"].map(|n| shader::uniform(gl, prog, n));
        let vao = shader::pos_normal_vao(gl, &shader::cube_vertices());
        Ok(Cubes {
            prog,
            vao,
            loc,
            near: 0.1,
            far: Some(100.0),
            reversed: false,
            orbit: 0.0,
            spin: 1.0,
            weapon: Weapon::None,
        })
    }

    /// Model matrix and colour of grid cell (i, j); heights and spin speeds
    /// vary per cell so parallax and motion are easy to see.
    fn cube(i: i32, j: i32, t: f32) -> (Mat4, [f32; 3]) {
        let h = 0.3 + 0.5 * (((i * 7 + j * 3) % 5) as f32);
        let (x, z) = ((i - GRID / 2) as f32 * 1.5, (j - GRID / 2) as f32 * 1.5);
        let angle = t * (0.5 + 0.25 * ((i + 2 * j) % 4) as f32) + (i * j) as f32 * 0.3;
        let m = math::mul(&math::translate(x, h / 2.0, z), &math::rotate(angle, [0.0, 1.0, 0.0]));
        let m = math::mul(&m, &math::scale(0.8, h, 0.8));
        let c = [
            i as f32 / (GRID - 1) as f32,
            0.4 + 0.1 * (h % 3.0),
            j as f32 / (GRID - 1) as f32,
        ];
        (m, c)
    }

    fn draw(&self, gl: &Gl, model: &Mat4, colour: [f32; 3]) {
        unsafe {
            gl.UniformMatrix4fv(self.loc[2], 1, gl::FALSE, model.as_ptr());
            gl.Uniform3f(self.loc[3], colour[0], colour[1], colour[2]);
            gl.DrawArrays(gl::TRIANGLES, 0, 36);
        }
    }
}

impl Scene for Cubes {
    fn render(&mut self, gl: &Gl, frame: u64, v: &View) {
        let t = seconds(frame) * self.spin;
        let p = v.projection(math::perspective_ext(
            45f32.to_radians(),
            v.aspect(),
            self.near,
            self.far,
            self.reversed,
        ));
        // The eye turned about the vertical axis through the centre: the camera moves every
        // frame while the scene (with --spin 0) stays still.
        let a = (self.orbit * frame as f32).to_radians();
        let eye = [
            EYE[0] * a.cos() + EYE[2] * a.sin(),
            EYE[1],
            EYE[2] * a.cos() - EYE[0] * a.sin(),
        ];
        let view = math::look_at(eye, CENTRE, [0.0, 1.0, 0.0]);
        unsafe {
            gl.Viewport(v.viewport[0], v.viewport[1], v.viewport[2], v.viewport[3]);
            gl.ClearColor(0.1, 0.12, 0.18, 1.0);
            gl.Enable(gl::DEPTH_TEST);
            if self.reversed {
                // Reversed-Z: depth 1 at the near plane, 0 at infinity, in [0,1] clip space.
                gl.ClipControl(gl::LOWER_LEFT, gl::ZERO_TO_ONE);
                gl.ClearDepth(0.0);
                gl.DepthFunc(gl::GREATER);
            }
            // Culling avoids front/back depth ties at silhouettes, which llvmpipe
            // resolves differently in FBOs and window surfaces.
            gl.Enable(gl::CULL_FACE);
            gl.Clear(gl::COLOR_BUFFER_BIT | gl::DEPTH_BUFFER_BIT);
            gl.UseProgram(self.prog);
            gl.UniformMatrix4fv(self.loc[0], 1, gl::FALSE, p.as_ptr());
            gl.UniformMatrix4fv(self.loc[1], 1, gl::FALSE, view.as_ptr());
            gl.Uniform3f(self.loc[4], 0.4, 1.0, 0.6);
            gl.BindVertexArray(self.vao);
        }
        let floor = math::mul(&math::translate(0.0, -0.07, 0.0), &math::scale(14.0, 0.1, 14.0));
        self.draw(gl, &floor, [0.35, 0.35, 0.4]);
        for i in 0..GRID {
            for j in 0..GRID {
                let (m, c) = Self::cube(i, j, t);
                self.draw(gl, &m, c);
            }
        }
        if self.weapon != Weapon::None {
            let identity = math::scale(1.0, 1.0, 1.0);
            let [x, y, z] = weapon::CENTRE;
            let [a, b, c] = weapon::HALF;
            // The cube's vertices span [-0.5, 0.5].
            let held = math::mul(&math::translate(x, y, z), &math::scale(2.0 * a, 2.0 * b, 2.0 * c));
            let (near, far) = weapon::depth_range(self.weapon);
            unsafe {
                gl.UniformMatrix4fv(self.loc[1], 1, gl::FALSE, identity.as_ptr());
                gl.DepthRange(near, far);
            }
            self.draw(gl, &held, [0.8, 0.75, 0.7]);
            unsafe { gl.DepthRange(0.0, 1.0) };
        }
    }
}

fn main() -> ExitCode {
    let info = AppInfo {
        name: "cubes",
        about: "GL 3.3 core lit cube grid (one draw call per cube)",
        default_convergence: math::distance(EYE, CENTRE),
        extra: &[
            ("near", "0.1", "near plane distance"),
            ("far", "100", "far plane distance, or inf"),
            (
                "depth",
                "standard",
                "standard | reversed (glClipControl ZERO_TO_ONE, GREATER, clear 0)",
            ),
            (
                "orbit",
                "0",
                "degrees per frame the camera orbits the centre (a moving camera)",
            ),
            ("spin", "1", "cube spin speed factor (0: still cubes)"),
            weapon::OPTION,
        ],
        switches: &[],
    };
    holoapps::run::main(
        &info,
        Profile::Core33,
        Box::new(|gl: &Gl, o: &Options| {
            let mut c = Cubes::new(gl)?;
            c.near = o.extra["near"]
                .parse()
                .map_err(|_| "--near: expected a number".to_string())?;
            c.far = match o.extra["far"].as_str() {
                "inf" => None,
                f => Some(f.parse().map_err(|_| "--far: expected a number or inf".to_string())?),
            };
            let number = |name: &str| {
                o.extra[name]
                    .parse::<f32>()
                    .ok()
                    .filter(|x| x.is_finite())
                    .ok_or_else(|| format!("--{name}: expected a number"))
            };
            c.orbit = number("orbit")?;
            c.spin = number("spin")?;
            c.weapon = weapon::parse(&o.extra["weapon"])?;
            if weapon::alpha(c.weapon).is_some() {
                return Err(format!("--weapon {}: legacy only", o.extra["weapon"]));
            }
            c.reversed = match o.extra["depth"].as_str() {
                "standard" => false,
                "reversed" => true,
                d => return Err(format!("--depth: expected standard|reversed, got '{d}'")),
            };
            Ok(Box::new(c) as Box<dyn Scene>)
        }),
    )
}
