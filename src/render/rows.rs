//! Pixels, rows and bands: the public render calls, the pixel loop, the row iterator, and the
//! brute-force reference path. Each render path (`lanes/`, `scalar.rs`) fills its rows its own
//! way (`rows_into`; hosts in tiles).

use embedded_graphics::prelude::{Point, Size};
use embedded_graphics::primitives::Rectangle;

use super::*;

impl<'a, const S: usize, const L: usize> Frame<'a, S, L> {
    /// The linear colour seen along a primary ray from the eye, tested against every sphere:
    /// the brute-force reference of the renderer (it takes any ray, so no screen box applies).
    ///
    /// ```
    /// # use microray::{Camera, Color, Frame, RenderOptions, Scene, Vec3};
    /// let mut scene: Scene<1, 0> = Scene::new();
    /// scene.set_background(Color::splat(0.3))?;
    /// let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 4, 4)?;
    /// let mut storage = microray::FrameStorage::new();
    /// let frame = Frame::new(&scene, &cam, RenderOptions::default(), &mut storage)?;
    /// assert_eq!(frame.trace(&cam.ray(2.0, 2.0)), Color::splat(0.3));
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn trace(&self, ray: &Ray) -> Color {
        self.shade_from(ray, self.primary_hit(ray), None)
    }

    /// The linear colour of pixel `(i, j)`: the average of its `samples²` rays, unclamped.
    /// Primary rays test only the spheres whose screen box holds the pixel; shadow rays test
    /// every sphere (use [`Frame::render_rows`] for whole rows, which culls those too).
    ///
    /// ```
    /// # use microray::{Camera, Color, Frame, RenderOptions, Scene, Vec3};
    /// let mut scene: Scene<1, 0> = Scene::new();
    /// scene.set_background(Color::splat(2.0))?;
    /// let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 4, 4)?;
    /// let mut storage = microray::FrameStorage::new();
    /// let frame = Frame::new(&scene, &cam, RenderOptions { samples: 2, ..Default::default() }, &mut storage)?;
    /// assert_eq!(frame.pixel_color(0, 0), Color::splat(2.0));
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn pixel_color(&self, i: u32, j: u32) -> Color {
        let mut cands: List<S> = heapless::Vec::new();
        for (s, b) in self.tables.boxes.iter().enumerate() {
            if b.contains(i, j) {
                let _ = cands.push(SphereId::new(s));
            }
        }
        self.average(i, j, |ray| {
            self.shade_from(ray, self.primary_hit_among(ray, i, &cands), None)
        })
    }

    /// [`Frame::pixel_color`] the brute-force way: every ray against every sphere. The
    /// reference that the accelerated paths must equal bit for bit.
    ///
    /// ```
    /// # use microray::{Camera, Color, Frame, Material, RenderOptions, Scene, Sphere, Vec3};
    /// let mut scene: Scene<1, 0> = Scene::new();
    /// scene.add_sphere(Sphere::new(Vec3::ZERO, 1.0), Material::default())?;
    /// let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 8, 8)?;
    /// let mut storage = microray::FrameStorage::new();
    /// let frame = Frame::new(&scene, &cam, RenderOptions::default(), &mut storage)?;
    /// assert_eq!(frame.pixel_color_brute(4, 4), frame.pixel_color(4, 4));
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn pixel_color_brute(&self, i: u32, j: u32) -> Color {
        self.average(i, j, |ray| {
            let first = self.primary_hit(ray);
            // A constant test first: a capacity of 8 or less has no hierarchy, and links no
            // second copy of the shading.
            if self.culled().is_some() {
                return self.shade_brute(ray, first);
            }
            self.shade_from(ray, first, None)
        })
    }

    /// The average over the pixel's `samples²` rays of `f(ray)` (with one sample, `f(ray)`
    /// itself). `f` is called from one place, so it is inlined once.
    #[inline]
    pub(super) fn average(&self, i: u32, j: u32, mut f: impl FnMut(&Ray) -> Color) -> Color {
        let n = self.samples;
        let mut sum = Color::ZERO;
        for sy in 0..n {
            for sx in 0..n {
                let c = f(&self.camera.primary_ray(i, j, sx, sy, n));
                if n == 1 {
                    return c;
                }
                sum += c;
            }
        }
        sum / (n * n) as f32
    }

    /// The encoded colour of pixel `(i, j)` (row 0 at the top).
    ///
    /// ```
    /// # use embedded_graphics::pixelcolor::Rgb888;
    /// # use microray::{Camera, Color, Frame, RenderOptions, Scene, Vec3};
    /// let mut scene: Scene<1, 0> = Scene::new();
    /// scene.set_background(Color::new(1.0, 0.5, 0.0))?;
    /// let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 4, 4)?;
    /// let mut storage = microray::FrameStorage::new();
    /// let frame = Frame::new(&scene, &cam, RenderOptions::default(), &mut storage)?;
    /// assert_eq!(frame.pixel(3, 3), Rgb888::new(255, 128, 0));
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn pixel(&self, i: u32, j: u32) -> Rgb888 {
        self.encode(self.pixel_color(i, j))
    }

    /// The pixels of row `j`, left to right, traced span by span with every culling of
    /// [`Frame::render_rows`]; for displays that consume a row as an iterator. Rows past the
    /// image yield nothing.
    ///
    /// ```
    /// # use embedded_graphics::pixelcolor::Rgb888;
    /// # use microray::{Camera, Color, Frame, RenderOptions, Scene, Vec3};
    /// let mut scene: Scene<1, 0> = Scene::new();
    /// scene.set_background(Color::new(1.0, 0.5, 0.0))?;
    /// let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 4, 4)?;
    /// let mut storage = microray::FrameStorage::new();
    /// let frame = Frame::new(&scene, &cam, RenderOptions::default(), &mut storage)?;
    /// assert!(frame.row(1).all(|p| p == Rgb888::new(255, 128, 0)));
    /// assert_eq!(frame.row(1).count(), 4);
    /// assert_eq!(frame.row(4).count(), 0);
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn row(&self, j: u32) -> Pixels<'_, 'a, S, L> {
        self.pixels(&Rectangle::new(
            Point::new(0, j as i32),
            Size::new(self.width(), 1),
        ))
    }

    /// The pixels of `area` (clipped to the image), row by row from the top, each row left to
    /// right, traced as [`Frame::row`] traces them: what a display's `fill_contiguous` over
    /// that rectangle consumes. Each pixel equals [`Frame::pixel`]'s, bit for bit.
    ///
    /// ```
    /// # use embedded_graphics::{prelude::*, primitives::Rectangle};
    /// # use microray::{Camera, Frame, Material, RenderOptions, Scene, Sphere, Vec3};
    /// let mut scene: Scene<1, 0> = Scene::new();
    /// scene.add_sphere(Sphere::new(Vec3::ZERO, 1.0), Material::default())?;
    /// let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 16, 16)?;
    /// let mut storage = microray::FrameStorage::new();
    /// let frame = Frame::new(&scene, &cam, RenderOptions::default(), &mut storage)?;
    /// let area = Rectangle::new(Point::new(6, 5), Size::new(4, 3));
    /// let mut pixels = frame.pixels(&area);
    /// assert_eq!(pixels.len(), 12);
    /// for p in area.points() {
    ///     assert_eq!(pixels.next(), Some(frame.pixel(p.x as u32, p.y as u32)));
    /// }
    /// // Clipped to the image: only the 2 × 2 pixels of the corner are inside.
    /// assert_eq!(frame.pixels(&Rectangle::new(Point::new(14, -3), Size::new(9, 5))).count(), 4);
    /// # Ok::<(), microray::Error>(())
    /// ```
    // Out of line: whatever temporary the compiler builds the `Pixels` in stays in this frame,
    // which is gone before a row is traced (a caller's frame would keep it).
    #[inline(never)]
    pub fn pixels(&self, area: &Rectangle) -> Pixels<'_, 'a, S, L> {
        // Clipped in i64: a rectangle may start anywhere in i32 and reach past it.
        let clip = |start: i32, len: u32, n: u32| {
            let a = (start as i64).clamp(0, n as i64) as u32;
            let b = (start as i64 + len as i64).clamp(0, n as i64) as u32;
            (a, b.max(a))
        };
        let (i0, i1) = clip(area.top_left.x, area.size.width, self.width());
        let (j0, j1) = clip(area.top_left.y, area.size.height, self.height());
        // The row's lists are made by its first pixel: the `Pixels` is built in place, never
        // moved with them filled in (it is large, microcontroller stacks are small).
        Pixels {
            frame: self,
            i0,
            i1,
            step: 1,
            next_row: if i0 < i1 { j0 } else { j1 },
            end_row: j1,
            j: j0,
            i: i1,
            cull: Cull::new(),
        }
    }

    /// Starts row `j`: its spheres are those whose box crosses it, in scene order.
    pub(super) fn start_row(&self, j: u32, cull: &mut Cull<S, L>) {
        cull.spheres.row.clear();
        cull.spheres.sorted = false;
        for (s, b) in self.tables.boxes.iter().enumerate() {
            if b.has_row(j) {
                let _ = cull.spheres.row.push(SphereId::new(s));
            }
        }
        self.index_row(cull);
        self.start_miss(cull);
    }

    /// The rest of starting rows: no span yet, and the pixel of every ray that misses.
    #[inline(always)]
    pub(super) fn start_miss(&self, cull: &mut Cull<S, L>) {
        cull.span_end = 0;
        // A miss shows the background, whatever its ray: one pixel for all of them. Shaded
        // here, on the render path's stack, rather than in `Frame::new` (set-up's).
        let nowhere = Ray::new(self.camera.eye(), Vec3::ZERO);
        cull.miss = self.encode(self.shade_from(&nowhere, None, None));
    }

    /// The pixel `(i, j)` of row `j`, pixels taken in order from `i = 0` (which starts the
    /// row with [`Frame::start_row`]): the Cortex-M path's `render_rows`.
    #[cfg(not(lanes))]
    #[inline]
    pub(super) fn next_pixel(&self, j: u32, i: u32, cull: &mut Cull<S, L>) -> Rgb888 {
        if i == 0 {
            self.start_row(j, cull);
        }
        self.row_pixel(j, i, cull)
    }

    /// The pixel `(i, j)` of the row started in `cull`, pixels taken in order from any
    /// column: a span starts wherever the last one ended.
    #[inline(always)]
    pub(super) fn row_pixel(&self, j: u32, i: u32, cull: &mut Cull<S, L>) -> Rgb888 {
        if i >= cull.span_end {
            self.start_span(j, i, cull);
        }
        self.span_output(j, i, cull)
    }

    /// Starts the span of row `j` at column `i`: its candidates, hits and bounds
    /// ([`Frame::gather`]), and on hosts all its pixels ([`Frame::fill_span`]).
    #[inline(always)]
    pub(super) fn start_span(&self, j: u32, i: u32, cull: &mut Cull<S, L>) {
        cull.span_start = i;
        cull.span_end = (i + SPAN as u32).min(self.width());
        self.gather(j, cull);
        self.span_gathered(j, cull);
    }

    /// Pixel `(i, j)` of the span gathered in `cull`, shaded on its own.
    #[inline(always)]
    pub(super) fn span_pixel(&self, j: u32, i: u32, cull: &Cull<S, L>) -> Rgb888 {
        let c = if cull.hits.kept == Kept::Pixels {
            let k = cull.slot((i - cull.span_start) as usize);
            // A miss: the pixel `start_row` shaded for all of them (gather built no ray).
            let Some((t, s)) = cull.hit(k) else {
                return cull.miss;
            };
            let dir = match cull.dir(k) {
                Some(dir) => dir,
                None => self.camera.primary_ray(i, j, 0, 0, 1).dir,
            };
            let ray = Ray::new(self.camera.eye(), dir);
            // The scalar path's speed builds build the hit record where they shade it; hosts
            // and size builds go on below.
            if INLINE_SHADING {
                return self.shade_stored(&ray, t, s.index(), cull.lists_at(k));
            }
            // The hit record from (t, sphere): `make_hit` is a pure function of them. Its ray
            // built anew from the values, not read back from `ray`, which shading takes by
            // address: the direction and eye stay in registers, not copied out of memory.
            let first = if KEEPS_OFFSETS && SPHERE_MAJOR {
                self.kept_hit(&ray, t, s.index(), k, cull)
            } else {
                self.eye_hit(&Ray::new(self.camera.eye(), dir), t, s.index())
            };
            self.shade_from(&ray, first, cull.lists_at(k))
        } else if KEPT > 1 && cull.hits.kept == Kept::Samples {
            let k = (i - cull.span_start) as usize;
            // `average`'s sum, in its order, of the samples' kept hits (slot `m·SPAN + k`).
            let n = self.samples;
            let mut sum = Color::ZERO;
            for m in 0..n * n {
                let slot = m as usize * SPAN + k;
                sum += match cull.hit(slot) {
                    Some(h) => self.shade_kept(i, j, slot, h, cull),
                    // What `shade_from` gives a ray that hits nothing.
                    None => self.scene.background(),
                };
            }
            sum / (n * n) as f32
        } else {
            self.average(i, j, |ray| {
                let hit = self.primary_hit_among(ray, i, &cull.spheres.span);
                let lists = hit.as_ref().and_then(|h| cull.lists(h.sphere));
                self.shade_from(ray, hit, lists)
            })
        };
        self.encode(c)
    }

    /// Renders rows `first_row ..` into `buf`, which holds a whole number of rows; returns how
    /// many rows it rendered. This is how a microcontroller without room for a framebuffer
    /// streams an image, and how the desktop renderer splits a frame between threads.
    ///
    /// ```
    /// # use embedded_graphics::pixelcolor::{Rgb565, Rgb888};
    /// # use microray::{Camera, Color, Error, Frame, RenderOptions, Scene, Vec3};
    /// # let mut scene: Scene<1, 0> = Scene::new();
    /// # scene.set_background(Color::new(1.0, 0.0, 0.0))?;
    /// let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 8, 6)?;
    /// let mut storage = microray::FrameStorage::new();
    /// let frame = Frame::new(&scene, &cam, RenderOptions::default(), &mut storage)?;
    /// let mut band = [Rgb565::new(0, 0, 0); 2 * 8]; // two rows, straight into a display format
    /// for first in (0..6).step_by(2) {
    ///     assert_eq!(frame.render_rows(first, &mut band)?, 2);
    ///     // ... send `band` to the display ...
    /// }
    /// assert_eq!(band[0], Rgb565::new(31, 0, 0));
    /// assert_eq!(frame.render_rows(5, &mut band), Err(Error::BufferSize)); // only 1 row left
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn render_rows<C: From<Rgb888>>(
        &self,
        first_row: u32,
        buf: &mut [C],
    ) -> Result<u32, Error> {
        let rows = self.check_rows(first_row, buf.len())?;
        self.rows_into(first_row, rows, buf);
        Ok(rows)
    }

    /// [`Frame::render_rows`] the brute-force way, every ray against every sphere: the
    /// reference for tests and benchmarks.
    ///
    /// ```
    /// # use embedded_graphics::pixelcolor::Rgb888;
    /// # use microray::{Camera, Frame, Material, RenderOptions, Scene, Sphere, Vec3};
    /// let mut scene: Scene<1, 0> = Scene::new();
    /// scene.add_sphere(Sphere::new(Vec3::ZERO, 1.0), Material::default())?;
    /// let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 8, 8)?;
    /// let mut storage = microray::FrameStorage::new();
    /// let frame = Frame::new(&scene, &cam, RenderOptions::default(), &mut storage)?;
    /// let (mut a, mut b) = ([Rgb888::new(0, 0, 0); 64], [Rgb888::new(0, 0, 0); 64]);
    /// frame.render_rows(0, &mut a)?;
    /// frame.render_rows_brute(0, &mut b)?;
    /// assert_eq!(a, b);
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn render_rows_brute<C: From<Rgb888>>(
        &self,
        first_row: u32,
        buf: &mut [C],
    ) -> Result<u32, Error> {
        let rows = self.check_rows(first_row, buf.len())?;
        let w = self.width() as usize;
        for (r, row) in buf.chunks_exact_mut(w).enumerate() {
            let j = first_row + r as u32;
            for (i, px) in row.iter_mut().enumerate() {
                *px = self.encode(self.pixel_color_brute(i as u32, j)).into();
            }
        }
        Ok(rows)
    }

    /// How many rows a buffer of `len` pixels holds, if whole rows inside the image.
    pub(super) fn check_rows(&self, first_row: u32, len: usize) -> Result<u32, Error> {
        let w = self.width() as usize; // ≥ 1 (Camera checks); checked_div links no panic
        let (Some(rows), Some(0)) = (len.checked_div(w), len.checked_rem(w)) else {
            return Err(Error::BufferSize);
        };
        if first_row as usize + rows > self.height() as usize {
            return Err(Error::BufferSize);
        }
        Ok(rows as u32)
    }

    /// Renders the whole image into `buf` (`width × height` pixels, row by row from the top).
    ///
    /// ```
    /// # use embedded_graphics::pixelcolor::Rgb888;
    /// # use microray::{Camera, Error, Frame, RenderOptions, Scene, Vec3};
    /// # let scene: Scene<1, 0> = Scene::new();
    /// let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 4, 3)?;
    /// let mut storage = microray::FrameStorage::new();
    /// let frame = Frame::new(&scene, &cam, RenderOptions::default(), &mut storage)?;
    /// let mut too_small = [Rgb888::new(0, 0, 0); 4 * 2];
    /// assert_eq!(frame.render(&mut too_small), Err(Error::BufferSize));
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn render<C: From<Rgb888>>(&self, buf: &mut [C]) -> Result<(), Error> {
        if buf.len() != self.width() as usize * self.height() as usize {
            return Err(Error::BufferSize);
        }
        self.render_rows(0, buf).map(|_| ())
    }
}

/// The pixels of a rectangle of the image, row by row from the top, traced span by span (see
/// [`Frame::pixels`] and [`Frame::row`]).
#[derive(Debug)]
pub struct Pixels<'f, 'a, const S: usize, const L: usize> {
    pub(super) frame: &'f Frame<'a, S, L>,
    /// The columns `i0..i1`, every `step`-th.
    i0: u32,
    i1: u32,
    step: u32,
    /// The rows still to start, `next_row..end_row`.
    next_row: u32,
    end_row: u32,
    /// The row being traced, and its next column (`i1` once done).
    j: u32,
    i: u32,
    pub(super) cull: Cull<S, L>,
}

impl<const S: usize, const L: usize> Pixels<'_, '_, S, L> {
    /// Column and row of the pixel that `next` returned last (meaningless before the first).
    #[inline]
    pub(crate) fn last_position(&self) -> (u32, u32) {
        (self.i.wrapping_sub(self.step), self.j)
    }

    /// From now on every `step`-th pixel of each row (`step` ≥ 1; set before the first
    /// `next`), each traced with the row's culling: every span they fall in is gathered whole
    /// (its primary rays, hit groups and shadow lists), so a small `step` costs little beyond
    /// the pixels themselves. (Set on a `Pixels` already built, not passed to a constructor
    /// of its own: one place builds the large value in place.)
    #[inline]
    pub(crate) fn set_step(&mut self, step: u32) {
        self.step = step.max(1);
    }

    /// Starts the next row; false when none is left.
    #[cold]
    fn start_next_row(&mut self) -> bool {
        if self.next_row >= self.end_row {
            return false;
        }
        (self.j, self.i) = (self.next_row, self.i0);
        self.next_row += 1;
        self.frame.start_row(self.j, &mut self.cull);
        true
    }
}

impl<const S: usize, const L: usize> Iterator for Pixels<'_, '_, S, L> {
    type Item = Rgb888;

    // Out of line: the row's whole pixel pipeline, which displays reach through adapters
    // (`by_ref`, `map`); one copy of it, whatever wraps the pixels.
    #[inline(never)]
    fn next(&mut self) -> Option<Rgb888> {
        if self.i >= self.i1 && !self.start_next_row() {
            return None;
        }
        let px = self.frame.row_pixel(self.j, self.i, &mut self.cull);
        self.i += self.step;
        Some(px)
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        // `step` ≥ 1; `checked_div` links no panic. `i` may pass `i1` by less than a step.
        let step = self.step as usize;
        let count = |n: u32| (n as usize + step - 1).checked_div(step).unwrap_or(0);
        let rows = (self.end_row - self.next_row) as usize;
        let n = count(self.i1.saturating_sub(self.i)) + rows * count(self.i1 - self.i0);
        (n, Some(n))
    }
}

impl<const S: usize, const L: usize> ExactSizeIterator for Pixels<'_, '_, S, L> {}
