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
        #[cfg(lanes)]
        Encoding::Srgb => srgb_byte(c),
        #[cfg(not(lanes))]
        Encoding::Srgb => srgb_curve_byte(c),
    }
}

/// [`encode_channel`]'s sRGB byte by its definition: the channel clamped, [`srgb`], rounded.
#[cfg_attr(lanes, allow(dead_code))]
#[inline]
pub(super) fn srgb_curve_byte(c: f32) -> u8 {
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

/// An encoded channel value `c` rounded to its byte: `255c + 0.5`, then truncated with
/// saturation. For one f32 and for four lanes (`Frame::encode4`), so the same bytes.
#[inline(always)]
pub(super) fn byte_of<T: Byte>(c: T) -> T::Out {
    (T::splat(255.0) * c + T::splat(0.5)).byte()
}

/// The sRGB transfer curve on [0, 1]. Out of line: one copy for the three channels.
#[cfg_attr(lanes, allow(dead_code))]
#[inline(never)]
pub(super) fn srgb(c: f32) -> f32 {
    if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * powf(c, 1.0 / 2.4) - 0.055
    }
}

/// The least f32 that [`srgb_curve_byte`] takes to each byte from 1 to 255, in order (hosts):
/// that byte function does not decrease with its channel (on [0, 1]; the clamp decides the
/// rest), so a channel's byte is the number of these at or below it (the test
/// `srgb_steps_are_the_curves_bytes` checks each step and the f32 about it).
#[cfg(lanes)]
#[rustfmt::skip]
pub(super) const SRGB_STEPS: [f32; 255] = [
    1.5176348e-4, 4.552905e-4, 7.588175e-4, 1.0623444e-3, 1.3658715e-3, 1.6693984e-3,
    1.9729254e-3, 2.2764525e-3, 2.5799794e-3, 2.8835065e-3, 3.188301e-3, 3.5092593e-3,
    3.8483152e-3, 4.205748e-3, 4.581833e-3, 4.976838e-3, 5.3910245e-3, 5.824651e-3,
    6.277969e-3, 6.751227e-3, 7.244668e-3, 7.75853e-3, 8.293048e-3, 8.848452e-3,
    9.424971e-3, 1.0022826e-2, 1.0642237e-2, 1.1283421e-2, 1.1946592e-2, 1.2631958e-2,
    1.333973e-2, 1.4070112e-2, 1.4823306e-2, 1.5599506e-2, 1.6398912e-2, 1.7221719e-2,
    1.8068116e-2, 1.8938296e-2, 1.9832447e-2, 2.0750748e-2, 2.1693386e-2, 2.266054e-2,
    2.3652392e-2, 2.4669116e-2, 2.5710888e-2, 2.6777888e-2, 2.7870275e-2, 2.8988225e-2,
    3.0131904e-2, 3.1301484e-2, 3.249713e-2, 3.3718996e-2, 3.4967247e-2, 3.6242045e-2,
    3.7543554e-2, 3.887193e-2, 4.022733e-2, 4.16099e-2, 4.3019794e-2, 4.445717e-2,
    4.5922183e-2, 4.741497e-2, 4.8935693e-2, 5.048449e-2, 5.206151e-2, 5.36669e-2,
    5.5300806e-2, 5.696336e-2, 5.8654718e-2, 6.0375027e-2, 6.2124398e-2, 6.390299e-2,
    6.571093e-2, 6.7548364e-2, 6.941543e-2, 7.131225e-2, 7.323897e-2, 7.5195715e-2,
    7.718263e-2, 7.919983e-2, 8.124745e-2, 8.332563e-2, 8.543449e-2, 8.757417e-2,
    8.974478e-2, 9.194645e-2, 9.417931e-2, 9.644349e-2, 9.87391e-2, 1.0106628e-1,
    1.0342514e-1, 1.05815805e-1, 1.0823841e-1, 1.1069305e-1, 1.1317987e-1, 1.1569897e-1,
    1.1825048e-1, 1.20834544e-1, 1.23451225e-1, 1.2610066e-1, 1.2878297e-1, 1.3149828e-1,
    1.3424669e-1, 1.3702832e-1, 1.3984329e-1, 1.426917e-1, 1.4557368e-1, 1.4848931e-1,
    1.5143874e-1, 1.5442206e-1, 1.574394e-1, 1.6049086e-1, 1.6357651e-1, 1.6669649e-1,
    1.6985093e-1, 1.7303991e-1, 1.7626356e-1, 1.79522e-1, 1.8281527e-1, 1.8614352e-1,
    1.8950683e-1, 1.9290534e-1, 1.9633915e-1, 1.9980834e-1, 2.0331304e-1, 2.0685333e-1,
    2.1042933e-1, 2.1404113e-1, 2.1768883e-1, 2.2137254e-1, 2.2509237e-1, 2.2884846e-1,
    2.326408e-1, 2.3646954e-1, 2.4033481e-1, 2.4423666e-1, 2.4817523e-1, 2.521506e-1,
    2.5616288e-1, 2.6021212e-1, 2.642985e-1, 2.6842204e-1, 2.725829e-1, 2.767811e-1,
    2.8101683e-1, 2.852901e-1, 2.8960103e-1, 2.9394972e-1, 2.983363e-1, 3.0276078e-1,
    3.0722335e-1, 3.1172404e-1, 3.1626296e-1, 3.2084018e-1, 3.2545584e-1, 3.3010995e-1,
    3.3480272e-1, 3.3953413e-1, 3.4430435e-1, 3.4911352e-1, 3.5396153e-1, 3.5884863e-1,
    3.637748e-1, 3.6874026e-1, 3.73745e-1, 3.787892e-1, 3.838728e-1, 3.8899603e-1,
    3.941589e-1, 3.9936155e-1, 4.0460402e-1, 4.0988645e-1, 4.1520882e-1, 4.2057136e-1,
    4.2597404e-1, 4.3141702e-1, 4.3690032e-1, 4.4242412e-1, 4.479884e-1, 4.535933e-1,
    4.592389e-1, 4.649253e-1, 4.706525e-1, 4.764207e-1, 4.822299e-1, 4.8808023e-1,
    4.9397185e-1, 4.9990457e-1, 5.058788e-1, 5.1189435e-1, 5.179515e-1, 5.240502e-1,
    5.301906e-1, 5.363727e-1, 5.425968e-1, 5.488627e-1, 5.551707e-1, 5.615207e-1,
    5.6791294e-1, 5.743474e-1, 5.808242e-1, 5.8734334e-1, 5.9390503e-1, 6.005092e-1,
    6.0715616e-1, 6.138457e-1, 6.205781e-1, 6.2735337e-1, 6.3417166e-1, 6.410329e-1,
    6.4793724e-1, 6.5488476e-1, 6.618756e-1, 6.689097e-1, 6.759874e-1, 6.831085e-1,
    6.9027317e-1, 6.9748145e-1, 7.0473343e-1, 7.120292e-1, 7.193689e-1, 7.267525e-1,
    7.341801e-1, 7.4165183e-1, 7.4916774e-1, 7.567279e-1, 7.643323e-1, 7.719812e-1,
    7.796745e-1, 7.8741235e-1, 7.9519475e-1, 8.030219e-1, 8.1089383e-1, 8.188106e-1,
    8.2677215e-1, 8.347788e-1, 8.428305e-1, 8.5092723e-1, 8.590692e-1, 8.6725646e-1,
    8.7548906e-1, 8.837672e-1, 8.920905e-1, 9.0045965e-1, 9.0887415e-1, 9.173346e-1,
    9.2584056e-1, 9.3439263e-1, 9.429903e-1, 9.516342e-1, 9.603239e-1, 9.6906006e-1,
    9.7784203e-1, 9.8667055e-1, 9.9554527e-1,
];

/// [`srgb_curve_byte`] through [`SRGB_STEPS`] (hosts): eight comparisons of a binary search
/// instead of a `powf` (about 250 instructions), the same byte for every f32; a NaN, below
/// every step by no comparison, gives 0 as the clamp does.
#[cfg(lanes)]
#[inline(always)]
pub(super) fn srgb_byte(c: f32) -> u8 {
    // The steps at or below `c` so far; each half searched decides the next bit.
    let mut below = 0;
    for half in [128, 64, 32, 16, 8, 4, 2, 1] {
        if SRGB_STEPS.get(below + half - 1).is_some_and(|&s| s <= c) {
            below += half;
        }
    }
    below as u8
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
