//! # GLSL analysis and the per-view clip-space rewrite
//!
//! At `glLinkProgram` the layer hands us the program's last pre-rasterization shader (vertex,
//! tessellation-evaluation or geometry). We rewrite it so that every quilt view sees a camera
//! moved along its x axis (DESIGN.md §3):
//!
//! ```text
//! x_clip' = x_clip + k*(w_clip - c) + h*w_clip        holoinject_view = (k, c, h, mode)
//! ```
//!
//! ## Why clip space
//! The shift is applied to `gl_Position` *after* the app's own transform, so we never need to
//! understand how the app builds its matrices (one MVP, P*V*M, uniform blocks, `ftransform()`,
//! skinning, instancing…). In clip space the shift is exact for any projection: it is the
//! projection matrix of a translated, sheared camera; y, z and w stay untouched, so depth and
//! occlusion are unchanged. What clip space cannot tell is *whether* a draw is perspective: that
//! is the `mode` component, chosen per draw by the layer from its tracked projection, with a
//! per-vertex `w == 1` guess (mode 2) only when nothing is known.
//!
//! ## Why a minimal text edit
//! `glsl-lang` parses well but re-printing its AST drops comments, reflows lines and would
//! re-emit preprocessor decisions made against its own extension list (DESIGN §8). The app's
//! info logs, its `#ifdef`s and its line numbers must survive, so the rewrite only splices a
//! few lines into the app's text: `#define main holoinject_app_main` after `#version` (followed
//! by a `#line` that restores the app's numbering) and a wrapper `main` appended at the end, or,
//! for geometry shaders, a hook on `EmitVertex()`. The parser is used to *analyse* (which
//! matrices feed `gl_Position`, is it a `.xyww` skybox, a full-screen pass, a layered pass).
//!
//! ## Why fall back
//! The parser refuses some shaders real drivers accept (later keywords such as `sample` used as
//! identifiers under old versions). Refusing to inject would make the whole program mono, so
//! analysis then falls back to a comment-aware token scan (`parsed = false`) that still answers
//! the questions that gate the rewrite, more conservatively (`Unknown` rather than a guess).

mod analyse;
mod ast_symbols;
mod ast_values;
mod ast_walk;
mod findings;
pub mod fragcoord;
pub mod record;
mod rewrite;
#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_lines;
#[cfg(test)]
mod tests_mutations;
mod text;
mod text_scan;
pub mod vec4_matrix;

pub use analyse::{analyse, parse_error};
pub use rewrite::{rewrite, rewrite_recording};

/// The uniform the rewritten shader reads: `(k, c, h, mode)`, see [`ViewMode`].
pub const VIEW_UNIFORM: &str = "holoinject_view";

/// The uniform holding the comfort remap in units of parallax (`camera::comfort`), zero when
/// off.
pub const REMAP_UNIFORM: &str = "holoinject_comfort";

/// The GLSL injected into rewritten shaders: the uniforms, the remap and
/// `vec4 holoinject_shift(vec4)`.
pub const VIEW_SHIFT_GLSL: &str = concat!(
    include_str!("../../glsl-patches/depth_remap.glsl"),
    include_str!("../../glsl-patches/view_shift.glsl")
);

/// The varying from the last pre-rasterisation stage to the fragment shader: the parallax its
/// shift used times clip w (`record`).
pub const RECORD_VARYING: &str = "holoinject_parallax_w";

/// The declaration of `RECORD_VARYING` for a stage (`out`: written by it), `None` for GLSL ES.
pub fn record_varying(version: Option<(u32, bool)>, out: bool) -> Option<String> {
    match version {
        Some((_, true)) => None,
        Some((v, _)) if v >= 130 => Some(format!("{} float {RECORD_VARYING};\n", if out { "out" } else { "in" })),
        _ => Some(format!("varying float {RECORD_VARYING};\n")),
    }
}

/// Values of `holoinject_view.w` (passed as exact small floats).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum ViewMode {
    /// Shift; far-plane vertices (`z` within 1e-6·w of `w`) are at infinity: `x += k*w + h*w`.
    /// For an infinite far plane, or a perspective whose depth model is unknown: directions
    /// (`w = 0` positions) through an infinite projection land a few ulps off `z == w`.
    Perspective = 0,
    /// No shift at all: the screen plane.
    Orthographic = 1,
    /// Projection unknown: no shift where `w == 1.0` exactly, else as `Perspective`.
    Unknown = 2,
    /// Perspective with reversed-Z: the far plane is exactly `z == 0`.
    PerspectiveReversedZ = 3,
    /// Perspective with a finite far plane: far-plane geometry (`.xyww`) has exactly
    /// `z == w`, so no tolerance takes distant scene geometry for sky.
    PerspectiveFiniteFar = 4,
}

impl ViewMode {
    /// The float to store in `holoinject_view.w`.
    pub fn as_uniform(self) -> f32 {
        self as u8 as f32
    }

    /// The mode for a draw whose tracked matrix classified as `p` (`None`: no usable matrix).
    pub fn of(p: Option<&crate::camera::projection::Projection>) -> ViewMode {
        use crate::camera::projection::ProjectionKind;
        match p {
            None => ViewMode::Unknown,
            Some(p) if p.kind == ProjectionKind::Orthographic => ViewMode::Orthographic,
            Some(p) => match p.depth {
                Some(d) if d.a > 0.0 => ViewMode::PerspectiveReversedZ,
                Some(d) if d.far().is_finite() => ViewMode::PerspectiveFiniteFar,
                _ => ViewMode::Perspective,
            },
        }
    }

    pub fn is_perspective(self) -> bool {
        !matches!(self, ViewMode::Orthographic | ViewMode::Unknown)
    }
}

/// A shader stage, from the GL enum given to `glCreateShader`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    Vertex,
    TessControl,
    TessEval,
    Geometry,
    Fragment,
    Compute,
}

impl Stage {
    pub fn from_gl(ty: u32) -> Option<Stage> {
        match ty {
            0x8B31 => Some(Stage::Vertex),
            0x8B30 => Some(Stage::Fragment),
            0x8DD9 => Some(Stage::Geometry),
            0x8E87 => Some(Stage::TessEval),
            0x8E88 => Some(Stage::TessControl),
            0x91B9 => Some(Stage::Compute),
            _ => None,
        }
    }

    /// Stages whose `gl_Position` can reach the rasterizer.
    pub fn can_feed_rasterizer(self) -> bool {
        matches!(self, Stage::Vertex | Stage::TessEval | Stage::Geometry)
    }
}

/// How `gl_Position` is produced.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum PositionKind {
    /// From an attribute/expression with no matrix multiply, e.g. `vec4(a.xy, 0.0, 1.0)`:
    /// full-screen passes, HUDs already in NDC.
    Identity,
    /// Some `mat4 * vec`, including `ftransform()` and `gl_ModelViewProjectionMatrix`.
    MatrixMultiply,
    /// `.xyww` style: z copies w (skyboxes at infinity).
    FarPlane,
    Constant,
    /// Several different kinds, unresolved calls, or positions passed through from an earlier
    /// stage (`gl_in[i].gl_Position`).
    Unknown,
}

#[derive(Clone, Debug)]
pub struct Analysis {
    pub stage: Stage,
    /// `(#version number, is_es)`; `None` when absent (1.10, or ES 1.00).
    pub version: Option<(u32, bool)>,
    /// False: glsl-lang refused the source and the text-only analysis was used.
    pub parsed: bool,
    pub writes_position: bool,
    /// `gl_Layer` or `gl_ViewportIndex` written (layered passes: not multiplied by us).
    pub writes_layer: bool,
    pub position_kind: PositionKind,
    /// `uniform mat4` names feeding `gl_Position`, in multiplication order, as GL introspection
    /// names them: `name`, `Block.member` for instanced uniform blocks (bare `member` for
    /// anonymous ones), `s.member` for uniform structs; built-ins `gl_ModelViewProjectionMatrix`
    /// (also for `ftransform()`), `gl_ProjectionMatrix`, `gl_ModelViewMatrix`.
    pub matrix_uniforms: Vec<String>,
    /// Matrices held in `vec4` uniform arrays that the shader applies (`vec4_matrix`), found
    /// wherever they go: the caller decides whether one is the position's.
    pub vec4_matrices: Vec<vec4_matrix::Vec4Matrix>,
    /// Whether `main` is defined in the code the preprocessor keeps (known only when
    /// glsl-lang parsed the source): a shader object may lack it, or have it under an `#if`
    /// that is off, and then it compiles but our wrapper's call would not.
    pub has_main: Option<bool>,
}
