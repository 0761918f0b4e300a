//! The sized internal format GL actually gave a texture or renderbuffer.
//!
//! `GL_TEXTURE_INTERNAL_FORMAT` answers what the app asked for, which may be unsized
//! (`GL_DEPTH_COMPONENT`, `GL_RGBA`). The driver then picks the storage itself, from the
//! pixel type of the upload too: Mesa gives `GL_DEPTH_COMPONENT` with `GL_UNSIGNED_INT` 32
//! bits, not the 24 a fixed guess would. An image of ours made with a guessed format differs
//! from the app's, and a depth or stencil blit between different formats is an error (a
//! colour one quietly converts). So the sized format is read back from the component sizes
//! and types GL reports for the storage it chose.

use super::*;

/// The sized format with `bits` depth bits (`float` or normalised) and `stencil` stencil
/// bits in the same image; stencil-only images too.
pub fn sized_depth_format(bits: i32, float: bool, stencil: i32) -> Option<GLenum> {
    Some(match (bits, float, stencil > 0) {
        (0, _, true) if stencil == 8 => STENCIL_INDEX8,
        (16, false, false) => DEPTH_COMPONENT16,
        (24, false, false) => DEPTH_COMPONENT24,
        (24, false, true) => DEPTH24_STENCIL8,
        (32, false, false) => DEPTH_COMPONENT32,
        (32, true, false) => DEPTH_COMPONENT32F,
        (32, true, true) => DEPTH32F_STENCIL8,
        _ => return None,
    })
}

/// What GL reports of an image's storage: bits of red, green, blue, alpha, depth and
/// stencil, and the component types of colour and of depth (`GL_NONE` when unknown).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Components {
    pub bits: [i32; 6],
    pub color_type: GLenum,
    pub depth_type: GLenum,
}

const TEXTURE_SIZES: [GLenum; 6] = [
    TEXTURE_RED_SIZE,
    TEXTURE_GREEN_SIZE,
    TEXTURE_BLUE_SIZE,
    TEXTURE_ALPHA_SIZE,
    TEXTURE_DEPTH_SIZE,
    TEXTURE_STENCIL_SIZE,
];

const RENDERBUFFER_SIZES: [GLenum; 6] = [
    RENDERBUFFER_RED_SIZE,
    RENDERBUFFER_GREEN_SIZE,
    RENDERBUFFER_BLUE_SIZE,
    RENDERBUFFER_ALPHA_SIZE,
    RENDERBUFFER_DEPTH_SIZE,
    RENDERBUFFER_STENCIL_SIZE,
];

/// Level 0 of texture `name` (which exists).
pub fn texture_components(gl: &Gl, name: u32) -> Components {
    let mut c = Components::default();
    let mut types = [0i32; 2];
    // SAFETY: single-integer queries on an existing texture.
    unsafe {
        for (v, p) in c.bits.iter_mut().zip(TEXTURE_SIZES) {
            gl.GetTextureLevelParameteriv(name, 0, p, v);
        }
        gl.GetTextureLevelParameteriv(name, 0, TEXTURE_RED_TYPE, &mut types[0]);
        gl.GetTextureLevelParameteriv(name, 0, TEXTURE_DEPTH_TYPE, &mut types[1]);
    }
    c.color_type = types[0] as GLenum;
    c.depth_type = types[1] as GLenum;
    c
}

/// Renderbuffer `name` (which exists). Renderbuffers have no type query: their unsized
/// formats are all normalised, and the only float depth formats are sized.
pub fn renderbuffer_components(gl: &Gl, name: u32) -> Components {
    let mut c = Components::default();
    let mut format = 0;
    // SAFETY: single-integer queries on an existing renderbuffer.
    unsafe {
        for (v, p) in c.bits.iter_mut().zip(RENDERBUFFER_SIZES) {
            gl.GetNamedRenderbufferParameteriv(name, p, v);
        }
        gl.GetNamedRenderbufferParameteriv(name, RENDERBUFFER_INTERNAL_FORMAT, &mut format);
    }
    c.color_type = UNSIGNED_NORMALIZED;
    c.depth_type = match format as GLenum {
        DEPTH_COMPONENT32F | DEPTH32F_STENCIL8 => FLOAT,
        _ => UNSIGNED_NORMALIZED,
    };
    c
}

/// Depth bits, float depth, stencil bits: what depth and stencil blits compare.
pub fn depth_stencil(c: Components) -> (i32, bool, i32) {
    (c.bits[4], c.depth_type == FLOAT, c.bits[5])
}

/// The sized format for an image that was given `requested` and has `components`: the
/// requested one when it is sized already.
pub fn sized(requested: GLenum, c: Components) -> Result<GLenum, String> {
    let unknown = || format!("format {requested:#x} ({c:?}) has no sized equivalent");
    Ok(match requested {
        SRGB => SRGB8,
        SRGB_ALPHA => SRGB8_ALPHA8,
        DEPTH_COMPONENT | DEPTH_STENCIL | STENCIL_INDEX => {
            let [.., depth, stencil] = c.bits;
            sized_depth_format(depth, c.depth_type == FLOAT, stencil).ok_or_else(unknown)?
        }
        RGBA | RGB | RG | RED => sized_color_format(c).ok_or_else(unknown)?,
        ALPHA | LUMINANCE | LUMINANCE_ALPHA | INTENSITY => return Err(unknown()),
        sized => sized,
    })
}

fn sized_color_format(c: Components) -> Option<GLenum> {
    let [r, g, b, a, ..] = c.bits;
    let channels = [r, g, b, a].iter().filter(|&&n| n > 0).count();
    let pick = |formats: [GLenum; 4]| formats.get(channels.checked_sub(1)?).copied();
    match (c.color_type, [r, g, b, a]) {
        (UNSIGNED_NORMALIZED, [4, 4, 4, 4]) => Some(RGBA4),
        (UNSIGNED_NORMALIZED, [5, 5, 5, 1]) => Some(RGB5_A1),
        (UNSIGNED_NORMALIZED, [5, 6, 5, 0]) => Some(RGB565),
        (UNSIGNED_NORMALIZED, [10, 10, 10, 2]) => Some(RGB10_A2),
        (FLOAT, [11, 11, 10, 0]) => Some(R11F_G11F_B10F),
        (UNSIGNED_NORMALIZED, [8, ..]) => pick([R8, RG8, RGB8, RGBA8]),
        (UNSIGNED_NORMALIZED, [16, ..]) => pick([R16, RG16, RGB16, RGBA16]),
        (SIGNED_NORMALIZED, [8, ..]) => pick([R8_SNORM, RG8_SNORM, RGB8_SNORM, RGBA8_SNORM]),
        (FLOAT, [16, ..]) => pick([R16F, RG16F, RGB16F, RGBA16F]),
        (FLOAT, [32, ..]) => pick([R32F, RG32F, RGB32F, RGBA32F]),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn depth(bits: i32, stencil: i32, ty: GLenum) -> Components {
        Components {
            bits: [0, 0, 0, 0, bits, stencil],
            color_type: NONE,
            depth_type: ty,
        }
    }

    fn color(bits: [i32; 4], ty: GLenum) -> Components {
        Components {
            bits: [bits[0], bits[1], bits[2], bits[3], 0, 0],
            color_type: ty,
            depth_type: NONE,
        }
    }

    #[test]
    fn depth_formats_follow_the_bits() {
        assert_eq!(sized_depth_format(24, false, 8), Some(DEPTH24_STENCIL8));
        assert_eq!(sized_depth_format(24, false, 0), Some(DEPTH_COMPONENT24));
        assert_eq!(sized_depth_format(32, true, 0), Some(DEPTH_COMPONENT32F));
        assert_eq!(sized_depth_format(32, true, 8), Some(DEPTH32F_STENCIL8));
        assert_eq!(sized_depth_format(32, false, 0), Some(DEPTH_COMPONENT32));
        assert_eq!(sized_depth_format(16, false, 0), Some(DEPTH_COMPONENT16));
        assert_eq!(sized_depth_format(0, false, 8), Some(STENCIL_INDEX8));
        assert_eq!(sized_depth_format(8, false, 0), None);
    }

    /// glmark2 `refract`: `glTexImage2D(GL_DEPTH_COMPONENT, …, GL_UNSIGNED_INT)`, which Mesa
    /// stores with 32 bits; a 24-bit guess made every depth blit of its layers an error.
    #[test]
    fn unsized_depth_takes_the_drivers_choice() {
        let z32 = depth(32, 0, UNSIGNED_NORMALIZED);
        assert_eq!(sized(DEPTH_COMPONENT, z32), Ok(DEPTH_COMPONENT32));
        let z24 = depth(24, 0, UNSIGNED_NORMALIZED);
        assert_eq!(sized(DEPTH_COMPONENT, z24), Ok(DEPTH_COMPONENT24));
        assert_eq!(sized(DEPTH_COMPONENT, depth(32, 0, FLOAT)), Ok(DEPTH_COMPONENT32F));
        let z24s8 = depth(24, 8, UNSIGNED_NORMALIZED);
        assert_eq!(sized(DEPTH_STENCIL, z24s8), Ok(DEPTH24_STENCIL8));
        assert_eq!(sized(STENCIL_INDEX, depth(0, 8, NONE)), Ok(STENCIL_INDEX8));
        assert!(sized(DEPTH_COMPONENT, depth(8, 0, UNSIGNED_NORMALIZED)).is_err());
    }

    #[test]
    fn unsized_colour_takes_the_drivers_choice() {
        let un = UNSIGNED_NORMALIZED;
        assert_eq!(sized(RGBA, color([8, 8, 8, 8], un)), Ok(RGBA8));
        assert_eq!(sized(RGB, color([8, 8, 8, 0], un)), Ok(RGB8));
        assert_eq!(sized(RGB, color([5, 6, 5, 0], un)), Ok(RGB565));
        assert_eq!(sized(RGBA, color([4, 4, 4, 4], un)), Ok(RGBA4));
        assert_eq!(sized(RG, color([8, 8, 0, 0], un)), Ok(RG8));
        assert_eq!(sized(RED, color([16, 0, 0, 0], FLOAT)), Ok(R16F));
        assert_eq!(sized(RGBA, color([32, 32, 32, 32], FLOAT)), Ok(RGBA32F));
        assert_eq!(sized(SRGB_ALPHA, color([8, 8, 8, 8], un)), Ok(SRGB8_ALPHA8));
        assert!(sized(LUMINANCE, color([0, 0, 0, 0], un)).is_err());
    }

    #[test]
    fn sized_formats_are_kept() {
        let z24 = depth(24, 0, UNSIGNED_NORMALIZED);
        assert_eq!(sized(DEPTH_COMPONENT24, z24), Ok(DEPTH_COMPONENT24));
        assert_eq!(sized(RGBA16F, color([16, 16, 16, 16], FLOAT)), Ok(RGBA16F));
    }
}
