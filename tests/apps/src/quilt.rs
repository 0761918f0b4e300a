//! Ground-truth quilt: every view of one frame rendered into an offscreen FBO.
use crate::cli::Options;
use crate::gl::{self, Gl};
use crate::image;
use crate::scene::{Scene, Shear, View};

struct Fbo {
    fbo: u32,
    rbs: [u32; 2],
}

fn create_fbo(gl: &Gl, w: i32, h: i32) -> Result<Fbo, String> {
    let mut f = Fbo { fbo: 0, rbs: [0; 2] };
    unsafe {
        gl.GenFramebuffers(1, &mut f.fbo);
        gl.BindFramebuffer(gl::FRAMEBUFFER, f.fbo);
        gl.GenRenderbuffers(2, f.rbs.as_mut_ptr());
        let attach = [
            (gl::RGBA8, gl::COLOR_ATTACHMENT0),
            (gl::DEPTH24_STENCIL8, gl::DEPTH_STENCIL_ATTACHMENT),
        ];
        for (rb, (format, point)) in f.rbs.iter().zip(attach) {
            gl.BindRenderbuffer(gl::RENDERBUFFER, *rb);
            gl.RenderbufferStorage(gl::RENDERBUFFER, format, w, h);
            gl.FramebufferRenderbuffer(gl::FRAMEBUFFER, point, gl::RENDERBUFFER, *rb);
        }
        let status = gl.CheckFramebufferStatus(gl::FRAMEBUFFER);
        if status != gl::FRAMEBUFFER_COMPLETE {
            delete_fbo(gl, &f);
            return Err(format!("quilt framebuffer {w}x{h} incomplete (0x{status:04X})"));
        }
    }
    Ok(f)
}

fn delete_fbo(gl: &Gl, f: &Fbo) {
    unsafe {
        gl.BindFramebuffer(gl::FRAMEBUFFER, 0);
        gl.DeleteRenderbuffers(2, f.rbs.as_ptr());
        gl.DeleteFramebuffers(1, &f.fbo);
    }
}

/// Viewport of view `i`: column i mod C, row i / C counted from the bottom.
pub fn tile_rect(i: u32, cols: u32, tile: (u32, u32)) -> [i32; 4] {
    let (x, y) = (i % cols, i / cols);
    [(x * tile.0) as i32, (y * tile.1) as i32, tile.0 as i32, tile.1 as i32]
}

pub fn render(gl: &Gl, scene: &mut dyn Scene, frame: u64, o: &Options) -> Result<(), String> {
    let (cols, rows) = o.quilt.expect("quilt mode");
    let (w, h) = (cols * o.tile.0, rows * o.tile.1);
    let fbo = create_fbo(gl, w as i32, h as i32)?;
    let n = (cols * rows) as usize;
    for i in 0..n {
        let viewport = tile_rect(i as u32, cols, o.tile);
        let shear = Shear {
            index: i,
            count: n,
            depthiness: o.depthiness,
            convergence: o.convergence,
            focus: o.focus,
        };
        unsafe {
            // Scissor keeps each view's glClear inside its own tile.
            gl.Enable(gl::SCISSOR_TEST);
            gl.Scissor(viewport[0], viewport[1], viewport[2], viewport[3]);
        }
        scene.render(
            gl,
            frame,
            &View {
                viewport,
                shear: Some(shear),
            },
        );
    }
    let rgb = unsafe {
        gl.Disable(gl::SCISSOR_TEST);
        // COLOR_ATTACHMENT0 is the FBO default anyway; ES 2.0 lacks the call.
        if !image::is_es(gl) {
            gl.ReadBuffer(gl::COLOR_ATTACHMENT0);
        }
        image::read_rgb(gl, w, h)
    };
    delete_fbo(gl, &fbo);
    image::write_png(o.out.as_ref().unwrap(), w, h, &rgb)
}
