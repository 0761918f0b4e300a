//! Which display the headless EGL back-ends open.
//!
//! Mesa has a platform without any window system (`EGL_MESA_platform_surfaceless`);
//! NVIDIA's driver has none, and its way to render with no X server is a device
//! (`EGL_EXT_platform_device`, devices listed by `EGL_EXT_device_enumeration`). Mesa offers
//! devices too (llvmpipe is its software device, listed last), and both answer pbuffer
//! configs, so everything after the display is the same for either. `egl` takes the
//! surfaceless platform where there is one and a device elsewhere; `egl-device` always
//! takes a device, so a GPU machine's path can be tested on Mesa.
//!
//! The entry points of the device extensions are looked up only after the client
//! extension string names them: libglvnd hands out a non-NULL stub for any name.
use super::{Api, EglInt, Ptr};
use std::ffi::CStr;
use std::ptr;

const EGL_EXTENSIONS: EglInt = 0x3055;
const EGL_PLATFORM_DEVICE_EXT: u32 = 0x313F;
const EGL_PLATFORM_SURFACELESS_MESA: u32 = 0x31DD;
const EGL_DRM_DEVICE_FILE_EXT: EglInt = 0x3233;

/// `HOLOAPPS_EGL_DEVICE=N` picks device N (from 0) of `eglQueryDevicesEXT`'s list.
pub const DEVICE_VAR: &str = "HOLOAPPS_EGL_DEVICE";

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Headless {
    /// Surfaceless where the driver has it, else a device.
    Any,
    /// Always a device.
    Device,
}

/// An uninitialised display and what it is, for `describe()`.
pub(super) fn open(api: &Api, which: Headless) -> Result<(Ptr, String), String> {
    let client = client_extensions(api);
    if platform_for(&client, which)? == EGL_PLATFORM_SURFACELESS_MESA {
        let dpy = api.platform_display(EGL_PLATFORM_SURFACELESS_MESA, ptr::null_mut())?;
        return Ok((dpy, "egl (surfaceless pbuffer)".into()));
    }
    let devices = query_devices(api)?;
    let (i, dev) = pick(api, &client, &devices)?;
    let dpy = api.platform_display(EGL_PLATFORM_DEVICE_EXT, dev)?;
    let what = format!(
        "egl-device (device {i} of {}{}, pbuffer)",
        devices.len(),
        describe(api, &client, dev)
    );
    Ok((dpy, what))
}

/// The platform a headless display comes from, given the client extensions.
fn platform_for(client: &str, which: Headless) -> Result<u32, String> {
    if which == Headless::Any && has(client, "EGL_MESA_platform_surfaceless") {
        return Ok(EGL_PLATFORM_SURFACELESS_MESA);
    }
    for ext in ["EGL_EXT_device_enumeration", "EGL_EXT_platform_device"] {
        if !has(client, ext) {
            let why = match which {
                Headless::Any => "no EGL_MESA_platform_surfaceless and ",
                Headless::Device => "",
            };
            return Err(format!("headless EGL: {why}no {ext} (client extensions: {client})"));
        }
    }
    Ok(EGL_PLATFORM_DEVICE_EXT)
}

/// The client extensions (EGL 1.5 / EGL_EXT_client_extensions); empty if not supported.
fn client_extensions(api: &Api) -> String {
    let s = unsafe { (api.query_string)(ptr::null_mut(), EGL_EXTENSIONS) };
    if s.is_null() {
        return String::new();
    }
    unsafe { CStr::from_ptr(s) }.to_string_lossy().into_owned()
}

fn has(extensions: &str, name: &str) -> bool {
    extensions.split_ascii_whitespace().any(|e| e == name)
}

fn query_devices(api: &Api) -> Result<Vec<Ptr>, String> {
    type QueryDevices = unsafe extern "C" fn(EglInt, *mut Ptr, *mut EglInt) -> u32;
    let f = unsafe { (api.get_proc_address)(c"eglQueryDevicesEXT".as_ptr()) };
    if f.is_null() {
        return Err("EGL_EXT_device_enumeration listed but eglQueryDevicesEXT missing".into());
    }
    let f: QueryDevices = unsafe { std::mem::transmute(f) };
    let mut devices = [ptr::null_mut(); 32];
    let mut n = 0;
    if unsafe { f(devices.len() as EglInt, devices.as_mut_ptr(), &mut n) } == 0 {
        return Err(api.err("eglQueryDevicesEXT"));
    }
    if n <= 0 {
        return Err("eglQueryDevicesEXT: no EGL devices (no GPU driver with EGL, no Mesa software device)".into());
    }
    Ok(devices[..n as usize].to_vec())
}

/// `HOLOAPPS_EGL_DEVICE`, else the first device that is not Mesa's software renderer (a GPU
/// machine with Mesa lists llvmpipe as well), else the first.
fn pick(api: &Api, client: &str, devices: &[Ptr]) -> Result<(usize, Ptr), String> {
    if let Some(v) = std::env::var_os(DEVICE_VAR) {
        let v = v.to_string_lossy();
        let i: usize = v
            .parse()
            .map_err(|_| format!("{DEVICE_VAR}={v}: expected a device index"))?;
        let dev = devices
            .get(i)
            .ok_or_else(|| format!("{DEVICE_VAR}={i}, but there are only {} EGL device(s)", devices.len()))?;
        return Ok((i, *dev));
    }
    let found = devices.iter().enumerate().find(|(_, d)| !is_software(api, client, **d));
    let (i, dev) = found.unwrap_or((0, &devices[0]));
    Ok((i, *dev))
}

fn is_software(api: &Api, client: &str, dev: Ptr) -> bool {
    let extensions = device_string(api, client, dev, EGL_EXTENSIONS);
    has(&extensions, "EGL_MESA_device_software")
}

/// ": software" or ": /dev/dri/cardN", or nothing where the driver does not say.
fn describe(api: &Api, client: &str, dev: Ptr) -> String {
    if is_software(api, client, dev) {
        return ": software".into();
    }
    let file = device_string(api, client, dev, EGL_DRM_DEVICE_FILE_EXT);
    if file.is_empty() { file } else { format!(": {file}") }
}

/// eglQueryDeviceStringEXT (EGL_EXT_device_query); empty when absent or unanswered.
fn device_string(api: &Api, client: &str, dev: Ptr, name: EglInt) -> String {
    type QueryDeviceString = unsafe extern "C" fn(Ptr, EglInt) -> *const std::ffi::c_char;
    if !has(client, "EGL_EXT_device_query") && !has(client, "EGL_EXT_device_base") {
        return String::new();
    }
    let f = unsafe { (api.get_proc_address)(c"eglQueryDeviceStringEXT".as_ptr()) };
    if f.is_null() {
        return String::new();
    }
    let f: QueryDeviceString = unsafe { std::mem::transmute(f) };
    let s = unsafe { f(dev, name) };
    if s.is_null() {
        // A failed query leaves EGL_BAD_PARAMETER behind; clear it for later error reports.
        unsafe { (api.get_error)() };
        return String::new();
    }
    unsafe { CStr::from_ptr(s) }.to_string_lossy().into_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    const MESA: &str = "EGL_EXT_device_base EGL_EXT_device_enumeration EGL_EXT_device_query \
        EGL_EXT_platform_base EGL_EXT_platform_device EGL_KHR_platform_x11 EGL_MESA_platform_surfaceless";
    /// NVIDIA's libEGL_nvidia alone (no Mesa vendor under libglvnd): no surfaceless platform.
    const NVIDIA: &str = "EGL_EXT_platform_base EGL_EXT_device_base EGL_EXT_device_enumeration \
        EGL_EXT_device_query EGL_KHR_client_get_all_proc_addresses EGL_EXT_client_extensions \
        EGL_KHR_platform_x11 EGL_EXT_platform_x11 EGL_EXT_platform_device";

    #[test]
    fn egl_prefers_the_surfaceless_platform() {
        assert_eq!(platform_for(MESA, Headless::Any), Ok(EGL_PLATFORM_SURFACELESS_MESA));
    }

    #[test]
    fn egl_takes_a_device_where_there_is_no_surfaceless_platform() {
        assert_eq!(platform_for(NVIDIA, Headless::Any), Ok(EGL_PLATFORM_DEVICE_EXT));
    }

    #[test]
    fn egl_device_takes_a_device_even_beside_surfaceless() {
        assert_eq!(platform_for(MESA, Headless::Device), Ok(EGL_PLATFORM_DEVICE_EXT));
    }

    #[test]
    fn a_missing_extension_is_named() {
        let e = platform_for("EGL_EXT_platform_base EGL_EXT_device_enumeration", Headless::Any).unwrap_err();
        assert!(
            e.contains("no EGL_MESA_platform_surfaceless and no EGL_EXT_platform_device"),
            "{e}"
        );
        let e = platform_for("", Headless::Device).unwrap_err();
        assert!(e.starts_with("headless EGL: no EGL_EXT_device_enumeration"), "{e}");
    }
}
