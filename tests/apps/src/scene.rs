//! What an app implements, and what the runner tells it about each view.
use crate::camera::{sheared_projection, sheared_projection_at_infinity};
use crate::gl::Gl;
use crate::math::Mat4;

/// Light-field parameters of one quilt view.
#[derive(Clone, Copy, Debug)]
pub struct Shear {
    pub index: usize,
    pub count: usize,
    pub depthiness: f32,
    pub convergence: f32,
    pub focus: f32,
}

#[derive(Clone, Copy, Debug)]
pub struct View {
    /// x, y, w, h in the currently bound framebuffer.
    pub viewport: [i32; 4],
    /// None for a normal frame.
    pub shear: Option<Shear>,
}

impl View {
    pub fn size(&self) -> (f32, f32) {
        (self.viewport[2] as f32, self.viewport[3] as f32)
    }

    pub fn aspect(&self) -> f32 {
        self.viewport[2] as f32 / self.viewport[3] as f32
    }

    /// The projection this view must use in place of the app's `p`.
    pub fn projection(&self, p: Mat4) -> Mat4 {
        match self.shear {
            None => p,
            Some(s) => sheared_projection(p, s.index, s.count, s.depthiness, s.convergence, s.focus),
        }
    }

    /// The projection for far-plane (`.xyww`) geometry such as skyboxes, which
    /// the layer shifts as if at infinity.
    pub fn projection_at_infinity(&self, p: Mat4) -> Mat4 {
        match self.shear {
            None => p,
            Some(s) => sheared_projection_at_infinity(p, s.index, s.count, s.depthiness, s.focus),
        }
    }
}

pub trait Scene {
    /// Draw one complete frame (clear included) for `frame`; time is
    /// frame / 60 s so runs are deterministic.
    fn render(&mut self, gl: &Gl, frame: u64, view: &View);

    /// Called once at exit with the per-frame CPU times in milliseconds.
    fn finish(&mut self, _frame_ms: &[f64]) {}
}

pub fn seconds(frame: u64) -> f32 {
    frame as f32 / 60.0
}
