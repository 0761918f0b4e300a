//! `framebuffers`: GL 3.3 core, LearnOpenGL "Framebuffers". The lit scene is
//! rendered into an FBO (RGBA8 colour texture + depth24 renderbuffer), then a
//! full-screen quad draws that texture to the default framebuffer with a
//! sharpen kernel (texel offsets) and a vignette. Only the scene pass uses the
//! camera; the post pass is in NDC and view-independent.
//!
//! `--reattach` follows VTK's render passes (f3d, ParaView): every frame the
//! same texture and renderbuffer are attached again before the scene pass, the
//! texture's sampling parameters are sent again, and the colour texture is
//! detached after the pass, while the post pass samples it.
//! `--late-swizzle` swaps red and blue of the scene texture through
//! `GL_TEXTURE_SWIZZLE_R/B` from the second frame on: a sampling parameter
//! changed after the first frame has used the texture.
//! `--texel-fetch` reads the kernel's texels with `texelFetch` at `gl_FragCoord`
//! (integer pixel addresses, which a scaled layer cannot answer: `--fbo-scale`).
use holoapps::cli::{AppInfo, Options};
use holoapps::gl::{self, Gl};
use holoapps::math;
use holoapps::multipass::{self as mp, Attachment, Output};
use holoapps::platform::Profile;
use holoapps::scene::{Scene, View, seconds};
use holoapps::shader;
use std::process::ExitCode;

const SCENE_FS: &str = r#"#version 330 core
in vec3 FragPos;
in vec3 Normal;
uniform vec3 objectColor;
uniform vec3 lightDir;
uniform vec3 viewPos;
out vec4 FragColor;
void main() {
    vec3 n = normalize(Normal);
    vec3 l = normalize(lightDir);
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
    // Sharpen: 5*centre - 4 neighbours, one texel apart.
    vec2 texel = 1.0 / vec2(textureSize(screenTexture, 0));
    vec3 c = 5.0 * texture(screenTexture, UV).rgb;
    c -= texture(screenTexture, UV + vec2(texel.x, 0.0)).rgb;
    c -= texture(screenTexture, UV - vec2(texel.x, 0.0)).rgb;
    c -= texture(screenTexture, UV + vec2(0.0, texel.y)).rgb;
    c -= texture(screenTexture, UV - vec2(0.0, texel.y)).rgb;
    vec2 d = UV - 0.5;
    float vignette = 1.0 - 0.8 * dot(d, d);
    FragColor = vec4(clamp(c, 0.0, 1.0) * vignette, 1.0);
}
"#;

/// `POST_FS` with texels addressed by pixel, as post-processing written for a fixed
/// framebuffer size often does.
const POST_FETCH_FS: &str = r#"#version 330 core
in vec2 UV;
uniform sampler2D screenTexture;
out vec4 FragColor;
vec3 at(ivec2 p) { return texelFetch(screenTexture, p, 0).rgb; }
void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec3 c = 5.0 * at(p) - at(p + ivec2(1, 0)) - at(p - ivec2(1, 0)) - at(p + ivec2(0, 1)) - at(p - ivec2(0, 1));
    vec2 d = UV - 0.5;
    float vignette = 1.0 - 0.8 * dot(d, d);
    FragColor = vec4(clamp(c, 0.0, 1.0) * vignette, 1.0);
}
"#;

struct Framebuffers {
    out: Output,
    scene: u32,
    post: u32,
    cube: u32,
    quad: u32,
    fbo: u32,
    colour: u32,
    depth: u32,
    reattach: bool,
    late_swizzle: bool,
    /// projection, view, model, objectColor, lightDir, viewPos, screenTexture
    loc: [i32; 7],
}

impl Framebuffers {
    fn new(gl: &Gl, o: &Options) -> Result<Self, String> {
        let out = Output::new(o.size);
        let scene = shader::program(gl, mp::SCENE_VS, SCENE_FS)?;
        let post_fs = if o.switches.contains("texel-fetch") {
            POST_FETCH_FS
        } else {
            POST_FS
        };
        let post = shader::program(gl, mp::QUAD_VS, post_fs)?;
        let mut loc = [0; 7];
        for (l, n) in loc
            .iter_mut()
            .zip(["projection", "view", "model", "objectColor", "lightDir", "viewPos"])
        {
            *l = shader::uniform(gl, scene, n);
        }
        loc[6] = shader::uniform(gl, post, "screenTexture");
        // NEAREST: the sharpen kernel reads exact texels.
        let colour = mp::texture(
            gl,
            gl::RGBA8,
            out.size(),
            gl::RGBA,
            gl::UNSIGNED_BYTE,
            gl::NEAREST,
            None,
        );
        let depth = mp::renderbuffer(gl, gl::DEPTH_COMPONENT24, 0, out.size());
        let fbo = mp::framebuffer(
            gl,
            "scene",
            &[Attachment::Texture(colour)],
            Some(Attachment::Renderbuffer(depth)),
        )?;
        Ok(Framebuffers {
            out,
            scene,
            post,
            cube: shader::pos_normal_vao(gl, &shader::cube_vertices()),
            quad: mp::quad_vao(gl),
            fbo,
            colour,
            depth,
            reattach: o.switches.contains("reattach"),
            late_swizzle: o.switches.contains("late-swizzle"),
            loc,
        })
    }
}

impl Framebuffers {
    /// VTK's per-pass attachment: the same objects again, parameters re-sent.
    fn attach(&self, gl: &Gl) {
        unsafe {
            gl.FramebufferTexture2D(gl::FRAMEBUFFER, gl::COLOR_ATTACHMENT0, gl::TEXTURE_2D, self.colour, 0);
            gl.FramebufferRenderbuffer(gl::FRAMEBUFFER, gl::DEPTH_ATTACHMENT, gl::RENDERBUFFER, self.depth);
            gl.BindTexture(gl::TEXTURE_2D, self.colour);
            gl.TexParameteri(gl::TEXTURE_2D, gl::TEXTURE_MIN_FILTER, gl::NEAREST as i32);
            gl.TexParameteri(gl::TEXTURE_2D, gl::TEXTURE_MAG_FILTER, gl::NEAREST as i32);
            gl.BindTexture(gl::TEXTURE_2D, 0);
        }
    }

    /// VTK releases its colour attachments once a pass is drawn.
    fn detach(&self, gl: &Gl) {
        unsafe { gl.FramebufferTexture2D(gl::FRAMEBUFFER, gl::COLOR_ATTACHMENT0, gl::TEXTURE_2D, 0, 0) };
    }

    fn swizzle(&self, gl: &Gl, frame: u64) {
        if !self.late_swizzle || frame == 0 {
            return;
        }
        unsafe {
            gl.BindTexture(gl::TEXTURE_2D, self.colour);
            gl.TexParameteri(gl::TEXTURE_2D, gl::TEXTURE_SWIZZLE_R, gl::BLUE as i32);
            gl.TexParameteri(gl::TEXTURE_2D, gl::TEXTURE_SWIZZLE_B, gl::RED as i32);
            gl.BindTexture(gl::TEXTURE_2D, 0);
        }
    }
}

impl Scene for Framebuffers {
    fn render(&mut self, gl: &Gl, frame: u64, v: &View) {
        let target = self.out.begin(gl, v);
        let (w, h) = self.out.size();
        let (p, view) = mp::camera((w, h));
        let l = self.loc;
        unsafe {
            // Pass 1: the scene into the FBO, with view i's projection.
            gl.BindFramebuffer(gl::FRAMEBUFFER, self.fbo);
            if self.reattach {
                self.attach(gl);
            }
            gl.Viewport(0, 0, w, h);
            gl.ClearColor(0.1, 0.12, 0.18, 1.0);
            gl.Enable(gl::DEPTH_TEST);
            gl.Enable(gl::CULL_FACE);
            gl.Clear(gl::COLOR_BUFFER_BIT | gl::DEPTH_BUFFER_BIT);
            gl.UseProgram(self.scene);
            mp::set_mat4(gl, l[0], &v.projection(p));
            mp::set_mat4(gl, l[1], &view);
            mp::set_vec3(gl, l[4], [0.4, 1.0, 0.6]);
            mp::set_vec3(gl, l[5], mp::EYE);
            gl.BindVertexArray(self.cube);
            mp::draw_objects(gl, &mp::objects(seconds(frame)), l[2], l[3]);
            if self.reattach {
                self.detach(gl);
            }
            self.swizzle(gl, frame);

            // Pass 2: post effect to the default framebuffer.
            gl.BindFramebuffer(gl::FRAMEBUFFER, target);
            gl.Disable(gl::DEPTH_TEST);
            gl.ClearColor(1.0, 1.0, 1.0, 1.0);
            gl.Clear(gl::COLOR_BUFFER_BIT);
            gl.UseProgram(self.post);
            mp::bind_texture(gl, 0, self.colour, l[6]);
            mp::draw_quad(gl, self.quad);
        }
        self.out.end(gl, v);
    }
}

fn main() -> ExitCode {
    let info = AppInfo {
        name: "framebuffers",
        about: "GL 3.3 core: lit scene into an FBO (RGBA8 texture + depth24 renderbuffer), then a sharpen + vignette full-screen pass",
        default_convergence: math::distance(mp::EYE, mp::CENTRE),
        extra: &[],
        switches: &[
            (
                "reattach",
                "VTK's pattern: re-attach the same targets and re-send texture parameters every frame, detach the colour texture after the scene pass",
            ),
            (
                "late-swizzle",
                "swap red and blue of the scene texture (GL_TEXTURE_SWIZZLE_R/B) from frame 2 on",
            ),
            (
                "texel-fetch",
                "the post pass reads its texels with texelFetch at gl_FragCoord (pixel addresses)",
            ),
        ],
    };
    holoapps::run::main(
        &info,
        Profile::Core33,
        Box::new(|gl: &Gl, o: &Options| Ok(Box::new(Framebuffers::new(gl, o)?) as Box<dyn Scene>)),
    )
}
