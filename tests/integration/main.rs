//! The integration tests, one binary (one link of the layer's rlib and of `util`), one module
//! per topic. Each test runs built programs (the launcher, the sample apps of `tests/apps`,
//! real Debian programs) in its own temporary directory; GLX tests need an X server
//! (`scripts/test.sh` starts Xvfb).
//!
//! Run one topic: `cargo test --release --test integration sample_apps:: -- --nocapture`.
//! `tests/shift_on_mesa.rs` stays a binary of its own: it drives GL in its own process with
//! the layer's variables set in its environment, which every program the tests here start
//! would inherit.

mod util;

mod auto_mode;
mod bad_input;
mod camera_attached;
mod comfort;
mod convergence;
mod device_window;
mod fbo_scale;
mod forced_failures;
mod gpu_counts;
mod guard_band;
mod launcher;
mod layer_library;
mod live_controls;
mod output_modes;
mod real_programs;
mod reattachment;
mod reuse;
mod rows_on_cpu;
mod sample_apps;
mod synthesis;
mod synthesis_pixel;
mod tools;
mod wine;
