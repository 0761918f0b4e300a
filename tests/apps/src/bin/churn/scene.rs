//! `churn`'s scene: what the root context owns for the whole run, and what each context
//! B creates, draws with and deletes.
use holoapps::gl::{self, Gl};
use holoapps::math::{self, Mat4};
use holoapps::multipass::{self, Attachment};
use holoapps::scene::seconds;
use holoapps::shader;

const FS: &str = r#"#version 330 core
in vec3 Normal;
in vec2 Uv;
uniform sampler2D checker;
uniform sampler2D detail;
uniform vec3 tint;
uniform vec3 lightDir;
out vec4 FragColor;
void main() {
    float diff = max(dot(normalize(Normal), normalize(lightDir)), 0.0);
    vec3 c = texture(checker, Uv).rgb * texture(detail, Uv * 2.0).rgb * tint;
    FragColor = vec4((0.25 + 0.75 * diff) * c, 1.0);
}
"#;

/// Full-screen pass: the offscreen image with a vignette.
const POST_FS: &str = r#"#version 330 core
in vec2 UV;
uniform sampler2D scene;
out vec4 FragColor;
void main() {
    vec2 d = UV - 0.5;
    FragColor = vec4(texture(scene, UV).rgb * (1.0 - 0.8 * dot(d, d)), 1.0);
}
"#;

const EYE: [f32; 3] = [0.0, 2.5, 6.0];

/// What the root context owns for the whole run (all shared objects).
pub struct Root {
    checker: u32,
    cube_vbo: u32,
}

impl Root {
    pub fn new(gl: &Gl) -> Root {
        let mut cube_vbo = 0;
        let verts = shader::cube_vertices();
        unsafe {
            gl.GenBuffers(1, &mut cube_vbo);
            gl.BindBuffer(gl::ARRAY_BUFFER, cube_vbo);
            let bytes = std::mem::size_of_val(verts.as_slice()) as isize;
            gl.BufferData(gl::ARRAY_BUFFER, bytes, verts.as_ptr().cast(), gl::STATIC_DRAW);
            gl.BindBuffer(gl::ARRAY_BUFFER, 0);
        }
        Root {
            checker: pattern_texture(gl, 64, 8, [[240, 200, 60], [40, 90, 200]], gl::NEAREST),
            cube_vbo,
        }
    }
}

/// Two-colour `n`x`n` checker with `cell`-texel squares, RGBA8, repeating, no mipmaps.
fn pattern_texture(gl: &Gl, n: usize, cell: usize, colours: [[u8; 3]; 2], filter: u32) -> u32 {
    let px: Vec<f32> = (0..n * n)
        .flat_map(|i| {
            let c = colours[((i % n) / cell + (i / n) / cell) % 2];
            [c[0] as f32 / 255.0, c[1] as f32 / 255.0, c[2] as f32 / 255.0, 1.0]
        })
        .collect();
    let size = (n as i32, n as i32);
    let tex = multipass::texture(gl, gl::RGBA8, size, gl::RGBA, gl::FLOAT, filter, Some(&px));
    unsafe {
        gl.TexParameteri(gl::TEXTURE_2D, gl::TEXTURE_WRAP_S, gl::REPEAT as i32);
        gl.TexParameteri(gl::TEXTURE_2D, gl::TEXTURE_WRAP_T, gl::REPEAT as i32);
        gl.BindTexture(gl::TEXTURE_2D, 0);
    }
    tex
}

/// Offscreen colour texture (RGBA8, linear) and depth renderbuffer (DEPTH24); the colour
/// texture is `colour` when another context made it.
fn target(gl: &Gl, size: (i32, i32), colour: Option<u32>, reuse_name: bool) -> (u32, u32) {
    let colour = colour.unwrap_or_else(|| colour_target(gl, size, reuse_name));
    let depth = multipass::renderbuffer(gl, gl::DEPTH_COMPONENT24, 0, size);
    unsafe { gl.BindRenderbuffer(gl::RENDERBUFFER, 0) };
    (colour, depth)
}

/// The offscreen colour texture (RGBA8, linear), made with glGenTextures + glBindTexture +
/// glTexImage2D. With `reuse_name`, a cube map is made and deleted first, so the colour
/// texture gets a name that was a cube map's a moment ago (GL reuses freed names; a warning
/// on stderr says when it did not).
pub fn colour_target(gl: &Gl, size: (i32, i32), reuse_name: bool) -> u32 {
    let cube = if reuse_name { cube_map(gl) } else { 0 };
    let colour = multipass::texture(gl, gl::RGBA8, size, gl::RGBA, gl::UNSIGNED_BYTE, gl::LINEAR, None);
    unsafe { gl.BindTexture(gl::TEXTURE_2D, 0) };
    if reuse_name && colour != cube {
        eprintln!("warning: render target got texture name {colour}, not the deleted cube map's {cube}");
    }
    colour
}

/// A 4x4 RGBA8 cube map, created and deleted; returns its (now free) name.
fn cube_map(gl: &Gl) -> u32 {
    let mut cube = 0;
    unsafe {
        gl.GenTextures(1, &mut cube);
        gl.BindTexture(gl::TEXTURE_CUBE_MAP, cube);
        for face in 0..6 {
            let (f, ty) = (gl::TEXTURE_CUBE_MAP_POSITIVE_X + face, gl::UNSIGNED_BYTE);
            gl.TexImage2D(f, 0, gl::RGBA8 as i32, 4, 4, 0, gl::RGBA, ty, std::ptr::null());
        }
        gl.BindTexture(gl::TEXTURE_CUBE_MAP, 0);
        gl.DeleteTextures(1, &cube);
    }
    cube
}

/// VAO of the root context's cube mesh: position (0) + normal (1), 6 floats a vertex.
fn cube_vao(gl: &Gl, vbo: u32) -> u32 {
    let vao = shader::pos_normal_vao_of(gl, vbo);
    unsafe {
        gl.BindVertexArray(0);
        gl.BindBuffer(gl::ARRAY_BUFFER, 0);
    }
    vao
}

/// Everything one context B creates. Uniform locations: projection, view, model, tint,
/// lightDir, checker, detail; then the post pass's `scene`.
pub struct Scene {
    prog: u32,
    post: u32,
    loc: [i32; 8],
    cube_vao: u32,
    quad: (u32, u32),
    detail: u32,
    sampler: u32,
    fbo: u32,
    pub target: (u32, u32),
}

impl Scene {
    /// `colour`: the offscreen colour texture when another context made it; `reuse_name`:
    /// else make it under a just-deleted cube map's name.
    pub fn new(
        gl: &Gl,
        root: &Root,
        (cycle, size): (u64, (u32, u32)),
        colour: Option<u32>,
        reuse_name: bool,
    ) -> Result<Scene, String> {
        let prog = shader::program(gl, shader::TEXTURED_CUBE_VS, FS)?;
        let post = shader::program(gl, multipass::QUAD_VS, POST_FS)?;
        let names = ["projection", "view", "model", "tint", "lightDir", "checker", "detail"];
        let l = names.map(|n| shader::uniform(gl, prog, n));
        let loc = [
            l[0],
            l[1],
            l[2],
            l[3],
            l[4],
            l[5],
            l[6],
            shader::uniform(gl, post, "scene"),
        ];
        // A different detail pattern per cycle: each context really draws its own texture.
        let shade = 255 - (cycle % 4) as u8 * 40;
        let detail = pattern_texture(gl, 8, 2, [[255, 255, 255], [shade, 255, shade]], gl::LINEAR);
        let mut sampler = 0;
        unsafe {
            gl.GenSamplers(1, &mut sampler);
            gl.SamplerParameteri(sampler, gl::TEXTURE_MIN_FILTER, gl::NEAREST as i32);
            gl.SamplerParameteri(sampler, gl::TEXTURE_MAG_FILTER, gl::NEAREST as i32);
        }
        let target = self::target(gl, (size.0 as i32, size.1 as i32), colour, reuse_name);
        let (colour, depth) = (Attachment::Texture(target.0), Attachment::Renderbuffer(target.1));
        let fbo = multipass::framebuffer(gl, "offscreen", &[colour], Some(depth))?;
        Ok(Scene {
            prog,
            post,
            loc,
            cube_vao: cube_vao(gl, root.cube_vbo),
            quad: multipass::quad(gl),
            detail,
            sampler,
            fbo,
            target,
        })
    }

    /// (model, tint) of each cube at time t: a tall pillar with five cubes turning round it.
    fn cubes(t: f32) -> Vec<(Mat4, [f32; 3])> {
        let pillar = math::scale(0.6, 2.4, 0.6);
        let mut v = vec![(math::mul(&math::rotate(-t, [0.0, 1.0, 0.0]), &pillar), [1.0; 3])];
        for i in 0..5 {
            let phi = t * 0.8 + i as f32 * std::f32::consts::TAU / 5.0;
            let m = math::mul(
                &math::translate(2.2 * phi.cos(), 0.3 * (i as f32 - 2.0), 2.2 * phi.sin()),
                &math::rotate(t * 1.5 + i as f32, [1.0, 0.5, 0.0]),
            );
            let m = math::mul(&m, &math::scale(0.7, 0.7, 0.7));
            v.push((m, [0.5 + 0.1 * i as f32, 0.9, 1.0 - 0.1 * i as f32]));
        }
        v
    }

    /// The cubes into the FBO with the camera, then its colour into framebuffer 0.
    pub fn render(&self, gl: &Gl, root: &Root, frame: u64, size: (u32, u32)) {
        let (w, h) = (size.0 as i32, size.1 as i32);
        let p = math::perspective(45f32.to_radians(), w as f32 / h as f32, 0.1, 100.0);
        let view = math::look_at(EYE, [0.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        unsafe {
            gl.BindFramebuffer(gl::FRAMEBUFFER, self.fbo);
            gl.Viewport(0, 0, w, h);
            gl.ClearColor(0.1, 0.12, 0.18, 1.0);
            gl.Enable(gl::DEPTH_TEST);
            gl.Enable(gl::CULL_FACE);
            gl.Clear(gl::COLOR_BUFFER_BIT | gl::DEPTH_BUFFER_BIT);
            gl.UseProgram(self.prog);
            multipass::set_mat4(gl, self.loc[0], &p);
            multipass::set_mat4(gl, self.loc[1], &view);
            multipass::set_vec3(gl, self.loc[4], [-0.5, 1.0, 0.3]);
            multipass::bind_texture(gl, 0, root.checker, self.loc[5]);
            gl.BindSampler(0, self.sampler);
            multipass::bind_texture(gl, 1, self.detail, self.loc[6]);
            gl.BindVertexArray(self.cube_vao);
            multipass::draw_objects(gl, &Scene::cubes(seconds(frame)), self.loc[2], self.loc[3]);
            gl.BindFramebuffer(gl::FRAMEBUFFER, 0);
            gl.Disable(gl::DEPTH_TEST);
            gl.Disable(gl::CULL_FACE);
            gl.UseProgram(self.post);
            gl.BindSampler(0, 0);
            multipass::bind_texture(gl, 0, self.target.0, self.loc[7]);
            multipass::draw_quad(gl, self.quad.0);
        }
    }

    /// Deletes the shared objects this context created, but for the FBO's attachments
    /// when `keep_target`. The FBO and the VAOs are per-context objects: they die with
    /// the context, as an app may rely on.
    pub fn delete(&self, gl: &Gl, keep_target: bool) {
        unsafe {
            gl.BindVertexArray(0);
            gl.UseProgram(0);
            gl.DeleteProgram(self.prog);
            gl.DeleteProgram(self.post);
            gl.DeleteBuffers(1, &self.quad.1);
            gl.DeleteSamplers(1, &self.sampler);
            gl.DeleteTextures(1, &self.detail);
            if !keep_target {
                gl.DeleteTextures(1, &self.target.0);
                gl.DeleteRenderbuffers(1, &self.target.1);
            }
        }
    }
}
