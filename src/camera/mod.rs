//! The view rig of DESIGN §3 and projection estimation.
//!
//! Views are made by a shift in clip space *after* the app's own transform,
//! `x' = x + k_i (w - c) + h_i w`. It is exactly "move the camera sideways and shear the
//! frustum so the plane at eye distance `c` stays put", for any projection the app uses,
//! without decomposing its matrices. The projection estimate is only needed to speak in
//! physical terms (cone angle, convergence in scene units), to linearise depth for
//! auto-convergence, and to tell orthographic draws (HUDs) from perspective ones. The comfort
//! remap (`comfort`) bends that disparity where the display cannot show it sharply.

pub mod attached;
pub mod comfort;
pub mod convergence;
pub mod depth_fit;
pub mod estimate;
pub mod matrix;
pub mod precision;
pub mod projection;
pub mod rig;

pub use estimate::CameraEstimate;
pub use matrix::invert;
pub use projection::{Projection, ProjectionKind};
pub use rig::{ViewParams, ViewRig};
