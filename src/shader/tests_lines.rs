//! The rewrite keeps the app's line numbers (checked on glslang's error log) and the injected
//! shift reduces to the app's own position for the centre view.

use super::tests::{Profile, stage_of, validate};
use super::*;

const MARK: &str = "holoinject_test_undeclared";

/// The line glslang blames for the undeclared marker identifier.
fn error_line(name: &str, source: &str, profile: Profile) -> usize {
    let log = validate(name, source, profile).expect_err("the marker must not compile");
    let line = log
        .lines()
        .find(|l| l.contains(MARK))
        .unwrap_or_else(|| panic!("no marker error in:\n{log}"));
    // "ERROR: 0:LINE: 'holoinject_test_undeclared' : undeclared identifier"
    line.split(':')
        .nth(2)
        .and_then(|n| n.trim().parse().ok())
        .unwrap_or_else(|| panic!("{line}"))
}

/// Puts the marker statement right after the line containing `after`; returns its 1-based line.
fn with_marker(src: &str, after: &str) -> (String, usize) {
    let mut lines: Vec<String> = src.lines().map(str::to_string).collect();
    let at = lines.iter().position(|l| l.contains(after)).expect("anchor line") + 1;
    lines.insert(at, format!("    float marker = {MARK};"));
    (lines.join("\n") + "\n", at + 1)
}

fn check_lines(name: &str, src: &str, after: &str, profile: Profile) {
    let (marked, line) = with_marker(src, after);
    assert_eq!(error_line(name, &marked, profile), line, "original {name}");
    let out = rewrite(&marked, &analyse(&marked, stage_of(name))).unwrap();
    assert_eq!(error_line(name, &out, profile), line, "rewritten {name}:\n{out}");
}

#[test]
fn line_numbers_survive_for_every_version_style() {
    let body = "uniform mat4 mvp;\nattribute vec4 pos;\nvoid main()\n{\n    gl_Position = mvp * pos;\n}\n";
    // No #version: desktop 1.10 and ES 1.00 number `#line` differently; both must hold.
    check_lines(
        "noversion.vert",
        &format!("// leading comment\n\n{body}"),
        "{",
        Profile::Both,
    );
    check_lines("v110.vert", &format!("#version 110\n{body}"), "{", Profile::Default);
    check_lines(
        "v120.vert",
        &format!("\n/* header\n */\n#version 120\n{body}"),
        "{",
        Profile::Default,
    );
    check_lines("v100.vert", &format!("#version 100\n{body}"), "{", Profile::Default);
    let modern = "in vec4 pos;\nuniform mat4 mvp;\nvoid main()\n{\n    gl_Position = mvp * pos;\n}\n";
    check_lines(
        "v330.vert",
        &format!("// c\n#version 330 core\n{modern}"),
        "{",
        Profile::Default,
    );
    check_lines(
        "v300es.vert",
        &format!("#version 300 es\n{modern}"),
        "{",
        Profile::Default,
    );
    check_lines("v460.vert", &format!("#version 460\n{modern}"), "{", Profile::Default);
    let comment_on_version = format!("#version 150 /* spans\n lines */\n{modern}");
    check_lines("v150c.vert", &comment_on_version, "{", Profile::Default);
}

#[test]
fn line_numbers_survive_in_geometry_shaders() {
    let corpus = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/shaders/");
    for (file, after) in [
        ("geometry_triangles_150.geom", "gNormal = vNormal[i];"),
        ("geometry_passthrough_ext_330.geom", "bary[i] = 1.0;"),
        ("geometry_streams_400.geom", "color = vec4(1.0);"),
        ("es320_geometry_ext.geom", "for (int i"),
    ] {
        let src = std::fs::read_to_string(format!("{corpus}{file}")).unwrap();
        check_lines(file, &src, after, Profile::Default);
    }
}

#[test]
fn geometry_hook_goes_after_conditional_extensions() {
    let src = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/shaders/geometry_passthrough_ext_330.geom"
    ))
    .unwrap();
    let out = rewrite(&src, &analyse(&src, Stage::Geometry)).unwrap();
    let endif = out.find("#endif").unwrap();
    let proto = out.find("void holoinject_emit();").unwrap();
    assert!(endif < proto, "{out}");
    assert!(out.contains("#define EmitVertex() holoinject_emit()\n"));
}

/// The only statement that changes the position is the documented shift, and the centre view
/// (k = h = 0) returns the input untouched before any arithmetic: bit-identical output.
#[test]
fn centre_view_is_the_identity() {
    let patch = VIEW_SHIFT_GLSL;
    let shift = "holoinject_p.x += holoinject_view.x * (holoinject_p.w - holoinject_c) \
                 + holoinject_view.z * holoinject_p.w;";
    assert_eq!(patch.matches(shift).count(), 1, "the shift expression changed");
    let writes: Vec<&str> = patch
        .lines()
        .filter(|l| l.contains("holoinject_p.") && l.contains("=") && !l.contains("=="))
        .filter(|l| l.trim_start().starts_with("holoinject_p"))
        .collect();
    // The plain shift, and the comfort remap's (only reached with `holoinject_comfort` on).
    assert_eq!(writes.len(), 2, "{writes:?}");
    assert!(writes.contains(&format!("    {shift}").as_str()));
    assert!(
        writes.iter().all(|w| w.trim_start().starts_with("holoinject_p.x +=")),
        "y, z and w must never be written: {writes:?}"
    );
    let early = "if (holoinject_view.x == 0.0 && holoinject_view.z == 0.0)\n        return holoinject_p;";
    let (early_at, shift_at) = (
        patch.find(early).expect("centre early return"),
        patch.find(shift).unwrap(),
    );
    assert!(early_at < shift_at);
    assert!(patch.contains(&format!("uniform HOLOINJECT_HIGHP vec4 {VIEW_UNIFORM};")));
}

#[test]
fn vertex_wrapper_shifts_after_the_app_main() {
    let src = "#version 330 core\nuniform mat4 m;\nin vec4 p;\nvoid main(void) { gl_Position = m * p; }\n";
    let out = rewrite(src, &analyse(src, Stage::Vertex)).unwrap();
    assert!(
        out.starts_with("#version 330 core\n#define main holoinject_app_main\n#line 2\n"),
        "{out}"
    );
    let tail = "void main()\n{\n    holoinject_app_main();\n    gl_Position = holoinject_shift(gl_Position);\n}\n";
    assert!(out.ends_with(tail), "{out}");
    assert!(out.contains("#undef main\n"));
    // The app's text is kept verbatim.
    assert!(out.contains(&src["#version 330 core\n".len()..]));
}

#[test]
fn text_fallback_reads_blocks_and_skyboxes() {
    let blanked = text::blank_comments(
        "uniform highp mat4 a, b[2];\nuniform Cam { mat4 proj; vec4 eye; } cam;\n\
         void main() { vec4 p = cam.proj * a * v; gl_Position = p.xyww; } // gl_Layer = 1;\n",
    );
    let f = text_scan::scan(&blanked);
    assert_eq!(f.kind, Some(PositionKind::FarPlane));
    assert_eq!(f.matrices, vec!["Cam.proj".to_string(), "a".to_string()]);
    assert!(f.writes_position && !f.writes_layer);
}
