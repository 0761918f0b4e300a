//! Fragment shaders that read `gl_FragCoord` (screen-space lookups: refraction, SSAO at full
//! resolution, post-processing with `gl_FragCoord.xy / resolution`) would see the quilt's
//! coordinates — the tile's offset added — when replayed into a tile. A `#define` maps it back
//! to the app's window coordinates: `(gl_FragCoord.xy - origin) * scale`, with the origin and
//! scale of the view being drawn in `holoinject_fragcoord` (0, 0, 1, 1 outside tiles). The
//! macro names itself in its body, which the preprocessor does not expand again.

use super::rewrite::line_directive;
use super::text;

pub const FRAGCOORD_UNIFORM: &str = "holoinject_fragcoord";

/// The rewritten fragment shader, or why it is left alone.
pub fn rewrite(source: &str) -> Result<String, String> {
    let blanked = text::blank_comments(source);
    if !text::has_ident(&blanked, "gl_FragCoord") {
        return Err("does not read gl_FragCoord".into());
    }
    if text::has_ident(&blanked, FRAGCOORD_UNIFORM) {
        return Err("already rewritten by holoinject".into());
    }
    let dirs = text::directives(&blanked);
    if dirs
        .iter()
        .any(|d| d.name == "define" && d.rest.split_whitespace().next() == Some("gl_FragCoord"))
    {
        return Err("the shader #defines gl_FragCoord itself".into());
    }
    let toks = text::tokens(&blanked);
    if toks
        .windows(2)
        .any(|w| w[0].is_ident("vec4") && w[1].is_ident("gl_FragCoord"))
    {
        return Err("redeclares gl_FragCoord (layout qualifiers)".into());
    }
    let version = text::version(&dirs);
    // No non-preprocessor token may precede an #extension: the uniform goes after the last.
    let anchor = dirs
        .iter()
        .filter(|d| d.name == "extension")
        .map(|d| d.line)
        .next_back()
        .or(version.map(|v| v.1));
    let anchor = anchor.map(|line| text::line_after_conditionals(&dirs, line));
    let (offset, next_line) = anchor
        .and_then(|line| text::offset_after_line(source, line))
        .unwrap_or((0, 0));
    let head = format!(
        "#ifdef GL_FRAGMENT_PRECISION_HIGH\nuniform highp vec4 {u};\n#elif defined(GL_ES)\nuniform mediump vec4 {u};\n\
         #else\nuniform vec4 {u};\n#endif\n\
         #define gl_FragCoord vec4((gl_FragCoord.xy - {u}.xy) * {u}.zw, gl_FragCoord.zw)\n{line}",
        u = FRAGCOORD_UNIFORM,
        line = line_directive(version.map(|v| v.0), next_line + 1)
    );
    let mut out = String::with_capacity(source.len() + head.len());
    out.push_str(&source[..offset]);
    out.push_str(&head);
    out.push_str(&source[offset..]);
    Ok(out)
}

/// Why a fragment shader would read the wrong texels from a layer smaller than the app's
/// texture (`--fbo-scale`), if it would: integer texel addresses (`texelFetch`, image
/// loads and stores) come from pixel arithmetic the layer cannot see, and `gl_FragCoord`
/// (mapped back to the app's pixels) divided by `textureSize` (the layer's) is off by the
/// scale. `fragcoord_mapped`: the shader carries the `gl_FragCoord` mapping (`rewrite`).
pub fn pixel_addressing(source: &str, fragcoord_mapped: bool) -> Option<&'static str> {
    let blanked = text::blank_comments(source);
    let has = |name| text::has_ident(&blanked, name);
    if has("texelFetch") || has("texelFetchOffset") {
        Some("texelFetch")
    } else if has("imageLoad") || has("imageStore") || has("imageSize") {
        Some("images by pixel")
    } else if !has("gl_FragCoord") {
        None
    } else if !fragcoord_mapped {
        Some("gl_FragCoord, which could not be mapped")
    } else if has("textureSize") {
        Some("gl_FragCoord with textureSize")
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pixel_addressing_is_found() {
        let blur = "uniform sampler2D t; void main() { vec2 s = 1.0 / vec2(textureSize(t, 0)); }";
        assert_eq!(pixel_addressing(blur, false), None);
        let fetch = "uniform sampler2D t; void main() { gl_FragColor = texelFetch(t, ivec2(3), 0); }";
        assert_eq!(pixel_addressing(fetch, false), Some("texelFetch"));
        let uv = "uniform sampler2D t; void main() { gl_FragColor = texture(t, gl_FragCoord.xy / vec2(textureSize(t, 0))); }";
        assert_eq!(pixel_addressing(uv, true), Some("gl_FragCoord with textureSize"));
        let plain = "uniform vec2 r; void main() { gl_FragColor = vec4(gl_FragCoord.xy / r, 0, 1); }";
        assert_eq!(pixel_addressing(plain, true), None);
        assert!(pixel_addressing(plain, false).is_some());
        assert_eq!(pixel_addressing("// texelFetch\nvoid main() {}", false), None);
    }

    #[test]
    fn maps_fragcoord_after_version_and_extensions() {
        let src = "#version 330 core\n#extension GL_ARB_foo : enable\nout vec4 c;\nvoid main() { c = vec4(gl_FragCoord.xy / 100.0, 0.0, 1.0); }\n";
        let out = rewrite(src).unwrap();
        let ext = out.find("#extension").unwrap();
        let def = out.find("#define gl_FragCoord").unwrap();
        assert!(def > ext, "{out}");
        assert!(out.contains("uniform vec4 holoinject_fragcoord;"));
        assert!(out.ends_with("void main() { c = vec4(gl_FragCoord.xy / 100.0, 0.0, 1.0); }\n"));
    }

    #[test]
    fn leaves_other_shaders_alone() {
        assert!(rewrite("void main() { gl_FragColor = vec4(1.0); }").is_err());
        assert!(rewrite("// gl_FragCoord in a comment\nvoid main() { gl_FragColor = vec4(1.0); }").is_err());
        assert!(rewrite("#version 150\nlayout(origin_upper_left) in vec4 gl_FragCoord;\nvoid main() {}").is_err());
    }

    #[test]
    fn rewritten_shaders_validate() {
        let cases = [
            (
                "frag",
                "#version 330 core\nout vec4 c;\nuniform sampler2D t;\nvoid main() { c = texture(t, gl_FragCoord.xy / vec2(textureSize(t, 0))); }\n",
            ),
            (
                "frag",
                "#version 100\nprecision mediump float;\nvoid main() { gl_FragColor = vec4(gl_FragCoord.x / 640.0); }\n",
            ),
            (
                "frag",
                "void main() { gl_FragColor = vec4(gl_FragCoord.xy, 0.0, 1.0); }\n",
            ),
        ];
        for (i, (ext, src)) in cases.iter().enumerate() {
            let out = rewrite(src).unwrap();
            let path = std::env::temp_dir().join(format!("holoinject-fragcoord-{i}.{ext}"));
            std::fs::write(&path, &out).unwrap();
            let r = std::process::Command::new("glslangValidator").arg(&path).output();
            let r = r.expect("glslangValidator missing: apt-get install glslang-tools (scripts/setup-debian.sh)");
            assert!(r.status.success(), "{out}\n{}", String::from_utf8_lossy(&r.stdout));
        }
    }
}
