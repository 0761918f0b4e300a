//! # holoinject
//!
//! An `LD_PRELOAD` layer that makes existing Linux OpenGL programs render light-field quilts
//! for lenticular multiview displays (Looking Glass), without touching their source.
//!
//! ## Architecture (see `DESIGN.md` §1)
//! `hook` interposes GL/GLX/EGL/OSMesa entry points (generated from `src/hook/policy.txt`) and
//! `dlsym`/`dlopen`; `state` shadows contexts per thread and share group; `output` owns the
//! frame boundary (dumps, exit-after; later the quilt and lenticular weave); `config` turns
//! `HOLOINJECT_*` variables into typed settings. `camera`, `shader`, `multiview` and `synth`
//! arrive with the multiview issues.
//!
//! ## Environment (the layer reads only these; `holoinject run --foo-bar` sets `HOLOINJECT_FOO_BAR`)
//! See `config::options::OPTIONS` for the full list with their syntax.
//!
//! ## Safety contract
//! - No panic crosses FFI: every exported shim runs its handler under `catch_unwind` and falls
//!   back to the real call; after one failure the layer is pass-through for the rest of the run.
//! - Every GL state the layer changes is restored before returning to the app
//!   (`gl::readback::PixelStateGuard`).
//! - Nothing on stdout; stderr only at `HOLOINJECT_LOG` level (default `warn`).
//! - GL may call the app back from inside any real call (a synchronous debug callback), and
//!   the app may call GL from there: a hook re-entered while its own thread holds the
//!   context's multiview lock passes straight through (`state::lock`); the share-group lock
//!   is never held across a GL call.
//! - Raw pointers stop at the handlers (`hook::handlers`), which make slices and `&CStr`s of
//!   the app's arguments; every `unsafe` block says why it is sound.

// Every `unsafe` block says why it is sound (generated bindings and shims opt out with `allow`).
#![deny(clippy::undocumented_unsafe_blocks)]

pub mod camera;
pub mod config;
pub mod gl;
pub mod hook;
pub mod log;
pub mod multiview;
pub mod output;
pub mod shader;
pub mod state;
