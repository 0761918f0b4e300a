//! The promise the link hook relies on, checked on Mesa itself: when the app's vertex or
//! geometry shader compiles, our rewrite of it compiles too, or the rewrite is refused
//! (and the app's original is used). A rewrite that breaks a valid shader is a finding.
#![no_main]

use holoapps::gl::{self, Gl};
use holoapps::platform::{Platform, Profile, create};
use holoinject::shader::{Stage, analyse, fragcoord, rewrite};
use libfuzzer_sys::fuzz_target;
use std::sync::OnceLock;

struct Mesa {
    _platform: Box<dyn Platform>,
    gl: Gl,
}

// SAFETY: libFuzzer runs the target on one thread; the context stays current on it.
unsafe impl Send for Mesa {}
unsafe impl Sync for Mesa {}

fn mesa() -> &'static Mesa {
    static MESA: OnceLock<Mesa> = OnceLock::new();
    MESA.get_or_init(|| {
        // This binary links the holoinject rlib, whose hooks (and `dlsym`) are exported and
        // live: keep the layer in pass-through.
        // SAFETY: the first GL call, which reads the settings, comes after this.
        unsafe { std::env::set_var("HOLOINJECT_OUTPUT", "mono") };
        let platform = create(holoapps::cli::Backend::OsMesa, (16, 16), Profile::Legacy)
            .expect("OSMesa context (apt-get install libosmesa6)");
        let gl = Gl::load_with(|s| platform.get_proc_address(s));
        Mesa { _platform: platform, gl }
    })
}


fuzz_target!(|data: &[u8]| {
    let Some((&first, rest)) = data.split_first() else { return };
    let Ok(source) = std::str::from_utf8(rest) else { return };
    // The same stage selector as glsl_rewrite, so the two share a corpus.
    let (stage, kind) = match first % 4 {
        0 => (Stage::Vertex, gl::VERTEX_SHADER),
        1 => (Stage::Geometry, gl::GEOMETRY_SHADER),
        2 => (Stage::TessEval, gl::TESS_EVALUATION_SHADER),
        _ => (Stage::Fragment, gl::FRAGMENT_SHADER),
    };
    let gl = &mesa().gl;
    if holoapps::shader::compile_status(gl, kind, source).is_err() {
        return;
    }
    if stage == Stage::Fragment {
        if let Ok(out) = fragcoord::rewrite(source) {
            if let Err(log) = holoapps::shader::compile_status(gl, kind, &out) {
                panic!("valid shader broken by the gl_FragCoord rewrite: {log}\n{out}");
            }
        }
    } else if let Ok(out) = rewrite(source, &analyse(source, stage)) {
        if let Err(log) = holoapps::shader::compile_status(gl, kind, &out) {
            panic!("valid shader broken by the rewrite: {log}\n{out}");
        }
    }
});
