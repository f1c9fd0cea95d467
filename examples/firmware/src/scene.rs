//! The firmware's benchmark scene and its checksums, shared word for word by the firmware
//! (`src/main.rs`) and the host test (`tests/firmware.rs`, through `#[path = ...]`), so the two
//! cannot drift apart: if the host and the microcontroller compute the same pixels, they print the
//! same CRC-32.
//!
//! Everything here is `no_std`, heap-free and panic-free; the frame is never stored: pixels are
//! folded into a CRC-32 as a display would consume them.

use embedded_graphics::pixelcolor::{Rgb565, Rgb888, RgbColor};
use embedded_graphics::prelude::{
    Dimensions, DrawTarget, IntoStorage, OriginDimensions, Pixel, PointsIter, Size,
};
use embedded_graphics::primitives::Rectangle;
use microray::{Camera, Color, Error, Frame, Light, Material, RenderOptions, Scene, Sphere, Vec3};

/// Image width in pixels (both boards).
pub const WIDTH: u32 = 320;
/// Image height in pixels (both boards).
pub const HEIGHT: u32 = 240;
/// Rows in the `Rgb565` strip buffer: one row, the only frame memory the firmware has.
pub const STRIP_ROWS: usize = 1;
/// Sphere capacity: the ground and four spheres.
pub const SPHERES: usize = 5;
/// Light capacity: one point and one directional light.
pub const LIGHTS: usize = 2;

/// CRC-32 of the `Rgb888` frame (bytes r, g, b per pixel, rows from the top), as the firmware
/// prints it on both boards and the host test computes it.
pub const EXPECTED_CRC32: u32 = 0x5732a37f;
/// CRC-32 of the ordered-dithered `Rgb565` frame (each pixel's raw `u16`, little-endian).
pub const EXPECTED_CRC32_RGB565: u32 = 0x042074a1;

/// The benchmark scene type: fixed capacities, no heap.
pub type BenchScene = Scene<SPHERES, LIGHTS>;

/// Fills `scene` (which must be empty) with the benchmark: a ground sphere, four spheres, one
/// point and one directional light, shadows on, no mirrors.
pub fn build_scene(scene: &mut BenchScene) -> Result<(), Error> {
    let plastic = |r, g, b, shininess| Material {
        diffuse: Color::new(r, g, b),
        specular: Color::splat(0.4),
        shininess,
        ..Material::default()
    };
    scene.set_ambient(Color::splat(0.08))?;
    scene.set_background(Color::new(0.10, 0.14, 0.25))?;
    scene.set_shadows(true);
    let ground = Material {
        diffuse: Color::new(0.55, 0.55, 0.5),
        ..Material::default()
    };
    scene.add_sphere(Sphere::new(Vec3::new(0.0, -1000.0, 0.0), 1000.0), ground)?;
    scene.add_sphere(
        Sphere::new(Vec3::new(-1.6, 0.7, 0.0), 0.7),
        plastic(0.8, 0.15, 0.1, 32.0),
    )?;
    scene.add_sphere(
        Sphere::new(Vec3::new(0.1, 1.0, -1.2), 1.0),
        plastic(0.15, 0.7, 0.2, 64.0),
    )?;
    scene.add_sphere(
        Sphere::new(Vec3::new(1.5, 0.5, 0.6), 0.5),
        plastic(0.15, 0.3, 0.85, 16.0),
    )?;
    scene.add_sphere(
        Sphere::new(Vec3::new(0.3, 0.3, 1.4), 0.3),
        plastic(0.9, 0.8, 0.1, 8.0),
    )?;
    scene.add_light(Light::Point {
        position: Vec3::new(4.0, 6.0, 5.0),
        intensity: Color::splat(0.75),
    })?;
    scene.add_light(Light::Directional {
        direction: Vec3::new(-1.0, -2.0, -0.5),
        intensity: Color::new(0.35, 0.33, 0.3),
    })
}

/// The benchmark camera: `WIDTH`×`HEIGHT`, 45° vertical field of view.
pub fn camera() -> Result<Camera, Error> {
    let eye = Vec3::new(0.0, 1.6, 6.0);
    Camera::new(
        eye,
        Vec3::new(0.0, 0.7, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
        45.0,
        WIDTH,
        HEIGHT,
    )
}

/// One sample per pixel, linear encoding.
pub fn options() -> RenderOptions {
    RenderOptions::default()
}

/// CRC-32 (IEEE 802.3, the one of zip and PNG) with a 256-entry table built at compile time.
#[derive(Debug, Clone, Copy)]
pub struct Crc32 {
    state: u32,
}

const CRC_TABLE: [u32; 256] = {
    let mut table = [0u32; 256];
    let mut n = 0;
    while n < 256 {
        let mut c = n as u32;
        let mut k = 0;
        while k < 8 {
            c = if c & 1 != 0 {
                0xEDB8_8320 ^ (c >> 1)
            } else {
                c >> 1
            };
            k += 1;
        }
        table[n] = c;
        n += 1;
    }
    table
};

impl Crc32 {
    /// A CRC of no bytes yet.
    pub const fn new() -> Self {
        Crc32 { state: 0xFFFF_FFFF }
    }

    /// Folds `bytes` in.
    #[inline]
    pub fn update(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.byte(b);
        }
    }

    /// Folds one byte in.
    #[inline(always)]
    pub fn byte(&mut self, b: u8) {
        self.state = CRC_TABLE[((self.state ^ b as u32) & 0xFF) as usize] ^ (self.state >> 8);
    }

    /// The CRC-32 of everything folded in so far.
    pub const fn value(&self) -> u32 {
        !self.state
    }
}

impl Default for Crc32 {
    fn default() -> Self {
        Self::new()
    }
}

/// An embedded-graphics display that stores nothing: it folds every `Rgb888` pixel it receives
/// (bytes r, g, b) into a CRC-32 and counts them. Pixels are folded in the order they arrive,
/// which for [`Frame::draw`] is row by row from the top. Its size `W × H` is a constant: as a
/// field, the M4F benchmark costs 1 instruction a pixel more (`run.sh m4f`).
#[derive(Debug)]
pub struct CrcDisplay<const W: u32 = WIDTH, const H: u32 = HEIGHT> {
    /// The checksum so far.
    pub crc: Crc32,
    /// Pixels received so far.
    pub pixels: u32,
}

impl<const W: u32, const H: u32> CrcDisplay<W, H> {
    /// An empty checksum display.
    pub const fn new() -> Self {
        CrcDisplay {
            crc: Crc32::new(),
            pixels: 0,
        }
    }

    #[inline]
    fn fold(&mut self, c: Rgb888) {
        self.crc.byte(c.r());
        self.crc.byte(c.g());
        self.crc.byte(c.b());
        self.pixels += 1;
    }
}

impl<const W: u32, const H: u32> Default for CrcDisplay<W, H> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const W: u32, const H: u32> OriginDimensions for CrcDisplay<W, H> {
    fn size(&self) -> Size {
        Size::new(W, H)
    }
}

impl<const W: u32, const H: u32> DrawTarget for CrcDisplay<W, H> {
    type Color = Rgb888;
    type Error = core::convert::Infallible;

    fn draw_iter<I>(&mut self, pixels: I) -> Result<(), Self::Error>
    where
        I: IntoIterator<Item = Pixel<Self::Color>>,
    {
        for Pixel(_, c) in pixels {
            self.fold(c);
        }
        Ok(())
    }

    fn fill_contiguous<I>(&mut self, area: &Rectangle, colors: I) -> Result<(), Self::Error>
    where
        I: IntoIterator<Item = Self::Color>,
    {
        // Only what lies on the display counts, as on a real panel.
        let visible = area.intersection(&self.bounding_box());
        if visible == *area {
            for c in colors {
                self.fold(c);
            }
            Ok(())
        } else {
            self.draw_iter(
                area.points()
                    .zip(colors)
                    .filter(|(p, _)| visible.contains(*p))
                    .map(|(p, c)| Pixel(p, c)),
            )
        }
    }
}

/// Folds a strip of `Rgb565` pixels (raw `u16`, little-endian) into `crc`: what a display
/// driver would send over SPI.
pub fn fold_rgb565(crc: &mut Crc32, strip: &[Rgb565]) {
    for p in strip {
        crc.update(&p.into_storage().to_le_bytes());
    }
}

/// Renders the whole frame through [`Frame::draw`] into a [`CrcDisplay`] of `W × H` pixels
/// (the frame's size): returns the CRC-32 and the number of pixels. Never inlined, so that the
/// firmware's panic check can find it as a root of the render path.
#[inline(never)]
pub fn crc_rgb888<const W: u32, const H: u32, const S: usize, const L: usize>(
    frame: &Frame<'_, S, L>,
) -> (u32, u32) {
    let mut display = CrcDisplay::<W, H>::new();
    // CrcDisplay's error type is Infallible.
    let _ = frame.draw(&mut display);
    (display.crc.value(), display.pixels)
}

/// Renders the frame strip by strip, ordered-dithered into `strip` (a whole number of rows), and
/// folds each strip with [`fold_rgb565`]; returns the CRC-32, or the error of a wrong-sized strip.
/// Never inlined: the other root of the render path for the panic check.
#[inline(never)]
pub fn crc_rgb565_dithered(
    frame: &Frame<'_, SPHERES, LIGHTS>,
    strip: &mut [Rgb565],
) -> Result<u32, Error> {
    if strip.is_empty() {
        return Err(Error::BufferSize); // zero rows per strip would never finish
    }
    let mut crc = Crc32::new();
    let mut row = 0;
    while row < frame.height() {
        let rows = frame.render_rows_dithered(row, strip)?;
        fold_rgb565(&mut crc, strip);
        row += rows;
    }
    Ok(crc.value())
}
