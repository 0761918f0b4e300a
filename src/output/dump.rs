//! `DIR/f{frame:06}_out.png`: exactly what the app presents, read back before the swap.

use crate::config::Settings;
use crate::gl::readback;

pub fn presented(frame: u64, surface: usize, settings: &Settings) -> Result<(), String> {
    let dir = settings.dump_dir.as_ref().ok_or("no dump directory")?;
    let cur = crate::state::current().ok_or("no current context at the frame boundary")?;
    if cur.binding.draw != surface {
        return Err(format!(
            "the presented surface {surface:#x} is not the one current on this thread"
        ));
    }
    let (w, h) = crate::state::surface_size(&cur).ok_or("the surface size is unknown")?;
    let (gl, info) = cur.ctx.gl().ok_or("the context's GL functions could not be loaded")?;
    let rgba = readback::read_presented(gl, *info, w, h)?;
    let rgb = super::png::rgba_bottom_up_to_rgb_top_down(&rgba, w, h);
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    super::png::write_rgb(&dir.join(format!("f{frame:06}_out.png")), w, h, &rgb)
}

/// `DIR/f{frame:06}_qs{C}x{R}a{aspect}.png`: the whole quilt, view 0 bottom-left.
pub fn quilt(
    frame: u64,
    gl: &crate::gl::Gl,
    mv: &crate::multiview::Multiview,
    settings: &Settings,
) -> Result<(), String> {
    let dir = settings.dump_dir.as_ref().ok_or("no dump directory")?;
    let target = mv.target.as_ref().ok_or("no quilt")?;
    let l = target.layout;
    let (w, h) = (l.width(), l.height());
    let mut rgba = readback::read_rgba(
        gl,
        mv.info,
        readback::Source::Fbo(target.resolved_fbo),
        [0, 0, w as i32, h as i32],
    )?;
    if let Some((a, b)) = l.swapped() {
        swap_tiles(&mut rgba, l, a, b);
    }
    let rgb = super::png::rgba_bottom_up_to_rgb_top_down(&rgba, w, h);
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    super::png::write_rgb(&dir.join(format!("f{frame:06}_{}.png", l.file_tag())), w, h, &rgb)?;
    if mv.guard > 0 {
        // The guard band's strips as the warp read them (`fast::guard`): each rendered view's
        // left and right strip side by side, one quilt row per rendered view from the bottom.
        let gw = 2 * l.guard;
        let rgba = readback::read_rgba(
            gl,
            mv.info,
            readback::Source::Fbo(target.resolved_fbo),
            [w as i32, 0, gw as i32, h as i32],
        )?;
        let rgb = super::png::rgba_bottom_up_to_rgb_top_down(&rgba, gw, h);
        super::png::write_rgb(&dir.join(format!("f{frame:06}_guard.png")), gw, h, &rgb)?;
    }
    Ok(())
}

/// Exchanges the tiles of grid cells `a` and `b` in a bottom-up RGBA8 image of the quilt: the
/// layer draws views `a` and `b` in each other's cell (`QuiltLayout::swapped`).
pub(super) fn swap_tiles(rgba: &mut [u8], l: crate::multiview::quilt::layout::QuiltLayout, a: u32, b: u32) {
    let ((ax, ay), (bx, by)) = (l.cell_origin(a), l.cell_origin(b));
    let (stride, row) = (l.width() as usize * 4, l.tile_w as usize * 4);
    for y in 0..l.tile_h as usize {
        let pa = (ay as usize + y) * stride + ax as usize * 4;
        let pb = (by as usize + y) * stride + bx as usize * 4;
        let (lo, hi) = (pa.min(pb), pa.max(pb));
        let (first, second) = rgba.split_at_mut(hi);
        first[lo..lo + row].swap_with_slice(&mut second[..row]);
    }
}

/// `DIR/f{frame:06}_native.png`: the lenticular image at the display's native resolution.
pub fn native(
    frame: u64,
    gl: &crate::gl::Gl,
    presenter: &super::Presenter,
    info: crate::gl::GlInfo,
    settings: &Settings,
) -> Result<(), String> {
    let (Some(dir), Some(t)) = (settings.dump_dir.as_ref(), presenter.native.as_ref()) else {
        return Ok(());
    };
    let (w, h) = t.size;
    let rgba = readback::read_rgba(gl, info, readback::Source::Fbo(t.fbo), [0, 0, w as i32, h as i32])?;
    let rgb = super::png::rgba_bottom_up_to_rgb_top_down(&rgba, w, h);
    super::png::write_rgb(&dir.join(format!("f{frame:06}_native.png")), w, h, &rgb)
}

#[cfg(test)]
mod tests {
    use crate::multiview::quilt::layout::QuiltLayout;

    #[test]
    fn swapped_tiles_go_back() {
        // 3x1 quilt of 2x1 tiles, one byte per channel naming the view drawn there.
        let l = QuiltLayout::new((3, 1), None, (2, 1));
        let mut rgba: Vec<u8> = [1u8, 1, 0, 0, 2, 2].iter().flat_map(|&v| [v; 4]).collect();
        let (a, b) = l.swapped().unwrap();
        super::swap_tiles(&mut rgba, l, a, b);
        let conventional: Vec<u8> = [0u8, 0, 1, 1, 2, 2].iter().flat_map(|&v| [v; 4]).collect();
        assert_eq!(rgba, conventional);
    }
}
