//! Link time: the app's last pre-rasterisation shader gets the view shift.
//!
//! The app's *own* shader object is recompiled with the rewritten source just before its
//! link, so program names, attribute and uniform locations and every `glGet*` answer stay the
//! app's (only `glGetShaderSource` needs correcting, see the query handlers). Anything that
//! fails — analysis, compile, link — puts the original source back and links again: the app
//! always ends up with a working program, at worst without parallax, and we log why once.

use crate::gl::*;
use crate::shader::{self, Stage};
use crate::state::ShareGroup;
use crate::state::share::ProgramInfo;
use std::ffi::CString;

fn shader_iv(gl: &Gl, shader: u32, pname: GLenum) -> i32 {
    let mut v = 0;
    // SAFETY: single-integer shader query into a local.
    unsafe { gl.GetShaderiv(shader, pname, &mut v) };
    v
}

fn attached_shaders(gl: &Gl, program: u32) -> Vec<u32> {
    let mut names = [0u32; 16];
    let mut n = 0;
    // SAFETY: room for 16 names; programs rarely have more than 5 stages.
    unsafe { gl.GetAttachedShaders(program, names.len() as i32, &mut n, names.as_mut_ptr()) };
    names[..n.max(0) as usize].to_vec()
}

fn source_of(gl: &Gl, shader: u32) -> String {
    let len = shader_iv(gl, shader, SHADER_SOURCE_LENGTH).max(1);
    let mut buf = vec![0u8; len as usize];
    let mut written = 0;
    // SAFETY: the buffer holds `len` bytes including the terminator.
    unsafe { gl.GetShaderSource(shader, len, &mut written, buf.as_mut_ptr().cast()) };
    buf.truncate(written.max(0) as usize);
    String::from_utf8_lossy(&buf).into_owned()
}

/// The first kilobyte of `shader`'s info log.
fn shader_log(gl: &Gl, shader: u32) -> String {
    let mut buf = [0u8; 1024];
    let mut len = 0;
    // SAFETY: the log into a local buffer of the stated size.
    unsafe { gl.GetShaderInfoLog(shader, buf.len() as i32, &mut len, buf.as_mut_ptr().cast()) };
    String::from_utf8_lossy(&buf[..len.clamp(0, buf.len() as i32) as usize]).into_owned()
}

fn compile(gl: &Gl, shader: u32, source: &str) -> bool {
    let Ok(c) = CString::new(source) else { return false };
    let ptr = c.as_ptr();
    // SAFETY: one NUL-terminated string.
    unsafe {
        gl.ShaderSource(shader, 1, &ptr, core::ptr::null());
        gl.CompileShader(shader);
    }
    shader_iv(gl, shader, COMPILE_STATUS) != 0
}

/// The stage whose gl_Position reaches the rasteriser: geometry, else tessellation
/// evaluation, else vertex.
fn last_position_stage(gl: &Gl, shaders: &[u32]) -> Option<(u32, Stage)> {
    let staged: Vec<(u32, Stage)> = shaders
        .iter()
        .filter_map(|&s| Some((s, Stage::from_gl(shader_iv(gl, s, SHADER_TYPE) as u32)?)))
        .collect();
    [Stage::Geometry, Stage::TessEval, Stage::Vertex]
        .into_iter()
        .find_map(|want| staged.iter().copied().find(|(_, st)| *st == want))
}

/// Links `program` (through `link`, the real glLinkProgram) with the view shift injected, and
/// with the disparity record (`shader::record`) when the fast modes read it; a link that
/// fails with the record is tried again without it, then with the app's own sources.
pub fn link_program(gl: &Gl, info: crate::gl::GlInfo, group: &ShareGroup, program: u32, link: impl Fn()) {
    // Not on ES (the record is desktop GLSL; and Mesa's ES linker crashed on the relinks the
    // attempt makes for shaders shared between programs: glmark2-es2's desktop scene).
    let record = crate::config::settings().records_disparity()
        && !info.es
        && info.at_least(4, 5)
        && gl.BlendFunci.is_loaded()
        && gl.BindFragDataLocation.is_loaded();
    if record && link_with(gl, group, program, &link, true) {
        return;
    }
    link_with(gl, group, program, &link, false);
}

/// One attempt; false when it failed with the record (the sources are the app's again).
fn link_with(gl: &Gl, group: &ShareGroup, program: u32, link: &impl Fn(), record: bool) -> bool {
    let shaders = attached_shaders(gl, program);
    let Some((shader, stage)) = last_position_stage(gl, &shaders) else {
        link();
        return true;
    };
    let known = group.lock().original_sources.get(&shader).cloned();
    let original = known.clone().unwrap_or_else(|| source_of(gl, shader));
    let analysis = shader::analyse(&original, stage);
    let rewritten = match known {
        // Rewritten for another program: with the record or without, as that one needed.
        Some(_) if record && !source_of(gl, shader).contains(shader::record::RECORD_VARYING) => {
            compile(gl, shader, &original);
            group.lock().original_sources.remove(&shader);
            try_rewrite(gl, group, shader, &original, &analysis, program, record)
        }
        Some(_) => true,
        None => try_rewrite(gl, group, shader, &original, &analysis, program, record),
    };
    let fs = fragment_shader(gl, &shaders);
    let fs_source = fs.map(|fs| app_source(gl, group, fs));
    let fragment = fs.and_then(|fs| rewrite_fragcoord(gl, group, fs, program));
    let pixel_addressing = fs_source.and_then(|src| shader::fragcoord::pixel_addressing(&src, fragment.is_some()));
    let varying = rewritten && source_of(gl, shader).contains(shader::record::RECORD_VARYING);
    let recorded = match fs.filter(|_| record && varying) {
        Some(fs) => record_fragment(gl, group, fs, program),
        None => None,
    };
    let fragment = fragment.or(recorded.as_ref().map(|_| fs.unwrap_or(0)));
    link();
    let linked = {
        let mut ok = 0;
        // SAFETY: single-integer program query.
        unsafe { gl.GetProgramiv(program, LINK_STATUS, &mut ok) };
        ok != 0
            && recorded
                .as_ref()
                .is_none_or(|outputs| outputs_clear_of_record(gl, program, outputs))
    };
    if (rewritten || fragment.is_some()) && !linked {
        if !record {
            crate::log::limited(
                "link",
                crate::log::Level::Warn,
                format_args!("program {program}: link failed with our edits; linking the app's original"),
            );
        }
        for s in [Some(shader).filter(|_| rewritten), fragment].into_iter().flatten() {
            // Not `if let … = group.lock()…`: the guard would live through the compile, and GL
            // may call the app back from inside it (see `state::lock`).
            let original = group.lock().original_sources.remove(&s);
            if let Some(src) = original {
                compile(gl, s, &src);
            }
        }
        compile(gl, shader, &original);
        if record {
            crate::log::info(format_args!(
                "program {program}: does not link with the disparity record; the fast modes read its depth"
            ));
            return false;
        }
        link();
        return true;
    }
    if linked {
        remember(
            gl,
            group,
            program,
            &analysis,
            (rewritten, pixel_addressing, recorded.is_some()),
        );
    }
    true
}

/// The fragment shader `fs` (its current source, which may carry the `gl_FragCoord` edit)
/// with the disparity record; `Some(app's outputs)` when it now writes it.
fn record_fragment(gl: &Gl, group: &ShareGroup, fs: u32, program: u32) -> Option<Vec<String>> {
    let current = source_of(gl, fs);
    let before = group.lock().original_sources.get(&fs).cloned();
    if let Some(before) = before.filter(|_| current.contains(shader::record::RECORD_VARYING)) {
        // Recording already, for another program it is shared with (wined3d attaches one
        // fragment shader to several programs): its output must be bound in this one too, or
        // the linker puts it on any draw buffer.
        let edit = shader::record::rewrite_fragment(&before).ok()?;
        bind_record_output(gl, program, edit.bind_output);
        return Some(edit.app_outputs);
    }
    let edit = match shader::record::rewrite_fragment(&current) {
        Ok(e) => e,
        Err(why) => {
            crate::log::debug(format_args!(
                "program {program}: fragment shader {fs} records no disparity: {why}"
            ));
            return None;
        }
    };
    if !compile(gl, fs, &edit.source) {
        crate::log::debug(format_args!(
            "program {program}: fragment shader {fs} with the disparity record does not compile: {}",
            shader_log(gl, fs).lines().next().unwrap_or("")
        ));
        compile(gl, fs, &current);
        return None;
    }
    bind_record_output(gl, program, edit.bind_output);
    group.lock().original_sources.entry(fs).or_insert(current);
    Some(edit.app_outputs)
}

fn bind_record_output(gl: &Gl, program: u32, bind: bool) {
    if bind {
        let name = CString::new(shader::record::RECORD_OUTPUT).unwrap_or_default();
        // SAFETY: a name binding on the app's program, effective at the link that follows.
        unsafe { gl.BindFragDataLocation(program, shader::record::RECORD_BUFFER, name.as_ptr()) };
    }
}

/// None of the app's own outputs was placed on the record's draw buffer by the linker.
fn outputs_clear_of_record(gl: &Gl, program: u32, outputs: &[String]) -> bool {
    outputs.iter().all(|o| {
        let Ok(name) = CString::new(o.as_str()) else {
            return true;
        };
        // SAFETY: a location query on a linked program.
        let at = unsafe { gl.GetFragDataLocation(program, name.as_ptr()) };
        at != shader::record::RECORD_BUFFER as i32
    })
}

/// The app's own source of `shader` (before any edit of ours).
fn app_source(gl: &Gl, group: &ShareGroup, shader: u32) -> String {
    // Two statements: the group's lock must not be held through a GL call.
    let known = group.lock().original_sources.get(&shader).cloned();
    known.unwrap_or_else(|| source_of(gl, shader))
}

fn fragment_shader(gl: &Gl, shaders: &[u32]) -> Option<u32> {
    shaders
        .iter()
        .copied()
        .find(|&s| Stage::from_gl(shader_iv(gl, s, SHADER_TYPE) as u32) == Some(Stage::Fragment))
}

/// The fragment shader with `gl_FragCoord` mapped back to window coordinates (see
/// `shader::fragcoord`); `Some(shader)` when it now carries our edit.
fn rewrite_fragcoord(gl: &Gl, group: &ShareGroup, fs: u32, program: u32) -> Option<u32> {
    if group.lock().original_sources.contains_key(&fs) {
        return Some(fs);
    }
    let original = source_of(gl, fs);
    let new = shader::fragcoord::rewrite(&original).ok()?;
    if !compile(gl, fs, &new) {
        crate::log::limited(
            "link",
            crate::log::Level::Warn,
            format_args!(
                "program {program}: fragment shader {fs} with gl_FragCoord mapping does not compile; using the original"
            ),
        );
        compile(gl, fs, &original);
        return None;
    }
    group.lock().original_sources.insert(fs, original);
    Some(fs)
}

fn try_rewrite(
    gl: &Gl,
    group: &ShareGroup,
    shader: u32,
    original: &str,
    analysis: &shader::Analysis,
    program: u32,
    record: bool,
) -> bool {
    // The shift without the record where the record cannot be had (GLSL ES, a stage whose
    // outputs are full): the fragment side then sees no varying and records nothing.
    if record {
        match shader::rewrite_recording(original, analysis, true) {
            Ok(new) if compile(gl, shader, &new) => {
                group.lock().original_sources.insert(shader, original.to_string());
                return true;
            }
            Ok(_) => {
                crate::log::debug(format_args!(
                    "program {program}: {:?} shader {shader} does not compile with the disparity record: {}",
                    analysis.stage,
                    shader_log(gl, shader).lines().next().unwrap_or("")
                ));
                compile(gl, shader, original);
            }
            Err(why) => crate::log::debug(format_args!(
                "program {program}: {:?} shader {shader} without the disparity record: {why}",
                analysis.stage
            )),
        }
    }
    let new = match shader::rewrite_recording(original, analysis, false) {
        Ok(s) => s,
        Err(why) => {
            crate::log::info(format_args!(
                "program {program}: {:?} shader {shader} left as is: {why}",
                analysis.stage
            ));
            return false;
        }
    };
    if !compile(gl, shader, &new) {
        crate::log::limited(
            "link",
            crate::log::Level::Warn,
            format_args!(
                "program {program}: rewritten {:?} shader {shader} does not compile; using the original",
                analysis.stage
            ),
        );
        compile(gl, shader, original);
        return false;
    }
    group.lock().original_sources.insert(shader, original.to_string());
    true
}

fn remember(
    gl: &Gl,
    group: &ShareGroup,
    program: u32,
    analysis: &shader::Analysis,
    (rewritten, pixel_addressing, records): (bool, Option<&'static str>, bool),
) {
    let (view_loc, remap_loc) = if rewritten {
        (
            crate::gl::program::uniform(gl, program, shader::VIEW_UNIFORM),
            crate::gl::program::uniform(gl, program, shader::REMAP_UNIFORM),
        )
    } else {
        (-1, -1)
    };
    // Only the leftmost matrix of the chain says what the projection is (P, VP or MVP); a
    // model matrix further right would look orthographic. When the leftmost one lives in a
    // uniform block (location -1) the projection stays unknown and the shader decides per
    // vertex.
    let leftmost = analysis.matrix_uniforms.first();
    let builtin = leftmost.is_some_and(|n| n.starts_with("gl_"));
    let projection_loc = leftmost
        .filter(|n| !n.starts_with("gl_"))
        .map(|n| crate::gl::program::uniform(gl, program, n))
        .filter(|&l| l >= 0);
    let projection_ubo = leftmost
        .filter(|n| projection_loc.is_none() && !n.starts_with("gl_"))
        .and_then(|n| super::ubo::find(gl, program, n));
    // No matrix in the position's expression: one held in a vec4 array, if the program
    // applies exactly one.
    let vec4 = if leftmost.is_none() && analysis.position_kind != shader::PositionKind::Identity {
        vec4_projection(gl, group, program)
    } else {
        None
    };
    let projection_loc = projection_loc.or(vec4.map(|(loc, _)| loc));
    let camera_chain: Vec<i32> = analysis
        .matrix_uniforms
        .iter()
        .map(|n| {
            if n.starts_with("gl_") {
                -1
            } else {
                crate::gl::program::uniform(gl, program, n)
            }
        })
        .collect();
    let camera_chain = if camera_chain.iter().all(|&l| l >= 0) {
        camera_chain
    } else {
        vec![]
    };
    let fragcoord_loc = crate::gl::program::uniform(gl, program, shader::fragcoord::FRAGCOORD_UNIFORM);
    if fragcoord_loc >= 0 {
        // SAFETY: our own uniform in the just-linked program: window coordinates unchanged.
        unsafe { gl.ProgramUniform4f(program, fragcoord_loc, 0.0, 0.0, 1.0, 1.0) };
    }
    crate::log::debug(format_args!(
        "program {program}: {:?}, view uniform at {view_loc}, matrices {:?}",
        analysis.position_kind, analysis.matrix_uniforms
    ));
    let mut info = ProgramInfo {
        view_loc,
        remap_loc,
        projection_loc,
        projection_vec4: vec4.map(|(_, rows)| rows),
        projection_ubo,
        builtin_projection: builtin,
        camera_chain,
        identity: analysis.position_kind == shader::PositionKind::Identity,
        fragcoord_loc,
        pixel_addressing,
        records,
        ..Default::default()
    };
    if view_loc >= 0 || fragcoord_loc >= 0 {
        info.hidden_uniforms = own_uniform_indices(gl, program);
    }
    group.linked(program, info);
}

/// The projection of a program whose vertex shader objects apply exactly one matrix held in
/// a vec4 array (`shader::vec4_matrix`; wined3d's `vs_c[]`): the location of its first
/// element and whether the elements are rows. Several (a world matrix beside the
/// world-view-projection) cannot be told apart here: the depth model is then fitted to what
/// the program draws (`camera::depth_fit`).
fn vec4_projection(gl: &Gl, group: &ShareGroup, program: u32) -> Option<(i32, bool)> {
    let mut found: Vec<shader::vec4_matrix::Vec4Matrix> = Vec::new();
    for s in attached_shaders(gl, program) {
        if Stage::from_gl(shader_iv(gl, s, SHADER_TYPE) as u32) != Some(Stage::Vertex) {
            continue;
        }
        for m in shader::analyse(&app_source(gl, group, s), Stage::Vertex).vec4_matrices {
            if !found.contains(&m) {
                found.push(m);
            }
        }
    }
    let [m] = found.as_slice() else {
        if found.len() > 1 {
            crate::log::debug(format_args!(
                "program {program}: {} matrices in vec4 arrays, none known to be the projection",
                found.len()
            ));
        }
        return None;
    };
    let first = crate::gl::program::uniform(gl, program, &m.first_name());
    let last = crate::gl::program::uniform(gl, program, &format!("{}[{}]", m.array, m.first + 3));
    // Uploads are assembled from one call covering the four: their locations must be in a row.
    if first < 0 || last != first + 3 {
        return None;
    }
    crate::state::share::VEC4_PROJECTIONS.store(true, std::sync::atomic::Ordering::Relaxed);
    crate::log::once_for(
        ("vec4-projection", u64::from(program)),
        crate::log::Level::Info,
        format_args!(
            "program {program}: projection read from the vec4 array {}[{}..{}] (its {})",
            m.array,
            m.first,
            m.first + 3,
            if m.rows { "rows" } else { "columns" }
        ),
    );
    Some((first, m.rows))
}

/// Active-uniform indices of our uniforms in a linked program (found by name, which works from
/// GL 2.0 and ES 2.0 on).
fn own_uniform_indices(gl: &Gl, program: u32) -> Vec<u32> {
    let ours = [
        shader::VIEW_UNIFORM,
        shader::REMAP_UNIFORM,
        shader::fragcoord::FRAGCOORD_UNIFORM,
    ];
    let mut count = 0;
    let mut found = vec![];
    let mut name = [0u8; 64];
    // SAFETY: integer query and name reads into a local buffer of the stated size.
    unsafe {
        gl.GetProgramiv(program, ACTIVE_UNIFORMS, &mut count);
        for i in 0..count.max(0) as u32 {
            let (mut len, mut size, mut ty) = (0, 0, 0);
            gl.GetActiveUniform(
                program,
                i,
                name.len() as i32,
                &mut len,
                &mut size,
                &mut ty,
                name.as_mut_ptr().cast(),
            );
            let n = &name[..len.clamp(0, name.len() as i32) as usize];
            if ours.iter().any(|o| o.as_bytes() == n) {
                found.push(i);
            }
        }
    }
    found
}
