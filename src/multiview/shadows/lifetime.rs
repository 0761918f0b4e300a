//! What the app's calls do to layered shadows and images.
//!
//! Shadows and images outlive everything that leaves the app's objects as they were:
//! attaching the same object again (renderers do it before every pass), detaching it after a
//! pass, attaching another one next to it, deleting the framebuffer, or specifying the same
//! storage again without new content. A changed attachment only marks the framebuffer's
//! shadow stale (it is pointed at the new set before its next use, `layers`); an image goes
//! only when its object is deleted or gets other storage or new content, and is then made
//! again from the app's content when needed.

use super::layered::{self, AppImage};
use crate::gl::*;
use crate::multiview::Multiview;

/// `glFramebufferTexture*`/`glFramebufferRenderbuffer` on the app's framebuffer `fbo`:
/// `object` (None: detached) at `point`, mip `level`.
pub fn attachment_changed(mv: &mut Multiview, fbo: u32, point: GLenum, object: Option<AppImage>, level: i32) {
    if fbo == 0 {
        return;
    }
    mv.fbo_facts.remove(&fbo);
    let same = match (mv.shadows.get(&fbo), mv.unshadowable.get(&fbo)) {
        (Some(s), _) => level == 0 && !s.stale && s.attached_at(point) == object,
        // Attaching again what made it unshadowable would only fail again, every frame.
        (None, Some(had)) => super::shadow::attached_at(had, point) == object.map(|o| (o, level)),
        (None, None) => true,
    };
    if same {
        return;
    }
    mv.unshadowable.remove(&fbo);
    if let Some(s) = mv.shadows.get_mut(&fbo) {
        s.stale = true;
    }
}

/// The storage of `app` was specified again (`uploads`: with new content). Its image is kept
/// when nothing changed; otherwise it goes and is made again from the app's content the next
/// time a shadow needs it.
pub fn storage_changed(gl: &Gl, mv: &mut Multiview, app: AppImage, target: GLenum, uploads: bool) {
    let Some(image) = mv.images.get(&app) else {
        return;
    };
    if !uploads && layered::storage(gl, app, target).ok() == Some(image.storage) {
        return;
    }
    drop_image(gl, mv, app);
}

/// The app deleted these textures or renderbuffers. GL detaches them from the bound
/// framebuffers, so every framebuffer's facts are asked again, and a framebuffer refused
/// with one of them attached may be tried again (the name may come back as another object).
pub fn objects_deleted(gl: &Gl, mv: &mut Multiview, gone: impl Iterator<Item = AppImage>) {
    for app in gone {
        drop_image(gl, mv, app);
        mv.full_size.remove(&app);
        mv.unshadowable.retain(|_, had| had.iter().all(|(_, a, _)| *a != app));
    }
    mv.fbo_facts.clear();
}

/// The app deleted these framebuffers: their shadows go, the images stay with their objects.
pub fn framebuffers_deleted(gl: &Gl, mv: &mut Multiview, gone: &[u32]) {
    for fbo in gone {
        mv.unshadowable.remove(fbo);
        mv.fbo_facts.remove(fbo);
        drop_shadow(gl, mv, *fbo);
    }
}

/// A sampling parameter of the app's texture `tex` changed: `set` makes the same change on
/// one of our textures (each layer view, and the array for the level range).
pub fn parameter_changed(gl: &Gl, mv: &Multiview, tex: u32, pname: GLenum, set: impl Fn(&Gl, u32)) {
    let Some(image) = mv.images.get(&AppImage::texture(tex)) else {
        return;
    };
    if !super::sampling::mirrored(pname) {
        return;
    }
    image.layer_views.iter().for_each(|&v| set(gl, v));
    if super::sampling::applies_to_array(pname) {
        set(gl, image.array);
    }
}

/// The app regenerated its texture's mipmaps: every rendered layer's too (`mipmaps`).
pub fn mipmaps_generated(gl: &Gl, mv: &Multiview, tex: u32) {
    if let Some(image) = mv.images.get(&AppImage::texture(tex)) {
        super::mipmaps::generate(gl, mv.info, image, |i| mv.plan.renders(i));
    }
}

/// Deletes the image of `app`, detaching it from the shadows that had it (they are rebuilt
/// before their next use).
pub fn drop_image(gl: &Gl, mv: &mut Multiview, app: AppImage) {
    if let Some(image) = mv.images.remove(&app) {
        for s in mv.shadows.values_mut() {
            s.forget_array(gl, image.array);
        }
        image.delete(gl);
    }
}

pub fn drop_shadow(gl: &Gl, mv: &mut Multiview, fbo: u32) {
    if let Some(s) = mv.shadows.remove(&fbo) {
        crate::log::debug(format_args!("framebuffer {fbo}: shadow dropped"));
        s.delete(gl);
    }
}

/// `fbo` cannot be shadowed: it is drawn once from now on (until an attachment changes), into
/// the app's own objects, so images of what it has attached could not follow: they give the
/// centre view back to the app's objects and go.
pub fn give_up(gl: &Gl, mv: &mut Multiview, fbo: u32) {
    drop_shadow(gl, mv, fbo);
    let centre = mv.camera.rig.centre();
    let attached = super::shadow::attachments(gl, fbo);
    for &(_, app, _) in &attached {
        if let Some(image) = mv.images.get(&app) {
            image.copy_back(gl, mv.info, centre);
        }
        drop_image(gl, mv, app);
    }
    mv.unshadowable.insert(fbo, attached);
}
