//! Hand-rolled CLI shared by every app (no clap: the flag set is tiny).
use std::collections::{HashMap, HashSet};
use std::path::PathBuf;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Backend {
    Glx,
    Egl,
    /// Headless EGL on a device (EGL_EXT_platform_device), as on NVIDIA without X.
    EglDevice,
    EglX11,
    OsMesa,
}

impl Backend {
    fn parse(s: &str) -> Result<Self, String> {
        Ok(match s {
            "glx" => Backend::Glx,
            "egl" => Backend::Egl,
            "egl-device" => Backend::EglDevice,
            "egl-x11" => Backend::EglX11,
            "osmesa" => Backend::OsMesa,
            _ => return Err(format!("unknown backend '{s}' (glx|egl|egl-device|egl-x11|osmesa)")),
        })
    }
}

/// What an app tells the CLI about itself.
pub struct AppInfo {
    pub name: &'static str,
    pub about: &'static str,
    pub default_convergence: f32,
    /// Extra value flags: (name without dashes, default, help).
    pub extra: &'static [(&'static str, &'static str, &'static str)],
    /// Extra on/off flags that take no value: (name without dashes, help).
    pub switches: &'static [(&'static str, &'static str)],
}

#[derive(Debug, Clone)]
pub struct Options {
    pub backend: Backend,
    pub size: (u32, u32),
    pub frames: u64,
    pub screenshot: Option<PathBuf>,
    /// Raw f32 depth of the last frame's default framebuffer (desktop GL only).
    pub depth_out: Option<PathBuf>,
    /// Raw f32 depth of the whole reference quilt (with --reference-quilt; desktop GL only).
    pub reference_depth_out: Option<PathBuf>,
    pub quilt: Option<(u32, u32)>,
    pub tile: (u32, u32),
    pub depthiness: f32,
    pub convergence: f32,
    pub focus: f32,
    pub out: Option<PathBuf>,
    pub extra: HashMap<String, String>,
    /// Names of the app's switches given on the command line.
    pub switches: HashSet<String>,
    /// Benchmark: render the reference quilt every frame.
    pub bench_quilt: bool,
    /// Print the median frame time at exit.
    pub timing: bool,
    /// Count GL errors through KHR_debug and print the count at exit.
    pub debug_output: bool,
    /// The default framebuffer's samples per pixel and alpha bits.
    pub samples: i32,
    pub alpha: bool,
    /// Draw with `GL_FRAMEBUFFER_SRGB` enabled (desktop GL).
    pub srgb: bool,
    /// `--freeze F[:G]`: frames F..G (exclusive) show frame F; frame G shows F + 1, and so
    /// on.
    pub freeze: Option<(u64, u64)>,
}

impl Options {
    pub fn extra_u64(&self, name: &str) -> Result<u64, String> {
        let v = &self.extra[name];
        v.parse()
            .map_err(|_| format!("--{name}: expected an integer, got '{v}'"))
    }
}

fn parse_pair(flag: &str, v: &str) -> Result<(u32, u32), String> {
    let bad = || format!("{flag}: expected AxB with integers in 1..=16384, got '{v}'");
    let (a, b) = v.split_once(['x', 'X']).ok_or_else(bad)?;
    let (a, b) = (
        a.parse::<u32>().map_err(|_| bad())?,
        b.parse::<u32>().map_err(|_| bad())?,
    );
    // 16384 is the largest texture/renderbuffer size llvmpipe supports.
    if a == 0 || b == 0 || a > 16384 || b > 16384 {
        return Err(bad());
    }
    Ok((a, b))
}

fn parse_freeze(v: &str) -> Result<(u64, u64), String> {
    let (f, g) = v.split_once(':').unwrap_or((v, ""));
    let f: u64 = parse_num("--freeze", f)?;
    let g = if g.is_empty() {
        u64::MAX
    } else {
        parse_num("--freeze", g)?
    };
    if g <= f {
        return Err(format!("--freeze {v}: expected F or F:G with G > F"));
    }
    Ok((f, g))
}

impl Options {
    /// The scene frame drawn as frame `frame` (`--freeze`).
    pub fn shown(&self, frame: u64) -> u64 {
        match self.freeze {
            Some((f, g)) if frame >= f && frame < g => f,
            Some((f, g)) if frame >= g => frame + f + 1 - g,
            _ => frame,
        }
    }
}

fn parse_num<T: std::str::FromStr>(flag: &str, v: &str) -> Result<T, String> {
    v.parse().map_err(|_| format!("{flag}: invalid number '{v}'"))
}

pub fn usage(app: &AppInfo) -> String {
    let mut s = format!(
        "{name} - {about}\n\nUSAGE: {name} [OPTIONS]\n\n\
         --backend B            glx | egl | egl-device | egl-x11 | osmesa (default glx)\n\
         --size WxH             window / framebuffer size (default 640x480)\n\
         --frames N             render N frames then exit (default 0 = until killed)\n\
         --screenshot PATH      PNG of the last frame's default framebuffer\n\
         --depth-out PATH       raw little-endian f32 depth of the last frame's default\n\
                                framebuffer (w*h, rows bottom-up; desktop GL only)\n\
         --reference-quilt CxR  also render a CxR reference quilt of the last frame\n\
         --tile WxH             quilt tile size (default = --size)\n\
         --depthiness S         shear strength (default 0.1)\n\
         --convergence C        eye-space convergence distance (default {conv})\n\
         --focus F              extra horizontal shift (default 0)\n\
         --out PATH             quilt PNG path (required with --reference-quilt)\n\
         --reference-depth-out PATH\n\
                                raw f32 depth of the reference quilt, as --depth-out\n\
         --bench-quilt          render the reference quilt every frame (benchmark; implies --timing)\n\
         --timing               print the median frame time to stderr at exit\n\
         --debug-output         count GL errors via KHR_debug; print `gl-debug: errors=N` at exit\n\
         --samples N            multisampled default framebuffer, N samples (not osmesa)\n\
         --no-alpha             default framebuffer without alpha bits (not osmesa)\n\
         --srgb                 draw with GL_FRAMEBUFFER_SRGB enabled (desktop GL)\n\
         --freeze F[:G]         frames F..G (counted from 0; G omitted: every frame from F on) draw\n\
                                frame F again, then time resumes where it stopped: a still scene\n",
        name = app.name,
        about = app.about,
        conv = app.default_convergence
    );
    for (n, d, h) in app.extra {
        s += &format!("  --{n:<20} {h} (default {d})\n");
    }
    for (n, h) in app.switches {
        s += &format!("  --{n:<20} {h}\n");
    }
    s + "  --help                 this text\n"
}

/// Ok(None) means --help was printed.
pub fn parse(args: &[String], app: &AppInfo) -> Result<Option<Options>, String> {
    let mut o = Options {
        backend: Backend::Glx,
        size: (640, 480),
        frames: 0,
        screenshot: None,
        depth_out: None,
        reference_depth_out: None,
        quilt: None,
        tile: (0, 0),
        depthiness: 0.1,
        convergence: app.default_convergence,
        focus: 0.0,
        out: None,
        extra: app
            .extra
            .iter()
            .map(|(n, d, _)| (n.to_string(), d.to_string()))
            .collect(),
        switches: HashSet::new(),
        bench_quilt: false,
        timing: false,
        debug_output: false,
        samples: 0,
        alpha: true,
        srgb: false,
        freeze: None,
    };
    let mut tile = None;
    let mut it = args.iter();
    while let Some(flag) = it.next() {
        if flag == "--help" || flag == "-h" {
            print!("{}", usage(app));
            return Ok(None);
        }
        if flag == "--debug-output" {
            o.debug_output = true;
            continue;
        }
        if flag == "--no-alpha" || flag == "--srgb" {
            o.alpha &= flag != "--no-alpha";
            o.srgb |= flag == "--srgb";
            continue;
        }
        if flag == "--bench-quilt" || flag == "--timing" {
            o.bench_quilt |= flag == "--bench-quilt";
            o.timing = true;
            continue;
        }
        if let Some((n, _)) = app.switches.iter().find(|(n, _)| flag.strip_prefix("--") == Some(n)) {
            o.switches.insert(n.to_string());
            continue;
        }
        let val = it.next().ok_or_else(|| format!("{flag} needs a value"))?;
        match flag.as_str() {
            "--backend" => o.backend = Backend::parse(val)?,
            "--size" => o.size = parse_pair(flag, val)?,
            "--frames" => o.frames = parse_num(flag, val)?,
            "--samples" => o.samples = parse_num(flag, val)?,
            "--freeze" => o.freeze = Some(parse_freeze(val)?),
            "--screenshot" => o.screenshot = Some(val.into()),
            "--depth-out" => o.depth_out = Some(val.into()),
            "--reference-quilt" => o.quilt = Some(parse_pair(flag, val)?),
            "--tile" => tile = Some(parse_pair(flag, val)?),
            "--depthiness" => o.depthiness = parse_num(flag, val)?,
            "--convergence" => o.convergence = parse_num(flag, val)?,
            "--focus" => o.focus = parse_num(flag, val)?,
            "--out" => o.out = Some(val.into()),
            "--reference-depth-out" => o.reference_depth_out = Some(val.into()),
            f => match f.strip_prefix("--").filter(|n| o.extra.contains_key(*n)) {
                Some(n) => _ = o.extra.insert(n.to_string(), val.clone()),
                None => return Err(format!("unknown option '{f}' (see --help)")),
            },
        }
    }
    o.tile = tile.unwrap_or(o.size);
    if o.quilt.is_some() && o.out.is_none() {
        return Err("--reference-quilt requires --out PATH".into());
    }
    if o.reference_depth_out.is_some() && o.quilt.is_none() {
        return Err("--reference-depth-out requires --reference-quilt CxR".into());
    }
    Ok(Some(o))
}
