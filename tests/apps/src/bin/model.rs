//! `model`: GL 3.3 core textured, Blinn-Phong lit torus knot on a floor, drawn
//! indexed from one VAO/VBO/EBO. The camera matrices live in a std140 uniform
//! block, not in plain uniforms: the layer has to find the projection in a UBO.
use holoapps::cli::{AppInfo, Options};
use holoapps::gl::{self, Gl};
use holoapps::math::{self, Mat4};
use holoapps::platform::Profile;
use holoapps::scene::{Scene, View, seconds};
use holoapps::shader;
use std::process::ExitCode;

const EYE: [f32; 3] = [0.0, 2.5, 8.0];
const CENTRE: [f32; 3] = [0.0, 0.0, 0.0];
const FLOOR_Y: f32 = -2.2;
/// Torus-knot resolution: segments along the curve and around the tube.
const SEGS: usize = 240;
const SIDES: usize = 20;

const VS: &str = r#"#version 330 core
layout (location = 0) in vec3 aPos;
layout (location = 1) in vec3 aNormal;
layout (location = 2) in vec2 aUV;
layout (std140) uniform Camera {
    mat4 projection;
    mat4 view;
};
uniform mat4 model;
out vec3 FragPos;
out vec3 Normal;
out vec2 UV;
void main() {
    vec4 world = model * vec4(aPos, 1.0);
    FragPos = world.xyz;
    Normal = mat3(transpose(inverse(model))) * aNormal;
    UV = aUV;
    gl_Position = projection * view * world;
}
"#;

const FS: &str = r#"#version 330 core
in vec3 FragPos;
in vec3 Normal;
in vec2 UV;
uniform sampler2D tex;
uniform vec3 lightPos;
uniform vec3 viewPos;
uniform vec3 tint;
out vec4 FragColor;
void main() {
    vec3 albedo = texture(tex, UV).rgb * tint;
    vec3 n = normalize(Normal);
    vec3 l = normalize(lightPos - FragPos);
    vec3 h = normalize(l + normalize(viewPos - FragPos));
    float diff = max(dot(n, l), 0.0);
    float spec = pow(max(dot(n, h), 0.0), 48.0);
    FragColor = vec4(albedo * (0.2 + 0.8 * diff) + vec3(0.5) * spec, 1.0);
}
"#;

/// Deterministic integer hash to [0, 1) for the noise texture.
fn hash(x: u32, y: u32) -> f32 {
    let mut h = x.wrapping_mul(0x8DA6_B343) ^ y.wrapping_mul(0xD816_3841) ^ 0x9E37_79B9;
    h ^= h >> 13;
    h = h.wrapping_mul(0x2C1B_3C6D);
    h ^= h >> 16;
    (h & 0xFFFF) as f32 / 65536.0
}

/// 256x256 RGBA: an 8x8 checker modulated by smoothed value noise, so the
/// mip chain actually differs from level to level.
fn texture_pixels() -> Vec<u8> {
    const N: u32 = 256;
    let mut px = Vec::with_capacity((N * N * 4) as usize);
    for y in 0..N {
        for x in 0..N {
            let (fx, fy) = (x as f32 / 16.0, y as f32 / 16.0);
            let (ix, iy) = (fx as u32, fy as u32);
            let (tx, ty) = (fx.fract(), fy.fract());
            let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t * t * (3.0 - 2.0 * t);
            let noise = lerp(
                lerp(hash(ix, iy), hash(ix + 1, iy), tx),
                lerp(hash(ix, iy + 1), hash(ix + 1, iy + 1), tx),
                ty,
            );
            let check = if ((x / 32) + (y / 32)) % 2 == 0 { 1.0 } else { 0.55 };
            let v = check * (0.6 + 0.4 * noise);
            px.extend_from_slice(&[
                (255.0 * v) as u8,
                (255.0 * v * 0.85) as u8,
                (255.0 * v * 0.6) as u8,
                255,
            ]);
        }
    }
    px
}

/// (2,3) torus knot: point on the centre curve at parameter `t`.
fn knot(t: f32) -> [f32; 3] {
    let r = 2.0 + (3.0 * t).cos();
    [
        0.8 * r * (2.0 * t).cos(),
        0.8 * r * (2.0 * t).sin(),
        -0.8 * (3.0 * t).sin(),
    ]
}

/// Interleaved pos/normal/uv vertices and u32 indices: the knot's tube first,
/// then a floor quad. Returns (vertices, indices, knot index count).
fn meshes() -> (Vec<f32>, Vec<u32>, usize) {
    let (mut v, mut idx) = (Vec::new(), Vec::new());
    let tau = std::f32::consts::TAU;
    let sub = |a: [f32; 3], b: [f32; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let norm = |a: [f32; 3]| {
        let l = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
        [a[0] / l, a[1] / l, a[2] / l]
    };
    for i in 0..=SEGS {
        let t = i as f32 / SEGS as f32 * tau;
        let (e, c) = (1e-3, knot(t));
        let (a, b) = (knot(t - e), knot(t + e));
        // Frenet frame from central differences (the knot's curvature never vanishes).
        let tan = norm(sub(b, a));
        let nrm = norm(sub(sub(b, c), sub(c, a)));
        let bin = [
            tan[1] * nrm[2] - tan[2] * nrm[1],
            tan[2] * nrm[0] - tan[0] * nrm[2],
            tan[0] * nrm[1] - tan[1] * nrm[0],
        ];
        for j in 0..=SIDES {
            let (s, co) = (j as f32 / SIDES as f32 * tau).sin_cos();
            let n: [f32; 3] = std::array::from_fn(|k| co * nrm[k] + s * bin[k]);
            v.extend((0..3).map(|k| c[k] + 0.38 * n[k]));
            v.extend(n);
            v.extend([i as f32 / SEGS as f32 * 12.0, j as f32 / SIDES as f32]);
        }
    }
    let ring = (SIDES + 1) as u32;
    for i in 0..SEGS as u32 {
        for j in 0..SIDES as u32 {
            let (a, b) = (i * ring + j, (i + 1) * ring + j);
            idx.extend([a, a + 1, b, a + 1, b + 1, b]);
        }
    }
    let knot_count = idx.len();
    let base = (v.len() / 8) as u32;
    for (x, z) in [(-7.0f32, 7.0f32), (7.0, 7.0), (7.0, -7.0), (-7.0, -7.0)] {
        v.extend([x, FLOOR_Y, z, 0.0, 1.0, 0.0, x / 2.0, z / 2.0]);
    }
    idx.extend([0, 1, 2, 0, 2, 3].map(|k| base + k));
    (v, idx, knot_count)
}

struct Model {
    prog: u32,
    vao: u32,
    ubo: u32,
    tex: u32,
    knot_count: usize,
    loc: [i32; 5],
}

impl Model {
    fn new(gl: &Gl) -> Result<Self, String> {
        let prog = shader::program(gl, VS, FS)?;
        let loc = ["model", "tex", "lightPos", "viewPos", "tint"].map(|n| shader::uniform(gl, prog, n));
        let (verts, idx, knot_count) = meshes();
        let (mut vao, mut bufs, mut ubo, mut tex) = (0, [0u32; 2], 0, 0);
        unsafe {
            let block = gl.GetUniformBlockIndex(prog, c"Camera".as_ptr());
            if block == gl::INVALID_INDEX {
                return Err("uniform block Camera not found".into());
            }
            gl.UniformBlockBinding(prog, block, 0);
            gl.GenBuffers(1, &mut ubo);
            gl.BindBuffer(gl::UNIFORM_BUFFER, ubo);
            gl.BufferData(gl::UNIFORM_BUFFER, 128, std::ptr::null(), gl::DYNAMIC_DRAW);
            gl.BindBufferBase(gl::UNIFORM_BUFFER, 0, ubo);

            gl.GenVertexArrays(1, &mut vao);
            gl.BindVertexArray(vao);
            gl.GenBuffers(2, bufs.as_mut_ptr());
            gl.BindBuffer(gl::ARRAY_BUFFER, bufs[0]);
            let bytes = std::mem::size_of_val(verts.as_slice()) as isize;
            gl.BufferData(gl::ARRAY_BUFFER, bytes, verts.as_ptr().cast(), gl::STATIC_DRAW);
            gl.BindBuffer(gl::ELEMENT_ARRAY_BUFFER, bufs[1]);
            let bytes = std::mem::size_of_val(idx.as_slice()) as isize;
            gl.BufferData(gl::ELEMENT_ARRAY_BUFFER, bytes, idx.as_ptr().cast(), gl::STATIC_DRAW);
            for (attr, (size, offset)) in [(3, 0), (3, 3), (2, 6)].into_iter().enumerate() {
                let ptr = (offset * 4) as *const std::ffi::c_void;
                gl.VertexAttribPointer(attr as u32, size, gl::FLOAT, gl::FALSE, 8 * 4, ptr);
                gl.EnableVertexAttribArray(attr as u32);
            }
            gl.BindVertexArray(0);

            gl.GenTextures(1, &mut tex);
            gl.BindTexture(gl::TEXTURE_2D, tex);
            let px = texture_pixels();
            let rgba = gl::RGBA as i32;
            gl.TexImage2D(
                gl::TEXTURE_2D,
                0,
                rgba,
                256,
                256,
                0,
                gl::RGBA,
                gl::UNSIGNED_BYTE,
                px.as_ptr().cast(),
            );
            gl.GenerateMipmap(gl::TEXTURE_2D);
            gl.TexParameteri(gl::TEXTURE_2D, gl::TEXTURE_MIN_FILTER, gl::LINEAR_MIPMAP_LINEAR as i32);
            gl.TexParameteri(gl::TEXTURE_2D, gl::TEXTURE_MAG_FILTER, gl::LINEAR as i32);
            gl.TexParameteri(gl::TEXTURE_2D, gl::TEXTURE_WRAP_S, gl::REPEAT as i32);
            gl.TexParameteri(gl::TEXTURE_2D, gl::TEXTURE_WRAP_T, gl::REPEAT as i32);
        }
        Ok(Model {
            prog,
            vao,
            ubo,
            tex,
            knot_count,
            loc,
        })
    }

    fn draw(&self, gl: &Gl, model: &Mat4, tint: [f32; 3], count: usize, first: usize) {
        unsafe {
            gl.UniformMatrix4fv(self.loc[0], 1, gl::FALSE, model.as_ptr());
            gl.Uniform3f(self.loc[4], tint[0], tint[1], tint[2]);
            let offset = (first * 4) as *const std::ffi::c_void;
            gl.DrawElements(gl::TRIANGLES, count as i32, gl::UNSIGNED_INT, offset);
        }
    }
}

impl Scene for Model {
    fn render(&mut self, gl: &Gl, frame: u64, v: &View) {
        let t = seconds(frame);
        let p = v.projection(math::perspective(45f32.to_radians(), v.aspect(), 0.1, 100.0));
        let view = math::look_at(EYE, CENTRE, [0.0, 1.0, 0.0]);
        unsafe {
            gl.Viewport(v.viewport[0], v.viewport[1], v.viewport[2], v.viewport[3]);
            gl.ClearColor(0.08, 0.09, 0.12, 1.0);
            gl.Enable(gl::DEPTH_TEST);
            gl.Enable(gl::CULL_FACE);
            gl.Clear(gl::COLOR_BUFFER_BIT | gl::DEPTH_BUFFER_BIT);
            // Every view rewrites the block: projection at offset 0, view at 64 (std140).
            gl.BindBuffer(gl::UNIFORM_BUFFER, self.ubo);
            gl.BufferSubData(gl::UNIFORM_BUFFER, 0, 64, p.as_ptr().cast());
            gl.BufferSubData(gl::UNIFORM_BUFFER, 64, 64, view.as_ptr().cast());
            gl.UseProgram(self.prog);
            gl.ActiveTexture(gl::TEXTURE0);
            gl.BindTexture(gl::TEXTURE_2D, self.tex);
            gl.Uniform1i(self.loc[1], 0);
            gl.Uniform3f(self.loc[2], 4.0, 6.0, 5.0);
            gl.Uniform3f(self.loc[3], EYE[0], EYE[1], EYE[2]);
            gl.BindVertexArray(self.vao);
        }
        let spin = math::mul(
            &math::rotate(t * 0.7, [0.0, 1.0, 0.0]),
            &math::rotate(0.5, [1.0, 0.0, 0.0]),
        );
        self.draw(gl, &spin, [1.0, 0.9, 0.9], self.knot_count, 0);
        self.draw(gl, &math::IDENTITY, [0.6, 0.7, 0.9], 6, self.knot_count);
    }
}

fn main() -> ExitCode {
    let info = AppInfo {
        name: "model",
        about: "GL 3.3 core textured (mipmapped), Blinn-Phong lit torus knot; indexed draws, camera matrices in a std140 UBO",
        default_convergence: math::distance(EYE, CENTRE),
        extra: &[],
        switches: &[],
    };
    holoapps::run::main(
        &info,
        Profile::Core33,
        Box::new(|gl: &Gl, _: &Options| Ok(Box::new(Model::new(gl)?) as Box<dyn Scene>)),
    )
}
