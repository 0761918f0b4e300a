//! Small GLSL / buffer helpers for the core-profile apps.
use crate::gl::{self, Gl};
use std::ffi::CString;

fn compile(gl: &Gl, kind: u32, src: &str) -> Result<u32, String> {
    unsafe {
        let s = gl.CreateShader(kind);
        let c = CString::new(src).unwrap();
        gl.ShaderSource(s, 1, &c.as_ptr(), std::ptr::null());
        gl.CompileShader(s);
        let mut ok = 0;
        gl.GetShaderiv(s, gl::COMPILE_STATUS, &mut ok);
        if ok == 0 {
            return Err(format!("shader compile failed: {}", shader_log(gl, s)));
        }
        Ok(s)
    }
}

fn shader_log(gl: &Gl, s: u32) -> String {
    let mut buf = vec![0u8; 4096];
    let mut len = 0;
    unsafe { gl.GetShaderInfoLog(s, buf.len() as i32, &mut len, buf.as_mut_ptr().cast()) };
    String::from_utf8_lossy(&buf[..len as usize]).into_owned()
}

/// A mesh of positions and normals seen through `projection * view * model` (rigid models:
/// the normal matrix is the model's own), shared by the apps that draw many such meshes.
pub const LIT_MESH_VS: &str = r#"#version 330 core
layout (location = 0) in vec3 aPos;
layout (location = 1) in vec3 aNormal;
uniform mat4 projection;
uniform mat4 view;
uniform mat4 model;
out vec3 Normal;
void main() {
    Normal = mat3(model) * aNormal;
    gl_Position = projection * view * model * vec4(aPos, 1.0);
}
"#;

/// A lit cube whose faces carry texture coordinates (the two coordinates across each face),
/// shared by the apps that texture their cubes with a render target.
pub const TEXTURED_CUBE_VS: &str = r#"#version 330 core
layout (location = 0) in vec3 aPos;
layout (location = 1) in vec3 aNormal;
uniform mat4 model;
uniform mat4 view;
uniform mat4 projection;
out vec3 Normal;
out vec2 Uv;
void main() {
    Normal = mat3(transpose(inverse(model))) * aNormal;
    // Unit cube: the two coordinates across the face are the texture coordinates.
    vec3 n = abs(aNormal);
    Uv = (n.x > 0.5 ? aPos.zy : n.y > 0.5 ? aPos.xz : aPos.xy) + 0.5;
    gl_Position = projection * view * model * vec4(aPos, 1.0);
}
"#;

/// Mesa's verdict on one shader, compiled on its own: `Err(info log)` when it does not
/// compile. The shader object is deleted either way.
pub fn compile_status(gl: &Gl, kind: u32, src: &str) -> Result<(), String> {
    let c = CString::new(src).map_err(|_| "NUL in source".to_string())?;
    unsafe {
        let s = gl.CreateShader(kind);
        gl.ShaderSource(s, 1, &c.as_ptr(), std::ptr::null());
        gl.CompileShader(s);
        let mut ok = 0;
        gl.GetShaderiv(s, gl::COMPILE_STATUS, &mut ok);
        let log = shader_log(gl, s);
        gl.DeleteShader(s);
        if ok != 0 { Ok(()) } else { Err(log) }
    }
}

pub fn program(gl: &Gl, vs: &str, fs: &str) -> Result<u32, String> {
    unsafe {
        let p = gl.CreateProgram();
        for (kind, src) in [(gl::VERTEX_SHADER, vs), (gl::FRAGMENT_SHADER, fs)] {
            let s = compile(gl, kind, src)?;
            gl.AttachShader(p, s);
            gl.DeleteShader(s);
        }
        gl.LinkProgram(p);
        let mut ok = 0;
        gl.GetProgramiv(p, gl::LINK_STATUS, &mut ok);
        if ok == 0 {
            return Err("shader program link failed".into());
        }
        if std::env::var_os("HOLOAPPS_LIST_UNIFORMS").is_some() {
            eprintln!("uniforms of program {p}: {}", active_uniforms(gl, p).join(" "));
        }
        Ok(p)
    }
}

/// What introspection tells about a program's uniforms, through every path an engine might
/// use: the count and `glGetActiveUniform`, `glGetActiveUniformName`, the location of each
/// name, `glGetActiveUniformsiv` types, and (GL 4.3) the program interface query.
pub fn active_uniforms(gl: &Gl, p: u32) -> Vec<String> {
    let mut out = vec![];
    unsafe {
        let mut count = 0;
        gl.GetProgramiv(p, gl::ACTIVE_UNIFORMS, &mut count);
        let indices: Vec<u32> = (0..count as u32).collect();
        let mut types = vec![0i32; indices.len()];
        if count > 0 {
            gl.GetActiveUniformsiv(p, count, indices.as_ptr(), gl::UNIFORM_TYPE, types.as_mut_ptr());
        }
        for (i, &ty) in indices.iter().zip(&types) {
            let mut buf = [0u8; 128];
            let (mut len, mut size, mut ty2) = (0, 0, 0);
            gl.GetActiveUniform(
                p,
                *i,
                buf.len() as i32,
                &mut len,
                &mut size,
                &mut ty2,
                buf.as_mut_ptr().cast(),
            );
            let name = String::from_utf8_lossy(&buf[..len as usize]).into_owned();
            let mut buf2 = [0u8; 128];
            let mut len2 = 0;
            if gl.GetActiveUniformName.is_loaded() {
                gl.GetActiveUniformName(p, *i, buf2.len() as i32, &mut len2, buf2.as_mut_ptr().cast());
            }
            let c = std::ffi::CString::new(name.clone()).unwrap_or_default();
            let loc = gl.GetUniformLocation(p, c.as_ptr());
            let same = String::from_utf8_lossy(&buf2[..len2 as usize]) == name && ty == ty2 as i32;
            out.push(format!(
                "{name}@{loc}:{ty:#x}{}",
                if same { "" } else { "(inconsistent)" }
            ));
        }
        if gl.GetProgramInterfaceiv.is_loaded() {
            let mut n = 0;
            gl.GetProgramInterfaceiv(p, gl::UNIFORM, gl::ACTIVE_RESOURCES, &mut n);
            let mut names = vec![];
            for i in 0..n.max(0) as u32 {
                let mut buf = [0u8; 128];
                let mut len = 0;
                gl.GetProgramResourceName(p, gl::UNIFORM, i, buf.len() as i32, &mut len, buf.as_mut_ptr().cast());
                let prop = gl::LOCATION;
                let mut loc = -1;
                gl.GetProgramResourceiv(p, gl::UNIFORM, i, 1, &prop, 1, std::ptr::null_mut(), &mut loc);
                names.push(format!("{}@{loc}", String::from_utf8_lossy(&buf[..len as usize])));
            }
            out.push(format!("| interface: {}", names.join(" ")));
        }
    }
    out
}

pub fn uniform(gl: &Gl, prog: u32, name: &str) -> i32 {
    let c = CString::new(name).unwrap();
    unsafe { gl.GetUniformLocation(prog, c.as_ptr()) }
}

/// VAO with interleaved position (loc 0) + normal (loc 1), 6 floats a vertex.
pub fn pos_normal_vao(gl: &Gl, verts: &[f32]) -> u32 {
    let mut vbo = 0;
    unsafe {
        gl.GenBuffers(1, &mut vbo);
        gl.BindBuffer(gl::ARRAY_BUFFER, vbo);
        let bytes = std::mem::size_of_val(verts) as isize;
        gl.BufferData(gl::ARRAY_BUFFER, bytes, verts.as_ptr().cast(), gl::STATIC_DRAW);
    }
    pos_normal_vao_of(gl, vbo)
}

/// A VAO reading position (0) + normal (1), 6 floats a vertex, from an existing buffer (one
/// shared between contexts, say). Leaves the VAO and buffer bound.
pub fn pos_normal_vao_of(gl: &Gl, vbo: u32) -> u32 {
    let mut vao = 0;
    unsafe {
        gl.GenVertexArrays(1, &mut vao);
        gl.BindVertexArray(vao);
        gl.BindBuffer(gl::ARRAY_BUFFER, vbo);
        let stride = 6 * 4;
        gl.VertexAttribPointer(0, 3, gl::FLOAT, gl::FALSE, stride, std::ptr::null());
        gl.EnableVertexAttribArray(0);
        gl.VertexAttribPointer(1, 3, gl::FLOAT, gl::FALSE, stride, (3 * 4) as *const _);
        gl.EnableVertexAttribArray(1);
    }
    vao
}

/// Unit cube centred on the origin as 36 position+normal vertices.
pub fn cube_vertices() -> Vec<f32> {
    // (normal axis, sign): each face as two triangles.
    let mut v = Vec::with_capacity(36 * 6);
    for axis in 0..3 {
        for sign in [-1.0f32, 1.0] {
            let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
            let corners = [
                (-1.0, -1.0),
                (1.0, -1.0),
                (1.0, 1.0),
                (-1.0, -1.0),
                (1.0, 1.0),
                (-1.0, 1.0),
            ];
            for (ca, cb) in corners {
                let mut p = [0.0f32; 3];
                p[axis] = 0.5 * sign;
                // Flip winding on the negative faces so all are CCW outside.
                p[a] = 0.5 * ca * sign;
                p[b] = 0.5 * cb;
                let mut n = [0.0f32; 3];
                n[axis] = sign;
                v.extend_from_slice(&p);
                v.extend_from_slice(&n);
            }
        }
    }
    v
}
