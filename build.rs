//! Generates, from `src/hook/policy.txt` and the Khronos XML registries bundled with
//! gl_generator: the exported hook shims, the hook table, the linker export list, and the
//! GL/GLX/EGL bindings the layer uses for its own calls. Nothing here is hand-maintained per
//! entry point; adding a hook is one line in the policy file plus its handler.

use gl_generator::{Api, Cmd, Fallbacks, Profile, Registry, StructGenerator};
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::{env, fs};

/// GL extensions whose entry points may be hooked (core names are always available).
const GL_EXTENSIONS: &[&str] = &[
    "GL_ARB_draw_instanced",
    "GL_ARB_multi_draw_indirect",
    "GL_EXT_direct_state_access",
    "GL_ARB_framebuffer_object",
    "GL_EXT_framebuffer_object",
];
const GLX_EXTENSIONS: &[&str] = &["GLX_ARB_create_context", "GLX_ARB_get_proc_address"];
const EGL_EXTENSIONS: &[&str] = &[
    "EGL_KHR_swap_buffers_with_damage",
    "EGL_EXT_swap_buffers_with_damage",
    "EGL_EXT_platform_base",
];

struct Entry {
    policy: String,
    name: String,
    /// `name = target`: the entry point uses `target`'s handler (same signature).
    alias_of: Option<String>,
    api: &'static str,
    params: Vec<(String, String)>,
    ret: String,
}

fn main() {
    let out = PathBuf::from(env::var("OUT_DIR").unwrap());
    println!("cargo:rerun-if-changed=src/hook/policy.txt");
    println!("cargo:rerun-if-changed=build.rs");

    let gl = Registry::new(Api::Gl, (4, 6), Profile::Compatibility, Fallbacks::All, GL_EXTENSIONS);
    let glx = Registry::new(Api::Glx, (1, 4), Profile::Core, Fallbacks::All, GLX_EXTENSIONS);
    let egl = Registry::new(Api::Egl, (1, 5), Profile::Core, Fallbacks::All, EGL_EXTENSIONS);
    write_bindings(&out, &gl, &glx, &egl);

    let policy = fs::read_to_string("src/hook/policy.txt").unwrap();
    let registries = [("gl", &gl), ("glx", &glx), ("egl", &egl)];
    let mut entries: Vec<Entry> = policy
        .lines()
        .enumerate()
        .filter_map(|(n, l)| parse_line(n + 1, l, &registries))
        .collect();
    entries.sort_by(|a, b| a.name.cmp(&b.name));
    check_aliases(&entries);
    fs::write(out.join("hooks.rs"), gen_hooks(&entries)).unwrap();
    fs::write(out.join("names.rs"), gen_table(&entries)).unwrap();
    fs::write(out.join("exports.map"), gen_export_map(&entries)).unwrap();

    let map = out.join("exports.map");
    println!("cargo:rustc-cdylib-link-arg=-Wl,--version-script={}", map.display());
    println!("cargo:rustc-cdylib-link-arg=-Wl,-Bsymbolic-functions");
}

fn write_bindings(out: &Path, gl: &Registry, glx: &Registry, egl: &Registry) {
    let mut f = Vec::new();
    gl.write_bindings(StructGenerator, &mut f).unwrap();
    fs::write(
        out.join("gl_bindings.rs"),
        count_gpu_work(&String::from_utf8(f).unwrap()),
    )
    .unwrap();
    let mut x = fs::File::create(out.join("glx_bindings.rs")).unwrap();
    glx.write_bindings(StructGenerator, &mut x).unwrap();
    let mut e = fs::File::create(out.join("egl_bindings.rs")).unwrap();
    egl.write_bindings(StructGenerator, &mut e).unwrap();
}

/// The layer's own calls that give the GPU work (draws, dispatches, clears, blits, copies) or
/// read back to the CPU count themselves (`log::counts`, `--gpu-counts`): the counting is put
/// into the generated table's methods, so no call site of the layer can be missed.
fn count_gpu_work(bindings: &str) -> String {
    let mut out = String::with_capacity(bindings.len() + 4096);
    for line in bindings.split_inclusive('\n') {
        let name = line
            .split_once("pub unsafe fn ")
            .and_then(|(_, rest)| rest.split_once('('))
            .map(|(name, _)| name);
        let count = match name {
            Some("ReadPixels") => {
                Some("crate::log::counts::read_back(crate::log::counts::pixel_bytes(width, height, format, type_));")
            }
            Some("GetBufferSubData") => Some("crate::log::counts::read_back(size as u64);"),
            Some(n) if is_gpu_work(n) => Some("crate::log::counts::layer_call();"),
            _ => None,
        };
        match (count, line.find(") -> () { ")) {
            (Some(count), Some(at)) => {
                let body = at + ") -> () { ".len();
                out.push_str(&line[..body]);
                out.push_str(count);
                out.push(' ');
                out.push_str(&line[body..]);
            }
            _ => out.push_str(line),
        }
    }
    out
}

fn is_gpu_work(name: &str) -> bool {
    let draw = name.starts_with("Draw") && !name.starts_with("DrawBuffer");
    let prefixed = [
        "MultiDraw",
        "DispatchCompute",
        "ClearBuffer",
        "ClearTex",
        "ClearNamedFramebuffer",
        "Blit",
        "CopyTex",
        "CopyImageSubData",
    ]
    .iter()
    .any(|p| name.starts_with(p));
    draw || prefixed || matches!(name, "Clear" | "CallList" | "CallLists" | "End")
}

fn api_of(name: &str) -> (&'static str, &str) {
    for (prefix, api) in [("glX", "glx"), ("egl", "egl"), ("OSMesa", "osmesa"), ("gl", "gl")] {
        if let Some(rest) = name.strip_prefix(prefix) {
            return (api, rest);
        }
    }
    panic!("policy.txt: cannot tell the API of `{name}`");
}

fn parse_line(line_no: usize, line: &str, regs: &[(&str, &Registry)]) -> Option<Entry> {
    let line = line.split('#').next().unwrap().trim();
    if line.is_empty() {
        return None;
    }
    let (policy, rest) = line.split_once(char::is_whitespace).expect("policy.txt: missing name");
    let policy = policy.to_string();
    assert!(
        ["track", "frame", "proc", "view", "view+", "matrix"].contains(&policy.as_str()),
        "policy.txt:{line_no}: unknown policy `{policy}`"
    );
    let (rest, alias_of) = match rest.split_once('=') {
        Some((name, target)) => (name, Some(target.trim().to_string())),
        None => (rest, None),
    };
    let rest = rest.trim_start();
    let split = rest.find(|c: char| c.is_whitespace() || c == '(').unwrap_or(rest.len());
    let (name, sig) = (rest[..split].to_string(), rest[split..].trim());
    let (api, short) = api_of(&name);
    let (params, ret) = match Some(sig).filter(|s| !s.is_empty()) {
        Some(sig) => parse_inline_signature(line_no, sig),
        None => {
            let reg = regs.iter().find(|(a, _)| *a == api).map(|(_, r)| *r);
            let reg = reg.unwrap_or_else(|| panic!("policy.txt:{line_no}: `{name}` needs a signature"));
            let cmd = find_cmd(reg, short)
                .unwrap_or_else(|| panic!("policy.txt:{line_no}: `{name}` is not in the {api} registry"));
            signature_of(cmd)
        }
    };
    assert!(
        !["view", "matrix"].contains(&policy.as_str()) || ret == "()",
        "policy.txt:{line_no}: `{name}` returns {ret}; a generated handler returns nothing"
    );
    Some(Entry {
        policy,
        name,
        alias_of,
        api,
        params,
        ret,
    })
}

/// Every alias names an entry of the same API with the same signature.
fn check_aliases(entries: &[Entry]) {
    for e in entries {
        let Some(target) = &e.alias_of else { continue };
        let t = entries.iter().find(|t| &t.name == target).unwrap_or_else(|| {
            panic!(
                "policy.txt: `{}` is an alias of `{target}`, which is not in the table",
                e.name
            )
        });
        let types = |e: &Entry| e.params.iter().map(|(_, t)| t.clone()).collect::<Vec<_>>();
        assert!(
            t.api == e.api && types(t) == types(e) && t.ret == e.ret && t.policy == e.policy && t.alias_of.is_none(),
            "policy.txt: `{}` = `{target}`: aliases need the same API, policy and signature, and a handler of their own",
            e.name
        );
    }
}

fn find_cmd<'a>(reg: &'a Registry, short: &str) -> Option<&'a Cmd> {
    reg.cmds.iter().find(|c| c.proto.ident == short)
}

fn signature_of(cmd: &Cmd) -> (Vec<(String, String)>, String) {
    let params = cmd.params.iter().map(|b| (b.ident.clone(), b.ty.to_string())).collect();
    (params, cmd.proto.ty.to_string())
}

/// `(a: T, b: U) -> R` with bare type names (resolved in the generated module's scope).
fn parse_inline_signature(line_no: usize, sig: &str) -> (Vec<(String, String)>, String) {
    let open = sig
        .find('(')
        .unwrap_or_else(|| panic!("policy.txt:{line_no}: bad signature"));
    let close = sig
        .rfind(')')
        .unwrap_or_else(|| panic!("policy.txt:{line_no}: bad signature"));
    let params = sig[open + 1..close]
        .split(',')
        .map(str::trim)
        .filter(|p| !p.is_empty())
        .map(|p| {
            let (n, t) = p.split_once(':').expect("param needs `name: Type`");
            (n.trim().to_string(), t.trim().to_string())
        })
        .collect();
    let ret = sig[close + 1..]
        .trim()
        .strip_prefix("->")
        .map(str::trim)
        .unwrap_or("()");
    (params, ret.to_string())
}

fn gen_hooks(entries: &[Entry]) -> String {
    let mut s = String::from("// @generated by build.rs from src/hook/policy.txt. Do not edit.\n\n");
    let mut by_api: BTreeMap<&str, Vec<(usize, &Entry)>> = BTreeMap::new();
    for (id, e) in entries.iter().enumerate() {
        by_api.entry(e.api).or_default().push((id, e));
    }
    for (api, list) in &by_api {
        writeln!(
            s,
            "pub mod {api} {{\n    #![allow(non_snake_case, unused_imports, clippy::all)]"
        )
        .unwrap();
        writeln!(s, "    use {};", types_path(api)).unwrap();
        writeln!(s, "    use core::ffi::{{c_void, c_char, c_int}};").unwrap();
        writeln!(s, "    mod __gl_imports {{\n        pub use std::os::raw;\n    }}\n").unwrap();
        for (id, e) in list {
            s.push_str(&gen_shim(*id, e));
        }
        s.push_str("}\n\n");
    }
    s.push_str(&gen_addrs(entries));
    s
}

fn types_path(api: &str) -> &'static str {
    match api {
        "egl" => "crate::gl::egl::types::{self, *}",
        "glx" => "crate::gl::glx::types::{self, *}",
        _ => "crate::gl::types::{self, *}",
    }
}

/// One exported shim. Safety, for all of them (the generated module is exempt from
/// `clippy::undocumented_unsafe_blocks`): the shim has the contract of the entry point it
/// replaces; `p` is the real function of the same name, hence signature; every `real(..)`
/// call passes either the app's own arguments or, from a handler, arguments the handler
/// vouches for (the app's, or objects and arrays of its own).
fn gen_shim(id: usize, e: &Entry) -> String {
    let params: Vec<String> = e.params.iter().map(|(n, t)| format!("{n}: {t}")).collect();
    let tys: Vec<&str> = e.params.iter().map(|(_, t)| t.as_str()).collect();
    let args: Vec<&str> = e.params.iter().map(|(n, _)| n.as_str()).collect();
    let (params, tys, args) = (params.join(", "), tys.join(", "), args.join(", "));
    let (name, ret, api) = (&e.name, &e.ret, e.api);
    let handler = handler_call(e, &args);
    // GL entry points differ per context (OSMesa's and libGL's glFinish in one process).
    let resolver = if api == "gl" {
        "crate::state::real_gl"
    } else {
        "crate::real::global"
    };
    format!(
        r#"    /// Hook ({policy}): see `{doc}`.
    #[unsafe(no_mangle)]
    pub unsafe extern "C" fn {name}({params}) -> {ret} {{
        type Real = unsafe extern "C" fn({tys}) -> {ret};
        let p = {resolver}({id});
        if p.is_null() {{
            return crate::real::missing({id});
        }}
        // SAFETY: `p` is the real entry point of this very name, so it has this signature.
        let real: Real = unsafe {{ core::mem::transmute::<*const c_void, Real>(p) }};
        if !crate::hook::is_active() {{
            return unsafe {{ real({args}) }};
        }}
        let last = core::cell::Cell::new(None);
        let out = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {{
            crate::hook::fail_point({id});
            {handler}
        }}));
        match out {{
            Ok(v) => v,
            Err(_) => {{
                crate::hook::handler_panicked({id});
                match last.get() {{
                    Some(v) => v,
                    None => unsafe {{ real({args}) }},
                }}
            }}
        }}
    }}

"#,
        policy = e.policy,
        doc = handler_doc(e),
    )
}

/// The handler the shim hands over to: a generated per-view replay for `view`, else the
/// handwritten one (the alias target's for an alias), given `real` as a closure that also
/// remembers what it returned (the fallback value if the handler panics afterwards).
fn handler_call(e: &Entry, args: &str) -> String {
    let body = format!(
        "{{\n                    let v = unsafe {{ real({args}) }};\n                    last.set(Some(v));\n                    v\n                }}"
    );
    if e.policy == "view" {
        return format!("crate::hook::handlers::gl::per_view(|| {body})");
    }
    if e.policy == "matrix" {
        // The EXT_direct_state_access spellings name the matrix; the others act on the
        // current matrix mode.
        let mode = if e.params.first().is_some_and(|(n, _)| n == "mode") {
            "Some(mode)"
        } else {
            "None"
        };
        return format!(
            "{{\n                let v = {body};\n                crate::hook::handlers::gl::matrix_changed({mode});\n                v\n            }}"
        );
    }
    let real = format!("|{args}| {body}");
    let name = e.alias_of.as_deref().unwrap_or(&e.name);
    let sep = if args.is_empty() { "" } else { ",\n                " };
    format!(
        "crate::hook::handlers::{api}::{name}(\n                {real}{sep}{args}\n            )",
        api = e.api
    )
}

fn handler_doc(e: &Entry) -> String {
    match (&e.alias_of, e.policy.as_str()) {
        (_, "view") => "crate::hook::handlers::gl::per_view".to_string(),
        (_, "matrix") => "crate::hook::handlers::gl::matrix_changed".to_string(),
        (Some(t), _) => format!("crate::hook::handlers::{}::{t}", e.api),
        (None, _) => format!("crate::hook::handlers::{}::{}", e.api, e.name),
    }
}

/// The name table `crate::real` owns: names, APIs and policies, no addresses of ours.
fn gen_table(entries: &[Entry]) -> String {
    let mut s = String::from("// @generated by build.rs from src/hook/policy.txt. Do not edit.\n\n");
    writeln!(s, "pub const HOOK_COUNT: usize = {};\n", entries.len()).unwrap();
    s.push_str("/// Sorted by name (binary search on the `dlsym` path, which must not allocate).\n");
    s.push_str("pub static HOOKS: [crate::real::HookEntry; HOOK_COUNT] = [\n");
    for e in entries {
        let policy = match e.policy.as_str() {
            "view+" => "ViewOwn".to_string(),
            p => capitalise(p),
        };
        let api = capitalise(e.api);
        writeln!(
            s,
            "    crate::real::HookEntry {{ name: c\"{n}\", api: crate::real::HookApi::{api}, policy: crate::real::Policy::{policy} }},",
            n = e.name
        )
        .unwrap();
    }
    s.push_str("];\n\n/// Index of each hook in `HOOKS`.\n#[allow(non_upper_case_globals, dead_code)]\npub mod id {\n");
    for (i, e) in entries.iter().enumerate() {
        writeln!(s, "    pub const {}: usize = {i};", e.name).unwrap();
    }
    s.push_str("}\n");
    s
}

/// The addresses of our exported shims, in the order of the name table.
fn gen_addrs(entries: &[Entry]) -> String {
    let mut s = String::from("/// Our shim for each entry of `crate::real::HOOKS`, by the same index.\n");
    s.push_str("pub static ADDRS: [crate::hook::HookAddr; crate::real::HOOK_COUNT] = [\n");
    for e in entries {
        writeln!(
            s,
            "    crate::hook::HookAddr({a}::{n} as *const core::ffi::c_void),",
            n = e.name,
            a = e.api
        )
        .unwrap();
    }
    s.push_str("];\n");
    s
}

fn capitalise(s: &str) -> String {
    let mut c = s.chars();
    c.next()
        .map(|f| f.to_uppercase().collect::<String>() + c.as_str())
        .unwrap_or_default()
}

/// The only symbols the shared object exports: the interposed loader functions and the hooks.
fn gen_export_map(entries: &[Entry]) -> String {
    let mut s = String::from("{\n  global:\n    dlsym;\n    dlopen;\n");
    for e in entries {
        writeln!(s, "    {};", e.name).unwrap();
    }
    s.push_str("  local:\n    *;\n};\n");
    s
}
