//! Outputs: drawing a frame onto any embedded-graphics display, in one window or
//! progressively, and ordered dithering to the display's colour ([`Dither`]).
//!
//! A frame is an [`ImageDrawable`] of `Rgb888` pixels: `Image::new(&frame, point)` places it,
//! `sub_image` redraws part of it, and a display of another colour takes it through
//! `color_converted`. Every path hands the display one rectangle per call
//! (`fill_contiguous`), traced row by row as the display consumes it: no framebuffer.

use core::marker::PhantomData;

use embedded_graphics::image::ImageDrawable;
use embedded_graphics::pixelcolor::Rgb888;
use embedded_graphics::prelude::{
    Dimensions, DrawTarget, OriginDimensions, Point, Size, Transform,
};
use embedded_graphics::primitives::Rectangle;

use crate::error::Error;
use crate::render::{Frame, Pixels};

mod dither;
mod progressive;

pub use dither::{dither_rgb565, Dither};
pub use progressive::Progress;

impl<const S: usize, const L: usize> Frame<'_, S, L> {
    /// Draws the frame onto an embedded-graphics display (or any [`DrawTarget`]) whose colour
    /// converts from [`Rgb888`], such as an `Rgb565` panel, at the display's origin: one
    /// `fill_contiguous` over the frame's rectangle (clipped to the display), its rows traced
    /// as the display consumes them. A display driver sets its address window once per frame,
    /// and no frame or row buffer is needed. (On hosts [`Frame::render_rows`] is faster: it
    /// shares each span's shadow lists between 8 rows, which a row-by-row stream cannot.)
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
        let Some((dest, src)) = self.visible(target, &self.bounding_box(), Point::zero()) else {
            return Ok(());
        };
        let mut pixels = self.pixels(&src);
        // The display takes the iterator by value: give it a reference to the pixels, which
        // are large, rather than moving them through its adapters.
        target.fill_contiguous(&dest, pixels.by_ref().map(Into::into))
    }

    /// Like [`Frame::draw`], but ordered-dithered to the display's colour ([`Dither`]): an
    /// `Rgb565` panel without banding, grey levels on a `Gray4` OLED, or 1-bit `BinaryColor`
    /// (SSD1306, e-paper) with its gradients kept.
    ///
    /// ```
    /// use embedded_graphics::{mock_display::MockDisplay, pixelcolor::{BinaryColor, Rgb565}, prelude::Point};
    /// use microray::{output::{dither_rgb565, Dither}, Camera, Color, Frame, RenderOptions, Scene, Vec3};
    ///
    /// let mut scene: Scene<1, 0> = Scene::new();
    /// scene.set_background(Color::new(0.0, 0.3, 0.7))?;
    /// let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 8, 8)?;
    /// let mut storage = microray::FrameStorage::new();
    /// let frame = Frame::new(&scene, &cam, RenderOptions::default(), &mut storage)?;
    /// let mut display: MockDisplay<Rgb565> = MockDisplay::new();
    /// frame.draw_dithered(&mut display).unwrap();
    /// assert_eq!(display.get_pixel(Point::new(6, 3)), Some(dither_rgb565(frame.pixel(6, 3), 6, 3)));
    /// let mut oled: MockDisplay<BinaryColor> = MockDisplay::new();
    /// frame.draw_dithered(&mut oled).unwrap();
    /// assert_eq!(oled.get_pixel(Point::new(2, 5)), Some(BinaryColor::dither(frame.pixel(2, 5), 2, 5)));
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn draw_dithered<D>(&self, target: &mut D) -> Result<(), D::Error>
    where
        D: DrawTarget,
        D::Color: Dither,
    {
        let Some((dest, src)) = self.visible(target, &self.bounding_box(), Point::zero()) else {
            return Ok(());
        };
        let mut pixels = self.pixels(&src);
        let dithered = Dithered {
            pixels: &mut pixels,
            color: PhantomData,
        };
        target.fill_contiguous(&dest, dithered)
    }

    /// Like [`Frame::render_rows`], but ordered-dithered to the buffer's colour ([`Dither`]):
    /// the strip or row buffer of a 16-bit, grey or 1-bit display without banding.
    ///
    /// ```
    /// use embedded_graphics::pixelcolor::{Gray4, Rgb565};
    /// use microray::{output::{dither_rgb565, Dither}, Camera, Color, Frame, RenderOptions, Scene, Vec3};
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
    /// let mut grey = [Gray4::new(0); 8];
    /// frame.render_rows_dithered(1, &mut grey)?;
    /// assert_eq!(grey[3], Gray4::dither(frame.pixel(3, 1), 3, 1));
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn render_rows_dithered<C: Dither>(
        &self,
        first_row: u32,
        buf: &mut [C],
    ) -> Result<u32, Error> {
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

    /// The part of `area` (frame coordinates, drawn at `offset` on the target) that is both in
    /// the frame and on the target: the target's rectangle and the frame's, or `None` when
    /// nothing is visible. Tracing stops at the display's edge. (The caller builds the
    /// `Pixels` itself: returned through here, the large value would be copied.)
    fn visible<D: Dimensions>(
        &self,
        target: &D,
        area: &Rectangle,
        offset: Point,
    ) -> Option<(Rectangle, Rectangle)> {
        let src = area.intersection(&self.bounding_box());
        let dest = src.translate(offset).intersection(&target.bounding_box());
        if dest.is_zero_sized() {
            return None;
        }
        Some((dest, dest.translate(-offset)))
    }
}

impl<const S: usize, const L: usize> OriginDimensions for Frame<'_, S, L> {
    /// The image's size: `Image::new(&frame, point)` covers this much of the display.
    ///
    /// ```
    /// # use embedded_graphics::prelude::*;
    /// # use microray::{Camera, Frame, RenderOptions, Scene, Vec3};
    /// # let scene: Scene<1, 0> = Scene::new();
    /// let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 32, 24)?;
    /// let mut storage = microray::FrameStorage::new();
    /// let frame = Frame::new(&scene, &cam, Default::default(), &mut storage)?;
    /// assert_eq!(frame.size(), Size::new(32, 24));
    /// # Ok::<(), microray::Error>(())
    /// ```
    fn size(&self) -> Size {
        Size::new(self.width(), self.height())
    }
}

/// A frame is an image of `Rgb888` pixels, traced as it is drawn: place it with
/// `Image::new(&frame, point)`, redraw a part with `sub_image`, and draw it on a display of
/// another colour through `color_converted`. Each draw is one `fill_contiguous` over the
/// visible rectangle; pixels off the display are not traced.
///
/// ```
/// use embedded_graphics::{image::{Image, ImageDrawableExt}, mock_display::MockDisplay};
/// use embedded_graphics::{pixelcolor::{Rgb565, Rgb888}, prelude::*, primitives::Rectangle};
/// use microray::{Camera, Frame, Material, RenderOptions, Scene, Sphere, Vec3};
///
/// let mut scene: Scene<1, 0> = Scene::new();
/// scene.add_sphere(Sphere::new(Vec3::ZERO, 1.0), Material::default())?;
/// let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 16, 16)?;
/// let mut storage = microray::FrameStorage::new();
/// let frame = Frame::new(&scene, &cam, RenderOptions::default(), &mut storage)?;
///
/// // An Rgb565 panel; the frame at (40, 8), then its centre 4 × 4 redrawn at (0, 0).
/// let mut display: MockDisplay<Rgb565> = MockDisplay::new();
/// Image::new(&frame, Point::new(40, 8)).draw(&mut display.color_converted()).unwrap();
/// assert_eq!(display.get_pixel(Point::new(47, 15)), Some(frame.pixel(7, 7).into()));
/// let centre = frame.sub_image(&Rectangle::new(Point::new(6, 6), Size::new(4, 4)));
/// Image::new(&centre, Point::zero()).draw(&mut display.color_converted()).unwrap();
/// assert_eq!(display.get_pixel(Point::new(1, 2)), Some(frame.pixel(7, 8).into()));
/// # Ok::<(), microray::Error>(())
/// ```
impl<const S: usize, const L: usize> ImageDrawable for Frame<'_, S, L> {
    type Color = Rgb888;

    fn draw<D>(&self, target: &mut D) -> Result<(), D::Error>
    where
        D: DrawTarget<Color = Rgb888>,
    {
        Frame::draw(self, target)
    }

    /// `area` of the frame, drawn with its top-left corner at the target's origin (as
    /// `SubImage` asks); the part of `area` outside the frame draws nothing.
    fn draw_sub_image<D>(&self, target: &mut D, area: &Rectangle) -> Result<(), D::Error>
    where
        D: DrawTarget<Color = Rgb888>,
    {
        let Some((dest, src)) = self.visible(target, area, Point::zero() - area.top_left) else {
            return Ok(());
        };
        let mut pixels = self.pixels(&src);
        target.fill_contiguous(&dest, pixels.by_ref())
    }
}

/// The pixels of a [`Pixels`], dithered to `C` by their place in the frame.
struct Dithered<'p, 'f, 'a, const S: usize, const L: usize, C> {
    pixels: &'p mut Pixels<'f, 'a, S, L>,
    color: PhantomData<C>,
}

impl<const S: usize, const L: usize, C: Dither> Iterator for Dithered<'_, '_, '_, S, L, C> {
    type Item = C;

    #[inline]
    fn next(&mut self) -> Option<C> {
        let c = self.pixels.next()?;
        let (x, y) = self.pixels.last_position();
        Some(C::dither(c, x, y))
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        self.pixels.size_hint()
    }
}

/// [`Frame::render_rows_dithered`]'s rows from `first_row` into `buf` (whole rows of `w`
/// pixels): on hosts tile by tile, as `render_rows` traces them.
#[cfg(lanes)]
fn dither_rows<const S: usize, const L: usize, C: Dither>(
    frame: &Frame<'_, S, L>,
    first_row: u32,
    buf: &mut [C],
    (w, rows): (usize, u32),
) {
    let _ = frame.tile_rows(first_row, rows, |t| {
        let out = t.place(buf, first_row, w);
        for (k, (o, &c)) in out.iter_mut().zip(t.px).enumerate() {
            *o = C::dither(c, t.i + k as u32, t.j);
        }
        Ok::<(), core::convert::Infallible>(())
    });
}

/// [`Frame::render_rows_dithered`]'s rows from `first_row` into `buf` (whole rows of `w`
/// pixels): on Cortex-M row by row with the renderer's culling (the same pixels as `pixel`).
#[cfg(not(lanes))]
fn dither_rows<const S: usize, const L: usize, C: Dither>(
    frame: &Frame<'_, S, L>,
    first_row: u32,
    buf: &mut [C],
    (w, _rows): (usize, u32),
) {
    for (r, row) in buf.chunks_exact_mut(w).enumerate() {
        let j = first_row + r as u32;
        let mut pixels = frame.row(j);
        for (i, (px, c)) in row.iter_mut().zip(pixels.by_ref()).enumerate() {
            *px = C::dither(c, i as u32, j);
        }
    }
}
