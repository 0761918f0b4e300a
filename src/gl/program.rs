//! Compiling and linking the layer's own small GLSL programs (the output passes, the depth
//! read-back pass). Sources are written as GLSL 3.30 core; ES 3 contexts get the same code
//! under `#version 300 es` with explicit precision.

use super::GlInfo;
use super::*;
use std::ffi::CString;

/// The location of uniform `name` of our linked `program` (-1 when it has none: GL ignores
/// uniform calls there, so an unused uniform the compiler dropped is no error).
pub fn uniform(gl: &Gl, program: u32, name: &str) -> i32 {
    let c = CString::new(name).unwrap_or_default();
    // SAFETY: a NUL-terminated name for our linked program.
    unsafe { gl.GetUniformLocation(program, c.as_ptr()) }
}

/// `source` (whose first line is its `#version`) for the context's API.
pub fn for_context(source: &str, info: GlInfo) -> String {
    if !info.es {
        return source.to_string();
    }
    let body = source.split_once('\n').map_or("", |(_, rest)| rest);
    format!("#version 300 es\nprecision highp float;\nprecision highp int;\nprecision highp sampler2D;\n{body}")
}

fn compile(gl: &Gl, kind: GLenum, source: &str) -> Result<u32, String> {
    let c = CString::new(source).map_err(|_| "NUL in shader source")?;
    // SAFETY: creating and compiling our own shader object.
    unsafe {
        let s = gl.CreateShader(kind);
        gl.ShaderSource(s, 1, &c.as_ptr(), core::ptr::null());
        gl.CompileShader(s);
        let mut ok = 0;
        gl.GetShaderiv(s, COMPILE_STATUS, &mut ok);
        if ok == 0 {
            let log = info_log(|n, l, b| gl.GetShaderInfoLog(s, n, l, b));
            gl.DeleteShader(s);
            return Err(log);
        }
        Ok(s)
    }
}

fn info_log(get: impl Fn(i32, *mut i32, *mut types::GLchar)) -> String {
    let mut buf = vec![0u8; 4096];
    let mut n = 0;
    get(buf.len() as i32, &mut n, buf.as_mut_ptr().cast());
    buf.truncate(n.max(0) as usize);
    String::from_utf8_lossy(&buf).lines().next().unwrap_or("").to_string()
}

/// Our program from a vertex and a fragment shader source (each made `for_context`).
pub fn link(gl: &Gl, info: GlInfo, vert: &str, frag: &str) -> Result<u32, String> {
    let vs = compile(gl, VERTEX_SHADER, &for_context(vert, info))?;
    let fs = match compile(gl, FRAGMENT_SHADER, &for_context(frag, info)) {
        Ok(fs) => fs,
        Err(e) => {
            // SAFETY: our own shader object.
            unsafe { gl.DeleteShader(vs) };
            return Err(e);
        }
    };
    link_shaders(gl, &[vs, fs])
}

/// Our compute program (desktop GL 4.3 source, used as is).
pub fn link_compute(gl: &Gl, source: &str) -> Result<u32, String> {
    let cs = compile(gl, COMPUTE_SHADER, source)?;
    link_shaders(gl, &[cs])
}

/// A program from compiled `shaders`, which are deleted (they live on in the program).
fn link_shaders(gl: &Gl, shaders: &[u32]) -> Result<u32, String> {
    // SAFETY: linking our own program from our own shaders.
    unsafe {
        let p = gl.CreateProgram();
        for &s in shaders {
            gl.AttachShader(p, s);
        }
        gl.LinkProgram(p);
        for &s in shaders {
            gl.DeleteShader(s);
        }
        let mut ok = 0;
        gl.GetProgramiv(p, LINK_STATUS, &mut ok);
        if ok == 0 {
            let log = info_log(|n, l, b| gl.GetProgramInfoLog(p, n, l, b));
            gl.DeleteProgram(p);
            return Err(log);
        }
        Ok(p)
    }
}
