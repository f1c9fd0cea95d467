//! Pixel encoding: linear colour to bytes, linear or sRGB, one channel or four pixels at once.

use super::*;

/// How linear colour becomes a byte.
///
/// ```
/// use microray::{render::encode_channel, Encoding};
/// assert_eq!(encode_channel(0.5, Encoding::Linear), 128);
/// assert_eq!(encode_channel(0.5, Encoding::Srgb), 188);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Encoding {
    /// The channel value as it is.
    #[default]
    Linear,
    /// The sRGB transfer curve (`12.92c` below 0.0031308, else `1.055c^(1/2.4) − 0.055`).
    Srgb,
}

/// Clamps a linear channel to [0, 1], encodes it and rounds to a byte (NaN counts as 0).
///
/// ```
/// use microray::{render::encode_channel, Encoding};
/// assert_eq!(encode_channel(2.0, Encoding::Linear), 255);
/// assert_eq!(encode_channel(-1.0, Encoding::Srgb), 0);
/// assert_eq!(encode_channel(f32::NAN, Encoding::Linear), 0);
/// ```
#[inline]
pub fn encode_channel(c: f32, encoding: Encoding) -> u8 {
    let v = match encoding {
        // Not clamped first: 255c + 0.5 is monotone in c, so a c ≥ 1 gives ≥ 255.5 and a
        // c ≤ 0 at most 0.5, which the cast below maps to 255 and 0 as the clamp would.
        Encoding::Linear => 255.0 * c + 0.5,
        Encoding::Srgb => {
            let c = if c > 0.0 {
                if c < 1.0 {
                    c
                } else {
                    1.0
                }
            } else {
                0.0
            };
            255.0 * srgb(c) + 0.5
        }
    };
    // The cast saturates (NaN to 0), which a Cortex-M4F's `vcvt` does by itself, and truncates,
    // which is floor for v ≥ 0; the clamp is one `usat` there.
    (v as i32).clamp(0, 255) as u8
}

/// [`encode_channel`] with [`Encoding::Linear`] of four channel values in vector lanes: `255c +
/// 0.5`, then the saturating cast's cases as selections (NaN and below 0 give 0, 256 and above
/// 255) and a plain truncation of what is left, in `[0, 256)`: the same bytes, as integer lanes.
#[cfg(lanes)]
#[inline(always)]
pub(super) fn linear_bytes(c: crate::simd::F) -> crate::simd::I {
    use crate::simd::F;
    use crate::simd::{CmpGe, CmpLt};
    let v = F::splat(255.0) * c + F::splat(0.5);
    let (zero, top, end) = (F::ZERO, F::splat(255.0), F::splat(256.0));
    let outside = v.cmp_ge(end).blend(top, zero);
    let v = (v.cmp_ge(zero) & v.cmp_lt(end)).blend(v, outside);
    v.fast_trunc_int()
}

/// The sRGB transfer curve on [0, 1]. Out of line: one copy for the three channels.
#[inline(never)]
pub(super) fn srgb(c: f32) -> f32 {
    if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * powf(c, 1.0 / 2.4) - 0.055
    }
}

impl<'a, const S: usize, const L: usize> Frame<'a, S, L> {
    /// A linear colour encoded as a pixel.
    #[inline]
    pub(super) fn encode(&self, c: Color) -> Rgb888 {
        let e = self.encoding;
        Rgb888::new(
            encode_channel(c.x, e),
            encode_channel(c.y, e),
            encode_channel(c.z, e),
        )
    }

    /// [`Frame::encode`] of four colours in vector lanes (`cfg(lanes)`): `encode_channel`'s
    /// `255c + 0.5` and its saturating cast lane by lane (the cast's cases as selections: NaN
    /// and below 0 to 0, 256 and above to 255), the same bytes. sRGB goes channel by channel
    /// through the scalar curve.
    #[cfg(lanes)]
    #[inline(always)]
    pub(super) fn encode4(&self, c: &crate::simd::V) -> [Rgb888; 4] {
        if self.encoding != Encoding::Linear {
            return core::array::from_fn(|l| self.encode(c.lane(l)));
        }
        // The three bytes of each pixel in one integer lane: one extraction a pixel, not three.
        let (r, g, b) = (linear_bytes(c.x), linear_bytes(c.y), linear_bytes(c.z));
        let rgb: crate::simd::I = r | (g << 8_i32) | (b << 16_i32);
        let rgb = rgb.to_array();
        rgb.map(|w| Rgb888::new(w as u8, (w >> 8) as u8, (w >> 16) as u8))
    }
}
