//! `bloom`: GL 3.3 core, LearnOpenGL "Bloom". The HDR scene (four coloured
//! point lights drawn as emissive cubes, intensities > 1) goes into an RGBA16F
//! FBO with two colour attachments written through MRT: the scene and its
//! bright parts. Ping-pong FBOs blur the bright parts with a separable
//! Gaussian, and a final pass tone-maps scene + bloom to the default
//! framebuffer. Only the scene pass uses the camera; blur and composite are
//! full-screen NDC passes and view-independent.
use holoapps::cli::{AppInfo, Options};
use holoapps::gl::{self, Gl};
use holoapps::math;
use holoapps::multipass::{self as mp, Attachment, Output};
use holoapps::platform::Profile;
use holoapps::scene::{Scene, View, seconds};
use holoapps::shader;
use std::process::ExitCode;

/// Blur passes (alternating horizontal / vertical), as in LearnOpenGL.
const BLUR_PASSES: usize = 10;

const LIGHTS: [([f32; 3], [f32; 3]); 4] = [
    ([0.0, 0.6, 1.5], [6.0, 5.0, 2.0]),
    ([-3.2, 2.2, -1.0], [8.0, 1.0, 1.0]),
    ([3.2, 1.8, -0.5], [1.0, 2.0, 9.0]),
    ([0.0, 3.6, -3.5], [1.0, 7.0, 1.5]),
];

const SCENE_FS: &str = r#"#version 330 core
layout (location = 0) out vec4 FragColor;
layout (location = 1) out vec4 BrightColor;
in vec3 FragPos;
in vec3 Normal;
uniform vec3 objectColor;
uniform vec3 emissive;  // non-zero for the light cubes
uniform vec3 lightPos[4];
uniform vec3 lightColor[4];
void main() {
    vec3 c = emissive;
    if (c == vec3(0.0)) {
        vec3 n = normalize(Normal);
        c = 0.04 * objectColor;
        for (int i = 0; i < 4; ++i) {
            vec3 d = lightPos[i] - FragPos;
            float diff = max(dot(n, normalize(d)), 0.0);
            c += objectColor * lightColor[i] * diff / (1.0 + dot(d, d));
        }
    }
    FragColor = vec4(c, 1.0);
    float brightness = dot(c, vec3(0.2126, 0.7152, 0.0722));
    BrightColor = vec4(brightness > 1.0 ? c : vec3(0.0), 1.0);
}
"#;

const BLUR_FS: &str = r#"#version 330 core
in vec2 UV;
uniform sampler2D image;
uniform bool horizontal;
out vec4 FragColor;
const float weight[5] = float[](0.227027, 0.1945946, 0.1216216, 0.054054, 0.016216);
void main() {
    vec2 step = (horizontal ? vec2(1.0, 0.0) : vec2(0.0, 1.0)) / vec2(textureSize(image, 0));
    vec3 r = texture(image, UV).rgb * weight[0];
    for (int i = 1; i < 5; ++i) {
        r += texture(image, UV + step * float(i)).rgb * weight[i];
        r += texture(image, UV - step * float(i)).rgb * weight[i];
    }
    FragColor = vec4(r, 1.0);
}
"#;

const FINAL_FS: &str = r#"#version 330 core
in vec2 UV;
uniform sampler2D scene;
uniform sampler2D bloomBlur;
uniform float exposure;
out vec4 FragColor;
void main() {
    vec3 hdr = texture(scene, UV).rgb + texture(bloomBlur, UV).rgb;
    vec3 mapped = vec3(1.0) - exp(-hdr * exposure);
    FragColor = vec4(pow(mapped, vec3(1.0 / 2.2)), 1.0);
}
"#;

struct Bloom {
    out: Output,
    progs: [u32; 3],
    cube: u32,
    quad: u32,
    hdr_fbo: u32,
    /// scene, bright parts
    hdr_tex: [u32; 2],
    ping_fbo: [u32; 2],
    ping_tex: [u32; 2],
    /// scene: projection, view, model, objectColor, emissive, lightPos, lightColor
    sloc: [i32; 7],
    /// blur: image, horizontal; final: scene, bloomBlur, exposure
    bloc: [i32; 2],
    floc: [i32; 3],
}

impl Bloom {
    fn new(gl: &Gl, o: &Options) -> Result<Self, String> {
        let out = Output::new(o.size);
        let size = out.size();
        let progs = [
            shader::program(gl, mp::SCENE_VS, SCENE_FS)?,
            shader::program(gl, mp::QUAD_VS, BLUR_FS)?,
            shader::program(gl, mp::QUAD_VS, FINAL_FS)?,
        ];
        let names = [
            "projection",
            "view",
            "model",
            "objectColor",
            "emissive",
            "lightPos",
            "lightColor",
        ];
        let sloc = names.map(|n| shader::uniform(gl, progs[0], n));
        let bloc = ["image", "horizontal"].map(|n| shader::uniform(gl, progs[1], n));
        let floc = ["scene", "bloomBlur", "exposure"].map(|n| shader::uniform(gl, progs[2], n));
        // LINEAR: the blur and composite sample between texels like LearnOpenGL.
        let hdr = || mp::texture(gl, gl::RGBA16F, size, gl::RGBA, gl::FLOAT, gl::LINEAR, None);
        let hdr_tex = [hdr(), hdr()];
        let ping_tex = [hdr(), hdr()];
        let depth = mp::renderbuffer(gl, gl::DEPTH_COMPONENT24, 0, size);
        let hdr_fbo = mp::framebuffer(
            gl,
            "HDR",
            &hdr_tex.map(Attachment::Texture),
            Some(Attachment::Renderbuffer(depth)),
        )?;
        let ping_fbo = [
            mp::framebuffer(gl, "ping", &[Attachment::Texture(ping_tex[0])], None)?,
            mp::framebuffer(gl, "pong", &[Attachment::Texture(ping_tex[1])], None)?,
        ];
        Ok(Bloom {
            out,
            progs,
            cube: shader::pos_normal_vao(gl, &shader::cube_vertices()),
            quad: mp::quad_vao(gl),
            hdr_fbo,
            hdr_tex,
            ping_fbo,
            ping_tex,
            sloc,
            bloc,
            floc,
        })
    }
}

impl Scene for Bloom {
    fn render(&mut self, gl: &Gl, frame: u64, v: &View) {
        let target = self.out.begin(gl, v);
        let (w, h) = self.out.size();
        let (p, view) = mp::camera((w, h));
        let s = self.sloc;
        let t = seconds(frame);
        unsafe {
            gl.Viewport(0, 0, w, h);
            // 1: HDR scene + bright parts (MRT), with view i's projection.
            gl.BindFramebuffer(gl::FRAMEBUFFER, self.hdr_fbo);
            gl.ClearColor(0.0, 0.0, 0.0, 1.0);
            gl.Enable(gl::DEPTH_TEST);
            gl.Enable(gl::CULL_FACE);
            gl.Clear(gl::COLOR_BUFFER_BIT | gl::DEPTH_BUFFER_BIT);
            gl.UseProgram(self.progs[0]);
            mp::set_mat4(gl, s[0], &v.projection(p));
            mp::set_mat4(gl, s[1], &view);
            let lights: Vec<_> = LIGHTS
                .iter()
                .enumerate()
                .map(|(i, (pos, col))| ([pos[0], pos[1] + 0.3 * (t * 2.0 + i as f32).sin(), pos[2]], *col))
                .collect();
            let pos: Vec<f32> = lights.iter().flat_map(|l| l.0).collect();
            let col: Vec<f32> = lights.iter().flat_map(|l| l.1).collect();
            gl.Uniform3fv(s[5], 4, pos.as_ptr());
            gl.Uniform3fv(s[6], 4, col.as_ptr());
            gl.BindVertexArray(self.cube);
            mp::set_vec3(gl, s[4], [0.0; 3]);
            mp::draw_objects(gl, &mp::objects(t), s[2], s[3]);
            for (pos, col) in &lights {
                mp::set_vec3(gl, s[4], *col);
                let m = math::mul(&math::translate(pos[0], pos[1], pos[2]), &math::scale(0.3, 0.3, 0.3));
                mp::draw_objects(gl, &[(m, [0.0; 3])], s[2], s[3]);
            }
            gl.Disable(gl::DEPTH_TEST);

            // 2: ping-pong Gaussian blur of the bright parts.
            gl.UseProgram(self.progs[1]);
            for i in 0..BLUR_PASSES {
                let horizontal = i % 2;
                gl.BindFramebuffer(gl::FRAMEBUFFER, self.ping_fbo[horizontal]);
                gl.Uniform1i(self.bloc[1], (horizontal == 0) as i32);
                let src = if i == 0 {
                    self.hdr_tex[1]
                } else {
                    self.ping_tex[1 - horizontal]
                };
                mp::bind_texture(gl, 0, src, self.bloc[0]);
                mp::draw_quad(gl, self.quad);
            }

            // 3: tone-mapped composite to the default framebuffer.
            gl.BindFramebuffer(gl::FRAMEBUFFER, target);
            gl.Clear(gl::COLOR_BUFFER_BIT | gl::DEPTH_BUFFER_BIT);
            gl.UseProgram(self.progs[2]);
            mp::bind_texture(gl, 0, self.hdr_tex[0], self.floc[0]);
            mp::bind_texture(gl, 1, self.ping_tex[(BLUR_PASSES - 1) % 2], self.floc[1]);
            gl.Uniform1f(self.floc[2], 1.0);
            mp::draw_quad(gl, self.quad);
        }
        self.out.end(gl, v);
    }
}

fn main() -> ExitCode {
    let info = AppInfo {
        name: "bloom",
        about: "GL 3.3 core HDR bloom: RGBA16F MRT scene FBO (scene + bright parts), ping-pong Gaussian blur FBOs, tone-mapped composite",
        default_convergence: math::distance(mp::EYE, mp::CENTRE),
        extra: &[],
        switches: &[],
    };
    holoapps::run::main(
        &info,
        Profile::Core33,
        Box::new(|gl: &Gl, o: &Options| Ok(Box::new(Bloom::new(gl, o)?) as Box<dyn Scene>)),
    )
}
