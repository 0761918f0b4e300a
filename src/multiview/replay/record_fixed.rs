//! The disparity record of fixed-function draws (DESIGN §5: fixed-function draws included).
//!
//! A fixed-function draw has no fragment shader to add an output to, so after it is drawn
//! into a view that records, it is drawn once more with a program of ours
//! (`record_fixed.vert`/`.frag`: `ftransform()`, invariant with the fixed function) that
//! writes the record's draw buffer alone, depth-tested `EQUAL` without writing depth: every
//! pixel the draw left visible gets the parallax its sheared projection gave it. Draws that
//! write no depth left none to match: they are drawn again under their own depth state,
//! which passes where it passed (they changed no depth), blended into the record by
//! coverage as the shader record is (the fixed function's alpha from unit 0's texture and the
//! colour or material: where it contributes at all, `≥ 1/255`). Those attached to the
//! camera (a sky around the eye, drawn first with depth writes or the depth test off, as
//! fixed-function games draw theirs) record infinity; translucent sprites and particles
//! their own disparity. Only draws whose replay has no side effects are recorded: vertex
//! arrays and the layer's own immediate-mode lists, not the app's display lists, which may
//! change state or matrices as they run.
//!
//! The alpha and stencil tests are off for the second draw (the depth already says which
//! pixels passed them; a stencil operation must not run twice), and everything it changes is
//! put back before the next view.

use crate::gl::guard::get_i;
use crate::gl::*;
use crate::shader::record::RECORD_BUFFER;
use std::cell::Cell;

const VERT: &str = include_str!("../../../glsl-patches/record_fixed.vert");
const FRAG: &str = include_str!("../../../glsl-patches/record_fixed.frag");

thread_local! {
    /// The draw being replayed cannot be repeated for the record: the app's display list
    /// (`glCallList`, `glCallLists`), a pixel rectangle (its fragments carry no parallax).
    static UNREPEATABLE: Cell<bool> = const { Cell::new(false) };
}

/// Runs `f` (the replay of a draw that must not be drawn twice) with the fixed-function
/// record off.
pub fn unrepeatable<R>(f: impl FnOnce() -> R) -> R {
    UNREPEATABLE.with(|c| c.set(true));
    let r = f();
    UNREPEATABLE.with(|c| c.set(false));
    r
}

/// Our program and the locations of its uniforms, linked on first use.
#[derive(Debug, Default)]
pub struct FixedProgram(Option<Result<Linked, String>>);

#[derive(Clone, Copy, Debug)]
struct Linked {
    program: u32,
    /// `holoinject_c`, `holoinject_lit`, `holoinject_texture`.
    locations: [i32; 3],
}

impl FixedProgram {
    fn get(&mut self, gl: &Gl, info: GlInfo) -> Option<Linked> {
        let p = self.0.get_or_insert_with(|| {
            let program = crate::gl::program::link(gl, info, VERT, FRAG)?;
            let at = |name| crate::gl::program::uniform(gl, program, name);
            Ok(Linked {
                program,
                locations: [at("holoinject_c"), at("holoinject_lit"), at("holoinject_texture")],
            })
        });
        match p {
            Ok(p) => Some(*p),
            Err(e) => {
                crate::log::once_for(
                    ("record-fixed", 0),
                    crate::log::Level::Info,
                    format_args!("fixed-function draws record no disparity: {e}"),
                );
                None
            }
        }
    }

    pub fn program(&self) -> Option<u32> {
        self.0.as_ref().and_then(|p| p.as_ref().ok()).map(|p| p.program)
    }
}

/// How a fixed-function draw is recorded: the second draw's program and convergence, and the
/// app's state it changes.
#[derive(Clone, Copy, Debug)]
pub struct FixedRecord {
    linked: Linked,
    c: f32,
    /// Tested `EQUAL` against the depth the draw wrote (else under its own depth state,
    /// blended by coverage).
    equal: bool,
    /// Where the coverage's alpha comes from (`record_fixed.vert` and `.frag`).
    alpha: AlphaSource,
    depth_func: GLenum,
    alpha_test: bool,
    stencil_test: bool,
}

/// Whether this fixed-function draw (into a recording target) can be recorded, and how:
/// `c` is its convergence (0 for a draw attached to the camera, at infinity).
pub fn plan(
    gl: &Gl,
    info: GlInfo,
    app: &mut crate::state::AppState,
    program: &mut FixedProgram,
    c: f32,
) -> Option<FixedRecord> {
    if UNREPEATABLE.with(Cell::get) || app.transform_feedback {
        return None;
    }
    let equal = app.enabled(gl, DEPTH_TEST) && get_i(gl, DEPTH_WRITEMASK) != 0;
    let linked = program.get(gl, info)?;
    let alpha = if !equal && app.enabled(gl, BLEND) {
        AlphaSource::of(gl)
    } else {
        AlphaSource::OPAQUE
    };
    Some(FixedRecord {
        linked,
        c,
        equal,
        alpha,
        depth_func: if equal { get_i(gl, DEPTH_FUNC) as GLenum } else { LESS },
        alpha_test: app.enabled(gl, ALPHA_TEST),
        stencil_test: app.enabled(gl, STENCIL_TEST),
    })
}

const POINT: GLenum = COLOR_ATTACHMENT0 + RECORD_BUFFER;

impl FixedRecord {
    /// After view `f`'s fixed-function draw: `f` again, into the record alone (by the write
    /// masks, not the draw buffers, whose change costs a software rasteriser a flush; the
    /// app's mask is put back on every buffer, as `glColorMask` sets it).
    pub fn redraw(&self, gl: &Gl, f: impl Fn()) {
        if get_i(gl, DRAW_BUFFER0 + RECORD_BUFFER) as GLenum != POINT {
            return;
        }
        let mut mask = [0u8; 4];
        // SAFETY: state of the current context, each put back below; our linked program.
        unsafe {
            gl.GetBooleanv(COLOR_WRITEMASK, mask.as_mut_ptr());
            gl.ColorMask(FALSE, FALSE, FALSE, FALSE);
            gl.ColorMaski(RECORD_BUFFER, TRUE, TRUE, TRUE, TRUE);
            if self.equal {
                gl.DepthMask(FALSE);
                gl.DepthFunc(EQUAL);
            }
            if self.alpha_test {
                gl.Disable(ALPHA_TEST);
            }
            if self.stencil_test {
                gl.Disable(STENCIL_TEST);
            }
            if self.equal {
                gl.Disablei(BLEND, RECORD_BUFFER);
            } else {
                gl.BlendFunci(RECORD_BUFFER, SRC_ALPHA, ONE_MINUS_SRC_ALPHA);
            }
            let [c, lit, texture] = self.linked.locations;
            gl.UseProgram(self.linked.program);
            gl.Uniform1f(c, self.c);
            gl.Uniform1i(lit, self.alpha.lit);
            gl.Uniform1i(texture, self.alpha.texture);
        }
        f();
        // SAFETY: as above: the app's state back (the record's blend is `before_draw`'s).
        unsafe {
            gl.UseProgram(0);
            gl.Enablei(BLEND, RECORD_BUFFER);
            gl.BlendFunci(RECORD_BUFFER, ZERO, ZERO);
            if self.stencil_test {
                gl.Enable(STENCIL_TEST);
            }
            if self.alpha_test {
                gl.Enable(ALPHA_TEST);
            }
            if self.equal {
                gl.DepthFunc(self.depth_func);
                gl.DepthMask(TRUE);
            }
            gl.ColorMask(mask[0], mask[1], mask[2], mask[3]);
        }
    }
}

/// What the fixed function's alpha is made of, for a blended draw's coverage.
#[derive(Clone, Copy, Debug)]
struct AlphaSource {
    /// 1: the front material's diffuse alpha (lighting without colour material), 0: the
    /// vertex colour's.
    lit: i32,
    /// -1: not blended (alpha 1), 0: the colour's alpha alone, 1: times unit 0's texture
    /// alpha, 2: unit 0's texture alpha alone.
    texture: i32,
}

impl AlphaSource {
    const OPAQUE: AlphaSource = AlphaSource { lit: 0, texture: -1 };

    /// Read from the fixed-function state of texture unit 0 (2D textures only; other targets
    /// count as untextured).
    fn of(gl: &Gl) -> AlphaSource {
        // SAFETY: enable and texture-environment queries of the compatibility profile; the
        // active texture unit is put back.
        unsafe {
            let lit = gl.IsEnabled(LIGHTING) != 0 && gl.IsEnabled(COLOR_MATERIAL) == 0;
            let active = get_i(gl, ACTIVE_TEXTURE) as GLenum;
            if active != TEXTURE0 {
                gl.ActiveTexture(TEXTURE0);
            }
            let two_d =
                gl.IsEnabled(TEXTURE_2D) != 0 && gl.IsEnabled(TEXTURE_3D) == 0 && gl.IsEnabled(TEXTURE_CUBE_MAP) == 0;
            let mut env = 0;
            gl.GetTexEnviv(TEXTURE_ENV, TEXTURE_ENV_MODE, &mut env);
            if active != TEXTURE0 {
                gl.ActiveTexture(active);
            }
            let texture = match (two_d, env as GLenum) {
                (false, _) | (true, DECAL) => 0,
                (true, REPLACE) => 2,
                // MODULATE, BLEND, ADD: the colour's alpha times the texture's; COMBINE taken
                // as the default combiner, which modulates.
                _ => 1,
            };
            AlphaSource {
                lit: lit as i32,
                texture,
            }
        }
    }
}
