//! `ssao`: GL 3.3 core, LearnOpenGL "SSAO". Four passes, each into its own
//! FBO except the last: a VIEW-space G-buffer (position/normal RGBA16F,
//! albedo RGBA8, depth24), the SSAO pass (32-sample hemisphere kernel, 4x4
//! rotation-noise texture, samples re-projected to the screen with the
//! `projection` uniform), a 4x4 blur, and Blinn-Phong lighting with ambient
//! occlusion to the default framebuffer. The SSAO pass re-projects into the
//! G-buffer it reads, so in view i it must use the same sheared projection P'_i
//! as the G-buffer pass; view-space positions themselves do not depend on P.
use holoapps::cli::{AppInfo, Options};
use holoapps::gl::{self, Gl};
use holoapps::math;
use holoapps::multipass::{self as mp, Attachment, Output};
use holoapps::platform::Profile;
use holoapps::scene::{Scene, View, seconds};
use holoapps::shader;
use std::process::ExitCode;

const KERNEL: usize = 32;

const GBUFFER_VS: &str = r#"#version 330 core
layout (location = 0) in vec3 aPos;
layout (location = 1) in vec3 aNormal;
uniform mat4 projection;
uniform mat4 view;
uniform mat4 model;
out vec3 FragPos;
out vec3 Normal;
void main() {
    vec4 viewPos = view * model * vec4(aPos, 1.0);
    FragPos = viewPos.xyz;
    Normal = mat3(transpose(inverse(view * model))) * aNormal;
    gl_Position = projection * viewPos;
}
"#;

const GBUFFER_FS: &str = r#"#version 330 core
layout (location = 0) out vec4 gPosition;
layout (location = 1) out vec4 gNormal;
layout (location = 2) out vec4 gAlbedo;
in vec3 FragPos;
in vec3 Normal;
uniform vec3 objectColor;
void main() {
    gPosition = vec4(FragPos, 1.0);  // w = 0 (clear) marks the background
    gNormal = vec4(normalize(Normal), 0.0);
    gAlbedo = vec4(objectColor, 1.0);
}
"#;

const SSAO_FS: &str = r#"#version 330 core
in vec2 UV;
uniform sampler2D gPosition;
uniform sampler2D gNormal;
uniform sampler2D texNoise;
uniform vec3 samples[32];
uniform mat4 projection;
uniform vec2 noiseScale;
out float FragColor;
const float radius = 1.0;
const float bias = 0.025;
void main() {
    vec4 pos = texture(gPosition, UV);
    if (pos.w == 0.0) {
        FragColor = 1.0;
        return;
    }
    vec3 normal = normalize(texture(gNormal, UV).rgb);
    vec3 randomVec = normalize(texture(texNoise, UV * noiseScale).xyz);
    vec3 tangent = normalize(randomVec - normal * dot(randomVec, normal));
    mat3 TBN = mat3(tangent, cross(normal, tangent), normal);
    float occlusion = 0.0;
    for (int i = 0; i < 32; ++i) {
        vec3 samplePos = pos.xyz + TBN * samples[i] * radius;
        // View space -> clip -> NDC -> texture coordinates of the G-buffer.
        vec4 offset = projection * vec4(samplePos, 1.0);
        offset.xyz = offset.xyz / offset.w * 0.5 + 0.5;
        float sampleDepth = texture(gPosition, offset.xy).z;
        float rangeCheck = smoothstep(0.0, 1.0, radius / abs(pos.z - sampleDepth));
        occlusion += (sampleDepth >= samplePos.z + bias ? 1.0 : 0.0) * rangeCheck;
    }
    FragColor = 1.0 - occlusion / 32.0;
}
"#;

const BLUR_FS: &str = r#"#version 330 core
in vec2 UV;
uniform sampler2D ssaoInput;
out float FragColor;
void main() {
    // 4x4 box: exactly undoes the 4x4 noise tiling.
    vec2 texel = 1.0 / vec2(textureSize(ssaoInput, 0));
    float r = 0.0;
    for (int x = -2; x < 2; ++x)
        for (int y = -2; y < 2; ++y)
            r += texture(ssaoInput, UV + vec2(x, y) * texel).r;
    FragColor = r / 16.0;
}
"#;

const LIGHT_FS: &str = r#"#version 330 core
in vec2 UV;
uniform sampler2D gPosition;
uniform sampler2D gNormal;
uniform sampler2D gAlbedo;
uniform sampler2D ssao;
uniform vec3 lightPos;  // view space
out vec4 FragColor;
void main() {
    vec4 pos = texture(gPosition, UV);
    if (pos.w == 0.0) {
        FragColor = vec4(0.1, 0.12, 0.18, 1.0);
        return;
    }
    vec3 n = normalize(texture(gNormal, UV).rgb);
    vec3 albedo = texture(gAlbedo, UV).rgb;
    float ao = texture(ssao, UV).r;
    vec3 l = normalize(lightPos - pos.xyz);
    vec3 h = normalize(l - normalize(pos.xyz));  // the eye is the view-space origin
    float diff = max(dot(n, l), 0.0);
    float spec = pow(max(dot(n, h), 0.0), 32.0);
    vec3 c = albedo * (0.6 * ao * ao + 0.45 * diff) + vec3(0.25) * spec;
    FragColor = vec4(min(c, vec3(1.0)), 1.0);
}
"#;

/// Deterministic integer hash to [0, 1): kernel and noise are the same every run.
fn rand(i: u32) -> f32 {
    let mut h = i.wrapping_mul(0x9E37_79B9) ^ 0x85EB_CA6B;
    h ^= h >> 15;
    h = h.wrapping_mul(0x2C1B_3C6D);
    h ^= h >> 12;
    h = h.wrapping_mul(0x297A_2D39);
    h ^= h >> 15;
    (h & 0xFF_FFFF) as f32 / 16_777_216.0
}

/// Hemisphere samples (z >= 0), denser near the centre like LearnOpenGL's.
fn kernel() -> Vec<f32> {
    let mut v = Vec::with_capacity(KERNEL * 3);
    for i in 0..KERNEL {
        let r = |k: u32| rand(i as u32 * 4 + k);
        let s = [r(0) * 2.0 - 1.0, r(1) * 2.0 - 1.0, r(2)];
        let len = (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]).sqrt().max(1e-4);
        let f = i as f32 / KERNEL as f32;
        let scale = r(3) * (0.1 + 0.9 * f * f) / len;
        v.extend(s.map(|c| c * scale));
    }
    v
}

/// 4x4 random rotations around z (tangent-space), tiled over the screen.
fn noise() -> Vec<f32> {
    (0..16u32)
        .flat_map(|i| [rand(1000 + 2 * i) * 2.0 - 1.0, rand(1001 + 2 * i) * 2.0 - 1.0, 0.0])
        .collect()
}

struct Ssao {
    out: Output,
    progs: [u32; 4],
    cube: u32,
    quad: u32,
    /// G-buffer, SSAO, blur
    fbos: [u32; 3],
    /// gPosition, gNormal, gAlbedo, ssao, blurred ssao, noise
    tex: [u32; 6],
    /// G-buffer: projection, view, model, objectColor
    gloc: [i32; 4],
    /// SSAO: gPosition, gNormal, texNoise, samples, projection, noiseScale
    sloc: [i32; 6],
    /// blur: ssaoInput; lighting: gPosition, gNormal, gAlbedo, ssao, lightPos
    bloc: i32,
    lloc: [i32; 5],
}

impl Ssao {
    fn new(gl: &Gl, o: &Options) -> Result<Self, String> {
        let out = Output::new(o.size);
        let size = out.size();
        let progs = [
            shader::program(gl, GBUFFER_VS, GBUFFER_FS)?,
            shader::program(gl, mp::QUAD_VS, SSAO_FS)?,
            shader::program(gl, mp::QUAD_VS, BLUR_FS)?,
            shader::program(gl, mp::QUAD_VS, LIGHT_FS)?,
        ];
        let gloc = ["projection", "view", "model", "objectColor"].map(|n| shader::uniform(gl, progs[0], n));
        let snames = [
            "gPosition",
            "gNormal",
            "texNoise",
            "samples",
            "projection",
            "noiseScale",
        ];
        let sloc = snames.map(|n| shader::uniform(gl, progs[1], n));
        let bloc = shader::uniform(gl, progs[2], "ssaoInput");
        let lloc = ["gPosition", "gNormal", "gAlbedo", "ssao", "lightPos"].map(|n| shader::uniform(gl, progs[3], n));
        let null = None;
        let tex = [
            mp::texture(gl, gl::RGBA16F, size, gl::RGBA, gl::FLOAT, gl::NEAREST, null),
            mp::texture(gl, gl::RGBA16F, size, gl::RGBA, gl::FLOAT, gl::NEAREST, null),
            mp::texture(gl, gl::RGBA8, size, gl::RGBA, gl::UNSIGNED_BYTE, gl::NEAREST, null),
            mp::texture(gl, gl::R8, size, gl::RED, gl::UNSIGNED_BYTE, gl::NEAREST, null),
            mp::texture(gl, gl::R8, size, gl::RED, gl::UNSIGNED_BYTE, gl::NEAREST, null),
            mp::texture(gl, gl::RGBA16F, (4, 4), gl::RGB, gl::FLOAT, gl::NEAREST, Some(&noise())),
        ];
        unsafe {
            // The noise texture (still bound) tiles over the screen.
            gl.TexParameteri(gl::TEXTURE_2D, gl::TEXTURE_WRAP_S, gl::REPEAT as i32);
            gl.TexParameteri(gl::TEXTURE_2D, gl::TEXTURE_WRAP_T, gl::REPEAT as i32);
        }
        let depth = mp::renderbuffer(gl, gl::DEPTH_COMPONENT24, 0, size);
        let t = |i: usize| Attachment::Texture(tex[i]);
        let fbos = [
            mp::framebuffer(
                gl,
                "G-buffer",
                &[t(0), t(1), t(2)],
                Some(Attachment::Renderbuffer(depth)),
            )?,
            mp::framebuffer(gl, "SSAO", &[t(3)], None)?,
            mp::framebuffer(gl, "SSAO blur", &[t(4)], None)?,
        ];
        Ok(Ssao {
            out,
            progs,
            cube: shader::pos_normal_vao(gl, &shader::cube_vertices()),
            quad: mp::quad_vao(gl),
            fbos,
            tex,
            gloc,
            sloc,
            bloc,
            lloc,
        })
    }
}

impl Scene for Ssao {
    fn render(&mut self, gl: &Gl, frame: u64, v: &View) {
        let target = self.out.begin(gl, v);
        let (w, h) = self.out.size();
        let (p, view) = mp::camera((w, h));
        // View i's projection, for the G-buffer AND the SSAO re-projection.
        let p = v.projection(p);
        let light = math::mul(&view, &math::translate(-3.0, 6.0, 4.0));
        let light = [light[12], light[13], light[14]];
        let (g, s, l) = (self.gloc, self.sloc, self.lloc);
        unsafe {
            gl.Viewport(0, 0, w, h);
            // 1: view-space G-buffer.
            gl.BindFramebuffer(gl::FRAMEBUFFER, self.fbos[0]);
            gl.ClearColor(0.0, 0.0, 0.0, 0.0);
            gl.Enable(gl::DEPTH_TEST);
            gl.Enable(gl::CULL_FACE);
            gl.Clear(gl::COLOR_BUFFER_BIT | gl::DEPTH_BUFFER_BIT);
            gl.UseProgram(self.progs[0]);
            mp::set_mat4(gl, g[0], &p);
            mp::set_mat4(gl, g[1], &view);
            gl.BindVertexArray(self.cube);
            mp::draw_objects(gl, &mp::objects(seconds(frame)), g[2], g[3]);
            gl.Disable(gl::DEPTH_TEST);

            // 2: SSAO, re-projecting kernel samples with `projection`.
            gl.BindFramebuffer(gl::FRAMEBUFFER, self.fbos[1]);
            gl.Clear(gl::COLOR_BUFFER_BIT);
            gl.UseProgram(self.progs[1]);
            mp::bind_texture(gl, 0, self.tex[0], s[0]);
            mp::bind_texture(gl, 1, self.tex[1], s[1]);
            mp::bind_texture(gl, 2, self.tex[5], s[2]);
            gl.Uniform3fv(s[3], KERNEL as i32, kernel().as_ptr());
            mp::set_mat4(gl, s[4], &p);
            gl.Uniform2f(s[5], w as f32 / 4.0, h as f32 / 4.0);
            mp::draw_quad(gl, self.quad);

            // 3: blur.
            gl.BindFramebuffer(gl::FRAMEBUFFER, self.fbos[2]);
            gl.Clear(gl::COLOR_BUFFER_BIT);
            gl.UseProgram(self.progs[2]);
            mp::bind_texture(gl, 0, self.tex[3], self.bloc);
            mp::draw_quad(gl, self.quad);

            // 4: lighting with AO to the default framebuffer.
            gl.BindFramebuffer(gl::FRAMEBUFFER, target);
            gl.ClearColor(0.0, 0.0, 0.0, 1.0);
            gl.Clear(gl::COLOR_BUFFER_BIT | gl::DEPTH_BUFFER_BIT);
            gl.UseProgram(self.progs[3]);
            for (unit, tex) in [self.tex[0], self.tex[1], self.tex[2], self.tex[4]]
                .into_iter()
                .enumerate()
            {
                mp::bind_texture(gl, unit as u32, tex, l[unit]);
            }
            mp::set_vec3(gl, l[4], light);
            mp::draw_quad(gl, self.quad);
        }
        self.out.end(gl, v);
    }
}

fn main() -> ExitCode {
    let info = AppInfo {
        name: "ssao",
        about: "GL 3.3 core SSAO: view-space G-buffer, 32-sample SSAO re-projected with `projection`, 4x4 blur, lighting pass",
        default_convergence: math::distance(mp::EYE, mp::CENTRE),
        extra: &[],
        switches: &[],
    };
    holoapps::run::main(
        &info,
        Profile::Core33,
        Box::new(|gl: &Gl, o: &Options| Ok(Box::new(Ssao::new(gl, o)?) as Box<dyn Scene>)),
    )
}
