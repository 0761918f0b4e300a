//! Layer objects left behind by destroyed contexts.
//!
//! Most of what the layer builds for a context is shared by its whole share group: the
//! quilt's colour texture and depth renderbuffer, the layer arrays and texture views of
//! framebuffer shadows, the native weave target's texture, the programs of our full-screen
//! passes, the display list recording immediate-mode blocks. Destroying the context frees
//! only its per-context objects (framebuffers, vertex arrays); the shared ones live as long
//! as any context of the group does. An app that keeps a root context and creates and
//! destroys others would see them pile up, one quilt per context.
//!
//! They can only be deleted with a context of the group current, and the destroyed one
//! usually is not (apps release before destroying, and EGL/GLX keep a context that is
//! destroyed while current alive until it is released). So when the layer's last reference
//! to a context goes — it is destroyed and no thread has it current — its shared objects
//! are handed to the share group ([`super::ShareGroup::adopt`]), and the next context of
//! the group that becomes current, or presents a frame, deletes them with the real GL
//! functions. Deleting objects that are bound nowhere in that context changes nothing the
//! app can see. When the destroyed context was the last of its group, the driver frees the
//! whole group and the list is dropped with it.

use crate::gl::Gl;

/// Names of layer objects shared by a share group.
#[derive(Debug, Default)]
pub struct LayerObjects {
    pub textures: Vec<u32>,
    pub renderbuffers: Vec<u32>,
    pub programs: Vec<u32>,
    /// Display lists (compatibility contexts only).
    pub lists: Vec<u32>,
    pub buffers: Vec<u32>,
}

impl LayerObjects {
    pub fn count(&self) -> usize {
        self.textures.len() + self.renderbuffers.len() + self.programs.len() + self.lists.len() + self.buffers.len()
    }

    pub fn append(&mut self, mut other: LayerObjects) {
        self.textures.append(&mut other.textures);
        self.renderbuffers.append(&mut other.renderbuffers);
        self.programs.append(&mut other.programs);
        self.lists.append(&mut other.lists);
        self.buffers.append(&mut other.buffers);
    }

    /// Leaves out zero names (objects never created or already deleted).
    pub fn without_zeros(mut self) -> LayerObjects {
        for v in [
            &mut self.textures,
            &mut self.renderbuffers,
            &mut self.programs,
            &mut self.lists,
            &mut self.buffers,
        ] {
            v.retain(|&n| n != 0);
        }
        self
    }

    /// Deletes them all in `gl`'s context, which must be current and of the same share group.
    pub fn delete(&self, gl: &Gl) {
        // SAFETY: names the layer created in this share group; the slices hold `len` names.
        unsafe {
            gl.DeleteTextures(self.textures.len() as i32, self.textures.as_ptr());
            gl.DeleteRenderbuffers(self.renderbuffers.len() as i32, self.renderbuffers.as_ptr());
            if !self.buffers.is_empty() {
                gl.DeleteBuffers(self.buffers.len() as i32, self.buffers.as_ptr());
            }
            for &p in &self.programs {
                gl.DeleteProgram(p);
            }
            if gl.DeleteLists.is_loaded() {
                for &l in &self.lists {
                    gl.DeleteLists(l, 1);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::LayerObjects;

    #[test]
    fn counts_appends_and_drops_zero_names() {
        let mut a = LayerObjects {
            textures: vec![3, 0, 4],
            renderbuffers: vec![0],
            ..Default::default()
        }
        .without_zeros();
        a.append(LayerObjects {
            programs: vec![7],
            lists: vec![1],
            ..Default::default()
        });
        assert_eq!((a.textures.as_slice(), a.renderbuffers.len()), (&[3, 4][..], 0));
        assert_eq!(a.count(), 4);
    }
}
