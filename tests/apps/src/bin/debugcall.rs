//! `debugcall`: GL 3.3 core, one lit cube, and a synchronous KHR_debug callback that itself
//! calls GL (`glGetIntegerv(GL_VIEWPORT)`, `glGetError`), as engines that log the viewport or
//! drain errors from their debug callback do. Every frame also issues one draw with an invalid
//! primitive mode, so GL calls the callback from *inside* `glDrawArrays`: a layer holding a
//! lock across the real draw must not deadlock when the callback re-enters it.
use holoapps::cli::{AppInfo, Options};
use holoapps::gl::{self, Gl};
use holoapps::math::{self, Mat4};
use holoapps::platform::Profile;
use holoapps::scene::{Scene, View, seconds};
use holoapps::shader;
use std::ffi::c_void;
use std::process::ExitCode;
use std::sync::atomic::{AtomicU64, Ordering};

const EYE: [f32; 3] = [0.0, 2.0, 5.0];

const FS: &str = r#"#version 330 core
in vec3 Normal;
out vec4 FragColor;
void main() {
    float diff = max(dot(normalize(Normal), normalize(vec3(0.4, 1.0, 0.6))), 0.0);
    FragColor = vec4((0.25 + 0.75 * diff) * vec3(0.9, 0.5, 0.2), 1.0);
}
"#;

/// Not a primitive mode: `glDrawArrays` with it is GL_INVALID_ENUM, reported to the callback.
const BAD_MODE: u32 = 0xFFFF;

static MESSAGES: AtomicU64 = AtomicU64::new(0);

/// The debug callback. `user` is the app's own GL table (leaked, so it outlives the context).
extern "system" fn on_message(
    _source: gl::types::GLenum,
    _ty: gl::types::GLenum,
    _id: gl::types::GLuint,
    _severity: gl::types::GLenum,
    _length: gl::types::GLsizei,
    _message: *const gl::types::GLchar,
    user: *mut c_void,
) {
    // SAFETY: `user` is the `&'static Gl` given to glDebugMessageCallback below, and a
    // synchronous callback runs on the thread whose context is current.
    let gl = unsafe { &*user.cast::<Gl>() };
    let mut viewport = [0i32; 4];
    // SAFETY: GL_VIEWPORT answers four integers.
    unsafe {
        gl.GetIntegerv(gl::VIEWPORT, viewport.as_mut_ptr());
        gl.GetError();
    }
    MESSAGES.fetch_add(1, Ordering::Relaxed);
}

struct DebugCall {
    prog: u32,
    vao: u32,
    loc: [i32; 3],
}

impl DebugCall {
    fn new(gl: &Gl) -> Result<Self, String> {
        if !gl.DebugMessageCallback.is_loaded() {
            return Err("debugcall needs KHR_debug (GL 4.3)".into());
        }
        let prog = shader::program(gl, shader::LIT_MESH_VS, FS)?;
        let loc = ["projection", "view", "model"].map(|n| shader::uniform(gl, prog, n));
        let vao = shader::pos_normal_vao(gl, &shader::cube_vertices());
        // The callback outlives this borrow of the runner's table: it gets a copy of its own.
        let table: &'static Gl = Box::leak(Box::new(gl.clone()));
        unsafe {
            gl.Enable(gl::DEBUG_OUTPUT);
            gl.Enable(gl::DEBUG_OUTPUT_SYNCHRONOUS);
            gl.DebugMessageCallback(Some(on_message), (table as *const Gl).cast());
        }
        Ok(DebugCall { prog, vao, loc })
    }
}

impl Scene for DebugCall {
    fn render(&mut self, gl: &Gl, frame: u64, v: &View) {
        let p = v.projection(math::perspective(45f32.to_radians(), v.aspect(), 0.1, 100.0));
        let view: Mat4 = math::look_at(EYE, [0.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        let model = math::rotate(seconds(frame), [0.0, 1.0, 0.0]);
        unsafe {
            gl.Viewport(v.viewport[0], v.viewport[1], v.viewport[2], v.viewport[3]);
            gl.ClearColor(0.1, 0.12, 0.18, 1.0);
            gl.Enable(gl::DEPTH_TEST);
            gl.Clear(gl::COLOR_BUFFER_BIT | gl::DEPTH_BUFFER_BIT);
            gl.UseProgram(self.prog);
            gl.UniformMatrix4fv(self.loc[0], 1, gl::FALSE, p.as_ptr());
            gl.UniformMatrix4fv(self.loc[1], 1, gl::FALSE, view.as_ptr());
            gl.UniformMatrix4fv(self.loc[2], 1, gl::FALSE, model.as_ptr());
            gl.BindVertexArray(self.vao);
            gl.DrawArrays(gl::TRIANGLES, 0, 36);
            // The callback runs inside this call (GL records the error after it returns).
            gl.DrawArrays(BAD_MODE, 0, 36);
            gl.GetError();
        }
    }

    fn finish(&mut self, _frame_ms: &[f64]) {
        eprintln!("debugcall: messages={}", MESSAGES.load(Ordering::Relaxed));
    }
}

fn main() -> ExitCode {
    let info = AppInfo {
        name: "debugcall",
        about: "GL 3.3 core cube whose synchronous debug callback calls GL from inside a draw",
        default_convergence: math::distance(EYE, [0.0, 0.0, 0.0]),
        extra: &[],
        switches: &[],
    };
    holoapps::run::main(
        &info,
        Profile::Core33,
        Box::new(|gl: &Gl, _: &Options| Ok(Box::new(DebugCall::new(gl)?) as Box<dyn Scene>)),
    )
}
