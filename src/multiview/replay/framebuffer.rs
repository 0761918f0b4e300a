//! Framebuffer 0 as the app sees it, standing on our quilt: bindings, draw/read buffers,
//! `glGet*` answers (clears, reads and blits per view are `transfers`).

use crate::gl::*;
use crate::multiview::Multiview;
use crate::multiview::quilt::layout::QuiltLayout;
use crate::multiview::quilt::target::QuiltTarget;
use crate::state::AppState;

/// Creates (or re-creates, when the window size changed) the quilt, and binds it wherever
/// the app has framebuffer 0 bound.
pub fn ensure_target(gl: &Gl, app: &AppState, mv: &mut Multiview, window: (u32, u32)) {
    let wanted = QuiltLayout::new(mv.settings.quilt, mv.settings.tile, window);
    let mode = crate::multiview::fast::synthesis::mode_for(&mv.settings, mv.info);
    let wanted = wanted.with_guard(crate::multiview::fast::guard::room(&mv.settings, mode, wanted.tile_w));
    if mv
        .target
        .as_ref()
        .is_some_and(|t| t.layout == wanted.stored(t.layout.flipped))
        || mv.failed
    {
        return;
    }
    if let Some(old) = mv.target.take() {
        old.delete(gl);
    }
    match QuiltTarget::create(gl, mv.info, wanted) {
        Ok(t) => {
            crate::log::info(format_args!(
                "quilt {}x{} views, tiles {}x{} ({}x{} px) for a {}x{} window",
                wanted.cols,
                wanted.rows,
                wanted.tile_w,
                wanted.tile_h,
                wanted.width(),
                wanted.height(),
                window.0,
                window.1
            ));
            crate::log::info(format_args!(
                "quilt made like the window ({:?}): colour {:#x}, stored {}",
                t.window,
                t.color_format,
                if t.layout.flipped {
                    "top-down as the window is"
                } else {
                    "bottom-up"
                },
            ));
            mv.target = Some(t);
            // The band is decided again at the frame's end, for the room the new quilt has.
            mv.guard = 0;
            mv.update_rig(wanted);
            rebind(gl, app, mv);
        }
        Err(e) => {
            crate::log::error(format_args!("{e}; multiview off for this context"));
            mv.failed = true;
        }
    }
}

/// Makes GL's bindings match the app's, with the quilt standing in for 0.
pub fn rebind(gl: &Gl, app: &AppState, mv: &Multiview) {
    let map = |fbo: u32| if fbo == 0 { mv.quilt_fbo().unwrap_or(0) } else { fbo };
    // SAFETY: binding framebuffers that exist (the app's or ours).
    unsafe {
        gl.BindFramebuffer(DRAW_FRAMEBUFFER, map(app.draw_fbo));
        gl.BindFramebuffer(READ_FRAMEBUFFER, map(app.read_fbo));
    }
}

/// Before the layer gives up on a context (internal failure), the frame in progress moves to
/// where the app believes it is: the centre view's tile into the real default framebuffer
/// (colour, depth, stencil), and the centre layer of every layered image into the app's own
/// texture or renderbuffer, attached or not (a pass may sample it next). Without this, an
/// app that reads back or keeps drawing after the failure would see the previous frame, or a
/// quilt.
pub fn hand_back(gl: &Gl, mv: &Multiview) {
    let centre = mv.camera.rig.centre();
    let mut caps = vec![SCISSOR_TEST];
    if !mv.info.es {
        caps.push(FRAMEBUFFER_SRGB);
    }
    let _guard = crate::gl::guard::StateGuard::new(gl, mv.info)
        .framebuffers()
        .caps(&caps);
    // SAFETY: blits from our quilt into framebuffer 0; bindings, scissor and sRGB restored by
    // the guard.
    unsafe {
        caps.iter().for_each(|&c| gl.Disable(c));
        if let Some(t) = mv.target.as_ref() {
            let [x, y, w, h] = t.layout.tile_rect(centre);
            let (ww, wh) = (t.layout.window_w as i32, t.layout.window_h as i32);
            t.resolve(gl, mv.info, [x, y, w, h], ALL_BUFFERS);
            gl.BindFramebuffer(READ_FRAMEBUFFER, t.resolved_fbo);
            gl.BindFramebuffer(DRAW_FRAMEBUFFER, 0);
            gl.ReadBuffer(COLOR_ATTACHMENT0);
            let filter = if (w, h) == (ww, wh) { NEAREST } else { LINEAR };
            gl.BlitFramebuffer(x, y, x + w, y + h, 0, 0, ww, wh, COLOR_BUFFER_BIT, filter);
        }
    }
    if let Some(t) = mv.target.as_ref() {
        let window = (t.layout.window_w as i32, t.layout.window_h as i32);
        hand_back_depth(gl, mv.info, t, t.layout.tile_rect(centre), window);
    }
    for image in mv.images.values() {
        image.copy_back(gl, mv.info, centre);
    }
}

/// The centre tile's depth and stencil into the window (`hand_back`, under its guard: quilt
/// bound for reading, the window for drawing, no scissor): a blit where the two formats
/// allow one, else the depth through a pass and the stencil left as it is.
fn hand_back_depth(gl: &Gl, info: crate::gl::GlInfo, t: &QuiltTarget, tile: [i32; 4], (ww, wh): (i32, i32)) {
    use crate::gl::depth_write;
    let [x, y, w, h] = tile;
    let formats = (
        depth_write::depth_format(gl, info, t.resolved_fbo),
        depth_write::depth_format(gl, info, 0),
    );
    let (Some(quilt), Some(window)) = formats else {
        return;
    };
    if depth_write::blittable(quilt, window) {
        let ds = DEPTH_BUFFER_BIT | STENCIL_BUFFER_BIT;
        // SAFETY: a blit between formats that allow it, in the caller's bindings.
        unsafe { gl.BlitFramebuffer(x, y, x + w, y + h, 0, 0, ww, wh, ds, NEAREST) };
        return;
    }
    crate::log::info(format_args!(
        "hand-back: the window's depth ({window:?}) is not the quilt's ({quilt:?}): depth copied by a pass, stencil not handed back"
    ));
    let read = t.resolved_fbo;
    let copied = crate::gl::depth_copy::describe(gl, info, read).and_then(|source| {
        let mut copy = crate::gl::depth_copy::DepthCopy::default();
        let restore = crate::gl::depth_copy::Restore {
            draw_fbo: 0,
            read_fbo: read,
            scissor: false,
        };
        copy.take(gl, info, (read, source), tile, restore);
        let (texture, rect) = copy.copied();
        let drawn = depth_write::draw(gl, info, texture, rect, 0, [0, 0, ww, wh]);
        copy.delete(gl);
        drawn
    });
    if let Err(e) = copied {
        crate::log::info(format_args!("hand-back: window depth not written: {e}"));
    }
}

pub(super) const ALL_BUFFERS: u32 = COLOR_BUFFER_BIT | DEPTH_BUFFER_BIT | STENCIL_BUFFER_BIT;

/// `glBindFramebuffer(target, fbo)`: records the app's binding; returns the name GL gets.
pub fn bind(mv: &Multiview, fbo: u32) -> u32 {
    if fbo == 0 { mv.quilt_fbo().unwrap_or(0) } else { fbo }
}

/// Maps a default-framebuffer colour buffer name to the quilt's attachment.
pub fn map_buffer(buffer: GLenum) -> GLenum {
    match buffer {
        NONE => NONE,
        BACK | FRONT | BACK_LEFT | FRONT_LEFT | LEFT | FRONT_AND_BACK => COLOR_ATTACHMENT0,
        other => other,
    }
}

/// Corrects a `glGetIntegerv` answer about framebuffer 0 so the app sees its own values.
pub fn patch_get(app: &AppState, mv: &Multiview, pname: GLenum) -> Option<i32> {
    mv.quilt_fbo()?;
    Some(match pname {
        DRAW_FRAMEBUFFER_BINDING => app.draw_fbo as i32,
        READ_FRAMEBUFFER_BINDING => app.read_fbo as i32,
        DRAW_BUFFER | DRAW_BUFFER0 if app.draw_fbo == 0 => app.draw_buffer as i32,
        READ_BUFFER if app.read_fbo == 0 => app.read_buffer as i32,
        _ => return None,
    })
}

/// Queries whose answer describes the bound draw framebuffer: while the quilt stands in for
/// framebuffer 0 they must describe the real window (an engine asking GL_DOUBLEBUFFER or
/// GL_SAMPLES at start-up would otherwise see our framebuffer object).
const DEFAULT_FRAMEBUFFER_QUERIES: [GLenum; 10] = [
    DOUBLEBUFFER,
    STEREO,
    SAMPLES,
    SAMPLE_BUFFERS,
    RED_BITS,
    GREEN_BITS,
    BLUE_BITS,
    ALPHA_BITS,
    DEPTH_BITS,
    STENCIL_BITS,
];

/// Runs `query` with the real framebuffer 0 bound where the app believes it is, when `pname`
/// describes the draw framebuffer and the app's is 0; `None` when no rebinding is needed.
pub fn on_real_default<R>(
    gl: &Gl,
    app: &AppState,
    mv: &Multiview,
    pname: GLenum,
    query: impl FnOnce() -> R,
) -> Option<R> {
    if mv.quilt_fbo().is_none() || app.draw_fbo != 0 || !DEFAULT_FRAMEBUFFER_QUERIES.contains(&pname) {
        return None;
    }
    // SAFETY: real framebuffer 0 for the query only; the app's (quilt) binding comes back.
    unsafe { gl.BindFramebuffer(DRAW_FRAMEBUFFER, 0) };
    let r = query();
    rebind(gl, app, mv);
    Some(r)
}

/// `glGetFramebufferAttachmentParameteriv` on framebuffer 0 (GL_BACK_LEFT, GL_DEPTH…): asked
/// of the real default framebuffer, where those attachment names exist.
pub fn on_real_target<R>(
    gl: &Gl,
    app: &AppState,
    mv: &Multiview,
    target: GLenum,
    query: impl FnOnce() -> R,
) -> Option<R> {
    let bound = if target == READ_FRAMEBUFFER {
        app.read_fbo
    } else {
        app.draw_fbo
    };
    if mv.quilt_fbo().is_none() || bound != 0 {
        return None;
    }
    let binding = if target == READ_FRAMEBUFFER {
        READ_FRAMEBUFFER
    } else {
        DRAW_FRAMEBUFFER
    };
    // SAFETY: as in `on_real_default`.
    unsafe { gl.BindFramebuffer(binding, 0) };
    let r = query();
    rebind(gl, app, mv);
    Some(r)
}
