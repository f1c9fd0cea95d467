//! Ordered (4×4 Bayer) dithering from `Rgb888` to the colours of small displays: 16- and 18-bit
//! colour, 1-bit (`BinaryColor`: SSD1306, SH1106, e-paper) and grey (`Gray2`, `Gray4`,
//! `Gray8`). A plain conversion rounds every pixel of a slow gradient to the same level, so the
//! display shows bands (or, at 1 bit, one threshold); a dithered pixel rounds up or down by its
//! place in a 4×4 tile, so each tile averages to the colour.
//!
//! Integer-only: no float, the same bits on every target.

use embedded_graphics::pixelcolor::{
    BinaryColor, Gray2, Gray4, Gray8, PixelColor, Rgb555, Rgb565, Rgb666, Rgb888, RgbColor,
};

/// The 4×4 Bayer index matrix: every threshold rank 0..16 once, neighbours far apart.
pub(crate) const BAYER4: [[u8; 4]; 4] =
    [[0, 8, 2, 10], [12, 4, 14, 6], [3, 11, 1, 9], [15, 7, 13, 5]];

/// The threshold rank of pixel `(x, y)` in its tile.
#[inline]
fn rank(x: u32, y: u32) -> u32 {
    BAYER4[(y & 3) as usize][(x & 3) as usize] as u32
}

/// Quantises `v` of `0..=full` to `0..=max` as `floor(v·max/full + (2b+1)/32)`, `b` in 0..16:
/// the 16 thresholds average ½, so a flat area averages to the exact value `v·max/full`.
/// `v = full` gives `max`, never more. Exact in u32 for `full·max·32 < 2³²` (the callers:
/// `full` is 255 or 65 280, `max` at most 255).
#[inline]
pub(crate) fn dither_level(v: u32, full: u32, max: u32, b: u32) -> u32 {
    (v * max * 32 + (2 * b + 1) * full) / (full * 32)
}

/// BT.601 luma of `c` in 1/256 steps, `0..=65 280`: the weights of embedded-graphics' own
/// grey conversion (77, 150, 29), kept unrounded so that dithering spreads the fraction.
#[inline]
fn luma256(c: Rgb888) -> u32 {
    77 * c.r() as u32 + 150 * c.g() as u32 + 29 * c.b() as u32
}

/// A display colour that an `Rgb888` pixel can be ordered-dithered to: 4×4 Bayer thresholds,
/// so that a pixel rounds up or down by its place in a tile and each tile averages to the
/// colour. Implemented for the colour types of embedded-graphics that have fewer levels than
/// `Rgb888` (grey from BT.601 luma, embedded-graphics' weights, unrounded), and for `Rgb888`
/// itself (unchanged). Integer-only: the same bits on every target. [`Frame::draw_dithered`] and
/// [`Frame::render_rows_dithered`] use it; a display colour of your own needs one impl.
///
/// [`Frame::draw_dithered`]: crate::Frame::draw_dithered
/// [`Frame::render_rows_dithered`]: crate::Frame::render_rows_dithered
///
/// ```
/// use embedded_graphics::pixelcolor::{BinaryColor, Gray4, GrayColor, Rgb888};
/// use microray::output::Dither;
/// // 25% grey on a 1-bit display: 4 of a tile's 16 pixels on.
/// let grey = Rgb888::new(64, 64, 64);
/// let on = (0..16).filter(|k| BinaryColor::dither(grey, k % 4, k / 4).is_on()).count();
/// assert_eq!(on, 4);
/// // 100/255 of white is 5.88 of Gray4's 15 levels: most pixels 6, some 5.
/// let sum: u32 = (0..16).map(|k| Gray4::dither(Rgb888::new(100, 100, 100), k % 4, k / 4).luma() as u32).sum();
/// assert_eq!(sum, 94);
/// ```
pub trait Dither: PixelColor {
    /// `c` as the pixel at column `x`, row `y` shows it, its tile's threshold applied.
    fn dither(c: Rgb888, x: u32, y: u32) -> Self;
}

impl Dither for Rgb888 {
    #[inline]
    fn dither(c: Rgb888, _x: u32, _y: u32) -> Self {
        c
    }
}

/// RGB colours: each channel dithered to its bit depth, with the same threshold.
macro_rules! dither_rgb {
    ($($t:ty),*) => {$(
        impl Dither for $t {
            #[inline]
            fn dither(c: Rgb888, x: u32, y: u32) -> Self {
                let b = rank(x, y);
                let ch = |v: u8, max: u8| dither_level(v as u32, 255, max as u32, b) as u8;
                <$t>::new(ch(c.r(), <$t>::MAX_R), ch(c.g(), <$t>::MAX_G), ch(c.b(), <$t>::MAX_B))
            }
        }
    )*};
}
dither_rgb!(Rgb555, Rgb565, Rgb666);

/// Grey levels: the luma, unrounded, dithered to `2ⁿ` levels.
macro_rules! dither_gray {
    ($($t:ty: $max:expr),*) => {$(
        impl Dither for $t {
            #[inline]
            fn dither(c: Rgb888, x: u32, y: u32) -> Self {
                <$t>::new(dither_level(luma256(c), 65_280, $max, rank(x, y)) as u8)
            }
        }
    )*};
}
dither_gray!(Gray2: 3, Gray4: 15, Gray8: 255);

impl Dither for BinaryColor {
    /// On where the luma, as a fraction of white, reaches one less the pixel's threshold: a
    /// tile has `k` of its 16 pixels on for a luma in `[(2k − 1)/32, (2k + 1)/32)` of white.
    #[inline]
    fn dither(c: Rgb888, x: u32, y: u32) -> Self {
        BinaryColor::from(dither_level(luma256(c), 65_280, 1, rank(x, y)) != 0)
    }
}

/// Converts `c` to `Rgb565` with 4×4 ordered dithering for the pixel at column `x`, row `y`
/// ([`Dither`] for `Rgb565`).
///
/// Plain conversion rounds every pixel of a slow gradient to the same 5- or 6-bit level, so a
/// 16-bit display shows bands; the dithered pixel rounds up or down according to its place in
/// a 4×4 tile, so the tile's average is the 8-bit colour (to within 1/32 of a level).
///
/// ```
/// use embedded_graphics::pixelcolor::{Rgb565, Rgb888, RgbColor};
/// use microray::output::dither_rgb565;
/// // 100/255 of full red is 12.16 of Rgb565's 31 levels: most pixels of a tile get 12, a few 13.
/// let tile: u32 = (0..16).map(|k| dither_rgb565(Rgb888::new(100, 0, 0), k % 4, k / 4).r() as u32).sum();
/// assert_eq!(tile, 12 * 16 + 3);
/// assert_eq!(dither_rgb565(Rgb888::WHITE, 3, 1), Rgb565::WHITE); // the extremes stay exact
/// assert_eq!(dither_rgb565(Rgb888::BLACK, 2, 2), Rgb565::BLACK);
/// ```
#[inline]
pub fn dither_rgb565(c: Rgb888, x: u32, y: u32) -> Rgb565 {
    Rgb565::dither(c, x, y)
}

#[cfg(test)]
mod tests {
    use super::*;
    use embedded_graphics::pixelcolor::GrayColor;

    #[test]
    fn bayer_matrix_is_a_permutation() {
        let mut seen = [false; 16];
        for v in BAYER4.iter().flatten() {
            seen[*v as usize] = true;
        }
        assert!(seen.iter().all(|&s| s));
    }

    #[test]
    fn every_tile_averages_to_the_exact_level() {
        for (full, step) in [(255u32, 1), (65_280, 7)] {
            for max in [1u32, 3, 15, 31, 63, 255] {
                for v in (0..=full).step_by(step).chain([full]) {
                    let exact = v as f64 * max as f64 / full as f64;
                    let sum: u32 = (0..16).map(|b| dither_level(v, full, max, b)).sum();
                    let mean = sum as f64 / 16.0;
                    assert!(
                        (mean - exact).abs() <= 1.0 / 32.0 + 1e-9,
                        "v={v} full={full} max={max} mean={mean}"
                    );
                    // Each pixel is one of the two levels around the exact value.
                    for b in 0..16 {
                        let q = dither_level(v, full, max, b) as f64;
                        assert!(q >= exact.floor() && q <= exact.ceil() && q <= max as f64);
                    }
                }
            }
        }
    }

    #[test]
    fn dithering_is_monotone_per_threshold() {
        for b in 0..16 {
            for v in 0..255u32 {
                for max in [1, 15, 31, 63] {
                    assert!(dither_level(v, 255, max, b) <= dither_level(v + 1, 255, max, b));
                }
            }
        }
    }

    #[test]
    fn exact_levels_are_not_dithered() {
        // Black and white are exact levels at every depth; they must come out flat.
        for (x, y) in [(0, 0), (1, 2), (3, 3)] {
            let (w, k) = (Rgb888::WHITE, Rgb888::BLACK);
            assert_eq!(Rgb565::dither(w, x, y), Rgb565::new(31, 63, 31));
            assert_eq!(Rgb565::dither(k, x, y), Rgb565::new(0, 0, 0));
            assert_eq!(Rgb666::dither(w, x, y), Rgb666::WHITE);
            assert_eq!(Gray8::dither(w, x, y), Gray8::WHITE);
            assert_eq!(Gray4::dither(k, x, y), Gray4::BLACK);
            assert_eq!(Gray2::dither(w, x, y), Gray2::WHITE);
            assert_eq!(BinaryColor::dither(w, x, y), BinaryColor::On);
            assert_eq!(BinaryColor::dither(k, x, y), BinaryColor::Off);
        }
        // A grey that is an exact Gray4 level (17·5) stays flat.
        let g = Rgb888::new(85, 85, 85);
        assert!((0..16).all(|k| Gray4::dither(g, k % 4, k / 4) == Gray4::new(5)));
    }

    #[test]
    fn gray8_spreads_the_luma_fraction() {
        // Luma 77·1 / 256 of a level: pure dark red is 0.3 of Gray8's first step.
        let c = Rgb888::new(1, 0, 0);
        let on: u32 = (0..16)
            .map(|k| Gray8::dither(c, k % 4, k / 4).luma() as u32)
            .sum();
        assert_eq!(on, 5); // 0.3 × 16 = 4.8 → 5 of 16 pixels at level 1
                           // The luma weights are embedded-graphics' own: a flat colour's tile averages to its
                           // plain conversion (which rounds) to within half a level.
        for c in [
            Rgb888::new(10, 200, 30),
            Rgb888::new(250, 3, 99),
            Rgb888::new(128, 128, 128),
        ] {
            let mean = (0..16)
                .map(|k| Gray8::dither(c, k % 4, k / 4).luma() as f64)
                .sum::<f64>()
                / 16.0;
            assert!(
                (mean - Gray8::from(c).luma() as f64).abs() <= 0.5 + 1.0 / 32.0,
                "{c:?}"
            );
        }
    }

    #[test]
    fn binary_tile_counts_follow_the_grey() {
        // A tile of grey g has round(16 g / 255) pixels on, one more pixel per 1/16 of white.
        for g in 0..=255u8 {
            let c = Rgb888::new(g, g, g);
            let on = (0..16)
                .filter(|k| BinaryColor::dither(c, k % 4, k / 4).is_on())
                .count();
            let exact = 16.0 * g as f64 / 255.0;
            assert!((on as f64 - exact).abs() <= 0.5, "g={g} on={on}");
        }
    }

    #[test]
    fn tile_repeats_every_four_pixels() {
        let c = Rgb888::new(77, 140, 201);
        for (x, y) in [(0, 0), (1, 3), (2, 1)] {
            assert_eq!(dither_rgb565(c, x, y), dither_rgb565(c, x + 4, y + 8));
            assert_eq!(Gray4::dither(c, x, y), Gray4::dither(c, x + 8, y + 4));
        }
    }
}
