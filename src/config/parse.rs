//! Value syntax shared by the launcher (flags) and the layer (environment). The options that
//! name one of a few words have their parsers next to their types (`values`), re-exported
//! here so every option's syntax is found in one place.

use super::{Convergence, FrameSet, Mode};

pub use super::values::{
    boundary, fbo_scale, fbo_views, guard_band, output, present, preview, rows_on, synth_warp, weave_filter,
};
// The unit tests name these through `super::`, as they did when their parsers lived here.
#[cfg(test)]
use super::{FboScale, SynthWarp};

pub fn grid(v: &str) -> Result<(u32, u32), String> {
    let (a, b) = v
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("`{v}`: expected CxR, e.g. 8x6"))?;
    let a: u32 = a.trim().parse().map_err(|_| format!("`{v}`: expected CxR, e.g. 8x6"))?;
    let b: u32 = b.trim().parse().map_err(|_| format!("`{v}`: expected CxR, e.g. 8x6"))?;
    if a == 0 || b == 0 || a > 16384 || b > 16384 {
        return Err(format!("`{v}`: both numbers must be in 1..=16384"));
    }
    Ok((a, b))
}

/// Most views a quilt may have: every draw is replayed once per view, so a mistyped
/// `16384x16384` must not turn into 268 million draws per draw. Looking Glass panels use up
/// to 100.
pub const MAX_VIEWS: u32 = 1024;

pub fn quilt(v: &str) -> Result<(u32, u32), String> {
    let (c, r) = grid(v)?;
    if c * r > MAX_VIEWS {
        return Err(format!("`{v}`: {} views; at most {MAX_VIEWS}", c * r));
    }
    Ok((c, r))
}

/// `--mode`: `synth:pixel` is not built yet and says so.
pub fn mode(v: &str) -> Result<Mode, String> {
    match v.trim() {
        "exact" => Ok(Mode::Exact),
        "synth" => Ok(Mode::Synth),
        "synth:pixel" => Ok(Mode::SynthPixel),
        "auto" => Ok(Mode::Auto),
        m => {
            let (k, pixel) = match m.strip_suffix(":pixel") {
                Some(k) => (k, true),
                None => (m, false),
            };
            match k.strip_prefix("hybrid:").map(str::parse::<u32>) {
                Some(Ok(k)) if (1..=MAX_VIEWS).contains(&k) && pixel => Ok(Mode::HybridPixel(k)),
                Some(Ok(k)) if (1..=MAX_VIEWS).contains(&k) => Ok(Mode::Hybrid(k)),
                _ => Err(format!(
                    "`{v}`: expected exact|synth[:pixel]|hybrid:K[:pixel]|auto (K ≥ 1 rendered views)"
                )),
            }
        }
    }
}

/// `--frame-budget`: milliseconds per frame, 1 to 60,000.
pub fn frame_budget(v: &str) -> Result<f64, String> {
    finite(v).and_then(|x| {
        if (1.0..=60_000.0).contains(&x) {
            Ok(x)
        } else {
            Err(format!("`{v}`: milliseconds per frame in 1..=60000"))
        }
    })
}

/// A switch's value: `1|true|on|yes` or `0|false|off|no` (the launcher sets `1`; a preset may
/// say `true`).
pub fn switch(v: &str) -> Result<bool, String> {
    match v.trim().to_ascii_lowercase().as_str() {
        "1" | "true" | "on" | "yes" => Ok(true),
        "0" | "false" | "off" | "no" => Ok(false),
        _ => Err(format!("`{v}`: expected 1|0|true|false")),
    }
}

/// `--hotkeys` when not given: the layer grabs Ctrl+Alt with its keys (README "Live controls").
pub const DEFAULT_HOTKEYS: &str = "ctrl+alt";

/// `--hotkeys off|MOD+MOD…`: the modifiers held with every hotkey (`None`: no hotkeys).
pub fn hotkeys(v: &str) -> Result<Option<Vec<String>>, String> {
    let v = v.trim().to_ascii_lowercase();
    if v == "off" {
        return Ok(None);
    }
    let mods: Vec<String> = v.split('+').map(|m| m.trim().to_string()).collect();
    match mods
        .iter()
        .find(|m| !["ctrl", "alt", "shift", "super"].contains(&m.as_str()))
    {
        Some(bad) => Err(format!(
            "`{bad}`: expected off or modifiers joined by +, from ctrl, alt, shift, super"
        )),
        None => Ok(Some(mods)),
    }
}

/// `--reuse` is only meaningful where views are synthesised: `Err` is the one line saying so.
pub fn reuse_with(reuse: bool, mode: Mode) -> Result<(), String> {
    match mode {
        Mode::Synth | Mode::SynthPixel | Mode::Hybrid(_) | Mode::HybridPixel(_) => Ok(()),
        _ if !reuse => Ok(()),
        _ => Err("--reuse needs --mode synth or hybrid:K (it reuses views that would otherwise be synthesised; auto chooses its own)".into()),
    }
}

/// `--reuse-motion`: `None` for off, else the relative eye-distance tolerance.
pub fn reuse_motion(v: &str) -> Result<Option<f64>, String> {
    if v.trim() == "off" {
        return Ok(None);
    }
    match finite(v) {
        Ok(x) if x > 0.0 && x <= 1.0 => Ok(Some(x)),
        _ => Err(format!("`{v}`: expected off or a tolerance in (0, 1]")),
    }
}

/// `--synth-threshold`: pixels of disparity range a grid cell may hold before it is split.
pub fn synth_threshold(v: &str) -> Result<f64, String> {
    finite(v).and_then(|x| {
        if (0.01..=64.0).contains(&x) {
            Ok(x)
        } else {
            Err(format!("`{v}`: pixels in 0.01..=64"))
        }
    })
}

/// `--monitor`: a monitor by name, or a rectangle of the X screen given by hand.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum MonitorSpec {
    /// A RandR monitor, output or EDID name (`HDMI-1`, `LKG-P…`).
    Name(String),
    Geometry {
        w: u32,
        h: u32,
        x: i32,
        y: i32,
    },
}

/// `NAME` or `WxH+X+Y` (X and Y may be negative: `-1920+0` or `+-1920+0`).
pub fn monitor(v: &str) -> Result<MonitorSpec, String> {
    let v = v.trim();
    if v.is_empty() {
        return Err("expected a monitor name or WxH+X+Y".into());
    }
    let size_end = v.find(['+', '-']).unwrap_or(v.len());
    let size = &v[..size_end];
    // A name such as `HDMI-1` or `LKG-P…` is not a size.
    if !size.contains('x')
        || !size
            .split('x')
            .all(|d| !d.is_empty() && d.bytes().all(|b| b.is_ascii_digit()))
    {
        return Ok(MonitorSpec::Name(v.to_string()));
    }
    let bad = || format!("`{v}`: expected WxH+X+Y, e.g. 1536x2048+1920+0");
    let (w, h) = grid(size).map_err(|_| bad())?;
    let (x, y) = offsets(&v[size_end..]).ok_or_else(bad)?;
    Ok(MonitorSpec::Geometry { w, h, x, y })
}

/// `+X+Y` as X11 geometry writes it: each offset starts at a sign, `+-N` is `-N`.
fn offsets(s: &str) -> Option<(i32, i32)> {
    let b = s.as_bytes();
    let split = (1..b.len()).find(|&i| matches!(b[i], b'+' | b'-') && b[i - 1].is_ascii_digit())?;
    // `str::parse::<i32>` takes `-N` and `+N` but not `+-N`.
    let one = |t: &str| {
        t.strip_prefix('+')
            .filter(|t| t.starts_with('-'))
            .unwrap_or(t)
            .parse::<i32>()
            .ok()
    };
    (s.starts_with(['+', '-'])).then_some(())?;
    Some((one(&s[..split])?, one(&s[split..])?))
}

pub fn view_cone(v: &str) -> Result<f64, String> {
    finite(v).and_then(|d| {
        if d > 0.0 && d < 180.0 {
            Ok(d)
        } else {
            Err(format!("`{v}`: degrees in (0, 180)"))
        }
    })
}

pub fn convergence(v: &str) -> Result<Convergence, String> {
    if v.trim() == "auto" {
        Ok(Convergence::Auto)
    } else {
        positive(v).map(Convergence::Fixed)
    }
}

pub fn finite(v: &str) -> Result<f64, String> {
    v.trim()
        .parse::<f64>()
        .ok()
        .filter(|x| x.is_finite())
        .ok_or_else(|| format!("`{v}`: expected a number"))
}

pub fn positive(v: &str) -> Result<f64, String> {
    finite(v).and_then(|x| {
        if x > 0.0 {
            Ok(x)
        } else {
            Err(format!("`{v}`: must be > 0"))
        }
    })
}

pub fn nonempty(v: &str) -> Result<(), String> {
    if v.trim().is_empty() {
        Err("empty value".into())
    } else {
        Ok(())
    }
}

/// A video file ffmpeg can write a quilt into: `.mp4` (what Looking Glass players read),
/// `.mkv` or `.mov`.
pub fn record_path(v: &str) -> Result<(), String> {
    nonempty(v)?;
    let ext = std::path::Path::new(v)
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("");
    match ext.to_ascii_lowercase().as_str() {
        "mp4" | "mkv" | "mov" => Ok(()),
        _ => Err("expected a video file name ending in .mp4 (or .mkv, .mov)".into()),
    }
}

pub fn frame_number(v: &str) -> Result<u64, String> {
    match v.trim().parse::<u64>() {
        Ok(n) if n >= 1 => Ok(n),
        _ => Err(format!("`{v}`: expected a frame number ≥ 1 (frames count from 1)")),
    }
}

pub fn frames(v: &str) -> Result<FrameSet, String> {
    if let Some(n) = v.trim().strip_prefix("every:") {
        return frame_number(n).map(FrameSet::Every);
    }
    let list: Result<Vec<u64>, String> = v.split(',').map(frame_number).collect();
    list.map(FrameSet::List)
        .map_err(|e| format!("{e}; expected a list like 1,10,30 or every:N"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn record_wants_a_video_name() {
        assert!(record_path("run.mp4").is_ok() && record_path("a/b.MKV").is_ok());
        assert!(record_path("run.png").unwrap_err().contains(".mp4"));
        assert!(record_path(" ").is_err());
    }

    #[test]
    fn monitor_is_a_name_or_x11_geometry() {
        let g = |w, h, x, y| Ok(MonitorSpec::Geometry { w, h, x, y });
        assert_eq!(monitor("1536x2048+1920+0"), g(1536, 2048, 1920, 0));
        assert_eq!(monitor("800x600-800+0"), g(800, 600, -800, 0));
        assert_eq!(monitor("800x600+-800-10"), g(800, 600, -800, -10));
        assert_eq!(monitor("HDMI-1"), Ok(MonitorSpec::Name("HDMI-1".into())));
        assert_eq!(monitor("LKG-P00123"), Ok(MonitorSpec::Name("LKG-P00123".into())));
        for bad in [
            "1536x2048",
            "1536x2048+1920",
            "0x2048+0+0",
            "1536x2048+a+0",
            "1536x2048++0+0",
            " ",
        ] {
            assert!(monitor(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn grid_accepts_cxr_and_rejects_nonsense() {
        assert_eq!(grid("8x6"), Ok((8, 6)));
        assert!(grid("0x6").is_err());
        assert!(grid("8*6").is_err());
        assert!(grid("100000x2").is_err());
    }

    #[test]
    fn frame_lists_and_every() {
        assert_eq!(frames("1,10,30"), Ok(FrameSet::List(vec![1, 10, 30])));
        assert_eq!(frames("every:10"), Ok(FrameSet::Every(10)));
        assert!(frames("0").is_err());
        assert!(frames("every:x").is_err());
        assert!(frames("1,,2").is_err());
    }

    #[test]
    fn modes() {
        assert_eq!(mode("exact"), Ok(Mode::Exact));
        assert_eq!(mode("hybrid:3"), Ok(Mode::Hybrid(3)));
        assert_eq!(mode("synth:pixel"), Ok(Mode::SynthPixel));
        assert_eq!(mode("hybrid:2:pixel"), Ok(Mode::HybridPixel(2)));
        assert!(mode("hybrid:0:pixel").unwrap_err().contains("expected"));
        assert!(mode("exact:pixel").unwrap_err().contains("expected"));
        assert_eq!(mode("auto"), Ok(Mode::Auto));
        assert_eq!(frame_budget("100"), Ok(100.0));
        assert!(frame_budget("0.5").unwrap_err().contains("1..=60000"));
        assert!(frame_budget("fast").is_err());
        assert!(mode("hybrid:0").unwrap_err().contains("expected"));
        assert!(mode("hybrid:x").unwrap_err().contains("expected"));
        assert!(mode("fast").is_err());
        assert!(synth_threshold("0").is_err());
        assert_eq!(fbo_scale("tile"), Ok(FboScale::Tile));
        assert_eq!(fbo_scale("window"), Ok(FboScale::Window));
        assert_eq!(fbo_scale("0.5"), Ok(FboScale::Factor(0.5)));
        assert_eq!(fbo_scale("1"), Ok(FboScale::Factor(1.0)));
        for bad in ["0", "2", "foo", "-0.5", "NaN", "inf", ""] {
            assert!(fbo_scale(bad).is_err(), "{bad}");
        }
        assert_eq!(
            (switch("1"), switch("true"), switch("off")),
            (Ok(true), Ok(true), Ok(false))
        );
        assert!(switch("maybe").is_err());
        assert!(reuse_with(true, Mode::Hybrid(3)).is_ok() && reuse_with(true, Mode::Synth).is_ok());
        assert!(reuse_with(true, Mode::Exact).unwrap_err().contains("--reuse needs"));
        assert!(reuse_with(false, Mode::Exact).is_ok());
        assert_eq!(synth_threshold("2"), Ok(2.0));
        assert_eq!(reuse_motion("off"), Ok(None));
        assert_eq!(reuse_motion("0.05"), Ok(Some(0.05)));
        assert!(reuse_motion("0").unwrap_err().contains("off or a tolerance"));
        assert!(reuse_motion("soon").unwrap_err().contains("off or a tolerance"));
        assert_eq!(synth_warp("grid"), Ok(super::SynthWarp::Grid));
        assert!(synth_warp("quads").is_err());
    }
}
