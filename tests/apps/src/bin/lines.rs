//! `lines`: OpenGL 1.x drawing that a window rasterises differently from a framebuffer
//! object: a spinning wire globe of thin smooth lines (`GL_LINE_SMOOTH`, width 0.3, blended,
//! as xscreensaver's hacks draw them), smooth points, a textured floor and a 2:1 minified
//! texture, a HUD strip coloured from `gl_FragCoord` (GLSL 1.20), and a HUD quad blended by
//! destination alpha (it shows only where the window has alpha bits). Run with the common
//! `--samples N`, `--no-alpha` and `--srgb` switches for the other window formats.
use holoapps::cli::{AppInfo, Options};
use holoapps::gl::{self, Gl};
use holoapps::platform::Profile;
use holoapps::scene::{Scene, View, seconds};
use std::process::ExitCode;

const EYE_Z: f32 = 6.0;
/// Texels of the HUD texture per window pixel along each axis.
const MINIFICATION: usize = 2;

const FRAGCOORD_VS: &str = "#version 120
void main() { gl_Position = ftransform(); }
";
const FRAGCOORD_FS: &str = "#version 120
void main() { gl_FragColor = vec4(fract(gl_FragCoord.xy / vec2(13.0, 7.0)), 0.6, 1.0); }
";

struct Lines {
    floor: u32,
    hud: (u32, usize),
    fragcoord: u32,
}

/// A deterministic pseudo-random byte per index.
fn noise(i: usize) -> u8 {
    let x = (i as u32).wrapping_mul(2_654_435_761) ^ 0x9e37_79b9;
    (x.wrapping_mul(0x85eb_ca6b) >> 24) as u8
}

unsafe fn texture(gl: &Gl, size: usize, texel: impl Fn(usize, usize) -> [u8; 4]) -> u32 {
    let data: Vec<u8> = (0..size * size).flat_map(|i| texel(i % size, i / size)).collect();
    let mut t = 0;
    unsafe {
        gl.GenTextures(1, &mut t);
        gl.BindTexture(gl::TEXTURE_2D, t);
        let (s, fmt) = (size as i32, gl::RGBA);
        gl.TexImage2D(
            gl::TEXTURE_2D,
            0,
            gl::RGBA8 as i32,
            s,
            s,
            0,
            fmt,
            gl::UNSIGNED_BYTE,
            data.as_ptr().cast(),
        );
        gl.TexParameteri(gl::TEXTURE_2D, gl::TEXTURE_MIN_FILTER, gl::LINEAR as i32);
        gl.TexParameteri(gl::TEXTURE_2D, gl::TEXTURE_MAG_FILTER, gl::LINEAR as i32);
    }
    t
}

impl Lines {
    fn new(gl: &Gl) -> Result<Self, String> {
        let hud_px = 96;
        unsafe {
            let floor = texture(gl, 64, |x, y| {
                let c = if (x / 8 + y / 8) % 2 == 0 { 200 } else { 60 };
                [c, c, c / 2 + noise(x + 64 * y) / 4, 255]
            });
            let n = hud_px * MINIFICATION;
            let hud = texture(gl, n, |x, y| {
                [noise(x + n * y), noise(3 * x + y), noise(x ^ (y << 8)), 255]
            });
            let fragcoord = holoapps::shader::program(gl, FRAGCOORD_VS, FRAGCOORD_FS)?;
            Ok(Lines {
                floor,
                hud: (hud, hud_px),
                fragcoord,
            })
        }
    }

    unsafe fn projection(gl: &Gl, v: &View) {
        let top = 0.1 * 25f32.to_radians().tan();
        let right = top * v.aspect();
        unsafe {
            gl.MatrixMode(gl::PROJECTION);
            gl.LoadIdentity();
            gl.Frustum(-right as f64, right as f64, -top as f64, top as f64, 0.1, 50.0);
            if v.shear.is_some() {
                let mut p = [0f32; 16];
                gl.GetFloatv(gl::PROJECTION_MATRIX, p.as_mut_ptr());
                gl.LoadMatrixf(v.projection(p).as_ptr());
            }
            gl.MatrixMode(gl::MODELVIEW);
            gl.LoadIdentity();
            gl.Translatef(0.0, -0.3, -EYE_Z);
            gl.Rotatef(20.0, 1.0, 0.0, 0.0);
        }
    }

    unsafe fn floor(&self, gl: &Gl) {
        unsafe {
            gl.Enable(gl::TEXTURE_2D);
            gl.BindTexture(gl::TEXTURE_2D, self.floor);
            gl.Color3f(1.0, 1.0, 1.0);
            gl.Begin(gl::QUADS);
            for (s, t, x, z) in [
                (0.0, 0.0, -8.0, -8.0),
                (6.0, 0.0, 8.0, -8.0),
                (6.0, 6.0, 8.0, 8.0),
                (0.0, 6.0, -8.0, 8.0),
            ] {
                gl.TexCoord2f(s, t);
                gl.Vertex3f(x, -1.2, z);
            }
            gl.End();
            gl.Disable(gl::TEXTURE_2D);
        }
    }

    /// Latitude and longitude circles of a unit sphere, and a shell of smooth points.
    unsafe fn globe(gl: &Gl, t: f32) {
        let p = |lat: f32, lon: f32| (lat.cos() * lon.cos(), lat.sin(), lat.cos() * lon.sin());
        unsafe {
            gl.PushMatrix();
            gl.Rotatef(t * 25.0, 0.2, 1.0, 0.1);
            gl.Enable(gl::BLEND);
            gl.BlendFunc(gl::SRC_ALPHA, gl::ONE_MINUS_SRC_ALPHA);
            gl.Enable(gl::LINE_SMOOTH);
            gl.Hint(gl::LINE_SMOOTH_HINT, gl::DONT_CARE);
            gl.LineWidth(0.3);
            for k in 0..24 {
                let (a, b) = (k as f32 / 24.0, std::f32::consts::PI);
                gl.Color4f(0.3 + 0.7 * a, 0.9 - 0.5 * a, 1.0, 0.9);
                gl.Begin(gl::LINE_LOOP);
                for j in 0..96 {
                    let u = j as f32 / 96.0 * 2.0 * b;
                    let (x, y, z) = if k < 12 {
                        p(u, a * 2.0 * b)
                    } else {
                        p((a - 0.75) * b, u)
                    };
                    gl.Vertex3f(x, y, z);
                }
                gl.End();
            }
            gl.Disable(gl::LINE_SMOOTH);
            gl.Enable(gl::POINT_SMOOTH);
            gl.PointSize(2.5);
            gl.Begin(gl::POINTS);
            for i in 0..400 {
                let (lat, lon) = (noise(i) as f32 / 255.0 * 3.0 - 1.5, noise(i + 999) as f32 / 40.0);
                gl.Color4f(1.0, 0.9, noise(i + 7) as f32 / 255.0, 1.0);
                let (x, y, z) = p(lat, lon);
                gl.Vertex3f(1.6 * x, 1.6 * y, 1.6 * z);
            }
            gl.End();
            gl.Disable(gl::POINT_SMOOTH);
            gl.Disable(gl::BLEND);
            gl.PopMatrix();
        }
    }

    /// Orthographic: the minified texture, the `gl_FragCoord` strip and the quad that only
    /// destination alpha below one lets through.
    unsafe fn hud(&self, gl: &Gl, v: &View) {
        let (w, h) = v.size();
        let s = self.hud.1 as f32;
        unsafe {
            gl.MatrixMode(gl::PROJECTION);
            gl.LoadIdentity();
            gl.Ortho(0.0, w as f64, 0.0, h as f64, -1.0, 1.0);
            gl.MatrixMode(gl::MODELVIEW);
            gl.LoadIdentity();
            gl.Enable(gl::TEXTURE_2D);
            gl.BindTexture(gl::TEXTURE_2D, self.hud.0);
            gl.Color3f(1.0, 1.0, 1.0);
            gl.Begin(gl::QUADS);
            for (u, t) in [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)] {
                gl.TexCoord2f(u, t);
                gl.Vertex2f(8.0 + u * s, 8.0 + t * s);
            }
            gl.End();
            gl.Disable(gl::TEXTURE_2D);
            gl.UseProgram(self.fragcoord);
            gl.Rectf(w - 8.0 - s, 8.0, w - 8.0, 8.0 + s / 3.0);
            gl.UseProgram(0);
            gl.Enable(gl::BLEND);
            gl.BlendFunc(gl::ONE_MINUS_DST_ALPHA, gl::ONE);
            gl.Color3f(0.0, 0.5, 0.0);
            gl.Rectf(w - 8.0 - s, h - 8.0 - s / 3.0, w - 8.0, h - 8.0);
            gl.Disable(gl::BLEND);
        }
    }
}

impl Scene for Lines {
    fn render(&mut self, gl: &Gl, frame: u64, v: &View) {
        let t = seconds(frame);
        unsafe {
            gl.Viewport(v.viewport[0], v.viewport[1], v.viewport[2], v.viewport[3]);
            // Alpha 0 where nothing is drawn: the HUD's last quad shows there, with alpha bits.
            gl.ClearColor(0.02, 0.03, 0.08, 0.0);
            gl.Clear(gl::COLOR_BUFFER_BIT | gl::DEPTH_BUFFER_BIT);
            Self::projection(gl, v);
            self.floor(gl);
            Self::globe(gl, t);
            self.hud(gl, v);
        }
    }
}

fn main() -> ExitCode {
    let info = AppInfo {
        name: "lines",
        about: "OpenGL 1.x thin smooth lines, smooth points, minified textures, gl_FragCoord and destination alpha",
        default_convergence: EYE_Z,
        extra: &[],
        switches: &[],
    };
    holoapps::run::main(
        &info,
        Profile::Legacy,
        Box::new(|gl: &Gl, _: &Options| Ok(Box::new(Lines::new(gl)?) as Box<dyn Scene>)),
    )
}
