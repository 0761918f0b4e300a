//! Corpus tests: every shader in `tests/shaders/` is analysed against a hand-written
//! expectation, rewritten, and the rewrite is compiled by `glslangValidator`.

use std::path::{Path, PathBuf};
use std::process::Command;

use super::PositionKind::{self, *};
use super::*;

/// How to call glslangValidator for a corpus file.
#[derive(Clone, Copy, PartialEq)]
pub(super) enum Profile {
    /// As the file says (no `#version` means ES 1.00 to glslang).
    Default,
    /// No `#version` meant as desktop GLSL 1.10 (`-d`).
    Desktop110,
    /// No `#version`, valid both ways: check both.
    Both,
}

struct Case {
    file: &'static str,
    kind: PositionKind,
    matrices: &'static [&'static str],
    parsed: bool,
    /// `None`: rewrite must succeed; `Some(text)`: must fail with a reason containing it.
    refused: Option<&'static str>,
    profile: Profile,
}

const fn ok(file: &'static str, kind: PositionKind, matrices: &'static [&'static str]) -> Case {
    Case {
        file,
        kind,
        matrices,
        parsed: true,
        refused: None,
        profile: Profile::Default,
    }
}

const P: &str = "projection";
const MVP: &str = "gl_ModelViewProjectionMatrix";

fn cases() -> Vec<Case> {
    vec![
        ok("comments_mention_main.vert", MatrixMultiply, &["mvp"]),
        ok("compat_120_ftransform.vert", MatrixMultiply, &[MVP]),
        ok(
            "compat_130_builtins.vert",
            MatrixMultiply,
            &["gl_ProjectionMatrix", "gl_ModelViewMatrix"],
        ),
        ok(
            "compat_150_compatibility.vert",
            MatrixMultiply,
            &["gl_ProjectionMatrix", "gl_ModelViewMatrix"],
        ),
        ok("constant_point_330.vert", Constant, &[]),
        ok("core460_anonymous_ubo.vert", MatrixMultiply, &[P, "view", "model"]),
        ok(
            "core460_instanced_ubo_struct.vert",
            MatrixMultiply,
            &["Transforms.proj", "Transforms.view", "obj.model"],
        ),
        ok("core_140.vert", MatrixMultiply, &["mvp"]),
        ok("es100_attribute_precision.vert", MatrixMultiply, &["u_mvpMatrix"]),
        ok("es100_version100.vert", MatrixMultiply, &["uPMatrix", "uMVMatrix"]),
        ok("es2gears.vert", MatrixMultiply, &["ModelViewProjectionMatrix"]),
        ok(
            "es300_model_view_proj.vert",
            MatrixMultiply,
            &["u_projection", "u_view", "u_model"],
        ),
        ok("es310_ubo.vert", MatrixMultiply, &["Camera.viewProj", "model"]),
        ok("es320_geometry_ext.geom", MatrixMultiply, &["u_viewProj"]),
        ok("es320_mvp.vert", MatrixMultiply, &["mvp"]),
        ok("far_component_write_330.vert", FarPlane, &["viewProjection"]),
        ok("fullscreen_quad_ndc_330.vert", Identity, &[]),
        ok("fullscreen_triangle_vertexid_450.vert", Identity, &[]),
        Case {
            refused: Some("gl_Layer"),
            ..ok("geometry_cubemap_layer_330.geom", MatrixMultiply, &["shadowMatrices"])
        },
        ok("geometry_passthrough_ext_330.geom", Unknown, &[]),
        ok("geometry_streams_400.geom", MatrixMultiply, &["mvp"]),
        ok("geometry_triangles_150.geom", MatrixMultiply, &[P]),
        ok("gl_pervertex_410.vert", MatrixMultiply, &["MVP"]),
        ok("glmark2_desktop.vert", Identity, &[]),
        ok("glmark2_effect_2d.vert", Identity, &[]),
        ok("glmark2_ideas_paper.vert", MatrixMultiply, &[P, "modelview"]),
        ok("glmark2_jellyfish.vert", MatrixMultiply, &["uWorldViewProj"]),
        ok(
            "glmark2_light_basic.vert",
            MatrixMultiply,
            &["ModelViewProjectionMatrix"],
        ),
        ok("glmark2_shadow.vert", MatrixMultiply, &["ModelViewProjectionMatrix"]),
        // The displacement offset is built from the normal matrix, so it takes part too.
        ok(
            "glmark2_terrain.vert",
            MatrixMultiply,
            &["projectionMatrix", "normalMatrix", "modelViewMatrix"],
        ),
        ok("helper_function_330.vert", MatrixMultiply, &["u_viewProj", "u_model"]),
        ok("hud_ortho_330.vert", MatrixMultiply, &[P]),
        Case {
            parsed: false,
            ..ok(
                "identifiers_sample_flat_120.vert",
                MatrixMultiply,
                &["modelViewProjection"],
            )
        },
        Case {
            profile: Profile::Both,
            ..ok("ifdef_gl_es.vert", MatrixMultiply, &["u_matrix"])
        },
        ok("learnopengl_330_core.vert", MatrixMultiply, &[P, "view", "model"]),
        Case {
            profile: Profile::Desktop110,
            ..ok("legacy_110_noversion.vert", MatrixMultiply, &[MVP])
        },
        ok(
            "main_void_120.vert",
            MatrixMultiply,
            &["projectionMatrix", "modelViewMatrix"],
        ),
        ok("skybox_xyww_330.vert", FarPlane, &[P, "view"]),
        ok("tess_eval_400.tese", MatrixMultiply, &[P, "modelview"]),
        ok("tess_eval_passthrough_410.tese", Unknown, &[]),
        Case {
            refused: Some("gl_Position"),
            ..ok("transform_feedback_only_330.vert", Unknown, &[])
        },
        ok("version_after_comment.vert", MatrixMultiply, &["uMVP"]),
        // glsl-lang does not know the extension; its line is dropped before parsing.
        Case {
            refused: Some("gl_Layer"),
            ..ok("vertex_layer_ext_450.vert", MatrixMultiply, &["viewProj"])
        },
        // Wine 8.0 wined3d, a vs_2_0 shader: 20 #extension lines glsl-lang does not know, and
        // gl_Position written by a function of another shader object.
        ok("wined3d_vs_2_0.vert", Unknown, &[]),
        // Its Direct3D 11 path, an HLSL `mul(float4(p, 1), wvp)` with the matrix in a constant
        // buffer (a uniform block of vec4s), scalarised through registers: products of the
        // array with the vertex, not a pass-through.
        ok("wined3d_vs_4_0.vert", Unknown, &[]),
    ]
}

fn corpus_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/shaders")
}

pub(super) fn stage_of(file: &str) -> Stage {
    match file.rsplit('.').next() {
        Some("geom") => Stage::Geometry,
        Some("tese") => Stage::TessEval,
        _ => Stage::Vertex,
    }
}

/// Compiles `source` with glslangValidator; `Err(log)` when it does not compile.
pub(super) fn validate(name: &str, source: &str, profile: Profile) -> Result<(), String> {
    let dir = std::env::temp_dir().join(format!("holoinject-shader-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join(name);
    std::fs::write(&path, source).expect("write temp shader");
    let flags: &[&[&str]] = match profile {
        Profile::Default => &[&[]],
        Profile::Desktop110 => &[&["-d"]],
        Profile::Both => &[&[], &["-d"]],
    };
    for extra in flags {
        let out = Command::new("glslangValidator").args(*extra).arg(&path).output();
        let out = out.unwrap_or_else(|e| {
            panic!("glslangValidator not runnable ({e}): install it with `apt-get install -y glslang-tools`")
        });
        if !out.status.success() {
            let log = String::from_utf8_lossy(&out.stdout).into_owned();
            return Err(format!("{extra:?}: {log}"));
        }
    }
    Ok(())
}

#[test]
fn corpus_analysis_matches_expectations() {
    let cases = cases();
    let on_disk = std::fs::read_dir(corpus_dir()).unwrap().count();
    assert_eq!(on_disk, cases.len(), "every corpus file needs an expectation");
    let mut failures = Vec::new();
    for case in &cases {
        let src = std::fs::read_to_string(corpus_dir().join(case.file)).unwrap();
        let a = analyse(&src, stage_of(case.file));
        let got = (a.position_kind.clone(), a.matrix_uniforms.clone(), a.parsed);
        let want = (
            case.kind.clone(),
            case.matrices.iter().map(|s| s.to_string()).collect(),
            case.parsed,
        );
        if got != want {
            failures.push(format!("{}: got {got:?}, want {want:?}", case.file));
        }
        let writes = case.refused != Some("gl_Position");
        if a.writes_position != writes || a.writes_layer != (case.refused == Some("gl_Layer")) {
            failures.push(format!(
                "{}: writes_position/layer {}/{}",
                case.file, a.writes_position, a.writes_layer
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn corpus_rewrites_compile_with_glslang() {
    let mut failures = Vec::new();
    for case in cases() {
        let src = std::fs::read_to_string(corpus_dir().join(case.file)).unwrap();
        if let Err(log) = validate(case.file, &src, case.profile) {
            failures.push(format!("{} (original!) {log}", case.file));
        }
        let result = rewrite(&src, &analyse(&src, stage_of(case.file)));
        match (result, case.refused) {
            (Ok(out), None) => {
                if let Err(log) = validate(case.file, &out, case.profile) {
                    failures.push(format!("{}: {log}\n{out}", case.file));
                }
            }
            (Err(e), Some(reason)) if e.contains(reason) => {}
            (other, _) => failures.push(format!("{}: unexpected {other:?}", case.file)),
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

#[test]
fn rewriting_twice_is_refused() {
    for case in cases().iter().filter(|c| c.refused.is_none()) {
        let src = std::fs::read_to_string(corpus_dir().join(case.file)).unwrap();
        let stage = stage_of(case.file);
        let once = rewrite(&src, &analyse(&src, stage)).unwrap();
        let twice = rewrite(&once, &analyse(&once, stage));
        assert_eq!(
            twice,
            Err("already rewritten by holoinject".to_string()),
            "{}",
            case.file
        );
    }
}

#[test]
fn stages_from_gl_enums() {
    assert_eq!(Stage::from_gl(0x8B31), Some(Stage::Vertex));
    assert_eq!(Stage::from_gl(0x8B30), Some(Stage::Fragment));
    assert_eq!(Stage::from_gl(0x8DD9), Some(Stage::Geometry));
    assert_eq!(Stage::from_gl(0x8E87), Some(Stage::TessEval));
    assert_eq!(Stage::from_gl(0x8E88), Some(Stage::TessControl));
    assert_eq!(Stage::from_gl(0x91B9), Some(Stage::Compute));
    assert_eq!(Stage::from_gl(0x1234), None);
}

#[test]
fn non_rasterizing_stages_and_odd_sources_are_refused() {
    let vs = "#version 330 core\nuniform mat4 m; in vec4 p;\nvoid main() { gl_Position = m * p; }\n";
    for stage in [Stage::Fragment, Stage::Compute, Stage::TessControl] {
        let err = rewrite(vs, &analyse(vs, stage)).unwrap_err();
        assert_eq!(err, "not a position-writing stage");
    }
    let defines_main = "#version 330 core\n#define main app_main\nvoid main() { gl_Position = vec4(0.0); }\n";
    let err = rewrite(defines_main, &analyse(defines_main, Stage::Vertex)).unwrap_err();
    assert!(err.contains("#defines main"), "{err}");
    let no_main = "#version 330 core\nvoid f() { gl_Position = vec4(0.0); }\n";
    assert_eq!(
        rewrite(no_main, &analyse(no_main, Stage::Vertex)),
        Err("no main()".to_string())
    );
}

#[test]
fn wined3d_s_vs_c_rows_are_found_in_the_whole_shader() {
    let src = std::fs::read_to_string(corpus_dir().join("wined3d_vs_2_0.vert")).unwrap();
    let a = analyse(&src, Stage::Vertex);
    let want = super::vec4_matrix::Vec4Matrix {
        array: "vs_c".into(),
        first: 0,
        rows: true,
    };
    assert_eq!(a.vec4_matrices, vec![want]);
}
