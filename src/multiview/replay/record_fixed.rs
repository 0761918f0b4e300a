//! The disparity record of fixed-function draws (DESIGN §5: fixed-function draws included).
//!
//! A fixed-function draw has no fragment shader to add an output to, so after it is drawn
//! into a view that records, it is drawn once more with a program of ours
//! (`record_fixed.vert`/`.frag`: `ftransform()`, invariant with the fixed function) that
//! writes the record's draw buffer alone, depth-tested `EQUAL` without writing depth: every
//! pixel the draw left visible gets the parallax its sheared projection gave it. Draws that
//! write no depth left none to match: those attached to the camera (a sky around the eye,
//! drawn first with depth writes or the depth test off, as fixed-function games draw theirs)
//! are drawn again under their own depth state instead, which passes where it passed (they
//! changed no depth), and record infinity; the others (a translucent draw) leave the record of
//! what is behind them. Only draws whose replay has no side effects are recorded: vertex
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

/// Our program and the location of its convergence uniform, linked on first use.
#[derive(Debug, Default)]
pub struct FixedProgram(Option<Result<(u32, i32), String>>);

impl FixedProgram {
    fn get(&mut self, gl: &Gl, info: GlInfo) -> Option<(u32, i32)> {
        let p = self.0.get_or_insert_with(|| {
            let p = crate::gl::program::link(gl, info, VERT, FRAG)?;
            Ok((p, crate::gl::program::uniform(gl, p, "holoinject_c")))
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
        self.0.as_ref().and_then(|p| p.as_ref().ok()).map(|p| p.0)
    }
}

/// How a fixed-function draw is recorded: the second draw's program and convergence, and the
/// app's state it changes.
#[derive(Clone, Copy, Debug)]
pub struct FixedRecord {
    program: u32,
    c_loc: i32,
    c: f32,
    /// Tested `EQUAL` against the depth the draw wrote (else under its own depth state).
    equal: bool,
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
    if !equal && c != 0.0 {
        return None;
    }
    let (program, c_loc) = program.get(gl, info)?;
    Some(FixedRecord {
        program,
        c_loc,
        c,
        equal,
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
            gl.Disablei(BLEND, RECORD_BUFFER);
            gl.UseProgram(self.program);
            gl.Uniform1f(self.c_loc, self.c);
        }
        f();
        // SAFETY: as above: the app's state back (the record's blend is `before_draw`'s).
        unsafe {
            gl.UseProgram(0);
            gl.Enablei(BLEND, RECORD_BUFFER);
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
