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
    render_views(gl, scene, frame, o, (cols, rows));
    read_back_and_write(gl, fbo, o, w, h)
}

/// `--bench-quilt`: the app's own cost of a quilt, every frame, into one persistent FBO,
/// shown in the window like the layer's `--output quilt` (so both pay for the final blit).
pub struct BenchQuilt {
    fbo: Fbo,
    size: (i32, i32),
}

impl BenchQuilt {
    pub fn new(gl: &Gl, o: &Options) -> Result<BenchQuilt, String> {
        let (cols, rows) = o.quilt.ok_or("--bench-quilt needs --reference-quilt CxR")?;
        let size = ((cols * o.tile.0) as i32, (rows * o.tile.1) as i32);
        Ok(BenchQuilt {
            fbo: create_fbo(gl, size.0, size.1)?,
            size,
        })
    }

    pub fn frame(&self, gl: &Gl, scene: &mut dyn Scene, frame: u64, o: &Options, window: (u32, u32)) {
        unsafe { gl.BindFramebuffer(gl::FRAMEBUFFER, self.fbo.fbo) };
        render_views(gl, scene, frame, o, o.quilt.unwrap());
        unsafe {
            gl.Disable(gl::SCISSOR_TEST);
            gl.BindFramebuffer(gl::READ_FRAMEBUFFER, self.fbo.fbo);
            gl.BindFramebuffer(gl::DRAW_FRAMEBUFFER, 0);
            let (w, h) = (window.0 as i32, window.1 as i32);
            gl.BlitFramebuffer(
                0,
                0,
                self.size.0,
                self.size.1,
                0,
                0,
                w,
                h,
                gl::COLOR_BUFFER_BIT,
                gl::LINEAR,
            );
            gl.BindFramebuffer(gl::FRAMEBUFFER, 0);
        }
    }
}

fn render_views(gl: &Gl, scene: &mut dyn Scene, frame: u64, o: &Options, (cols, rows): (u32, u32)) {
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
}

fn read_back_and_write(gl: &Gl, fbo: Fbo, o: &Options, w: u32, h: u32) -> Result<(), String> {
    let rgb = unsafe {
        gl.Disable(gl::SCISSOR_TEST);
        // COLOR_ATTACHMENT0 is the FBO default anyway; ES 2.0 lacks the call.
        if !image::is_es(gl) {
            gl.ReadBuffer(gl::COLOR_ATTACHMENT0);
        }
        image::read_rgb(gl, w, h)
    };
    // Ground truth for the layer's depth: llvmpipe rounds depth differently in FBOs and
    // window surfaces, and the layer, like this quilt, renders views into an FBO's tiles.
    let depth = o
        .reference_depth_out
        .as_ref()
        .map(|_| image::read_depth(gl, w, h))
        .transpose()?;
    delete_fbo(gl, &fbo);
    if let (Some(path), Some(depth)) = (&o.reference_depth_out, depth) {
        image::write_f32(path, &depth)?;
    }
    image::write_png(o.out.as_ref().unwrap(), w, h, &rgb)
}
