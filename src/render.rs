//! Rendering: per-frame constants, the pixel loop, supersampling and pixel encoding.

use embedded_graphics::pixelcolor::Rgb888;

use crate::camera::Camera;
use crate::error::Error;
use crate::geometry::{Prepared, Ray};
use crate::math::{powf, Color};
use crate::scene::{make_hit, Hit, Light, Scene};
use crate::shading::{follow, in_shadow, shade_local, T_EPS};

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

/// Per-frame settings that are not part of the scene.
///
/// ```
/// use microray::{Encoding, RenderOptions};
/// let opts = RenderOptions { samples: 3, encoding: Encoding::Srgb };
/// assert_eq!(RenderOptions::default().samples, 1);
/// # let _ = opts;
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RenderOptions {
    /// Samples per pixel along each axis (1..=16): `samples²` rays per pixel.
    pub samples: u8,
    /// How pixels are encoded.
    pub encoding: Encoding,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            samples: 1,
            encoding: Encoding::Linear,
        }
    }
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
    let c = if c > 0.0 {
        if c < 1.0 {
            c
        } else {
            1.0
        }
    } else {
        0.0
    };
    let e = match encoding {
        Encoding::Linear => c,
        Encoding::Srgb => {
            if c <= 0.003_130_8 {
                12.92 * c
            } else {
                1.055 * powf(c, 1.0 / 2.4) - 0.055
            }
        }
    };
    // 0 ≤ 255e + 0.5 < 256, so truncation is floor and the cast cannot wrap.
    (255.0 * e + 0.5) as u8
}

/// A scene, a camera and options, with everything that all rays of the frame share computed
/// once: `o − m` and `|o − m|² − r²` of every sphere for the eye and for every point light.
///
/// Build it once, then render the whole image, bands of rows, single pixels, or draw onto an
/// embedded-graphics display.
///
/// ```
/// use embedded_graphics::pixelcolor::Rgb888;
/// use microray::{Camera, Color, Frame, Light, Material, RenderOptions, Scene, Sphere, Vec3};
///
/// let mut scene: Scene<4, 1> = Scene::new();
/// scene.set_ambient(Color::splat(0.1))?;
/// scene.add_sphere(Sphere::new(Vec3::ZERO, 1.0), Material::default())?;
/// scene.add_light(Light::Point { position: Vec3::new(3.0, 5.0, 4.0), intensity: Color::ONE })?;
/// let camera = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 32, 24)?;
/// let frame = Frame::new(&scene, &camera, RenderOptions::default())?;
///
/// let mut image = [Rgb888::new(0, 0, 0); 32 * 24];
/// frame.render(&mut image)?;
/// assert_eq!(image[0], Rgb888::new(0, 0, 0)); // the corner sees the black background
/// assert_ne!(image[12 * 32 + 16], Rgb888::new(0, 0, 0)); // the centre sees the sphere
/// # Ok::<(), microray::Error>(())
/// ```
#[derive(Debug)]
pub struct Frame<'a, const S: usize, const L: usize> {
    scene: &'a Scene<S, L>,
    camera: &'a Camera,
    samples: u32,
    encoding: Encoding,
    eye: heapless::Vec<Prepared, S>,
    lights: [heapless::Vec<Prepared, S>; L],
}

impl<'a, const S: usize, const L: usize> Frame<'a, S, L> {
    /// Prepares a frame; fails only for invalid options (`samples` outside 1..=16).
    ///
    /// ```
    /// # use microray::{Camera, Error, Frame, RenderOptions, Scene, Vec3};
    /// let scene: Scene<1, 0> = Scene::new();
    /// let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 4, 4)?;
    /// let bad = RenderOptions { samples: 0, ..RenderOptions::default() };
    /// assert_eq!(Frame::new(&scene, &cam, bad).err(), Some(Error::InvalidSamples));
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn new(
        scene: &'a Scene<S, L>,
        camera: &'a Camera,
        options: RenderOptions,
    ) -> Result<Self, Error> {
        if !(1..=16).contains(&options.samples) {
            return Err(Error::InvalidSamples);
        }
        let prepare = |origin| {
            let mut v = heapless::Vec::new();
            for s in scene.spheres() {
                // Capacity S, at most S spheres: cannot fail.
                let _ = v.push(Prepared::exact(origin, s));
            }
            v
        };
        let eye = prepare(camera.eye());
        let lights = core::array::from_fn(|i| match scene.lights().get(i) {
            Some(Light::Point { position, .. }) if scene.shadows() => prepare(*position),
            _ => heapless::Vec::new(),
        });
        Ok(Frame {
            scene,
            camera,
            samples: options.samples as u32,
            encoding: options.encoding,
            eye,
            lights,
        })
    }

    /// Image width in pixels.
    ///
    /// ```
    /// # use microray::{Camera, Frame, RenderOptions, Scene, Vec3};
    /// # let scene: Scene<1, 0> = Scene::new();
    /// # let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 4, 3)?;
    /// let frame = Frame::new(&scene, &cam, RenderOptions::default())?;
    /// assert_eq!((frame.width(), frame.height()), (4, 3));
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn width(&self) -> u32 {
        self.camera.width()
    }

    /// Image height in pixels.
    ///
    /// ```
    /// # use microray::{Camera, Frame, RenderOptions, Scene, Vec3};
    /// # let scene: Scene<1, 0> = Scene::new();
    /// # let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 4, 3)?;
    /// let frame = Frame::new(&scene, &cam, RenderOptions::default())?;
    /// assert_eq!(frame.height(), 3);
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn height(&self) -> u32 {
        self.camera.height()
    }

    /// The closest hit of a primary ray (one that starts at the eye).
    #[inline]
    fn primary_hit(&self, ray: &Ray) -> Option<Hit> {
        let mut best: Option<(f32, usize)> = None;
        let mut tmax = f32::INFINITY;
        for (i, k) in self.eye.iter().enumerate() {
            if let Some(t) = k.hit(ray.dir, T_EPS, tmax) {
                tmax = t;
                best = Some((t, i));
            }
        }
        // `get`, not `[i]`: the compiler cannot prove i in bounds and would link a panic.
        let (t, i) = best?;
        let k = self.eye.get(i)?;
        let sphere = self.scene.spheres().get(i)?;
        Some(make_hit(ray, t, i, k.f, sphere))
    }

    /// The linear colour seen along a primary ray from the eye.
    ///
    /// ```
    /// # use microray::{Camera, Color, Frame, RenderOptions, Scene, Vec3};
    /// let mut scene: Scene<1, 0> = Scene::new();
    /// scene.set_background(Color::splat(0.3))?;
    /// let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 4, 4)?;
    /// let frame = Frame::new(&scene, &cam, RenderOptions::default())?;
    /// assert_eq!(frame.trace(&cam.ray(2.0, 2.0)), Color::splat(0.3));
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn trace(&self, ray: &Ray) -> Color {
        let scene = self.scene;
        let first = self.primary_hit(ray);
        follow(scene, ray, first, |hit, ray| {
            shade_local(scene, hit, ray.dir, |i| {
                // `get`, not `[i]`: i < lights().len() ≤ L always, but the compiler cannot prove
                // it and would link a bounds-check panic into the render path.
                scene.shadows()
                    && scene.lights().get(i).is_some_and(|light| {
                        let consts = match light {
                            Light::Point { .. } => self.lights.get(i).map(|v| &v[..]),
                            Light::Directional { .. } => None,
                        };
                        in_shadow(scene, hit, light, consts)
                    })
            })
        })
    }

    /// The linear colour of pixel `(i, j)`: the average of its `samples²` rays, unclamped.
    ///
    /// ```
    /// # use microray::{Camera, Color, Frame, RenderOptions, Scene, Vec3};
    /// let mut scene: Scene<1, 0> = Scene::new();
    /// scene.set_background(Color::splat(2.0))?;
    /// let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 4, 4)?;
    /// let frame = Frame::new(&scene, &cam, RenderOptions { samples: 2, ..Default::default() })?;
    /// assert_eq!(frame.pixel_color(0, 0), Color::splat(2.0));
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn pixel_color(&self, i: u32, j: u32) -> Color {
        let n = self.samples;
        if n == 1 {
            return self.trace(&self.camera.view_ray(i, j, 0, 0, 1));
        }
        let mut sum = Color::ZERO;
        for sy in 0..n {
            for sx in 0..n {
                sum += self.trace(&self.camera.view_ray(i, j, sx, sy, n));
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
    /// let frame = Frame::new(&scene, &cam, RenderOptions::default())?;
    /// assert_eq!(frame.pixel(3, 3), Rgb888::new(255, 128, 0));
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn pixel(&self, i: u32, j: u32) -> Rgb888 {
        let c = self.pixel_color(i, j);
        let e = self.encoding;
        Rgb888::new(
            encode_channel(c.x, e),
            encode_channel(c.y, e),
            encode_channel(c.z, e),
        )
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
    /// let frame = Frame::new(&scene, &cam, RenderOptions::default())?;
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
        let w = self.width() as usize;
        let rows = buf.len() / w;
        if buf.len() % w != 0 || first_row as usize + rows > self.height() as usize {
            return Err(Error::BufferSize);
        }
        for (r, row) in buf.chunks_exact_mut(w).enumerate() {
            let j = first_row + r as u32;
            for (i, px) in row.iter_mut().enumerate() {
                *px = self.pixel(i as u32, j).into();
            }
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
    /// let frame = Frame::new(&scene, &cam, RenderOptions::default())?;
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
