//! `legacy`: OpenGL 1.x fixed-function app (compat context): glFrustum, immediate mode,
//! nested display lists (one moving the current matrix), client vertex arrays with texgen,
//! fog, lighting, a `GL_SELECT` picking pass, and a glOrtho HUD with `glBitmap` text.
//! `--sky` adds a sky box drawn around the eye first, as fixed-function racing games draw
//! theirs: a unit cube under the camera's rotation alone (no translation), depth writes off;
//! the reference quilt draws it at infinity (`View::projection_at_infinity`), where a viewer
//! expects a sky.
use holoapps::cli::{AppInfo, Options};
use holoapps::gl::{self, Gl};
use holoapps::legacy_extras::{self, Extras};
use holoapps::platform::Profile;
use holoapps::scene::{Scene, View, seconds};
use holoapps::weapon::{self, Weapon};
use std::process::ExitCode;

/// Camera 5 up and 12 back, pitched down to look at the origin (13 away).
const EYE_Y: f32 = 5.0;
const EYE_Z: f32 = 12.0;
const FOG: [f32; 4] = [0.55, 0.65, 0.75, 1.0];

struct Legacy {
    /// Outer list: turns the current matrix (outside any push/pop of its own, as xscreensaver's
    /// `engine` does) and calls the `ring` list, which calls the inner `pyramid` list several
    /// times.
    cluster: u32,
    extras: Extras,
    sky: bool,
    weapon: Weapon,
}

unsafe fn pyramid(gl: &Gl) {
    let apex = [0.0, 1.0, 0.0];
    let base = [[-0.5, 0.0, -0.5], [0.5, 0.0, -0.5], [0.5, 0.0, 0.5], [-0.5, 0.0, 0.5]];
    let colours = [[1.0, 0.3, 0.2], [0.2, 0.9, 0.3], [0.2, 0.4, 1.0], [1.0, 0.9, 0.2]];
    unsafe {
        gl.Begin(gl::TRIANGLES);
        for k in 0..4 {
            let (a, b) = (base[k], base[(k + 1) % 4]);
            let mid = [(a[0] + b[0]) / 2.0, 0.5, (a[2] + b[2]) / 2.0];
            gl.Normal3f(mid[0], mid[1], mid[2]);
            gl.Color3f(colours[k][0], colours[k][1], colours[k][2]);
            for p in [a, b, apex] {
                gl.Vertex3f(p[0], p[1], p[2]);
            }
        }
        gl.End();
    }
}

impl Legacy {
    fn new(gl: &Gl, sky: bool) -> Result<Self, String> {
        unsafe {
            let base = gl.GenLists(3);
            if base == 0 {
                return Err("glGenLists failed".into());
            }
            gl.NewList(base, gl::COMPILE);
            pyramid(gl);
            gl.EndList();
            gl.NewList(base + 1, gl::COMPILE);
            for k in 0..6 {
                let a = k as f32 * 60.0;
                gl.PushMatrix();
                gl.Rotatef(a, 0.0, 1.0, 0.0);
                gl.Translatef(3.0, 0.0, 0.0);
                gl.Rotatef(a * 2.0, 0.0, 1.0, 0.0);
                gl.Scalef(1.0, 1.0 + (k % 3) as f32 * 0.6, 1.0);
                gl.CallList(base);
                gl.PopMatrix();
            }
            gl.EndList();
            gl.NewList(base + 2, gl::COMPILE);
            gl.Rotatef(15.0, 0.0, 1.0, 0.0);
            gl.CallList(base + 1);
            gl.EndList();
            Ok(Legacy {
                cluster: base + 2,
                extras: Extras::new(gl),
                sky,
                weapon: Weapon::None,
            })
        }
    }

    /// Multiplies the app's frustum onto the current matrix.
    unsafe fn frustum(gl: &Gl, aspect: f32) {
        let top = 0.1 * (22.5f32).to_radians().tan();
        let right = top * aspect;
        unsafe { gl.Frustum(-right as f64, right as f64, -top as f64, top as f64, 0.1, 100.0) };
    }

    /// The frustum; in the reference quilt, its shear for the view (`at_infinity`: the
    /// shear of infinity, for the sky).
    unsafe fn projection(gl: &Gl, v: &View, at_infinity: bool) {
        unsafe {
            gl.MatrixMode(gl::PROJECTION);
            gl.LoadIdentity();
            Self::frustum(gl, v.aspect());
            if v.shear.is_some() {
                let mut p = [0f32; 16];
                gl.GetFloatv(gl::PROJECTION_MATRIX, p.as_mut_ptr());
                let sheared = if at_infinity {
                    v.projection_at_infinity(p)
                } else {
                    v.projection(p)
                };
                gl.LoadMatrixf(sheared.as_ptr());
            }
        }
    }

    /// The camera's pitch, the rotation the sky box shares with the world.
    fn pitch() -> f32 {
        EYE_Y.atan2(EYE_Z).to_degrees()
    }

    /// A sky box around the eye: each face a 16x16 checker of two blues graded by height, so
    /// that every part of it has texture to be found again in another view.
    unsafe fn sky(gl: &Gl, v: &View) {
        unsafe {
            Self::projection(gl, v, true);
            gl.MatrixMode(gl::MODELVIEW);
            gl.LoadIdentity();
            gl.Rotatef(Self::pitch(), 1.0, 0.0, 0.0);
            gl.Disable(gl::LIGHTING);
            gl.Disable(gl::FOG);
            gl.Enable(gl::DEPTH_TEST);
            gl.DepthMask(gl::FALSE);
            gl.Begin(gl::QUADS);
            // Faces as (origin, u axis, v axis) of the cube [-1, 1]^3.
            let faces: [([f32; 3], [f32; 3], [f32; 3]); 6] = [
                ([-1.0, -1.0, -1.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]),
                ([1.0, -1.0, 1.0], [-2.0, 0.0, 0.0], [0.0, 2.0, 0.0]),
                ([-1.0, -1.0, 1.0], [0.0, 0.0, -2.0], [0.0, 2.0, 0.0]),
                ([1.0, -1.0, -1.0], [0.0, 0.0, 2.0], [0.0, 2.0, 0.0]),
                ([-1.0, 1.0, -1.0], [2.0, 0.0, 0.0], [0.0, 0.0, 2.0]),
                ([-1.0, -1.0, 1.0], [2.0, 0.0, 0.0], [0.0, 0.0, -2.0]),
            ];
            const N: usize = 16;
            for (o, a, b) in faces {
                for i in 0..N {
                    for j in 0..N {
                        let at = |di: usize, dj: usize| {
                            let (s, t) = ((i + di) as f32 / N as f32, (j + dj) as f32 / N as f32);
                            [0, 1, 2].map(|k| o[k] + a[k] * s + b[k] * t)
                        };
                        let corner = at(0, 0);
                        let light = if (i + j) % 2 == 0 { 0.85 } else { 0.6 };
                        let height = 0.5 + 0.5 * corner[1];
                        gl.Color3f(0.3 * light, (0.5 + 0.3 * height) * light, light);
                        for (di, dj) in [(0, 0), (1, 0), (1, 1), (0, 1)] {
                            let p = at(di, dj);
                            gl.Vertex3f(p[0], p[1], p[2]);
                        }
                    }
                }
            }
            gl.End();
            gl.DepthMask(gl::TRUE);
        }
    }

    /// `--weapon`: the box before the eye, in immediate mode under the scene's projection.
    unsafe fn weapon(gl: &Gl, w: Weapon) {
        let (near, far) = weapon::depth_range(w);
        let (c, h) = (weapon::CENTRE, weapon::HALF);
        unsafe {
            gl.MatrixMode(gl::MODELVIEW);
            gl.PushMatrix();
            gl.LoadIdentity();
            gl.Translatef(c[0], c[1], c[2]);
            gl.Scalef(h[0], h[1], h[2]);
            gl.Disable(gl::FOG);
            let alpha = weapon::alpha(w);
            gl.Color4f(0.8, 0.75, 0.7, alpha.unwrap_or(1.0));
            if alpha.is_some() {
                gl.Enable(gl::BLEND);
                gl.BlendFunc(gl::SRC_ALPHA, gl::ONE_MINUS_SRC_ALPHA);
                gl.DepthMask(gl::FALSE);
                // One layer of glass, as a game draws a translucent mesh: its far side would
                // otherwise be blended over its near side.
                gl.Enable(gl::CULL_FACE);
            }
            gl.DepthRange(near, far);
            gl.Begin(gl::QUADS);
            for axis in 0..3 {
                for sign in [-1.0f32, 1.0] {
                    let mut n = [0.0f32; 3];
                    n[axis] = sign;
                    let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
                    gl.Normal3f(n[0], n[1], n[2]);
                    for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                        let mut p = n;
                        p[u] = a;
                        p[v] = b * sign;
                        gl.Vertex3f(p[0], p[1], p[2]);
                    }
                }
            }
            gl.End();
            if alpha.is_some() {
                gl.DepthMask(gl::TRUE);
                gl.Disable(gl::BLEND);
                gl.Disable(gl::CULL_FACE);
            }
            gl.DepthRange(0.0, 1.0);
            gl.Enable(gl::FOG);
            gl.PopMatrix();
        }
    }

    unsafe fn setup_world(gl: &Gl) {
        unsafe {
            gl.MatrixMode(gl::MODELVIEW);
            gl.LoadIdentity();
            gl.Rotatef(Self::pitch(), 1.0, 0.0, 0.0);
            gl.Translatef(0.0, -EYE_Y, -EYE_Z);
            gl.Enable(gl::DEPTH_TEST);
            gl.Enable(gl::LIGHTING);
            gl.Enable(gl::LIGHT0);
            gl.Enable(gl::NORMALIZE);
            gl.Enable(gl::COLOR_MATERIAL);
            gl.Lightfv(gl::LIGHT0, gl::POSITION, [0.5, 1.0, 0.7, 0.0].as_ptr());
            gl.Enable(gl::FOG);
            gl.Fogi(gl::FOG_MODE, gl::LINEAR as i32);
            gl.Fogf(gl::FOG_START, 10.0);
            gl.Fogf(gl::FOG_END, 35.0);
            gl.Fogfv(gl::FOG_COLOR, FOG.as_ptr());
        }
    }

    /// Checkerboard floor far enough back for the fog to show.
    unsafe fn floor(gl: &Gl) {
        unsafe {
            gl.Begin(gl::QUADS);
            gl.Normal3f(0.0, 1.0, 0.0);
            for i in -12..12 {
                for j in -20..8 {
                    let c = if (i + j) % 2 == 0 { 0.8 } else { 0.3 };
                    gl.Color3f(c, c, c * 0.9);
                    let (x, z) = (i as f32 * 1.5, j as f32 * 1.5);
                    gl.Vertex3f(x, 0.0, z);
                    gl.Vertex3f(x, 0.0, z + 1.5);
                    gl.Vertex3f(x + 1.5, 0.0, z + 1.5);
                    gl.Vertex3f(x + 1.5, 0.0, z);
                }
            }
            gl.End();
        }
    }

    unsafe fn hud(gl: &Gl, v: &View, t: f32, pick: (i32, Option<u32>)) {
        let (w, h) = v.size();
        unsafe {
            gl.Disable(gl::LIGHTING);
            gl.Disable(gl::FOG);
            gl.Disable(gl::DEPTH_TEST);
            gl.MatrixMode(gl::PROJECTION);
            gl.LoadIdentity();
            gl.Ortho(0.0, w as f64, 0.0, h as f64, -1.0, 1.0);
            gl.MatrixMode(gl::MODELVIEW);
            gl.LoadIdentity();
            let bars = [[0.9, 0.2, 0.2], [0.2, 0.8, 0.2], [0.2, 0.4, 0.9]];
            for (k, c) in bars.iter().enumerate() {
                let len = (0.2 + 0.15 * (t * (k + 1) as f32).sin().abs()) * w;
                let y = h - 20.0 - k as f32 * 16.0;
                gl.Color3f(c[0], c[1], c[2]);
                gl.Rectf(10.0, y, 10.0 + len, y + 10.0);
            }
            gl.Color3f(1.0, 1.0, 1.0);
            gl.Rectf(w - 40.0, 10.0, w - 10.0, 40.0);
            // Raster position relative to the viewport origin (tiles in the reference quilt).
            let picked = pick.1.map_or("-".to_string(), |n| n.to_string());
            legacy_extras::text(gl, 10.0, 12.0, &format!("HITS {} {}", pick.0, picked));
        }
    }
}

impl Scene for Legacy {
    fn render(&mut self, gl: &Gl, frame: u64, v: &View) {
        let t = seconds(frame);
        // Picking sees the app's own window and unsheared camera, in every view alike.
        let (w, h) = v.size();
        let pick = self.extras.pick(
            gl,
            (w, h),
            t,
            || unsafe { Self::setup_world(gl) },
            || unsafe { Self::frustum(gl, w / h) },
        );
        unsafe {
            gl.Viewport(v.viewport[0], v.viewport[1], v.viewport[2], v.viewport[3]);
            gl.ClearColor(FOG[0], FOG[1], FOG[2], FOG[3]);
            gl.Clear(gl::COLOR_BUFFER_BIT | gl::DEPTH_BUFFER_BIT);
            if self.sky {
                Self::sky(gl, v);
            }
            Self::projection(gl, v, false);
            Self::setup_world(gl);
            Self::floor(gl);
            gl.PushMatrix();
            gl.Rotatef(t * 30.0, 0.0, 1.0, 0.0);
            gl.CallList(self.cluster);
            gl.PopMatrix();
            // A spinning immediate-mode pyramid in the centre.
            gl.PushMatrix();
            gl.Translatef(0.0, 0.5, 0.0);
            gl.Rotatef(t * -90.0, 0.0, 1.0, 0.0);
            gl.Scalef(1.5, 2.0, 1.5);
            pyramid(gl);
            gl.PopMatrix();
            self.extras.ring(gl, t, pick.1);
            if self.weapon != Weapon::None {
                Self::weapon(gl, self.weapon);
            }
            Self::hud(gl, v, t, pick);
        }
    }
}

fn main() -> ExitCode {
    let info = AppInfo {
        name: "legacy",
        about: "OpenGL 1.x fixed-function scene: immediate mode, display lists, fog, lighting, glOrtho HUD",
        default_convergence: (EYE_Y * EYE_Y + EYE_Z * EYE_Z).sqrt(),
        extra: &[weapon::OPTION],
        switches: &[(
            "sky",
            "a sky box drawn around the eye before the scene, depth writes off",
        )],
    };
    holoapps::run::main(
        &info,
        Profile::Legacy,
        Box::new(|gl: &Gl, o: &Options| {
            let mut app = Legacy::new(gl, o.switches.contains("sky"))?;
            app.weapon = weapon::parse(&o.extra["weapon"])?;
            Ok(Box::new(app) as Box<dyn Scene>)
        }),
    )
}
