//! Shared code of the holoinject sample apps (cubes, legacy, asteroids, model,
//! skybox, compat120, gles, the multi-pass framebuffers, shadowmap,
//! deferred, ssao, bloom, msaa, and twothreads, churn, debugcall).

#[allow(
    clippy::all,
    non_upper_case_globals,
    non_snake_case,
    non_camel_case_types,
    unused,
    unsafe_op_in_unsafe_fn
)]
pub mod gl {
    include!(concat!(env!("OUT_DIR"), "/gl_bindings.rs"));
}

pub mod camera;
pub mod cli;
pub mod debug_output;
pub mod image;
pub mod legacy_extras;
pub mod math;
pub mod multipass;
pub mod platform;
pub mod quilt;
pub mod run;
pub mod scene;
pub mod shader;
pub mod weapon;
