//! `msaa`: GL 3.3 core, LearnOpenGL "Anti Aliasing" (off-screen MSAA). The
//! lit scene goes into a 4x multisample FBO (RGBA8 + depth24 renderbuffers),
//! is resolved with glBlitFramebuffer into a single-sample FBO (RGBA8
//! texture), and a full-screen pass draws that texture to the default
//! framebuffer with a slight colour grade. `--blit-to-default` instead
//! resolves straight into framebuffer 0 with glBlitFramebuffer (no last draw).
//! Only the scene pass uses the camera.
use holoapps::cli::{AppInfo, Options};
use holoapps::gl::{self, Gl};
use holoapps::math;
use holoapps::multipass::{self as mp, Attachment, Output};
use holoapps::platform::Profile;
use holoapps::scene::{Scene, View, seconds};
use holoapps::shader;
use std::process::ExitCode;

const SAMPLES: i32 = 4;

const SCENE_FS: &str = r#"#version 330 core
in vec3 FragPos;
in vec3 Normal;
uniform vec3 objectColor;
uniform vec3 viewPos;
out vec4 FragColor;
void main() {
    vec3 n = normalize(Normal);
    vec3 l = normalize(vec3(-0.5, 1.0, 0.4));
    vec3 h = normalize(l + normalize(viewPos - FragPos));
    float diff = max(dot(n, l), 0.0);
    float spec = pow(max(dot(n, h), 0.0), 32.0);
    FragColor = vec4(objectColor * (0.25 + 0.75 * diff) + vec3(0.3) * spec, 1.0);
}
"#;

const POST_FS: &str = r#"#version 330 core
in vec2 UV;
uniform sampler2D screenTexture;
out vec4 FragColor;
void main() {
    // Warm grade: proves the image went through this pass, not a blit.
    vec3 c = texture(screenTexture, UV).rgb;
    FragColor = vec4(c * vec3(1.05, 1.0, 0.88) + vec3(0.02, 0.01, 0.0), 1.0);
}
"#;

struct Msaa {
    out: Output,
    blit_to_default: bool,
    scene: u32,
    post: u32,
    cube: u32,
    quad: u32,
    ms_fbo: u32,
    resolve_fbo: u32,
    resolved: u32,
    /// projection, view, model, objectColor, viewPos, screenTexture
    loc: [i32; 6],
}

impl Msaa {
    fn new(gl: &Gl, o: &Options) -> Result<Self, String> {
        let out = Output::new(o.size);
        let size = out.size();
        let scene = shader::program(gl, mp::SCENE_VS, SCENE_FS)?;
        let post = shader::program(gl, mp::QUAD_VS, POST_FS)?;
        let mut loc = [0; 6];
        for (l, n) in loc
            .iter_mut()
            .zip(["projection", "view", "model", "objectColor", "viewPos"])
        {
            *l = shader::uniform(gl, scene, n);
        }
        loc[5] = shader::uniform(gl, post, "screenTexture");
        let colour = mp::renderbuffer(gl, gl::RGBA8, SAMPLES, size);
        let depth = mp::renderbuffer(gl, gl::DEPTH_COMPONENT24, SAMPLES, size);
        let ms_fbo = mp::framebuffer(
            gl,
            "multisample",
            &[Attachment::Renderbuffer(colour)],
            Some(Attachment::Renderbuffer(depth)),
        )?;
        let resolved = mp::texture(gl, gl::RGBA8, size, gl::RGBA, gl::UNSIGNED_BYTE, gl::NEAREST, None);
        let resolve_fbo = mp::framebuffer(gl, "resolve", &[Attachment::Texture(resolved)], None)?;
        Ok(Msaa {
            out,
            blit_to_default: o.switches.contains("blit-to-default"),
            scene,
            post,
            cube: shader::pos_normal_vao(gl, &shader::cube_vertices()),
            quad: mp::quad_vao(gl),
            ms_fbo,
            resolve_fbo,
            resolved,
            loc,
        })
    }
}

impl Scene for Msaa {
    fn render(&mut self, gl: &Gl, frame: u64, v: &View) {
        let target = self.out.begin(gl, v);
        let (w, h) = self.out.size();
        let (p, view) = mp::camera((w, h));
        let l = self.loc;
        unsafe {
            // 1: the scene into the 4x MSAA FBO, with view i's projection.
            gl.BindFramebuffer(gl::FRAMEBUFFER, self.ms_fbo);
            gl.Viewport(0, 0, w, h);
            gl.ClearColor(0.1, 0.12, 0.18, 1.0);
            gl.Enable(gl::DEPTH_TEST);
            gl.Enable(gl::CULL_FACE);
            gl.Clear(gl::COLOR_BUFFER_BIT | gl::DEPTH_BUFFER_BIT);
            gl.UseProgram(self.scene);
            mp::set_mat4(gl, l[0], &v.projection(p));
            mp::set_mat4(gl, l[1], &view);
            mp::set_vec3(gl, l[4], mp::EYE);
            gl.BindVertexArray(self.cube);
            mp::draw_objects(gl, &mp::objects(seconds(frame)), l[2], l[3]);
            gl.Disable(gl::DEPTH_TEST);

            // 2: resolve, to the single-sample FBO or straight to framebuffer 0.
            let dest = if self.blit_to_default { target } else { self.resolve_fbo };
            gl.BindFramebuffer(gl::READ_FRAMEBUFFER, self.ms_fbo);
            gl.BindFramebuffer(gl::DRAW_FRAMEBUFFER, dest);
            gl.BlitFramebuffer(0, 0, w, h, 0, 0, w, h, gl::COLOR_BUFFER_BIT, gl::NEAREST);
            if !self.blit_to_default {
                // 3: full-screen pass to the default framebuffer.
                gl.BindFramebuffer(gl::FRAMEBUFFER, target);
                gl.Clear(gl::COLOR_BUFFER_BIT | gl::DEPTH_BUFFER_BIT);
                gl.UseProgram(self.post);
                mp::bind_texture(gl, 0, self.resolved, l[5]);
                mp::draw_quad(gl, self.quad);
            }
        }
        self.out.end(gl, v);
    }
}

fn main() -> ExitCode {
    let info = AppInfo {
        name: "msaa",
        about: "GL 3.3 core off-screen 4x MSAA: multisample FBO, glBlitFramebuffer resolve, full-screen pass",
        default_convergence: math::distance(mp::EYE, mp::CENTRE),
        extra: &[],
        switches: &[(
            "blit-to-default",
            "resolve with glBlitFramebuffer straight into framebuffer 0 (no full-screen pass)",
        )],
    };
    holoapps::run::main(
        &info,
        Profile::Core33,
        Box::new(|gl: &Gl, o: &Options| Ok(Box::new(Msaa::new(gl, o)?) as Box<dyn Scene>)),
    )
}
