//! Asking the X server for its monitors (XRandR 1.5) and each output's EDID. libX11 and
//! libXrandr are opened with `dlopen` (`x11-dl`), so the layer loads in programs that never
//! use X11 and fails here with one line when they are missing.

use super::{Monitor, Rect, edid_monitor_name};
use std::ffi::CStr;
use std::os::raw::{c_int, c_uchar, c_ulong};
use x11_dl::xlib::{self, Xlib};
use x11_dl::xrandr::{self, Xrandr};

/// What the server says about one monitor, before its EDID is read.
pub struct RawMonitor {
    pub name: String,
    pub outputs: Vec<(String, Option<Vec<u8>>)>,
    pub geometry: Rect,
    pub primary: bool,
}

/// A monitor from the server's answer: the EDID name of the first output that has one.
pub fn from_raw(raw: RawMonitor) -> Monitor {
    let edid_name = raw
        .outputs
        .iter()
        .find_map(|(_, e)| e.as_deref().and_then(edid_monitor_name));
    Monitor {
        name: raw.name,
        outputs: raw.outputs.into_iter().map(|(n, _)| n).collect(),
        edid_name,
        geometry: raw.geometry,
        primary: raw.primary,
    }
}

struct Conn {
    x: Xlib,
    r: Xrandr,
    dpy: *mut xlib::Display,
}

impl Drop for Conn {
    fn drop(&mut self) {
        // SAFETY: `dpy` was opened by this connection and is closed once.
        unsafe { (self.x.XCloseDisplay)(self.dpy) };
    }
}

impl Conn {
    fn open() -> Result<Conn, String> {
        let x = Xlib::open().map_err(|e| format!("libX11 could not be loaded: {e}"))?;
        let r = Xrandr::open().map_err(|e| format!("libXrandr could not be loaded: {e}"))?;
        // SAFETY: a null name means $DISPLAY; the result is checked.
        let dpy = unsafe { (x.XOpenDisplay)(core::ptr::null()) };
        if dpy.is_null() {
            let name = std::env::var("DISPLAY").unwrap_or_default();
            return Err(format!("cannot open X display \"{name}\""));
        }
        let conn = Conn { x, r, dpy };
        let (mut major, mut minor) = (0, 0);
        // SAFETY: an open display; out-parameters are ours.
        let ok = unsafe { (conn.r.XRRQueryVersion)(conn.dpy, &mut major, &mut minor) } != 0;
        if !ok || (major, minor) < (1, 5) {
            return Err(format!("the X server has RandR {major}.{minor}; monitors need 1.5"));
        }
        Ok(conn)
    }

    fn atom_name(&self, atom: xlib::Atom) -> String {
        // SAFETY: an open display; the returned string is freed with XFree.
        unsafe {
            let p = (self.x.XGetAtomName)(self.dpy, atom);
            if p.is_null() {
                return String::new();
            }
            let s = CStr::from_ptr(p).to_string_lossy().into_owned();
            (self.x.XFree)(p.cast());
            s
        }
    }

    fn edid(&self, output: xrandr::RROutput) -> Option<Vec<u8>> {
        // SAFETY: an open display; `only_if_exists` keeps the server's atom table unchanged.
        let atom = unsafe { (self.x.XInternAtom)(self.dpy, c"EDID".as_ptr(), xlib::True) };
        if atom == 0 {
            return None;
        }
        let (mut ty, mut format, mut n, mut after) = (0, 0 as c_int, 0 as c_ulong, 0 as c_ulong);
        let mut data: *mut c_uchar = core::ptr::null_mut();
        // SAFETY: reads up to 128 32-bit units (an EDID with 3 extensions); freed below.
        let status = unsafe {
            (self.r.XRRGetOutputProperty)(
                self.dpy,
                output,
                atom,
                0,
                128,
                xlib::False,
                xlib::False,
                xlib::AnyPropertyType as u64,
                &mut ty,
                &mut format,
                &mut n,
                &mut after,
                &mut data,
            )
        };
        if status != 0 || data.is_null() {
            return None;
        }
        // SAFETY: the server returned `n` 8-bit items at `data`.
        let bytes = (format == 8).then(|| unsafe { std::slice::from_raw_parts(data, n as usize) }.to_vec());
        // SAFETY: `data` came from Xlib.
        unsafe { (self.x.XFree)(data.cast()) };
        bytes
    }

    fn output_name(&self, res: *mut xrandr::XRRScreenResources, output: xrandr::RROutput) -> String {
        // SAFETY: `res` is this display's screen resources; the info is freed here.
        unsafe {
            let info = (self.r.XRRGetOutputInfo)(self.dpy, res, output);
            if info.is_null() {
                return format!("output {output:#x}");
            }
            let name = CStr::from_ptr((*info).name).to_string_lossy().into_owned();
            (self.r.XRRFreeOutputInfo)(info);
            name
        }
    }
}

/// The monitors of `$DISPLAY`, in the server's order.
pub fn monitors() -> Result<Vec<Monitor>, String> {
    let conn = Conn::open()?;
    // SAFETY: an open display.
    let root = unsafe { (conn.x.XDefaultRootWindow)(conn.dpy) };
    let mut n = 0;
    // SAFETY: an open display; both lists are freed below.
    let (list, res) = unsafe {
        (
            (conn.r.XRRGetMonitors)(conn.dpy, root, xlib::True, &mut n),
            (conn.r.XRRGetScreenResourcesCurrent)(conn.dpy, root),
        )
    };
    let mut out = Vec::new();
    if !list.is_null() {
        // SAFETY: XRRGetMonitors returned `n` entries.
        for m in unsafe { std::slice::from_raw_parts(list, n.max(0) as usize) } {
            // SAFETY: each monitor lists `noutput` outputs.
            let ids = unsafe { std::slice::from_raw_parts(m.outputs, m.noutput.max(0) as usize) };
            let outputs = ids
                .iter()
                .map(|&o| {
                    (
                        if res.is_null() {
                            format!("output {o:#x}")
                        } else {
                            conn.output_name(res, o)
                        },
                        conn.edid(o),
                    )
                })
                .collect();
            out.push(from_raw(RawMonitor {
                name: conn.atom_name(m.name),
                outputs,
                geometry: Rect {
                    x: m.x,
                    y: m.y,
                    w: m.width.max(0) as u32,
                    h: m.height.max(0) as u32,
                },
                primary: m.primary != 0,
            }));
        }
        // SAFETY: freeing what XRRGetMonitors returned.
        unsafe { (conn.r.XRRFreeMonitors)(list) };
    }
    if !res.is_null() {
        // SAFETY: freeing what XRRGetScreenResourcesCurrent returned.
        unsafe { (conn.r.XRRFreeScreenResources)(res) };
    }
    Ok(out)
}
