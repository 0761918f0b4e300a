//! What doctor's checks measure: the probe children, what a context's version means for the
//! layer, where Looking Glass calibrations live, and the preload test.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Status {
    Ok,
    Warn,
    Fail,
}

impl Status {
    pub fn word(self) -> &'static str {
        match self {
            Status::Ok => "ok",
            Status::Warn => "warn",
            Status::Fail => "fail",
        }
    }
}

/// Longest a probe may take (llvmpipe compiles its first shaders in well under a second).
const PROBE_TIMEOUT: Duration = Duration::from_secs(60);

/// Runs `cmd` to completion or kills it after [`PROBE_TIMEOUT`].
fn run_with_timeout(mut cmd: Command) -> Result<Output, String> {
    let mut child = cmd
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| format!("cannot start the probe: {e}"))?;
    let start = Instant::now();
    while child.try_wait().map_err(|e| e.to_string())?.is_none() {
        if start.elapsed() > PROBE_TIMEOUT {
            let _ = child.kill();
            return Err(format!("the probe hung for {} s", PROBE_TIMEOUT.as_secs()));
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().map_err(|e| e.to_string())
}

fn this_exe() -> Result<PathBuf, String> {
    std::env::current_exe().map_err(|e| format!("cannot locate this executable: {e}"))
}

/// `holoinject __probe ARGS…` without the layer; its stdout, or its one-line error.
pub fn run_probe(args: &[&str]) -> Result<String, String> {
    let mut cmd = Command::new(this_exe()?);
    cmd.arg("__probe").args(args).env_remove("LD_PRELOAD");
    let out = run_with_timeout(cmd)?;
    if !out.status.success() {
        let err = String::from_utf8_lossy(&out.stderr);
        let line = err.lines().rev().find(|l| !l.trim().is_empty()).unwrap_or("no message");
        return Err(format!(
            "{} ({})",
            line.trim_start_matches("holoinject: error: "),
            out.status
        ));
    }
    Ok(String::from_utf8_lossy(&out.stdout).into_owned())
}

/// How bad a failed probe is: a back-end whose library is absent is one programs here cannot
/// use either (warn); one that is installed and fails is broken (fail).
pub fn probe_failure(backend: &str, e: &str) -> (Status, &'static str) {
    if e.contains("is not installed") {
        let fix = match backend {
            "osmesa" => "apt install libosmesa6 (only programs that render off-screen with OSMesa need it)",
            "egl" => "apt install libegl1 libegl-mesa0",
            _ => "apt install libgl1 libglx-mesa0",
        };
        (Status::Warn, fix)
    } else {
        (
            Status::Fail,
            "check the GL driver (`glxinfo -B`, `eglinfo -B`); programs on this back-end will not run",
        )
    }
}

/// What a probe printed.
#[derive(Default, Debug)]
pub struct GlReport {
    pub version: String,
    pub glsl: String,
    pub renderer: String,
    pub extensions: Vec<String>,
}

impl GlReport {
    pub fn parse(out: &str) -> GlReport {
        let mut g = GlReport::default();
        for line in out.lines() {
            let (k, v) = line.split_once(' ').unwrap_or((line, ""));
            match k {
                "version" => g.version = v.into(),
                "glsl" => g.glsl = v.into(),
                "renderer" => g.renderer = v.into(),
                "ext" => g.extensions.push(v.into()),
                _ => {}
            }
        }
        g
    }

    fn numbers(&self) -> (u32, u32) {
        let info = holoinject::gl::GlInfo::parse(&self.version);
        (info.major, info.minor)
    }

    fn has(&self, ext: &str) -> bool {
        self.extensions.iter().any(|e| e == ext)
    }

    /// The version line, then what the layer can do with it (DESIGN §5, §9): framebuffers
    /// (3.0) for any quilt, compute shaders (4.3) for the fast modes, texture views and image
    /// copies (4.5) for the layered shadows of the program's framebuffers.
    pub fn findings(&self) -> Vec<(Status, String, Option<&'static str>)> {
        let (major, minor) = self.numbers();
        let at_least = |a, b| (major, minor) >= (a, b);
        let head = format!("OpenGL {}, GLSL {}, {}", self.version, self.glsl, self.renderer);
        if !at_least(3, 0) {
            let fix = Some("the layer needs OpenGL 3.0 (framebuffer objects): update the driver (Mesa ≥ 10)");
            return vec![(Status::Fail, head, fix)];
        }
        let mut v = vec![(Status::Ok, head, None)];
        if !at_least(4, 3) {
            let fix = Some("--mode exact works; synth/hybrid/auto need compute shaders (OpenGL 4.3)");
            v.push((
                Status::Warn,
                "no compute shaders: fast modes fall back to exact".into(),
                fix,
            ));
        }
        let copies = self.has("GL_ARB_texture_view") && self.has("GL_ARB_copy_image");
        if !at_least(4, 5) || !copies {
            let fix = Some("scenes drawn through their own framebuffers may lose parallax; a newer driver has them");
            v.push((
                Status::Warn,
                "no OpenGL 4.5 texture views + image copies for layered shadows".into(),
                fix,
            ));
        }
        v
    }
}

/// Where a Looking Glass calibration (`visual.json`) may be, in that order: Looking Glass
/// Bridge's per-unit folders (`~/.local/share/LookingGlass/Bridge/Locations/LKG-*/`, where
/// Bridge for Linux keeps what it read from each unit), then the unit's own USB drive as
/// desktops mount it (`/media/$USER/*`, `/run/media/$USER/*`, `/media/*`), which holds the
/// factory file `LKG_calibration/visual.json`.
pub fn visual_json_candidates() -> Vec<PathBuf> {
    let home = std::env::var_os("HOME").map(PathBuf::from);
    let user = std::env::var("USER").unwrap_or_default();
    let mut roots: Vec<PathBuf> = Vec::new();
    if let Some(h) = &home {
        roots.extend(subdirs(&h.join(".local/share/LookingGlass/Bridge/Locations")));
    }
    for base in [format!("/media/{user}"), format!("/run/media/{user}"), "/media".into()] {
        roots.extend(subdirs(Path::new(&base)));
    }
    roots
        .into_iter()
        .map(|r| r.join("LKG_calibration/visual.json"))
        .filter(|p| p.is_file())
        .collect()
}

fn subdirs(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|rd| {
            rd.filter_map(|e| e.ok())
                .map(|e| e.path())
                .filter(|p| p.is_dir())
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

/// Renders the probe scene plainly and as a 3x1 quilt under the layer (`lib`); the quilt's
/// centre tile must equal the plain image and its outer tiles must not.
pub fn preload_quilt(lib: &Path) -> Result<String, (Status, String)> {
    let fail = |e: String| (Status::Fail, e);
    let dir = std::env::temp_dir().join(format!("holoinject-doctor-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).map_err(|e| fail(format!("{}: {e}", dir.display())))?;
    let result = preload_in(lib, &dir);
    let _ = std::fs::remove_dir_all(&dir);
    result
}

fn preload_in(lib: &Path, dir: &Path) -> Result<String, (Status, String)> {
    let fail = |e: String| (Status::Fail, e);
    let plain = dir.join("plain.png");
    let plain_arg = plain.to_string_lossy().into_owned();
    run_probe(&["osmesa", "--draw", &plain_arg]).map_err(|e| match e.contains("is not installed") {
        true => (
            Status::Warn,
            format!("not tried: the test program renders with OSMesa: {e}"),
        ),
        false => fail(format!("the test program failed without the layer: {e}")),
    })?;
    let exe = this_exe().map_err(fail)?;
    let mut cmd = Command::new(&exe);
    cmd.args(["run", "--quilt", "3x1", "--depthiness", "0.3", "--dump"])
        .arg(dir)
        .args(["--dump-frames", "2", "--exit-after", "2", "--preset", "none", "--"])
        .arg(&exe)
        .args(["__probe", "osmesa", "--draw"])
        .arg(dir.join("layered.png"))
        .env("HOLOINJECT_LIB", lib);
    let out = run_with_timeout(cmd).map_err(fail)?;
    let quilt = dir.join("f000002_qs3x1a1.png");
    if !out.status.success() || !quilt.is_file() {
        let err = String::from_utf8_lossy(&out.stderr);
        let last = err.lines().rev().find(|l| !l.trim().is_empty()).unwrap_or("no message");
        return Err(fail(format!(
            "no quilt from the test program under the layer ({}): {last}",
            out.status
        )));
    }
    compare(&plain, &quilt).map_err(fail)
}

fn compare(plain: &Path, quilt: &Path) -> Result<String, String> {
    let load = |p: &Path| holoinject::output::quilt_file::load(p, None);
    let (plain, quilt) = (load(plain)?, load(quilt)?);
    let (w, h) = (plain.width as usize, plain.height as usize);
    if (quilt.width as usize, quilt.height as usize) != (w * 3, h) {
        return Err(format!(
            "the quilt is {}x{}, expected 3 tiles of {w}x{h}",
            quilt.width, quilt.height
        ));
    }
    let at = |t: usize, x: usize, y: usize| &quilt.rgb[(y * w * 3 + t * w + x) * 3..][..3];
    let plain_at = |x: usize, y: usize| &plain.rgb[(y * w + x) * 3..][..3];
    // Pixels of tile `t` found in the program's frame neither at their place nor one pixel
    // left or right (within one level): llvmpipe rasterises the OSMesa window and the quilt's
    // tile one pixel apart at some edges (measured: 126 of 9,216 pixels, also with no
    // parallax at all), which is not what this check is about.
    let moved = |t: usize| -> usize {
        (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .filter(|&(x, y)| {
                let near = x.saturating_sub(1)..=(x + 1).min(w - 1);
                !near.into_iter().any(|px| {
                    at(t, x, y)
                        .iter()
                        .zip(plain_at(px, y))
                        .all(|(a, b)| a.abs_diff(*b) <= 1)
                })
            })
            .count()
    };
    let (left, centre, right) = (moved(0), moved(1), moved(2));
    if centre > 0 {
        return Err(format!(
            "the quilt's centre view differs from the program's own frame at {centre} pixels"
        ));
    }
    if left == 0 || right == 0 {
        return Err(
            "the quilt's outer views equal the centre one: no parallax (the shaders were not rewritten)".into(),
        );
    }
    Ok(format!(
        "a test program rendered a 3x1 quilt under the layer: its centre view is the program's own frame ({w}x{h}), the outer views show parallax ({left} and {right} pixels moved)"
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn versions_grade_the_layers_features() {
        let g = GlReport::parse(
            "version 4.5 (Core Profile) Mesa 22.3.6\nglsl 4.50\nrenderer llvmpipe\next GL_ARB_texture_view\next GL_ARB_copy_image\n",
        );
        assert_eq!(g.findings().iter().map(|f| f.0).collect::<Vec<_>>(), [Status::Ok]);
        let old = GlReport::parse("version 3.3 Mesa\nglsl 3.30\n");
        let s: Vec<Status> = old.findings().iter().map(|f| f.0).collect();
        assert_eq!(s, [Status::Ok, Status::Warn, Status::Warn]);
        assert_eq!(GlReport::parse("version 2.1 Mesa").findings()[0].0, Status::Fail);
    }
}
