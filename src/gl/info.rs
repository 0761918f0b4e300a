//! What a context's `glGetString(GL_VERSION)` says, and the capabilities the layer derives
//! from it. Every "does this context have X" question is one method here, so that the layer
//! never spells a version test twice.

/// The API and version of one context.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GlInfo {
    pub es: bool,
    pub major: u32,
    pub minor: u32,
}

impl GlInfo {
    pub fn parse(version: &str) -> GlInfo {
        let es = version.starts_with("OpenGL ES");
        let numbers = version.trim_start_matches(|c: char| !c.is_ascii_digit());
        let mut it = numbers
            .split(|c: char| !c.is_ascii_digit())
            .filter_map(|n| n.parse().ok());
        GlInfo {
            es,
            major: it.next().unwrap_or(1),
            minor: it.next().unwrap_or(0),
        }
    }

    pub fn at_least(&self, major: u32, minor: u32) -> bool {
        (self.major, self.minor) >= (major, minor)
    }

    /// Framebuffer objects at all (ES 2.0 has them; desktop from 3.0, `ARB_framebuffer_object`).
    pub fn has_framebuffers(&self) -> bool {
        self.es || self.at_least(3, 0)
    }

    /// GL 3.0 / ES 3.0: separate draw and read framebuffer bindings, blits, layered textures,
    /// vertex array objects, rasterizer discard. The layer's quilt needs them.
    pub fn has_gl3_features(&self) -> bool {
        self.at_least(3, 0)
    }

    /// `glReadBuffer` exists (every desktop version; ES from 3.0).
    pub fn has_read_buffer(&self) -> bool {
        !self.es || self.at_least(3, 0)
    }

    /// Pixel pack buffers (`GL_PIXEL_PACK_BUFFER`): desktop 2.1, ES 3.0.
    pub fn has_pack_buffer(&self) -> bool {
        if self.es {
            self.at_least(3, 0)
        } else {
            self.at_least(2, 1)
        }
    }

    /// Sampler objects (`GL_SAMPLER_BINDING`): desktop 3.3, ES 3.0.
    pub fn has_samplers(&self) -> bool {
        if self.es {
            self.at_least(3, 0)
        } else {
            self.at_least(3, 3)
        }
    }

    /// The compatibility built-ins (matrix stacks, immediate mode, display lists) may exist.
    pub fn has_fixed_function(&self) -> bool {
        !self.es
    }
}

/// The context's renderer is a software rasteriser, whose "GPU" is this machine's CPU:
/// llvmpipe, softpipe, OpenSWR, SwiftShader, the classic swrast ("Software Rasterizer").
pub fn software_renderer(gl: &super::Gl) -> bool {
    // SAFETY: glGetString returns a static NUL-terminated string or null.
    let renderer = unsafe {
        let p = gl.GetString(super::RENDERER);
        if p.is_null() {
            return false;
        }
        std::ffi::CStr::from_ptr(p.cast())
            .to_string_lossy()
            .to_ascii_lowercase()
    };
    ["llvmpipe", "softpipe", "swr", "swiftshader", "software rasterizer"]
        .iter()
        .any(|s| renderer.contains(s))
}

#[cfg(test)]
mod tests {
    use super::GlInfo;

    #[test]
    fn parses_desktop_and_es_version_strings() {
        let d = GlInfo::parse("4.5 (Compatibility Profile) Mesa 22.3.6");
        assert_eq!(
            d,
            GlInfo {
                es: false,
                major: 4,
                minor: 5
            }
        );
        let e = GlInfo::parse("OpenGL ES 3.2 Mesa 22.3.6");
        assert_eq!(
            e,
            GlInfo {
                es: true,
                major: 3,
                minor: 2
            }
        );
        assert!(e.at_least(3, 0) && !e.at_least(3, 3));
    }

    #[test]
    fn capabilities_follow_the_version_tables() {
        let es2 = GlInfo {
            es: true,
            major: 2,
            minor: 0,
        };
        let gl21 = GlInfo {
            es: false,
            major: 2,
            minor: 1,
        };
        let gl33 = GlInfo {
            es: false,
            major: 3,
            minor: 3,
        };
        assert!(es2.has_framebuffers() && !es2.has_gl3_features() && !es2.has_read_buffer());
        assert!(!gl21.has_framebuffers() && gl21.has_read_buffer() && gl21.has_pack_buffer());
        assert!(gl33.has_gl3_features() && gl33.has_samplers());
        assert!(!es2.has_pack_buffer() && !gl21.has_samplers());
    }
}
