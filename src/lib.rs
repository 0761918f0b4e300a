//! # holoinject
//!
//! An `LD_PRELOAD` layer that makes existing Linux OpenGL programs render light-field quilts
//! for lenticular multiview displays (Looking Glass), without touching their source.
//!
//! ## Layers (DESIGN.md §2)
//! Dependencies point one way, down this stack; a module never names one above it, and
//! `scripts/module-graph.sh` prints the edges and fails on a cycle.
//!
//! ```text
//!  hook        exported shims (generated from src/hook/policy.txt), dlsym/dlopen
//!              interposers, handlers; the order of things at make-current, draw, swap;
//!              the per-context `Layer` (replay state + presenter)
//!    │
//!  multiview   per-view replay, quilt target,     output   presenting: quilt, weave,
//!              layered FBO shadows, link-time              SBS, anaglyph, PNG dumps,
//!              rewrite, fixed-function replay  ◀──────     frame timing (`Presenter`)
//!    │
//!  state       contexts, share groups, the thread's current context, the app-visible
//!              GL state (`AppState`), surface sizes, per-context GL tables
//!    │
//!  real        finding the real functions: dlvsym, loaded sonames, *GetProcAddress,
//!              the generated name table; no state
//!    │
//!  control     live controls: the `holoinject ctl` socket and the hotkeys, on threads
//!    │         of their own; they only queue requests in `config::live`
//!  gl · camera · shader · config · log      leaves: bindings and GL helpers (`GlInfo`),
//!              the view rig and projection estimate, GLSL analysis and rewrite,
//!              settings, presets and the live settings store, logging
//! ```
//!
//! `state` holds each context's layer data without knowing its type
//! (`state::ContextLayer`): the type, `hook::layer::Layer`, is the layer's business.
//!
//! ## The journey of one draw
//! The app calls `glDrawElements`. The exported shim (`hook`, generated) resolves the real
//! function for the thread's current context (`state::real_gl`), catches panics, and calls
//! the handler (`hook::handlers::gl`), which takes the context's lock once and hands the
//! app's state, the context's `Multiview` and its GL table to `multiview::replay::draw`. With
//! framebuffer 0 bound (the quilt stands in for it, made like the real one and, on Mesa,
//! stored top-down as Mesa stores windows: `multiview::window_format`), the draw is issued
//! once per view: the viewport and scissor mapped into the view's tile, the view's shift set
//! (the injected `holoinject_view` uniform, or a sheared `GL_PROJECTION` for fixed
//! function), and the app's state put back after the last view. Into an app framebuffer that the main camera
//! draws into, the draw goes to each layer of its layered shadow instead. Each draw is also
//! counted against its framebuffer when it is the main camera's, which is how
//! auto-convergence knows where the scene's depth is (`multiview::scene`).
//!
//! ## The journey of one link
//! `glLinkProgram` reaches `multiview::link`: the attached vertex (or last geometry) shader
//! is analysed (`shader`, a real GLSL parser with a text fallback), rewritten to wrap `main`
//! with the clip-space shift of DESIGN §3, recompiled and linked; what the replay needs
//! (view-uniform location, where the projection lives, whether `gl_Position` is given in
//! NDC) is recorded in the share group (`state::share::ProgramInfo`). Anything unsure or
//! failing relinks the app's own sources: the program works, only without parallax.
//!
//! ## The journey of one swap
//! `glXSwapBuffers`/`eglSwapBuffers` (or `glFinish` for OSMesa) reach `hook::frame`: the
//! frame is numbered, a multisampled quilt is resolved (as the window resolves at its
//! swap), the comfort post-pass (edge fade, depth of field: `output::comfort`) runs over its
//! tiles, `output::Presenter` draws the quilt into the real framebuffer 0 as
//! `--output` asks (with `--present device`, into the layer's own window on the Looking
//! Glass monitor first, and the `--preview` into the program's window: `output::device`;
//! and dumps the quilt and weave), the presented image is dumped, the real
//! swap runs, then `multiview` estimates auto-convergence from the scene's depth (copied from
//! the centre view of the framebuffer the main camera draws into, before anything overwrote
//! it: `multiview::scene`) and resizes the quilt if the window changed; `--exit-after` ends
//! the process last. Live changes (`holoinject ctl`, hotkeys) are applied first, on this
//! thread: the values they queued (`config::live`) go into each context's settings, so a
//! frame never mixes old and new values.
//!
//! ## Environment
//! The layer reads only `HOLOINJECT_*` variables (`holoinject run --foo-bar` sets
//! `HOLOINJECT_FOO_BAR`); `config::options::OPTIONS` lists them with their syntax.
//!
//! ## Safety contract
//! - No panic crosses FFI: every exported shim runs its handler under `catch_unwind` and
//!   falls back to the real call; after one failure the layer hands the frame in progress
//!   back (`hook::layer::abandon`) and is pass-through for the rest of the run.
//! - Every GL state the layer changes is restored before returning to the app
//!   (`gl::guard::StateGuard`, `gl::readback`).
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
pub mod control;
pub mod gl;
pub mod hook;
pub mod log;
pub mod multiview;
pub mod output;
pub mod real;
pub mod shader;
pub mod state;
pub mod synth;
