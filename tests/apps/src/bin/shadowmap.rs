//! `shadowmap`: GL 3.3 core, LearnOpenGL "Shadow Mapping". Pass 1 renders the
//! scene depth-only into a 1024² depth texture from a directional light
//! (orthographic `lightSpaceMatrix`); pass 2 draws the lit scene with 3x3 PCF
//! shadows to the default framebuffer. The shadow pass never sees the camera,
//! so it is view-independent: only pass 2's `projection` is sheared.
use holoapps::cli::{AppInfo, Options};
use holoapps::gl::{self, Gl};
use holoapps::math;
use holoapps::multipass::{self as mp, Attachment, Output};
use holoapps::platform::Profile;
use holoapps::scene::{Scene, View, seconds};
use holoapps::shader;
use std::process::ExitCode;

const SHADOW: i32 = 1024;
const LIGHT_POS: [f32; 3] = [-4.0, 9.0, 3.0];

const DEPTH_VS: &str = r#"#version 330 core
layout (location = 0) in vec3 aPos;
uniform mat4 lightSpaceMatrix;
uniform mat4 model;
void main() {
    gl_Position = lightSpaceMatrix * model * vec4(aPos, 1.0);
}
"#;

const DEPTH_FS: &str = r#"#version 330 core
void main() {}
"#;

const VS: &str = r#"#version 330 core
layout (location = 0) in vec3 aPos;
layout (location = 1) in vec3 aNormal;
uniform mat4 projection;
uniform mat4 view;
uniform mat4 model;
uniform mat4 lightSpaceMatrix;
out vec3 FragPos;
out vec3 Normal;
out vec4 FragPosLightSpace;
void main() {
    vec4 world = model * vec4(aPos, 1.0);
    FragPos = world.xyz;
    Normal = mat3(transpose(inverse(model))) * aNormal;
    FragPosLightSpace = lightSpaceMatrix * world;
    gl_Position = projection * view * world;
}
"#;

const FS: &str = r#"#version 330 core
in vec3 FragPos;
in vec3 Normal;
in vec4 FragPosLightSpace;
uniform sampler2D shadowMap;
uniform vec3 objectColor;
uniform vec3 lightPos;
uniform vec3 viewPos;
out vec4 FragColor;

float shadow(vec3 n, vec3 l) {
    vec3 p = FragPosLightSpace.xyz / FragPosLightSpace.w * 0.5 + 0.5;
    if (p.z > 1.0)
        return 0.0;
    // Slope-scaled bias against acne; PCF over 3x3 texels for soft edges.
    float bias = max(0.004 * (1.0 - dot(n, l)), 0.0008);
    vec2 texel = 1.0 / vec2(textureSize(shadowMap, 0));
    float s = 0.0;
    for (int x = -1; x <= 1; ++x)
        for (int y = -1; y <= 1; ++y)
            s += p.z - bias > texture(shadowMap, p.xy + vec2(x, y) * texel).r ? 1.0 : 0.0;
    return s / 9.0;
}

void main() {
    vec3 n = normalize(Normal);
    vec3 l = normalize(lightPos);
    vec3 h = normalize(l + normalize(viewPos - FragPos));
    float diff = max(dot(n, l), 0.0);
    float spec = pow(max(dot(n, h), 0.0), 64.0);
    float lit = 1.0 - shadow(n, l);
    vec3 c = objectColor * (0.25 + 0.75 * lit * diff) + vec3(0.35) * lit * spec;
    FragColor = vec4(c, 1.0);
}
"#;

struct ShadowMap {
    out: Output,
    depth_prog: u32,
    prog: u32,
    cube: u32,
    fbo: u32,
    map: u32,
    /// depth pass: lightSpaceMatrix, model
    dloc: [i32; 2],
    /// projection, view, model, lightSpaceMatrix, shadowMap, objectColor, lightPos, viewPos
    loc: [i32; 8],
}

impl ShadowMap {
    fn new(gl: &Gl, o: &Options) -> Result<Self, String> {
        let depth_prog = shader::program(gl, DEPTH_VS, DEPTH_FS)?;
        let prog = shader::program(gl, VS, FS)?;
        let dloc = ["lightSpaceMatrix", "model"].map(|n| shader::uniform(gl, depth_prog, n));
        let names = [
            "projection",
            "view",
            "model",
            "lightSpaceMatrix",
            "shadowMap",
            "objectColor",
            "lightPos",
            "viewPos",
        ];
        let loc = names.map(|n| shader::uniform(gl, prog, n));
        let size = (SHADOW, SHADOW);
        let map = mp::texture(
            gl,
            gl::DEPTH_COMPONENT24,
            size,
            gl::DEPTH_COMPONENT,
            gl::FLOAT,
            gl::NEAREST,
            None,
        );
        unsafe {
            // Outside the light's frustum counts as lit (depth 1.0).
            gl.TexParameteri(gl::TEXTURE_2D, gl::TEXTURE_WRAP_S, gl::CLAMP_TO_BORDER as i32);
            gl.TexParameteri(gl::TEXTURE_2D, gl::TEXTURE_WRAP_T, gl::CLAMP_TO_BORDER as i32);
            gl.TexParameterfv(gl::TEXTURE_2D, gl::TEXTURE_BORDER_COLOR, [1.0f32; 4].as_ptr());
        }
        let fbo = mp::framebuffer(gl, "shadow", &[], Some(Attachment::Texture(map)))?;
        Ok(ShadowMap {
            out: Output::new(o.size),
            depth_prog,
            prog,
            cube: shader::pos_normal_vao(gl, &shader::cube_vertices()),
            fbo,
            map,
            dloc,
            loc,
        })
    }
}

impl Scene for ShadowMap {
    fn render(&mut self, gl: &Gl, frame: u64, v: &View) {
        let target = self.out.begin(gl, v);
        let (w, h) = self.out.size();
        let (p, view) = mp::camera((w, h));
        let objs = mp::objects(seconds(frame));
        let light = math::mul(
            &math::ortho(-10.0, 10.0, -10.0, 10.0, 1.0, 25.0),
            &math::look_at(LIGHT_POS, [0.0; 3], [0.0, 1.0, 0.0]),
        );
        let l = self.loc;
        unsafe {
            // Pass 1: depth from the light (same for every view).
            gl.BindFramebuffer(gl::FRAMEBUFFER, self.fbo);
            gl.Viewport(0, 0, SHADOW, SHADOW);
            gl.Enable(gl::DEPTH_TEST);
            gl.Enable(gl::CULL_FACE);
            // Back faces only (all objects are closed): keeps lit faces free of acne.
            gl.CullFace(gl::FRONT);
            gl.Clear(gl::DEPTH_BUFFER_BIT);
            gl.UseProgram(self.depth_prog);
            mp::set_mat4(gl, self.dloc[0], &light);
            gl.BindVertexArray(self.cube);
            mp::draw_objects(gl, &objs, self.dloc[1], -1);

            // Pass 2: the lit, shadowed scene to the default framebuffer.
            gl.BindFramebuffer(gl::FRAMEBUFFER, target);
            gl.Viewport(0, 0, w, h);
            gl.CullFace(gl::BACK);
            gl.ClearColor(0.1, 0.12, 0.18, 1.0);
            gl.Clear(gl::COLOR_BUFFER_BIT | gl::DEPTH_BUFFER_BIT);
            gl.UseProgram(self.prog);
            mp::set_mat4(gl, l[0], &v.projection(p));
            mp::set_mat4(gl, l[1], &view);
            mp::set_mat4(gl, l[3], &light);
            mp::bind_texture(gl, 0, self.map, l[4]);
            mp::set_vec3(gl, l[6], LIGHT_POS);
            mp::set_vec3(gl, l[7], mp::EYE);
            mp::draw_objects(gl, &objs, l[2], l[5]);
        }
        self.out.end(gl, v);
    }
}

fn main() -> ExitCode {
    let info = AppInfo {
        name: "shadowmap",
        about: "GL 3.3 core: directional-light shadow map (1024² depth FBO, ortho lightSpaceMatrix), then the lit scene with 3x3 PCF",
        default_convergence: math::distance(mp::EYE, mp::CENTRE),
        extra: &[],
        switches: &[],
    };
    holoapps::run::main(
        &info,
        Profile::Core33,
        Box::new(|gl: &Gl, o: &Options| Ok(Box::new(ShadowMap::new(gl, o)?) as Box<dyn Scene>)),
    )
}
