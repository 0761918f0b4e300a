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
        Ok(p)
    }
}

pub fn uniform(gl: &Gl, prog: u32, name: &str) -> i32 {
    let c = CString::new(name).unwrap();
    unsafe { gl.GetUniformLocation(prog, c.as_ptr()) }
}

/// VAO with interleaved position (loc 0) + normal (loc 1), 6 floats a vertex.
pub fn pos_normal_vao(gl: &Gl, verts: &[f32]) -> u32 {
    let (mut vao, mut vbo) = (0, 0);
    unsafe {
        gl.GenVertexArrays(1, &mut vao);
        gl.BindVertexArray(vao);
        gl.GenBuffers(1, &mut vbo);
        gl.BindBuffer(gl::ARRAY_BUFFER, vbo);
        let bytes = std::mem::size_of_val(verts) as isize;
        gl.BufferData(gl::ARRAY_BUFFER, bytes, verts.as_ptr().cast(), gl::STATIC_DRAW);
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
