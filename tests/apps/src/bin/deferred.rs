//! `deferred`: GL 3.3 core, LearnOpenGL "Deferred Shading". A G-buffer FBO
//! (world position RGBA16F, normal RGBA16F, albedo+specular RGBA8, depth24
//! renderbuffer) written through MRT, then a full-screen lighting pass with
//! eight orbiting point lights and `viewPos` to the default framebuffer. Only
//! the G-buffer pass uses the camera projection; the lighting pass works on
//! world-space data in NDC and keeps `viewPos` (the shear moves no eye).
use holoapps::cli::{AppInfo, Options};
use holoapps::gl::{self, Gl};
use holoapps::math;
use holoapps::multipass::{self as mp, Attachment, Output};
use holoapps::platform::Profile;
use holoapps::scene::{Scene, View, seconds};
use holoapps::shader;
use std::process::ExitCode;

const LIGHTS: usize = 8;

const GBUFFER_FS: &str = r#"#version 330 core
layout (location = 0) out vec4 gPosition;
layout (location = 1) out vec4 gNormal;
layout (location = 2) out vec4 gAlbedoSpec;
in vec3 FragPos;
in vec3 Normal;
uniform vec3 objectColor;
void main() {
    // w = 1 marks covered pixels; the clear leaves 0 for the background.
    gPosition = vec4(FragPos, 1.0);
    gNormal = vec4(normalize(Normal), 0.0);
    gAlbedoSpec = vec4(objectColor, 0.6);
}
"#;

const LIGHT_FS: &str = r#"#version 330 core
in vec2 UV;
uniform sampler2D gPosition;
uniform sampler2D gNormal;
uniform sampler2D gAlbedoSpec;
struct Light {
    vec3 Position;
    vec3 Color;
};
const int NR_LIGHTS = 8;
uniform Light lights[NR_LIGHTS];
uniform vec3 viewPos;
out vec4 FragColor;
void main() {
    vec4 pos = texture(gPosition, UV);
    if (pos.w == 0.0) {
        FragColor = vec4(0.06, 0.07, 0.1, 1.0);
        return;
    }
    vec3 n = texture(gNormal, UV).rgb;
    vec4 albedo = texture(gAlbedoSpec, UV);
    vec3 v = normalize(viewPos - pos.xyz);
    vec3 c = albedo.rgb * 0.12;
    for (int i = 0; i < NR_LIGHTS; ++i) {
        vec3 d = lights[i].Position - pos.xyz;
        float dist = length(d);
        vec3 l = d / dist;
        float att = 1.0 / (1.0 + 0.35 * dist + 0.44 * dist * dist);
        vec3 diffuse = max(dot(n, l), 0.0) * albedo.rgb * lights[i].Color;
        float spec = pow(max(dot(n, normalize(l + v)), 0.0), 32.0) * albedo.a;
        c += (diffuse + spec * lights[i].Color) * att * 2.0;
    }
    FragColor = vec4(min(c, vec3(1.0)), 1.0);
}
"#;

struct Deferred {
    out: Output,
    gbuffer_prog: u32,
    light_prog: u32,
    cube: u32,
    quad: u32,
    gbuffer: u32,
    /// position, normal, albedo+spec
    tex: [u32; 3],
    /// projection, view, model, objectColor
    gloc: [i32; 4],
    /// gPosition, gNormal, gAlbedoSpec, viewPos, lights[i].Position, lights[i].Color
    lloc: [i32; 4],
    light_locs: Vec<(i32, i32)>,
}

impl Deferred {
    fn new(gl: &Gl, o: &Options) -> Result<Self, String> {
        let out = Output::new(o.size);
        let gbuffer_prog = shader::program(gl, mp::SCENE_VS, GBUFFER_FS)?;
        let light_prog = shader::program(gl, mp::QUAD_VS, LIGHT_FS)?;
        let gloc = ["projection", "view", "model", "objectColor"].map(|n| shader::uniform(gl, gbuffer_prog, n));
        let lloc = ["gPosition", "gNormal", "gAlbedoSpec", "viewPos"].map(|n| shader::uniform(gl, light_prog, n));
        let light_locs = (0..LIGHTS)
            .map(|i| {
                let u = |f: &str| shader::uniform(gl, light_prog, &format!("lights[{i}].{f}"));
                (u("Position"), u("Color"))
            })
            .collect();
        let formats = [
            (gl::RGBA16F, gl::FLOAT),
            (gl::RGBA16F, gl::FLOAT),
            (gl::RGBA8, gl::UNSIGNED_BYTE),
        ];
        let tex = formats.map(|(f, ty)| mp::texture(gl, f, out.size(), gl::RGBA, ty, gl::NEAREST, None));
        let depth = mp::renderbuffer(gl, gl::DEPTH_COMPONENT24, 0, out.size());
        let colour = tex.map(Attachment::Texture);
        let gbuffer = mp::framebuffer(gl, "G-buffer", &colour, Some(Attachment::Renderbuffer(depth)))?;
        Ok(Deferred {
            out,
            gbuffer_prog,
            light_prog,
            cube: shader::pos_normal_vao(gl, &shader::cube_vertices()),
            quad: mp::quad_vao(gl),
            gbuffer,
            tex,
            gloc,
            lloc,
            light_locs,
        })
    }

    /// Light i circles the scene at its own height, radius and speed.
    fn light(i: usize, t: f32) -> ([f32; 3], [f32; 3]) {
        let f = i as f32;
        let a = f / LIGHTS as f32 * std::f32::consts::TAU + t * (0.4 + 0.1 * (i % 3) as f32);
        let r = 2.0 + 1.7 * (i % 2) as f32;
        let pos = [r * a.cos(), 0.4 + 0.5 * (i % 4) as f32, r * a.sin()];
        let col = [
            0.5 + 0.5 * (f * 1.3).cos(),
            0.5 + 0.5 * (f * 2.1 + 1.0).cos(),
            0.5 + 0.5 * (f * 0.7 + 2.0).cos(),
        ];
        (pos, col)
    }
}

impl Scene for Deferred {
    fn render(&mut self, gl: &Gl, frame: u64, v: &View) {
        let target = self.out.begin(gl, v);
        let (w, h) = self.out.size();
        let (p, view) = mp::camera((w, h));
        let t = seconds(frame);
        unsafe {
            // Geometry pass into the G-buffer, with view i's projection.
            gl.BindFramebuffer(gl::FRAMEBUFFER, self.gbuffer);
            gl.Viewport(0, 0, w, h);
            gl.ClearColor(0.0, 0.0, 0.0, 0.0);
            gl.Enable(gl::DEPTH_TEST);
            gl.Enable(gl::CULL_FACE);
            gl.Clear(gl::COLOR_BUFFER_BIT | gl::DEPTH_BUFFER_BIT);
            gl.UseProgram(self.gbuffer_prog);
            mp::set_mat4(gl, self.gloc[0], &v.projection(p));
            mp::set_mat4(gl, self.gloc[1], &view);
            gl.BindVertexArray(self.cube);
            mp::draw_objects(gl, &mp::objects(t), self.gloc[2], self.gloc[3]);

            // Lighting pass: full-screen quad to the default framebuffer.
            gl.BindFramebuffer(gl::FRAMEBUFFER, target);
            gl.Disable(gl::DEPTH_TEST);
            gl.ClearColor(0.0, 0.0, 0.0, 1.0);
            gl.Clear(gl::COLOR_BUFFER_BIT | gl::DEPTH_BUFFER_BIT);
            gl.UseProgram(self.light_prog);
            for (unit, tex) in self.tex.iter().enumerate() {
                mp::bind_texture(gl, unit as u32, *tex, self.lloc[unit]);
            }
            mp::set_vec3(gl, self.lloc[3], mp::EYE);
            for (i, (pl, cl)) in self.light_locs.iter().enumerate() {
                let (pos, col) = Self::light(i, t);
                mp::set_vec3(gl, *pl, pos);
                mp::set_vec3(gl, *cl, col);
            }
            mp::draw_quad(gl, self.quad);
        }
        self.out.end(gl, v);
    }
}

fn main() -> ExitCode {
    let info = AppInfo {
        name: "deferred",
        about: "GL 3.3 core deferred shading: G-buffer FBO (position/normal RGBA16F, albedo RGBA8, depth) + 8 point lights in a full-screen pass",
        default_convergence: math::distance(mp::EYE, mp::CENTRE),
        extra: &[],
        switches: &[],
    };
    holoapps::run::main(
        &info,
        Profile::Core33,
        Box::new(|gl: &Gl, o: &Options| Ok(Box::new(Deferred::new(gl, o)?) as Box<dyn Scene>)),
    )
}
