//! The main camera's view-projection of a frame, for `--reuse` to follow camera motion
//! (`reuse`, `synth::reproject`).
//!
//! The shader analysis lists, per program, the matrices multiplied into `gl_Position` in
//! multiplication order (`P * V * M * pos` gives `[P, V, M]`), and the layer follows their
//! uploads. The camera is the part of that chain that stays the same over every perspective
//! draw of the main camera in one frame: the whole product when it does (`P * V * pos`, or
//! one object drawn with its MVP, which then moves rigidly with it), else the chain without
//! its rightmost matrix (the model matrix of `P * V * M` and `VP * M`). Where neither stays
//! the same (one MVP per object), or a matrix of the chain is a built-in or lives in a
//! uniform block, the camera is unknown for the frame and camera motion is, as before
//! `--reuse` followed it, a change that drops the kept views.
//!
//! Products are formed in f64 from the uploaded f32 values.

use glam::DMat4;
use std::sync::atomic::AtomicBool;

static UNREADABLE: AtomicBool = AtomicBool::new(false);

/// One candidate over a frame's draws.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
enum Candidate {
    #[default]
    Unseen,
    Same([f64; 16]),
    Varies,
}

impl Candidate {
    fn see(&mut self, m: Option<[f64; 16]>) {
        *self = match (*self, m) {
            (Candidate::Unseen, Some(m)) => Candidate::Same(m),
            (Candidate::Same(old), Some(m)) if old == m => Candidate::Same(m),
            _ => Candidate::Varies,
        };
    }

    fn value(self) -> Option<[f64; 16]> {
        match self {
            Candidate::Same(m) => Some(m),
            _ => None,
        }
    }
}

/// The camera candidates of the frame being drawn.
#[derive(Clone, Debug, Default)]
pub struct CameraTrack {
    /// The whole chain's product.
    full: Candidate,
    /// The chain without its rightmost matrix.
    prefix: Candidate,
}

/// The product of `chain`'s matrices (locations) read from `values`; `None` when one has
/// never been uploaded or `chain` is empty.
fn product(chain: &[i32], values: &[(i32, [f32; 16])]) -> Option<[f64; 16]> {
    if chain.is_empty() {
        return None;
    }
    chain
        .iter()
        .try_fold(DMat4::IDENTITY, |acc, loc| {
            let (_, m) = values.iter().find(|(l, _)| l == loc)?;
            Some(acc * DMat4::from_cols_array(&m.map(f64::from)))
        })
        .map(|m| m.to_cols_array())
}

impl CameraTrack {
    /// A perspective draw of the main camera whose program's chain is `chain` (empty: not
    /// readable) with the program's followed matrix values `values`.
    pub fn see(&mut self, program: u32, chain: &[i32], values: &[(i32, [f32; 16])]) {
        if chain.is_empty() {
            crate::log::once_for(
                ("camera-unknown", u64::from(program)),
                crate::log::Level::Debug,
                format_args!(
                    "reuse: the camera of {} is not readable (built-in or block-held matrices): \
                     camera motion drops the kept views",
                    if program == 0 {
                        "fixed function".to_string()
                    } else {
                        format!("program {program}")
                    }
                ),
            );
        }
        self.full.see(product(chain, values));
        let prefix = chain.split_last().and_then(|(_, p)| product(p, values));
        self.prefix.see(prefix);
    }

    /// The frame's camera view-projection (column-major, invertible), or `None` when it is
    /// not known; starts the next frame.
    pub fn take(&mut self) -> Option<[f64; 16]> {
        let t = std::mem::take(self);
        let vp = t.full.value().or(t.prefix.value());
        if vp.is_none() && t.full == Candidate::Varies && t.prefix == Candidate::Varies {
            crate::log::once(
                &UNREADABLE,
                crate::log::Level::Debug,
                format_args!(
                    "reuse: no part of the camera draws' matrix chain stays the same over a frame \
                     (one MVP per object?): camera motion drops the kept views"
                ),
            );
        }
        vp.filter(|m| crate::camera::invert(m).is_some())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn m(x: f32) -> [f32; 16] {
        let mut m = [0.0; 16];
        for i in 0..4 {
            m[i * 5] = 1.0;
        }
        m[12] = x;
        m
    }

    #[test]
    fn the_camera_is_the_part_of_the_chain_that_stays_the_same() {
        let mut t = CameraTrack::default();
        // P * V * M: M differs per draw, P * V is the camera.
        t.see(1, &[0, 1, 2], &[(0, m(1.0)), (1, m(2.0)), (2, m(0.5))]);
        t.see(1, &[0, 1, 2], &[(0, m(1.0)), (1, m(2.0)), (2, m(0.25))]);
        assert_eq!(t.take().map(|v| v[12]), Some(3.0));
        // P * V alone: the whole product.
        t.see(1, &[0, 1], &[(0, m(1.0)), (1, m(2.0))]);
        assert_eq!(t.take().map(|v| v[12]), Some(3.0));
        // One MVP per object: unknown.
        t.see(1, &[0], &[(0, m(1.0))]);
        t.see(1, &[0], &[(0, m(2.0))]);
        assert_eq!(t.take(), None);
        // A built-in chain, nothing drawn: unknown.
        t.see(0, &[], &[]);
        assert_eq!(t.take(), None);
        assert_eq!(t.take(), None);
        // A model matrix never uploaded: the rest of the chain is still the camera.
        t.see(1, &[0, 1], &[(0, m(1.0))]);
        assert_eq!(t.take().map(|v| v[12]), Some(1.0));
        // Singular: unknown.
        t.see(1, &[0], &[(0, [0.0; 16])]);
        assert_eq!(t.take(), None);
    }
}
