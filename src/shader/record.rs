//! The disparity record's shader side (DESIGN §5, "One disparity per pixel").
//!
//! Every rendered view carries, per pixel, the parallax exact mode gave what that pixel shows,
//! so that the warps, auto-convergence and the comfort pass read the disparity the draw had —
//! its own projection and depth range, the infinity rule, the comfort remap, zero for HUDs —
//! instead of re-deriving it from depth with one camera's model.
//!
//! The last pre-rasterisation stage (already rewritten for the shift) passes `w·p` on, where
//! `p` is the parallax its shift used (`holoinject_parallax_of` in `view_shift.glsl`): `w·p`
//! is affine in clip space, so perspective-correct interpolation is exact and the fragment's
//! parallax is `w·p · gl_FragCoord.w`. The fragment shader's `main` is wrapped to write it
//! to draw buffer [`RECORD_BUFFER`] as `(p, 1, 0, coverage)`: `g = 1` marks the pixel as
//! recorded (fixed-function and unrewritten draws leave `0` there, see
//! `multiview::scene::record`), and `coverage` (the app's alpha contributes at all, `≥
//! 1/255`) is the blend factor when the app blends, so a translucent surface replaces the
//! record where it shows at all and leaves the record of what is behind it where it is fully
//! transparent (½ was tried: glmark2 jellyfish 44 % of blocks agree against 84 %,
//! chromium-bsu's sprites 44 % against 80 %).
//!
//! Two output styles: shaders writing `gl_FragColor` / `gl_FragData` (any version) get
//! `gl_FragColor` renamed to `gl_FragData[0]` (the two cannot be mixed) and write
//! `gl_FragData[RECORD_BUFFER]`; shaders with their own `out` variables (1.30+) get one more,
//! bound to `RECORD_BUFFER` with `glBindFragDataLocation` before the link. GLSL ES is left
//! alone (ES 2.0 has one draw buffer).

use super::rewrite::{conditionals_balanced, defines_main, line_directive, main_only_under_conditionals};
use super::text::{self, Token};

pub use super::RECORD_VARYING;
/// The fragment output added to shaders with their own `out` variables.
pub const RECORD_OUTPUT: &str = "holoinject_record";
/// The draw buffer (and colour attachment) the record is written to: the last one GL 3.0
/// guarantees, the one an app is least likely to use.
pub const RECORD_BUFFER: u32 = 7;

/// A fragment shader that writes the record.
#[derive(Debug)]
pub struct FragmentRecord {
    pub source: String,
    /// `RECORD_OUTPUT` must be bound to `RECORD_BUFFER` before the link.
    pub bind_output: bool,
    /// The app's own outputs, which must not have landed on `RECORD_BUFFER`.
    pub app_outputs: Vec<String>,
}

/// An app's fragment output at global scope: `[layout(location = N)] out T name`.
struct Output {
    name: String,
    ty: String,
    location: Option<u32>,
}

pub fn rewrite_fragment(source: &str) -> Result<FragmentRecord, String> {
    let blanked = text::blank_comments(source);
    if text::has_ident(&blanked, RECORD_VARYING) || text::has_ident(&blanked, RECORD_OUTPUT) {
        return Err("already records disparity".into());
    }
    let dirs = text::directives(&blanked);
    if !conditionals_balanced(&dirs) {
        return Err("unbalanced #if/#else/#endif".into());
    }
    let version = text::version(&dirs);
    if version.is_some_and(|v| v.0.1) {
        return Err("GLSL ES".into());
    }
    if dirs
        .iter()
        .any(|d| d.name == "define" && d.rest.split_whitespace().next() == Some("main"))
    {
        return Err("the shader #defines main itself".into());
    }
    if !defines_main(&blanked) || main_only_under_conditionals(&blanked, &dirs) {
        return Err("no main() outside #if".into());
    }
    let toks = text::tokens(&blanked);
    if layout_names(&toks, "index") {
        return Err("dual-source blending (a second draw buffer is not allowed with it)".into());
    }
    // `#define gl_FragColor out_Color` (ioquake3's GLSL 1.50 header, and others porting 1.10
    // shaders): the colour is that `out` variable, whatever the code calls it.
    let aliased = dirs
        .iter()
        .any(|d| d.name == "define" && d.rest.split_whitespace().next() == Some("gl_FragColor"));
    let frag_color = !aliased && text::has_ident(&blanked, "gl_FragColor");
    let legacy = frag_color || text::has_ident(&blanked, "gl_FragData");
    let number = version.map_or(110, |v| v.0.0);
    let varying = super::record_varying(version.map(|v| v.0), false).ok_or("GLSL ES")?;
    let (decls, write, outputs) = if legacy || number < 130 {
        if !legacy {
            return Err("writes no colour".into());
        }
        let rename = if frag_color {
            "#define gl_FragColor gl_FragData[0]\n"
        } else {
            ""
        };
        let write = format!("gl_FragData[{RECORD_BUFFER}] = holoinject_recorded(gl_FragData[0].a);",);
        (format!("{rename}{varying}"), write, vec![])
    } else {
        let outputs = outputs(&toks);
        if outputs.is_empty() {
            return Err("writes no colour".into());
        }
        let main = outputs
            .iter()
            .find(|o| o.location == Some(0))
            .or_else(|| (outputs.len() == 1).then(|| &outputs[0]));
        let alpha = match main {
            Some(o) if o.ty == "vec4" => format!("{}.a", o.name),
            _ => "1.0".to_string(),
        };
        if outputs.iter().any(|o| o.location == Some(RECORD_BUFFER)) {
            return Err(format!("an output of its own at location {RECORD_BUFFER}"));
        }
        let write = format!("{RECORD_OUTPUT} = holoinject_recorded({alpha});");
        let names = outputs.into_iter().map(|o| o.name).collect();
        (format!("{varying}out vec4 {RECORD_OUTPUT};\n"), write, names)
    };
    let anchor = dirs
        .iter()
        .filter(|d| d.name == "extension")
        .map(|d| d.line)
        .next_back()
        .or(version.map(|v| v.1))
        .map(|line| text::line_after_conditionals(&dirs, line));
    let (offset, next_line) = anchor
        .and_then(|line| text::offset_after_line(source, line))
        .unwrap_or((0, 0));
    let head = format!(
        "#define main holoinject_app_main\n{decls}{}",
        line_directive(version.map(|v| v.0), next_line + 1)
    );
    let tail = format!(
        "#undef main\nvec4 holoinject_recorded(float holoinject_alpha)\n{{\n    \
         return vec4({RECORD_VARYING} * gl_FragCoord.w, 1.0, 0.0, holoinject_alpha >= 1.0 / 255.0 ? 1.0 : 0.0);\n}}\n\
         void main()\n{{\n    holoinject_app_main();\n    {write}\n}}\n"
    );
    let mut out = String::with_capacity(source.len() + head.len() + tail.len() + 1);
    out.push_str(&source[..offset]);
    out.push_str(&head);
    out.push_str(&source[offset..]);
    if !out.ends_with('\n') {
        out.push('\n');
    }
    out.push_str(&tail);
    Ok(FragmentRecord {
        source: out,
        bind_output: !legacy,
        app_outputs: outputs,
    })
}

/// Whether some `layout(...)` names `what`.
fn layout_names(toks: &[Token], what: &str) -> bool {
    let mut i = 0;
    while i + 1 < toks.len() {
        if toks[i].is_ident("layout") && toks[i + 1].is_punct("(") {
            let end = toks[i..]
                .iter()
                .position(|t| t.is_punct(")"))
                .map_or(toks.len(), |e| i + e);
            if toks[i..end].iter().any(|t| t.is_ident(what)) {
                return true;
            }
            i = end;
        }
        i += 1;
    }
    false
}

/// The `out` declarations at global scope (brace depth 0).
fn outputs(toks: &[Token]) -> Vec<Output> {
    const QUALIFIERS: [&str; 9] = [
        "highp",
        "mediump",
        "lowp",
        "flat",
        "smooth",
        "noperspective",
        "centroid",
        "invariant",
        "precise",
    ];
    let mut found = vec![];
    let mut depth = 0i32;
    for (i, t) in toks.iter().enumerate() {
        if t.is_punct("{") {
            depth += 1;
        } else if t.is_punct("}") {
            depth -= 1;
        }
        if depth != 0 || !t.is_ident("out") {
            continue;
        }
        let mut j = i + 1;
        while toks.get(j).is_some_and(|t| QUALIFIERS.iter().any(|q| t.is_ident(q))) {
            j += 1;
        }
        let (Some(Token::Ident(ty)), Some(Token::Ident(name))) = (toks.get(j), toks.get(j + 1)) else {
            continue;
        };
        found.push(Output {
            name: name.clone(),
            ty: ty.clone(),
            location: location_before(toks, i),
        });
    }
    found
}

/// `N` of a `layout(... location = N ...)` right before token `i` (qualifiers between).
fn location_before(toks: &[Token], i: usize) -> Option<u32> {
    let close = (0..i).rev().take(4).find(|&k| toks[k].is_punct(")"))?;
    let open = (0..close).rev().find(|&k| toks[k].is_punct("("))?;
    if open == 0 || !toks[open - 1].is_ident("layout") {
        return None;
    }
    let at = (open..close).find(|&k| toks[k].is_ident("location"))?;
    match (toks.get(at + 1), toks.get(at + 2)) {
        (Some(eq), Some(Token::Number(n))) if eq.is_punct("=") => n.trim_end_matches(['u', 'U']).parse().ok(),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn legacy_shader_writes_gl_frag_data() {
        let src = "#version 120\nvoid main() { gl_FragColor = vec4(1.0); }\n";
        let r = rewrite_fragment(src).unwrap();
        assert!(r.source.contains("#define gl_FragColor gl_FragData[0]"));
        assert!(r.source.contains("varying float holoinject_parallax_w;"));
        assert!(
            r.source
                .contains("gl_FragData[7] = holoinject_recorded(gl_FragData[0].a);")
        );
        assert!(!r.bind_output);
    }

    #[test]
    fn modern_shader_gets_an_output_and_the_alpha_of_location_0() {
        let src = "#version 330 core\nlayout(location = 1) out vec4 n;\nlayout(location = 0) out vec4 c;\n\
                   void main() { c = vec4(1.0); n = vec4(0.0); }\n";
        let r = rewrite_fragment(src).unwrap();
        assert!(r.source.contains("out vec4 holoinject_record;"));
        assert!(r.source.contains("holoinject_record = holoinject_recorded(c.a);"));
        assert!(r.bind_output);
        assert_eq!(r.app_outputs, ["n", "c"]);
    }

    #[test]
    fn an_aliased_gl_frag_color_is_the_app_s_output() {
        let src = "#version 150\nout vec4 out_Color;\n#define gl_FragColor out_Color\n\
                   void main() { gl_FragColor.rgb = vec3(1.0); gl_FragColor.a = 0.5; }\n";
        let r = rewrite_fragment(src).unwrap();
        assert!(!r.source.contains("gl_FragData"));
        assert!(
            r.source
                .contains("holoinject_record = holoinject_recorded(out_Color.a);")
        );
        assert_eq!(r.app_outputs, ["out_Color"]);
    }

    #[test]
    fn refuses_what_it_cannot_record() {
        for src in [
            "#version 300 es\nprecision mediump float;\nout vec4 c;\nvoid main() { c = vec4(1.0); }\n",
            "#version 330\nlayout(location = 0, index = 1) out vec4 c;\nvoid main() { c = vec4(1.0); }\n",
            "#version 330\nlayout(location = 7) out vec4 c;\nvoid main() { c = vec4(1.0); }\n",
            "#version 330\nvoid main() { }\n",
            "#version 110\nvoid main() { }\n",
        ] {
            assert!(rewrite_fragment(src).is_err(), "{src}");
        }
    }

    #[test]
    fn vertex_rewrite_passes_the_parallax_on() {
        let src = "#version 330\nuniform mat4 mvp;\nin vec4 p;\nvoid main() { gl_Position = mvp * p; }\n";
        let a = super::super::analyse(src, super::super::Stage::Vertex);
        let out = super::super::rewrite::rewrite_recording(src, &a, true).unwrap();
        assert!(out.contains("out float holoinject_parallax_w;"));
        assert!(out.contains("holoinject_parallax_w = holoinject_parallax_of(gl_Position);"));
    }
}
