//! `asteroids`: GL 3.3 core draw-call overhead benchmark. Thousands of tiny
//! draws per frame, each preceded by its own glUniform* calls.
use holoapps::cli::{AppInfo, Options};
use holoapps::gl::{self, Gl};
use holoapps::math::{self, Mat4};
use holoapps::platform::Profile;
use holoapps::scene::{Scene, View, seconds};
use holoapps::shader;
use std::process::ExitCode;

const EYE: [f32; 3] = [0.0, 12.0, 30.0];
const CENTRE: [f32; 3] = [0.0, 0.0, 0.0];
/// Rock variants stored back to back in one VBO.
const VARIANTS: usize = 4;

const FS: &str = r#"#version 330 core
in vec3 Normal;
uniform vec3 colour;
out vec4 FragColor;
void main() {
    float diff = max(dot(normalize(Normal), normalize(vec3(0.5, 1.0, 0.3))), 0.0);
    FragColor = vec4((0.2 + 0.8 * diff) * colour, 1.0);
}
"#;

/// Deterministic pseudo-random value in [0, 1) (no rand crate, same every run).
fn hash(n: u32) -> f32 {
    let mut x = n.wrapping_mul(0x9E37_79B9) ^ 0x85EB_CA6B;
    x ^= x >> 15;
    x = x.wrapping_mul(0x2C1B_3C6D);
    x ^= x >> 12;
    (x & 0xFFFFFF) as f32 / 16_777_216.0
}

/// Octahedron with jittered corners, flat-shaded: 8 triangles.
fn rock(seed: u32) -> Vec<f32> {
    let j = |k: u32| 0.7 + 0.6 * hash(seed * 16 + k);
    let c = [
        [j(0), 0., 0.],
        [-j(1), 0., 0.],
        [0., j(2), 0.],
        [0., -j(3), 0.],
        [0., 0., j(4)],
        [0., 0., -j(5)],
    ];
    let mut v = Vec::with_capacity(8 * 3 * 6);
    for (x, y, z) in [
        (0, 2, 4),
        (2, 1, 4),
        (1, 3, 4),
        (3, 0, 4),
        (2, 0, 5),
        (1, 2, 5),
        (3, 1, 5),
        (0, 3, 5),
    ] {
        let (a, b, d) = (c[x], c[y], c[z]);
        let e1 = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let e2 = [d[0] - a[0], d[1] - a[1], d[2] - a[2]];
        let n = [
            e1[1] * e2[2] - e1[2] * e2[1],
            e1[2] * e2[0] - e1[0] * e2[2],
            e1[0] * e2[1] - e1[1] * e2[0],
        ];
        for p in [a, b, d] {
            v.extend_from_slice(&p);
            v.extend_from_slice(&n);
        }
    }
    v
}

struct Asteroids {
    prog: u32,
    vao: u32,
    loc: [i32; 4],
    draws: u32,
    /// `--deep`: the disc reaches from beside the camera to past the far plane.
    deep: bool,
}

impl Asteroids {
    fn new(gl: &Gl, o: &Options) -> Result<Self, String> {
        let draws = o.extra_u64("draws")? as u32;
        let prog = shader::program(gl, shader::LIT_MESH_VS, FS)?;
        let loc = ["projection", "view", "model", "colour"].map(|n| shader::uniform(gl, prog, n));
        let verts: Vec<f32> = (0..VARIANTS as u32).flat_map(rock).collect();
        let vao = shader::pos_normal_vao(gl, &verts);
        let deep = o.switches.contains("deep");
        Ok(Asteroids {
            prog,
            vao,
            loc,
            draws,
            deep,
        })
    }

    /// Rock `i` orbits the centre in a thick disc; inner rocks move faster. Deep: radii 2 to
    /// 110 (and sizes growing with them), so rocks pass a few units from the camera and others
    /// lie beyond the far plane.
    fn model(i: u32, t: f32, deep: bool) -> Mat4 {
        let r = if deep {
            2.0 + 108.0 * hash(i * 4).sqrt()
        } else {
            4.0 + 16.0 * hash(i * 4).sqrt()
        };
        let a = hash(i * 4 + 1) * std::f32::consts::TAU + t * 3.0 / r;
        let y = (hash(i * 4 + 2) - 0.5) * 3.0;
        // Deep rocks grow with their orbit, so far ones still cover pixels.
        let s = (0.08 + 0.25 * hash(i * 4 + 3)) * if deep { r / 6.0 } else { 1.0 };
        let m = math::mul(
            &math::translate(r * a.cos(), y, r * a.sin()),
            &math::rotate(t * 2.0 + i as f32, [1.0, 0.7, 0.2]),
        );
        math::mul(&m, &math::scale(s, s, s))
    }
}

impl Scene for Asteroids {
    fn render(&mut self, gl: &Gl, frame: u64, v: &View) {
        let t = seconds(frame);
        let p = v.projection(math::perspective(45f32.to_radians(), v.aspect(), 0.1, 100.0));
        let view = math::look_at(EYE, CENTRE, [0.0, 1.0, 0.0]);
        unsafe {
            gl.Viewport(v.viewport[0], v.viewport[1], v.viewport[2], v.viewport[3]);
            gl.ClearColor(0.02, 0.02, 0.08, 1.0);
            gl.Enable(gl::DEPTH_TEST);
            gl.Enable(gl::CULL_FACE);
            gl.Clear(gl::COLOR_BUFFER_BIT | gl::DEPTH_BUFFER_BIT);
            gl.UseProgram(self.prog);
            gl.UniformMatrix4fv(self.loc[0], 1, gl::FALSE, p.as_ptr());
            gl.UniformMatrix4fv(self.loc[1], 1, gl::FALSE, view.as_ptr());
            gl.BindVertexArray(self.vao);
            for i in 0..self.draws {
                let m = Self::model(i, t, self.deep);
                let g = 0.4 + 0.4 * hash(i * 7 + 5);
                gl.UniformMatrix4fv(self.loc[2], 1, gl::FALSE, m.as_ptr());
                gl.Uniform3f(self.loc[3], g + 0.15, g, g - 0.1);
                gl.DrawArrays(gl::TRIANGLES, (i as usize % VARIANTS * 24) as i32, 24);
            }
        }
    }

    fn finish(&mut self, frame_ms: &[f64]) {
        // The first frames include shader JIT and allocation warm-up.
        let mut ms: Vec<f64> = frame_ms.iter().skip(10).copied().collect();
        ms.sort_by(f64::total_cmp);
        let median = if ms.is_empty() { 0.0 } else { ms[ms.len() / 2] };
        eprintln!(
            "asteroids: frames={} draws_per_frame={} median_frame_ms={median:.3}",
            frame_ms.len(),
            self.draws
        );
    }
}

fn main() -> ExitCode {
    let info = AppInfo {
        name: "asteroids",
        about: "GL 3.3 core draw-call overhead benchmark (one glUniform + glDrawArrays per rock)",
        default_convergence: math::distance(EYE, CENTRE),
        extra: &[("draws", "5000", "rocks (draw calls) per frame")],
        switches: &[(
            "deep",
            "a disc from beside the camera to past the far plane (comfort figures)",
        )],
    };
    holoapps::run::main(
        &info,
        Profile::Core33,
        Box::new(|gl: &Gl, o: &Options| Ok(Box::new(Asteroids::new(gl, o)?) as Box<dyn Scene>)),
    )
}
