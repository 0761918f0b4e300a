//! The rest of the fixed-function feature set `legacy` exercises: client vertex arrays with
//! object-linear texgen on a texture, `glBitmap` text, and a `GL_SELECT` picking pass whose
//! result is drawn (so a layer that broke picking would change the image).

use crate::gl::{self, Gl};

/// A unit cube as 24 vertices (6 quads) with normals: positions then normals.
fn cube_arrays() -> (Vec<f32>, Vec<f32>) {
    let faces: [([f32; 3], [f32; 3], [f32; 3]); 6] = [
        ([0., 0., 1.], [1., 0., 0.], [0., 1., 0.]),
        ([0., 0., -1.], [-1., 0., 0.], [0., 1., 0.]),
        ([1., 0., 0.], [0., 0., -1.], [0., 1., 0.]),
        ([-1., 0., 0.], [0., 0., 1.], [0., 1., 0.]),
        ([0., 1., 0.], [1., 0., 0.], [0., 0., -1.]),
        ([0., -1., 0.], [1., 0., 0.], [0., 0., 1.]),
    ];
    let (mut pos, mut nrm) = (vec![], vec![]);
    for (n, u, v) in faces {
        for (a, b) in [(-1., -1.), (1., -1.), (1., 1.), (-1., 1.)] {
            for k in 0..3 {
                pos.push(0.5 * (n[k] + a * u[k] + b * v[k]));
            }
            nrm.extend_from_slice(&n);
        }
    }
    (pos, nrm)
}

pub struct Extras {
    positions: Vec<f32>,
    normals: Vec<f32>,
    texture: u32,
    select: Vec<u32>,
}

/// Where the ring cube `k` of `RING` sits.
const RING: usize = 8;

fn ring_place(gl: &Gl, k: usize, t: f32) {
    let a = k as f32 / RING as f32 * std::f32::consts::TAU + t * 0.4;
    unsafe {
        gl.Translatef(5.5 * a.cos(), 0.6, 5.5 * a.sin() - 1.0);
        gl.Rotatef(t * 50.0 + k as f32 * 20.0, 0.3, 1.0, 0.0);
        gl.Scalef(0.9, 0.9, 0.9);
    }
}

impl Extras {
    pub fn new(gl: &Gl) -> Extras {
        let (positions, normals) = cube_arrays();
        let mut texture = 0;
        let texels: Vec<u8> = (0..64)
            .flat_map(|i| {
                if (i % 8 + i / 8) % 2 == 0 {
                    [240, 200, 60]
                } else {
                    [60, 40, 160]
                }
            })
            .collect();
        unsafe {
            gl.GenTextures(1, &mut texture);
            gl.BindTexture(gl::TEXTURE_2D, texture);
            gl.TexParameteri(gl::TEXTURE_2D, gl::TEXTURE_MIN_FILTER, gl::NEAREST as i32);
            gl.TexParameteri(gl::TEXTURE_2D, gl::TEXTURE_MAG_FILTER, gl::NEAREST as i32);
            gl.PixelStorei(gl::UNPACK_ALIGNMENT, 1);
            gl.TexImage2D(
                gl::TEXTURE_2D,
                0,
                gl::RGB as i32,
                8,
                8,
                0,
                gl::RGB,
                gl::UNSIGNED_BYTE,
                texels.as_ptr().cast(),
            );
            gl.BindTexture(gl::TEXTURE_2D, 0);
        }
        Extras {
            positions,
            normals,
            texture,
            select: vec![0; 256],
        }
    }

    unsafe fn draw_cube(&self, gl: &Gl) {
        unsafe {
            gl.EnableClientState(gl::VERTEX_ARRAY);
            gl.EnableClientState(gl::NORMAL_ARRAY);
            gl.VertexPointer(3, gl::FLOAT, 0, self.positions.as_ptr().cast());
            gl.NormalPointer(gl::FLOAT, 0, self.normals.as_ptr().cast());
            gl.DrawArrays(gl::QUADS, 0, 24);
            gl.DisableClientState(gl::NORMAL_ARRAY);
            gl.DisableClientState(gl::VERTEX_ARRAY);
        }
    }

    /// Picks at a point that sweeps across the window; returns the hit count and the name
    /// of the nearest hit. `frustum` loads the app's projection into the current matrix.
    pub fn pick(
        &mut self,
        gl: &Gl,
        window: (f32, f32),
        t: f32,
        world: impl Fn(),
        frustum: impl Fn(),
    ) -> (i32, Option<u32>) {
        let (px, py) = (window.0 * (0.5 + 0.35 * (t * 0.7).sin()), window.1 * 0.45);
        let (w, h) = (8.0, 8.0);
        unsafe {
            gl.Viewport(0, 0, window.0 as i32, window.1 as i32);
            gl.SelectBuffer(self.select.len() as i32, self.select.as_mut_ptr());
            gl.RenderMode(gl::SELECT);
            gl.InitNames();
            gl.PushName(u32::MAX);
            gl.MatrixMode(gl::PROJECTION);
            gl.LoadIdentity();
            // gluPickMatrix(px, py, w, h, viewport)
            gl.Translatef((window.0 - 2.0 * px) / w, (window.1 - 2.0 * py) / h, 0.0);
            gl.Scalef(window.0 / w, window.1 / h, 1.0);
            frustum();
            world();
            for k in 0..RING {
                gl.LoadName(k as u32);
                gl.PushMatrix();
                ring_place(gl, k, t);
                self.draw_cube(gl);
                gl.PopMatrix();
            }
            let hits = gl.RenderMode(gl::RENDER);
            (hits, self.nearest(hits))
        }
    }

    fn nearest(&self, hits: i32) -> Option<u32> {
        let (mut i, mut best) = (0usize, None::<(u32, u32)>);
        for _ in 0..hits.max(0) {
            let names = self.select[i] as usize;
            let zmin = self.select[i + 1];
            if names > 0 && best.is_none_or(|(z, _)| zmin < z) {
                best = Some((zmin, self.select[i + 3 + names - 1]));
            }
            i += 3 + names;
        }
        best.map(|(_, n)| n)
    }

    /// The ring of textured (object-linear texgen) vertex-array cubes; `picked` is white.
    pub fn ring(&self, gl: &Gl, t: f32, picked: Option<u32>) {
        unsafe {
            gl.Enable(gl::TEXTURE_2D);
            gl.BindTexture(gl::TEXTURE_2D, self.texture);
            for (coord, plane) in [(gl::S, [1.0f32, 0.0, 0.0, 0.5]), (gl::T, [0.0, 1.0, 0.0, 0.5])] {
                gl.TexGeni(coord, gl::TEXTURE_GEN_MODE, gl::OBJECT_LINEAR as i32);
                gl.TexGenfv(coord, gl::OBJECT_PLANE, plane.as_ptr());
            }
            gl.Enable(gl::TEXTURE_GEN_S);
            gl.Enable(gl::TEXTURE_GEN_T);
            for k in 0..RING {
                let c = if picked == Some(k as u32) { 1.0 } else { 0.7 };
                gl.Color3f(c, c, c);
                gl.PushMatrix();
                ring_place(gl, k, t);
                self.draw_cube(gl);
                gl.PopMatrix();
            }
            gl.Disable(gl::TEXTURE_GEN_S);
            gl.Disable(gl::TEXTURE_GEN_T);
            gl.Disable(gl::TEXTURE_2D);
        }
    }
}

/// 5x7 glyphs for digits and a few letters, drawn with `glBitmap` (rows bottom-up).
fn glyph(c: char) -> [u8; 7] {
    let top_down: [u8; 7] = match c {
        '0' => [0x70, 0x88, 0x98, 0xA8, 0xC8, 0x88, 0x70],
        '1' => [0x20, 0x60, 0x20, 0x20, 0x20, 0x20, 0x70],
        '2' => [0x70, 0x88, 0x08, 0x10, 0x20, 0x40, 0xF8],
        '3' => [0xF8, 0x10, 0x20, 0x10, 0x08, 0x88, 0x70],
        '4' => [0x10, 0x30, 0x50, 0x90, 0xF8, 0x10, 0x10],
        '5' => [0xF8, 0x80, 0xF0, 0x08, 0x08, 0x88, 0x70],
        '6' => [0x30, 0x40, 0x80, 0xF0, 0x88, 0x88, 0x70],
        '7' => [0xF8, 0x08, 0x10, 0x20, 0x40, 0x40, 0x40],
        '8' => [0x70, 0x88, 0x88, 0x70, 0x88, 0x88, 0x70],
        '9' => [0x70, 0x88, 0x88, 0x78, 0x08, 0x10, 0x60],
        'H' => [0x88, 0x88, 0x88, 0xF8, 0x88, 0x88, 0x88],
        'I' => [0x70, 0x20, 0x20, 0x20, 0x20, 0x20, 0x70],
        'T' => [0xF8, 0x20, 0x20, 0x20, 0x20, 0x20, 0x20],
        'S' => [0x78, 0x80, 0x80, 0x70, 0x08, 0x08, 0xF0],
        _ => [0; 7],
    };
    let mut rows = top_down;
    rows.reverse();
    rows
}

/// Text at window position (x, y) with the current raster colour, one `glBitmap` per glyph.
pub fn text(gl: &Gl, x: f32, y: f32, s: &str) {
    unsafe {
        gl.PixelStorei(gl::UNPACK_ALIGNMENT, 1);
        gl.RasterPos2f(x, y);
        for c in s.chars() {
            let g = glyph(c);
            gl.Bitmap(5, 7, 0.0, 0.0, 7.0, 0.0, g.as_ptr());
        }
    }
}
