//! Progressive drawing for slow chips: a coarse image after 1/64 of the work, refined in four
//! interlaced passes to the exact final image, with a callback to show progress or stop.
//!
//! Pass `p` works on a grid of step `b = 8 >> p` (8, 4, 2, 1 pixels). Its samples are the grid
//! points that no earlier pass traced (pass 0: all of them; then the points with an odd
//! multiple of `b` in a coordinate), and each is drawn as the `b × b` block below and right of
//! it. A block never covers a point of a coarser grid, so every pixel ends with its own traced
//! colour: the last image is [`Frame::draw`]'s, bit for bit, and every pixel is traced once.
//! The work per pass is 1/64, 3/64, 12/64 and 48/64 of the frame's.
//!
//! How a row of samples is traced depends on how far apart they are: a row of new pixels is
//! streamed as `draw` streams it; samples 2 or 4 apart go through the same pipeline with a
//! step (`Pixels::set_step`), whose spans are gathered whole, so their shadow rays get the
//! span's lists, at the cost of primary rays for the skipped columns; samples 8
//! apart are traced one at a time (`Frame::pixel`: primary rays culled by the boxes, shadow rays
//! against every sphere), where a whole span would cost more than it saves.

use core::ops::ControlFlow;

use embedded_graphics::pixelcolor::Rgb888;
use embedded_graphics::prelude::{DrawTarget, Point, Size};
use embedded_graphics::primitives::Rectangle;

use crate::render::Frame;

/// The widest step between samples that are traced as a row is (a span gathered whole for
/// them); sparser ones are traced one by one. Of 2, 4 and 8, 4 takes the fewest M4F
/// instructions.
const STRIDED: u32 = 4;

/// How far [`Frame::draw_progressive`] has come; its callback gets one after every row of
/// samples.
///
/// ```
/// use microray::output::Progress;
/// let p = Progress { pass: 1, traced: 300, total: 1200 };
/// assert_eq!(p.block(), 4);
/// assert_eq!(p.percent(), 25);
/// assert!(!p.is_complete());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Progress {
    /// The pass, `0..Progress::PASSES`: the pass draws blocks of [`Progress::block`] pixels.
    pub pass: u8,
    /// Pixels traced so far.
    pub traced: u32,
    /// Pixels in the frame: the image is final when all are traced.
    pub total: u32,
}

impl Progress {
    /// The number of passes: blocks of 8, 4, 2 and 1 pixels.
    pub const PASSES: u8 = 4;

    /// The side of the blocks that this pass draws.
    ///
    /// ```
    /// # use microray::output::Progress;
    /// assert_eq!(Progress { pass: 3, traced: 0, total: 1 }.block(), 1);
    /// ```
    pub fn block(&self) -> u32 {
        8 >> (self.pass & 3)
    }

    /// Whether every pixel is traced: the image on the display is the final one.
    ///
    /// ```
    /// # use microray::output::Progress;
    /// assert!(Progress { pass: 3, traced: 64, total: 64 }.is_complete());
    /// ```
    pub fn is_complete(&self) -> bool {
        self.traced >= self.total
    }

    /// The share of pixels traced, in whole percent (rounded down): for a progress bar.
    ///
    /// ```
    /// # use microray::output::Progress;
    /// assert_eq!(Progress { pass: 0, traced: 1, total: 3 }.percent(), 33);
    /// ```
    pub fn percent(&self) -> u8 {
        // u64: 100 × a frame of up to 2²⁸ pixels.
        (self.traced as u64 * 100)
            .checked_div(self.total as u64)
            .unwrap_or(100)
            .min(100) as u8
    }
}

impl<const S: usize, const L: usize> Frame<'_, S, L> {
    /// Draws the frame progressively, for chips that take seconds a frame: a coarse image of
    /// 8 × 8 blocks after 1/64 of the work, then 4 × 4 (3/64 more), 2 × 2 (12/64) and single
    /// pixels (48/64). Each pass traces only the pixels it adds, each drawn as the block below
    /// and right of it, and the last image is [`Frame::draw`]'s, bit for bit.
    /// Blocks go to the display with `fill_solid`; rows whose every pixel is new, with one
    /// `fill_contiguous` each. No buffer: a traced pixel is drawn at once.
    ///
    /// `progress` is called after every row of samples with the display (to draw a bar in a
    /// corner, say) and a [`Progress`]; returning `ControlFlow::Break(())` stops the drawing
    /// there. Returns the last progress: complete, or where it stopped.
    ///
    /// ```
    /// use core::ops::ControlFlow;
    /// use embedded_graphics::{mock_display::MockDisplay, pixelcolor::Rgb565, prelude::Point};
    /// use microray::{Camera, Frame, Material, RenderOptions, Scene, Sphere, Vec3};
    ///
    /// let mut scene: Scene<1, 0> = Scene::new();
    /// scene.add_sphere(Sphere::new(Vec3::ZERO, 1.0), Material::default())?;
    /// let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 16, 16)?;
    /// let mut storage = microray::FrameStorage::new();
    /// let frame = Frame::new(&scene, &cam, RenderOptions::default(), &mut storage)?;
    ///
    /// // Stop after the first, coarsest pass: 2 × 2 samples, each an 8 × 8 block.
    /// let mut display: MockDisplay<Rgb565> = MockDisplay::new();
    /// display.set_allow_overdraw(true);
    /// let p = frame.draw_progressive(&mut display, |_, p| {
    ///     if p.pass == 0 { ControlFlow::Continue(()) } else { ControlFlow::Break(()) }
    /// }).unwrap();
    /// assert_eq!((p.traced, p.is_complete()), (4 + 2, false)); // stopped after pass 1's first row
    /// assert_eq!(display.get_pixel(Point::new(7, 7)), Some(frame.pixel(0, 0).into()));
    ///
    /// // Run to the end: the final image.
    /// let p = frame.draw_progressive(&mut display, |_, _| ControlFlow::Continue(())).unwrap();
    /// assert!(p.is_complete());
    /// assert_eq!(display.get_pixel(Point::new(7, 7)), Some(frame.pixel(7, 7).into()));
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn draw_progressive<D, F>(
        &self,
        target: &mut D,
        mut progress: F,
    ) -> Result<Progress, D::Error>
    where
        D: DrawTarget,
        D::Color: From<Rgb888>,
        F: FnMut(&mut D, Progress) -> ControlFlow<()>,
    {
        let (w, h) = (self.width(), self.height());
        let mut p = Progress {
            pass: 0,
            traced: 0,
            total: w * h,
        };
        for pass in 0..Progress::PASSES {
            p.pass = pass;
            let b = p.block();
            let mut j = 0;
            while j < h {
                // A row on the last pass's grid has that grid's points: only the odd ones are new.
                let (first, step) = if pass > 0 && j & (2 * b - 1) == 0 {
                    (b, 2 * b)
                } else {
                    (0, b)
                };
                if step == 1 {
                    // Every pixel of the row is new: streamed as `draw` streams it, culled.
                    self.stream_row(target, j)?;
                    p.traced += w;
                } else {
                    p.traced += if step <= STRIDED {
                        // Samples close together: traced as a row, spans gathered whole.
                        self.sample_row(target, (j, b), (first, step))?
                    } else {
                        // Sparse samples: one at a time, primary rays culled by the boxes.
                        self.sparse_row(target, (j, b), (first, step))?
                    };
                }
                if progress(target, p).is_break() {
                    return Ok(p);
                }
                j += b;
            }
        }
        Ok(p)
    }

    /// The samples `first, first + step, …` of row `j`, each drawn as its `b × b` block;
    /// returns how many. Out of line, as `stream_row`.
    #[inline(never)]
    fn sample_row<D>(
        &self,
        target: &mut D,
        (j, b): (u32, u32),
        (first, step): (u32, u32),
    ) -> Result<u32, D::Error>
    where
        D: DrawTarget,
        D::Color: From<Rgb888>,
    {
        let row = Rectangle::new(
            Point::new(first as i32, j as i32),
            Size::new(self.width().saturating_sub(first), 1),
        );
        let mut samples = self.pixels(&row);
        samples.set_step(step);
        let mut n = 0;
        while let Some(c) = samples.next() {
            let (i, _) = samples.last_position();
            target.fill_solid(&self.block(i, j, b), c.into())?;
            n += 1;
        }
        Ok(n)
    }

    /// [`Frame::sample_row`] one pixel at a time. Out of line too: `Frame::pixel`'s frame
    /// (its candidate list, the shading) is on the stack only while it traces.
    #[inline(never)]
    fn sparse_row<D>(
        &self,
        target: &mut D,
        (j, b): (u32, u32),
        (first, step): (u32, u32),
    ) -> Result<u32, D::Error>
    where
        D: DrawTarget,
        D::Color: From<Rgb888>,
    {
        let (mut i, mut n) = (first, 0);
        while i < self.width() {
            target.fill_solid(&self.block(i, j, b), self.pixel(i, j).into())?;
            (i, n) = (i + step, n + 1);
        }
        Ok(n)
    }

    /// The `b × b` block at `(i, j)`, clipped to the frame.
    fn block(&self, i: u32, j: u32, b: u32) -> Rectangle {
        let size = Size::new(b.min(self.width() - i), b.min(self.height() - j));
        Rectangle::new(Point::new(i as i32, j as i32), size)
    }

    /// Row `j` to the display in one `fill_contiguous`. Out of line: its `Pixels` (the row's
    /// lists) is on the stack only while the row is traced, never beside `row_samples`' own.
    #[inline(never)]
    fn stream_row<D>(&self, target: &mut D, j: u32) -> Result<(), D::Error>
    where
        D: DrawTarget,
        D::Color: From<Rgb888>,
    {
        let row = Rectangle::new(Point::new(0, j as i32), Size::new(self.width(), 1));
        let mut pixels = self.row(j);
        target.fill_contiguous(&row, pixels.by_ref().map(Into::into))
    }
}
