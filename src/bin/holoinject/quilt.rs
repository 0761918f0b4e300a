//! `holoinject quilt FILE.png|FILE.mp4 --device D --out native.png`: a quilt woven offline
//! for a display, by the same CPU weave the layer's native pass is tested against
//! (`output::weave::weave_cpu`), so a dump or a recording can be checked on the display it
//! was meant for, or a user's own quilt shown without running anything.

use holoinject::config::{device, parse};
use holoinject::output::{quilt_file, quilt_name, weave};
use std::ffi::OsString;
use std::path::PathBuf;

pub const USAGE: &str = "usage: holoinject quilt FILE.png|FILE.mp4 --device NAME|PATH --out OUT.png \
     [--quilt CxR] [--frame N] [--weave-filter nearest|blend|gaussian:S]";

struct Args {
    input: PathBuf,
    device: String,
    out: PathBuf,
    quilt: Option<(u32, u32)>,
    frame: Option<u64>,
    filter: weave::Filter,
}

fn parse_args(args: &[OsString]) -> Result<Args, String> {
    let (mut input, mut device, mut out, mut quilt, mut frame) = (None, None, None, None, None);
    let mut filter = weave::Filter::BlendNext;
    let mut it = args.iter().map(|a| a.to_string_lossy().into_owned());
    while let Some(a) = it.next() {
        let (name, inline) = match a.split_once('=') {
            Some((n, v)) if n.starts_with("--") => (n.to_string(), Some(v.to_string())),
            _ => (a.clone(), None),
        };
        if !name.starts_with("--") {
            input = Some(PathBuf::from(a));
            continue;
        }
        let value = inline
            .or_else(|| it.next())
            .ok_or_else(|| format!("{name} needs a value; {USAGE}"))?;
        let bad = |e: String| format!("{name} {value}: {e}");
        match name.as_str() {
            "--device" => device = Some(value.clone()),
            "--out" => out = Some(PathBuf::from(&value)),
            "--quilt" => quilt = Some(parse::quilt(&value).map_err(bad)?),
            "--frame" => frame = Some(value.parse().map_err(|e| bad(format!("{e}")))?),
            "--weave-filter" => filter = parse::weave_filter(&value).map_err(bad)?,
            _ => return Err(format!("unknown option {name}; {USAGE}")),
        }
    }
    Ok(Args {
        input: input.ok_or_else(|| format!("no quilt file given; {USAGE}"))?,
        device: device.ok_or_else(|| format!("--device is needed (the weave is the display's); {USAGE}"))?,
        out: out.ok_or_else(|| format!("--out is needed; {USAGE}"))?,
        quilt,
        frame,
        filter,
    })
}

/// The quilt's columns and rows: `--quilt`, else the file name's `qs{C}x{R}a{aspect}`.
fn layout(a: &Args) -> Result<(u32, u32), String> {
    if let Some(q) = a.quilt {
        return Ok(q);
    }
    let name = a.input.file_name().and_then(|n| n.to_str()).unwrap_or("");
    quilt_name::parse(name).map(|t| (t.cols, t.rows)).ok_or_else(|| {
        format!(
            "{}: the name has no qs{{C}}x{{R}}a{{aspect}} tag: give the layout with --quilt CxR",
            a.input.display()
        )
    })
}

pub fn run(args: &[OsString]) -> Result<(), String> {
    let a = parse_args(args)?;
    let (cols, rows) = layout(&a)?;
    let dev = device::load(&a.device).map_err(|e| format!("--device {}: {e}", a.device))?;
    let q = quilt_file::load(&a.input, a.frame)?;
    if q.width < cols || q.height < rows {
        return Err(format!(
            "{}: {}x{} pixels cannot hold {cols}x{rows} tiles",
            a.input.display(),
            q.width,
            q.height
        ));
    }
    let cal = &dev.calibration;
    let params = cal.weave_params(cols * rows);
    let (w, h) = (cal.screen_w, cal.screen_h);
    let out = weave::weave_cpu(&q.rgb, q.width, q.height, cols, rows, &params, a.filter, w, h);
    holoinject::output::png::write_rgb(&a.out, w, h, &out)?;
    eprintln!(
        "holoinject: wove {} ({cols}x{rows} views of {}x{}) for {} into {} ({w}x{h})",
        a.input.display(),
        q.width / cols,
        q.height / rows,
        dev.name,
        a.out.display()
    );
    Ok(())
}
