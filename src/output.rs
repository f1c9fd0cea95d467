//! Outputs: drawing a frame onto any embedded-graphics display.

use embedded_graphics::pixelcolor::Rgb888;
use embedded_graphics::prelude::{DrawTarget, Point, Size};
use embedded_graphics::primitives::Rectangle;

use crate::render::Frame;

impl<const S: usize, const L: usize> Frame<'_, S, L> {
    /// Draws the frame onto an embedded-graphics display (or any [`DrawTarget`]) whose colour
    /// converts from [`Rgb888`], such as an `Rgb565` panel. Each row is traced as the display
    /// consumes it through `fill_contiguous`: no frame or row buffer is needed.
    ///
    /// ```
    /// use embedded_graphics::{mock_display::MockDisplay, pixelcolor::Rgb565};
    /// use microray::{Camera, Color, Frame, RenderOptions, Scene, Vec3};
    ///
    /// let mut scene: Scene<1, 0> = Scene::new();
    /// scene.set_background(Color::new(0.0, 0.0, 1.0))?;
    /// let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 8, 8)?;
    /// let frame = Frame::new(&scene, &cam, RenderOptions::default())?;
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
            target.fill_contiguous(&row, self.row(j).map(Into::into))?;
        }
        Ok(())
    }
}
