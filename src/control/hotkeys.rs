//! Hotkeys that leave the app's input alone: the layer opens its own X connection to
//! `$DISPLAY` (never the app's), and grabs its keys on the root window with a modifier
//! combination (`--hotkeys`, default Ctrl+Alt). A grabbed key goes to the grabbing
//! connection only, so the app never sees it, and keys without the modifiers reach the app
//! as before. `x11rb` speaks the protocol itself: nothing of libX11 is loaded (EGL and
//! OSMesa programs run without it), and a grab another client holds comes back as an error
//! value rather than through Xlib's process-wide error handler, which would be the app's.

use crate::config::live::{self, Action};
use x11rb::connection::Connection;
use x11rb::protocol::Event;
use x11rb::protocol::xproto::{ConnectionExt, GrabMode, ModMask};

/// One hotkey: X keysym, name in messages, what it asks for.
pub type HotKey = (u32, &'static str, fn() -> Action);

/// The key map, documented in README "Live controls".
pub const KEYS: &[HotKey] = &[
    (0xff52, "Up", || Action::Step("depthiness", 1)),
    (0xff54, "Down", || Action::Step("depthiness", -1)),
    (0xff53, "Right", || Action::Step("convergence", 1)),
    (0xff51, "Left", || Action::Step("convergence", -1)),
    (0x61, "A", || Action::Set("convergence", "auto".into())),
    (0xff55, "Page Up", || Action::Step("focus", 1)),
    (0xff56, "Page Down", || Action::Step("focus", -1)),
    (0x72, "R", || Action::Next("depth-remap")),
    (0x66, "F", || Action::Next("dof")),
    (0x65, "E", || Action::Next("edge-fade")),
    (0x6f, "O", || Action::Next("output")),
    (0x64, "D", || Action::Dump(None)),
];

/// The X modifier bits of `--hotkeys` names.
pub fn mask(mods: &[String]) -> u16 {
    mods.iter()
        .map(|m| match m.as_str() {
            "ctrl" => u16::from(ModMask::CONTROL),
            "alt" => u16::from(ModMask::M1),
            "shift" => u16::from(ModMask::SHIFT),
            "super" => u16::from(ModMask::M4),
            _ => 0,
        })
        .fold(0, |a, b| a | b)
}

/// Caps Lock and Num Lock (Mod2 on common layouts) must not turn the hotkeys off.
const IGNORED: u16 = 0x0002 | 0x0010;

pub fn run(mods: &[String]) {
    let (conn, screen) = match x11rb::connect(None) {
        Ok(c) => c,
        Err(e) => {
            crate::log::debug(format_args!("hotkeys: no X display ({e}); hotkeys off"));
            return;
        }
    };
    let root = conn.setup().roots[screen].root;
    let want = mask(mods);
    let grabbed = match grab(&conn, root, want) {
        Ok(g) => g,
        Err(e) => return crate::log::warn(format_args!("hotkeys: {e}; hotkeys off")),
    };
    crate::log::info(format_args!(
        "hotkeys: {} grabbed with {} on {}",
        grabbed.len(),
        mods.join("+"),
        std::env::var("DISPLAY").unwrap_or_default()
    ));
    loop {
        match conn.wait_for_event() {
            Ok(Event::KeyPress(e)) if u16::from(e.state) & !IGNORED == want => {
                if let Some((_, name, action)) = grabbed.iter().find(|(code, _, _)| *code == e.detail) {
                    crate::log::debug(format_args!("hotkeys: {} {name}", mods.join("+")));
                    live::request(action(), "hotkey");
                }
            }
            Ok(_) => {}
            Err(e) => return crate::log::debug(format_args!("hotkeys: X connection closed ({e})")),
        }
    }
}

type Grabbed = Vec<(u8, &'static str, fn() -> Action)>;

/// Grabs every key of `KEYS` present in the keyboard map, with `want` and each combination
/// of the ignored locks; the keys another client holds (often another program under the
/// layer on the same display: the first one gets them) are left out and named in one line.
fn grab(conn: &impl Connection, root: u32, want: u16) -> Result<Grabbed, String> {
    let setup = conn.setup();
    let (min, max) = (setup.min_keycode, setup.max_keycode);
    let map = conn
        .get_keyboard_mapping(min, max - min + 1)
        .map_err(|e| e.to_string())?
        .reply()
        .map_err(|e| e.to_string())?;
    let per = usize::from(map.keysyms_per_keycode.max(1));
    let code_of = |sym: u32| {
        map.keysyms
            .chunks(per)
            .position(|syms| syms.contains(&sym))
            .map(|i| min + i as u8)
    };
    let mut grabbed = vec![];
    let mut taken = vec![];
    for &(sym, name, action) in KEYS {
        let Some(code) = code_of(sym) else {
            crate::log::debug(format_args!("hotkeys: no key for {name} on this keyboard"));
            continue;
        };
        let ok = [0, 0x0002, 0x0010, 0x0012].iter().all(|locks| {
            conn.grab_key(
                false,
                root,
                ModMask::from(want | locks),
                code,
                GrabMode::ASYNC,
                GrabMode::ASYNC,
            )
            .map_err(|e| e.to_string())
            .and_then(|c| c.check().map_err(|e| format!("{e:?}")))
            .inspect_err(|e| crate::log::debug(format_args!("hotkeys: grabbing {name}: {e}")))
            .is_ok()
        });
        if ok {
            grabbed.push((code, name, action));
        } else {
            taken.push(name);
        }
    }
    if !taken.is_empty() {
        crate::log::info(format_args!(
            "hotkeys: {} taken by another client (another program under the layer on this display?): \
             they do nothing here; holoinject ctl still works",
            taken.join(", ")
        ));
    }
    conn.flush().map_err(|e| e.to_string())?;
    Ok(grabbed)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::parse::hotkeys;

    #[test]
    fn modifiers_parse_into_x_masks() {
        let mods = hotkeys("Ctrl+Alt").unwrap().unwrap();
        assert_eq!(mask(&mods), 0x0004 | 0x0008);
        assert_eq!(mask(&hotkeys("super+shift").unwrap().unwrap()), 0x0040 | 0x0001);
        assert_eq!(hotkeys("off").unwrap(), None);
        let e = hotkeys("ctrl+hyper").unwrap_err();
        assert!(e.contains("`hyper`") && e.contains("ctrl, alt, shift, super"), "{e}");
    }

    #[test]
    fn every_key_is_distinct() {
        let mut syms: Vec<u32> = KEYS.iter().map(|k| k.0).collect();
        syms.sort();
        syms.dedup();
        assert_eq!(syms.len(), KEYS.len());
    }
}
