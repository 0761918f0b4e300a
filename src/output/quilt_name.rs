//! The Looking Glass quilt naming convention, `NAME_qs{C}x{R}a{aspect}.EXT`: players (Looking
//! Glass Studio, Bridge) read the layout from the name alone, so recordings carry it and
//! `holoinject quilt` reads it.

use std::path::{Path, PathBuf};

/// A quilt layout as a file name states it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuiltTag {
    pub cols: u32,
    pub rows: u32,
    /// View width / height.
    pub aspect: f64,
}

/// Finds `qs{C}x{R}a{aspect}` in a file name (the last one, if several).
pub fn parse(name: &str) -> Option<QuiltTag> {
    name.rmatch_indices("qs")
        .find_map(|(i, _)| parse_at(&name[i + 2..]).map(|(t, _)| t))
}

/// `{C}x{R}a{aspect}` at the start of `s`, and how many bytes it took.
fn parse_at(s: &str) -> Option<(QuiltTag, usize)> {
    let digits = |s: &str| s.bytes().take_while(u8::is_ascii_digit).count();
    let c = digits(s);
    let rest = s[c..].strip_prefix('x')?;
    let r = digits(rest);
    let rest2 = rest[r..].strip_prefix('a')?;
    let a = rest2.bytes().take_while(|b| b.is_ascii_digit() || *b == b'.').count();
    let aspect_text = rest2[..a].trim_end_matches('.');
    let tag = QuiltTag {
        cols: s[..c].parse().ok().filter(|&c| c > 0)?,
        rows: rest[..r].parse().ok().filter(|&r| r > 0)?,
        aspect: aspect_text.parse().ok().filter(|a: &f64| *a > 0.0)?,
    };
    Some((tag, c + 1 + r + 1 + aspect_text.len()))
}

/// `path` with `_{tag}` as the end of its stem: kept when it already ends so, replaced when it
/// ends with another layout's tag, appended otherwise. Returns the path and whether it changed.
pub fn with_tag(path: &Path, tag: &str) -> (PathBuf, bool) {
    let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("quilt");
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("mp4");
    let base = match stem.rfind("_qs") {
        Some(i) if parse_at(&stem[i + 3..]).is_some_and(|(_, n)| i + 3 + n == stem.len()) => &stem[..i],
        _ => stem,
    };
    let named = path.with_file_name(format!("{base}_{tag}.{ext}"));
    let changed = named != path;
    (named, changed)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_the_layout_from_names() {
        let t = parse("dump/f000002_qs8x6a0.75.png").unwrap();
        assert_eq!((t.cols, t.rows, t.aspect), (8, 6, 0.75));
        let t = parse("game_qs5x9a1.7778.mp4").unwrap();
        assert_eq!((t.cols, t.rows, t.aspect), (5, 9, 1.7778));
        assert_eq!(parse("qs3x2a1.mp4").map(|t| t.aspect), Some(1.0));
        assert_eq!(parse("quilts/plain.png"), None);
        assert_eq!(parse("x_qs0x6a0.75.png"), None);
        assert_eq!(parse("x_qs8x6.png"), None);
    }

    #[test]
    fn names_get_the_tag_once() {
        let tag = "qs8x6a0.75";
        assert_eq!(
            with_tag(Path::new("/v/run.mp4"), tag),
            ("/v/run_qs8x6a0.75.mp4".into(), true)
        );
        assert_eq!(
            with_tag(Path::new("/v/run_qs8x6a0.75.mp4"), tag),
            ("/v/run_qs8x6a0.75.mp4".into(), false)
        );
        // A stale tag (another layout) is replaced, not stacked.
        assert_eq!(
            with_tag(Path::new("run_qs5x9a1.7778.mp4"), tag),
            ("run_qs8x6a0.75.mp4".into(), true)
        );
        // "qs" inside the name is not a tag.
        assert_eq!(
            with_tag(Path::new("qsort.mp4"), tag),
            ("qsort_qs8x6a0.75.mp4".into(), true)
        );
    }
}
