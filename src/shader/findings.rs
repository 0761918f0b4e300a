//! What the two analysers (the AST walk and the token scan) find about the `gl_Position`
//! writes, in one shape, so the entry point can take either answer unchanged. Apart from
//! `analyse` because the walkers fill it and `analyse` calls the walkers: living here, it
//! lets the walkers sit below their caller.

use super::PositionKind;

/// What both analysers report about the `gl_Position` writes.
#[derive(Clone, Debug, Default)]
pub(super) struct Findings {
    pub writes_position: bool,
    pub writes_layer: bool,
    pub kind: Option<PositionKind>,
    pub matrices: Vec<String>,
}

impl Findings {
    /// Merges one more `gl_Position` write: the kinds must agree, else `Unknown`.
    pub fn add_write(&mut self, kind: PositionKind, matrices: &[String]) {
        self.writes_position = true;
        self.kind = Some(match self.kind.take() {
            None => kind,
            Some(prev) if prev == kind => prev,
            Some(_) => PositionKind::Unknown,
        });
        for m in matrices {
            if !self.matrices.contains(m) {
                self.matrices.push(m.clone());
            }
        }
    }
}
