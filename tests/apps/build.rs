// Compatibility-profile bindings: `legacy` needs the GL 1.x entry points,
// and the core-profile apps simply ignore them.
use gl_generator::{Api, Fallbacks, Profile, Registry, StructGenerator};
use std::{env, fs::File, path::Path};

fn main() {
    let out = env::var("OUT_DIR").unwrap();
    let mut file = File::create(Path::new(&out).join("gl_bindings.rs")).unwrap();
    Registry::new(Api::Gl, (4, 5), Profile::Compatibility, Fallbacks::All, [])
        .write_bindings(StructGenerator, &mut file)
        .unwrap();
    println!("cargo:rerun-if-changed=build.rs");
}
