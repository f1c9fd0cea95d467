//! Outputs: drawing a frame onto any embedded-graphics display, optionally with ordered
//! (4×4 Bayer) dithering to 16-bit `Rgb565`, which hides the banding of smooth gradients.

use embedded_graphics::pixelcolor::{Rgb565, Rgb888, RgbColor};
use embedded_graphics::prelude::{DrawTarget, Point, Size};
use embedded_graphics::primitives::Rectangle;

use crate::error::Error;
use crate::render::Frame;

/// The 4×4 Bayer index matrix: every threshold rank 0..16 once, neighbours far apart.
const BAYER4: [[u8; 4]; 4] = [[0, 8, 2, 10], [12, 4, 14, 6], [3, 11, 1, 9], [15, 7, 13, 5]];

/// Quantises an 8-bit channel to `0..=max` as `floor(v·max/255 + (2b+1)/32)`, `b` in 0..16:
/// the 16 thresholds average ½, so a flat area averages to the exact value `v·max/255`.
/// Integer-only (no float), and `v = 255` gives `max`, never more.
#[inline]
fn dither_channel(v: u8, max: u32, b: u32) -> u8 {
    ((v as u32 * max * 32 + (2 * b + 1) * 255) / (255 * 32)) as u8
}

/// Converts `c` to `Rgb565` with 4×4 ordered dithering for the pixel at column `x`, row `y`.
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
    let b = BAYER4[(y & 3) as usize][(x & 3) as usize] as u32;
    Rgb565::new(
        dither_channel(c.r(), 31, b),
        dither_channel(c.g(), 63, b),
        dither_channel(c.b(), 31, b),
    )
}

impl<const S: usize, const L: usize> Frame<'_, S, L> {
    /// Draws the frame onto an embedded-graphics display (or any [`DrawTarget`]) whose colour
    /// converts from [`Rgb888`], such as an `Rgb565` panel. Each row is traced as the display
    /// consumes it through `fill_contiguous`, rows from the top: no frame or row buffer is
    /// needed. (On hosts [`Frame::render_rows`] is faster: it shares each span's shadow
    /// lists between 8 rows, which a row-by-row stream cannot.)
    ///
    /// ```
    /// use embedded_graphics::{mock_display::MockDisplay, pixelcolor::Rgb565};
    /// use microray::{Camera, Color, Frame, RenderOptions, Scene, Vec3};
    ///
    /// let mut scene: Scene<1, 0> = Scene::new();
    /// scene.set_background(Color::new(0.0, 0.0, 1.0))?;
    /// let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 8, 8)?;
    /// let mut storage = microray::FrameStorage::new();
    /// let frame = Frame::new(&scene, &cam, RenderOptions::default(), &mut storage)?;
    /// let mut display: MockDisplay<Rgb565> = MockDisplay::new();
    /// frame.draw(&mut display).unwrap();
    /// assert_eq!(display.get_pixel(embedded_graphics::prelude::Point::new(7, 7)), Some(Rgb565::new(0, 0, 31)));
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn draw<D>(&self, target: &mut D) -> Result<(), D::Error>
    where
        D: DrawTarget,
        D::Color: From<Rgb888>,
    {
        let w = self.width();
        for j in 0..self.height() {
            let row = Rectangle::new(Point::new(0, j as i32), Size::new(w, 1));
            // The display takes the iterator by value: give it a reference to the row, which
            // is large, rather than moving the row itself through its adapters.
            let mut pixels = self.row(j);
            target.fill_contiguous(&row, pixels.by_ref().map(Into::into))?;
        }
        Ok(())
    }

    /// Like [`Frame::render_rows`] into `Rgb565`, but ordered-dithered ([`dither_rgb565`]):
    /// the strip or row buffer of a 16-bit display without banding.
    ///
    /// ```
    /// use embedded_graphics::pixelcolor::Rgb565;
    /// use microray::{output::dither_rgb565, Camera, Color, Frame, RenderOptions, Scene, Vec3};
    ///
    /// let mut scene: Scene<1, 0> = Scene::new();
    /// scene.set_background(Color::new(0.4, 0.4, 0.4))?;
    /// let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 8, 4)?;
    /// let mut storage = microray::FrameStorage::new();
    /// let frame = Frame::new(&scene, &cam, RenderOptions::default(), &mut storage)?;
    /// let mut row = [Rgb565::new(0, 0, 0); 8];
    /// frame.render_rows_dithered(2, &mut row)?;
    /// assert_eq!(row[5], dither_rgb565(frame.pixel(5, 2), 5, 2));
    /// assert_ne!(row[0], row[1]); // 0.4 lies between two Rgb565 levels: the tile mixes them
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn render_rows_dithered(&self, first_row: u32, buf: &mut [Rgb565]) -> Result<u32, Error> {
        let w = self.width() as usize; // ≥ 1 (Camera checks); checked_div links no panic
        let (Some(rows), Some(0)) = (buf.len().checked_div(w), buf.len().checked_rem(w)) else {
            return Err(Error::BufferSize);
        };
        if first_row as usize + rows > self.height() as usize {
            return Err(Error::BufferSize);
        }
        dither_rows(self, first_row, buf, (w, rows as u32));
        Ok(rows as u32)
    }

    /// Like [`Frame::draw`], but ordered-dithered to `Rgb565` ([`dither_rgb565`]) for
    /// displays whose colour converts from `Rgb565` (such as an `Rgb565` panel).
    ///
    /// ```
    /// use embedded_graphics::{mock_display::MockDisplay, pixelcolor::Rgb565, prelude::Point};
    /// use microray::{output::dither_rgb565, Camera, Color, Frame, RenderOptions, Scene, Vec3};
    ///
    /// let mut scene: Scene<1, 0> = Scene::new();
    /// scene.set_background(Color::new(0.0, 0.3, 0.7))?;
    /// let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 8, 8)?;
    /// let mut storage = microray::FrameStorage::new();
    /// let frame = Frame::new(&scene, &cam, RenderOptions::default(), &mut storage)?;
    /// let mut display: MockDisplay<Rgb565> = MockDisplay::new();
    /// frame.draw_dithered(&mut display).unwrap();
    /// assert_eq!(display.get_pixel(Point::new(6, 3)), Some(dither_rgb565(frame.pixel(6, 3), 6, 3)));
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn draw_dithered<D>(&self, target: &mut D) -> Result<(), D::Error>
    where
        D: DrawTarget,
        D::Color: From<Rgb565>,
    {
        let w = self.width();
        for j in 0..self.height() {
            let row = Rectangle::new(Point::new(0, j as i32), Size::new(w, 1));
            let mut pixels = self.row(j);
            let colours =
                (pixels.by_ref().enumerate()).map(|(i, c)| dither_rgb565(c, i as u32, j).into());
            target.fill_contiguous(&row, colours)?;
        }
        Ok(())
    }
}

/// [`Frame::render_rows_dithered`]'s rows from `first_row` into `buf` (whole rows of `w`
/// pixels): on hosts tile by tile, as `render_rows` traces them.
#[cfg(lanes)]
fn dither_rows<const S: usize, const L: usize>(
    frame: &Frame<'_, S, L>,
    first_row: u32,
    buf: &mut [Rgb565],
    (w, rows): (usize, u32),
) {
    let _ = frame.tile_rows(first_row, rows, |t| {
        let out = t.place(buf, first_row, w);
        for (k, (o, &c)) in out.iter_mut().zip(t.px).enumerate() {
            *o = dither_rgb565(c, t.i + k as u32, t.j);
        }
        Ok::<(), core::convert::Infallible>(())
    });
}

/// [`Frame::render_rows_dithered`]'s rows from `first_row` into `buf` (whole rows of `w`
/// pixels): on Cortex-M row by row with the renderer's culling (the same pixels as `pixel`).
#[cfg(not(lanes))]
fn dither_rows<const S: usize, const L: usize>(
    frame: &Frame<'_, S, L>,
    first_row: u32,
    buf: &mut [Rgb565],
    (w, _rows): (usize, u32),
) {
    for (r, row) in buf.chunks_exact_mut(w).enumerate() {
        let j = first_row + r as u32;
        let mut pixels = frame.row(j);
        for (i, (px, c)) in row.iter_mut().zip(pixels.by_ref()).enumerate() {
            *px = dither_rgb565(c, i as u32, j);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
        for max in [31u32, 63] {
            for v in 0..=255u8 {
                let exact = v as f64 * max as f64 / 255.0;
                let sum: u32 = (0..16).map(|b| dither_channel(v, max, b) as u32).sum();
                let mean = sum as f64 / 16.0;
                assert!(
                    (mean - exact).abs() <= 1.0 / 32.0 + 1e-9,
                    "v={v} max={max} mean={mean}"
                );
                // Each pixel is one of the two levels around the exact value.
                for b in 0..16 {
                    let q = dither_channel(v, max, b) as f64;
                    assert!(q >= exact.floor() && q <= exact.ceil() && q <= max as f64);
                }
            }
        }
    }

    #[test]
    fn dithering_is_monotone_per_threshold() {
        for b in 0..16 {
            for v in 0..255u8 {
                assert!(dither_channel(v, 31, b) <= dither_channel(v + 1, 31, b));
                assert!(dither_channel(v, 63, b) <= dither_channel(v + 1, 63, b));
            }
        }
    }

    #[test]
    fn exact_levels_are_not_dithered() {
        // Only 0 and 255 are exact levels at both 5 and 6 bits; they must come out flat.
        for (x, y) in [(0, 0), (1, 2), (3, 3)] {
            assert_eq!(
                dither_rgb565(Rgb888::new(255, 255, 255), x, y),
                Rgb565::new(31, 63, 31)
            );
            assert_eq!(
                dither_rgb565(Rgb888::new(0, 0, 0), x, y),
                Rgb565::new(0, 0, 0)
            );
        }
    }

    #[test]
    fn tile_repeats_every_four_pixels() {
        let c = Rgb888::new(77, 140, 201);
        for (x, y) in [(0, 0), (1, 3), (2, 1)] {
            assert_eq!(dither_rgb565(c, x, y), dither_rgb565(c, x + 4, y + 8));
        }
    }
}
