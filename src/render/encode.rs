//! Pixel encoding: linear colour to bytes, linear or sRGB, one channel or four pixels at once.

use super::*;
use crate::math::Byte;

/// How linear colour becomes a byte.
///
/// ```
/// use microray::{render::encode_channel, Encoding};
/// assert_eq!(encode_channel(0.5, Encoding::Linear), 128);
/// assert_eq!(encode_channel(0.5, Encoding::Srgb), 188);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
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
    match encoding {
        // Not clamped first: 255c + 0.5 is monotone in c, so a c ≥ 1 gives ≥ 255.5 and a
        // c ≤ 0 at most 0.5, which the saturating `byte` maps to 255 and 0 as the clamp would.
        Encoding::Linear => byte_of(c),
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
            byte_of(srgb(c))
        }
    }
}

/// An encoded channel value `c` rounded to its byte: `255c + 0.5`, then truncated with
/// saturation. For one f32 and for four lanes (`Frame::encode4`), so the same bytes.
#[inline(always)]
pub(super) fn byte_of<T: Byte>(c: T) -> T::Out {
    (T::splat(255.0) * c + T::splat(0.5)).byte()
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
    /// [`byte_of`] lane by lane, the same bytes. sRGB goes channel by channel through the
    /// scalar curve.
    #[cfg(lanes)]
    #[inline(always)]
    pub(super) fn encode4(&self, c: &crate::simd::V) -> [Rgb888; 4] {
        if self.encoding != Encoding::Linear {
            return core::array::from_fn(|l| self.encode(c.lane(l)));
        }
        // The three bytes of each pixel in one integer lane: one extraction a pixel, not three.
        let (r, g, b) = (byte_of(c.x), byte_of(c.y), byte_of(c.z));
        let rgb: crate::simd::I = r | (g << 8_i32) | (b << 16_i32);
        let rgb = rgb.to_array();
        rgb.map(|w| Rgb888::new(w as u8, (w >> 8) as u8, (w >> 16) as u8))
    }
}
