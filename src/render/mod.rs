//! Rendering: per-frame constants, the pixel loop, supersampling and pixel encoding.
//!
//! # How a frame is traced fast
//!
//! [`Frame::new`] fills the caller's [`FrameStorage`] with what all rays of the frame share:
//! for the eye, `o − m` and `|o − m|² − r²` of every sphere ([`Prepared::exact`]); for every
//! point light (when shadows are on) the `c = |o − m|² − r²` of those constants (the rest is
//! rebuilt exactly when used); for every sphere its exact, conservative screen-space box
//! ([`crate::raster`]); and, above a capacity of 8 spheres, for every light (with shadows) its
//! spheres sorted by a key across the light, with a bucket index over the sorted keys. A span's
//! shadow candidates are the entries within its band of keys, scanned from the bucket of the
//! band's low end: from the bucket's start where it holds at most 8 entries, else from a
//! binary search within the bucket.
//! [`Frame::render_rows`] then walks each row in spans of [`SPAN`] pixels (on hosts narrowed to
//! 16 or 8 where many spheres' boxes meet a span):
//!
//! 1. the row's spheres are those whose box crosses it, the span's those whose box overlaps
//!    the span, in scene order; a primary ray tests only the span's spheres whose box holds
//!    its pixel;
//! 2. with shadows on, the span's primary hits are traced first, grouped by the sphere hit and
//!    each group bounded by a ball; for each group and light, only the spheres that can meet a
//!    shadow ray from that ball are kept (for a point light: the cone hull of the light and the
//!    ball; for a directional light: the ball swept along the light), found in the light's
//!    sorted band among those that begin no farther along the light's rays than the ball
//!    reaches, or among all spheres at a capacity of 8 or less (never a group's own sphere,
//!    which shadow rays leave analytically); shadow rays stop at the first blocker, and a long
//!    list puts its spheres nearest the ball first;
//! 3. the pixels are shaded with those lists, from the stored hits and ray directions; every
//!    miss shows the background whatever its ray, so the row shades one miss for all.
//!
//! Every list is a superset of the spheres the full test could report, and the tests
//! themselves are the brute-force ones, in the same order where order matters (the closest
//! hit keeps the last of equal `t`s): the pixels are the brute-force pixels, bit for bit
//! ([`Frame::render_rows_brute`] is kept as the reference). Secondary rays (mirror and
//! refracted rays, and the shadow rays of their hits), which leave from anywhere, go through a
//! hierarchy of bounding boxes over the spheres (`bvh.rs`), built once a frame above a
//! capacity of 8 where the scene has more than 48 spheres and secondary rays; it names the
//! spheres a ray can meet, each asked with the brute-force test, equal `t`s decided in the
//! brute-force order. The shadow rays of secondary hits take their candidates from the
//! lights' sweeps where those name few (`shade.rs`).
//!
//! A scene pays only for what it has: without lights or shadows, step 2 is skipped; no
//! specular or mirror work is done for materials without them.

use embedded_graphics::pixelcolor::Rgb888;

use crate::camera::{sample_offset, Camera};
use crate::error::Error;
use crate::geometry::{hit_point_near, Prepared, Ray};
use crate::math::{powf, Color, Vec3};
use crate::raster::{PixelBox, Screen};
use crate::scene::{hit_from_offset, make_hit, Hit, Light, Scene, SphereId};
use crate::shading::{follow, in_shadow_among, shade_lit, LightKind, T_EPS};

mod bvh;
mod candidates;
mod config;
mod cull;
mod encode;
#[cfg(lanes)]
mod lanes;
mod primary;
mod rows;
#[cfg(not(lanes))]
mod scalar;
mod shade;
#[cfg(lanes)]
mod sort;
mod storage;
mod sweep;
#[cfg(test)]
mod tests;

use bvh::*;
use candidates::*;
use config::*;
use cull::*;
pub use encode::*;
#[cfg(lanes)]
use lanes::{Found, PathState};
#[cfg(lanes)]
use primary::wins;
pub use rows::*;
#[cfg(not(lanes))]
use scalar::{Found, PathState};
#[cfg(lanes)]
use sort::radix_sort;
pub use storage::*;
use sweep::*;

/// Per-frame settings that are not part of the scene.
///
/// ```
/// use microray::{Encoding, RenderOptions};
/// let opts = RenderOptions { samples: 3, encoding: Encoding::Srgb };
/// assert_eq!(RenderOptions::default().samples, 1);
/// # let _ = opts;
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
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

/// Pixels per span: the unit for which the renderer gathers candidate spheres (the widest; a
/// host narrows a span that many spheres' boxes meet).
pub const SPAN: usize = 32;

/// A scene, a camera and options, with everything that all rays of the frame share computed
/// once into a [`FrameStorage`]: `o − m` and `|o − m|² − r²` of every sphere for the eye,
/// `|o − m|² − r²` for every point light, and every sphere's box on the screen.
///
/// Build it once, then render the whole image, bands of rows, single pixels, or draw onto an
/// embedded-graphics display.
///
/// ```
/// use embedded_graphics::pixelcolor::Rgb888;
/// use microray::{Camera, Color, Frame, FrameStorage, Light, Material, RenderOptions, Scene, Sphere, Vec3};
///
/// let mut scene: Scene<4, 1> = Scene::new();
/// scene.set_ambient(Color::splat(0.1))?;
/// scene.add_sphere(Sphere::new(Vec3::ZERO, 1.0), Material::default())?;
/// scene.add_light(Light::Point { position: Vec3::new(3.0, 5.0, 4.0), intensity: Color::ONE })?;
/// let camera = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 32, 24)?;
/// let mut storage = FrameStorage::new(); // the per-frame tables, small at this capacity
/// let frame = Frame::new(&scene, &camera, RenderOptions::default(), &mut storage)?;
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
    /// The per-frame tables, in the caller's storage.
    tables: Tables<'a, S, L>,
    /// Shadows on and at least one light: the only case that casts shadow rays.
    shadow_rays: bool,
}

/// A frame's view of its [`FrameStorage`], wherever its tables live.
#[derive(Debug, Clone, Copy)]
struct Tables<'a, const S: usize, const L: usize> {
    eye: &'a [Prepared],
    boxes: &'a [PixelBox],
    lights: &'a [heapless::Vec<f32, S>; L],
    sweeps: &'a [Sweep<S>],
    all: &'a [SphereId],
    near: &'a [bool],
    #[cfg(lanes)]
    pile: &'a [f32],
    #[cfg(lanes)]
    box_rows: &'a [PixelBox],
    /// The hierarchy that culls secondary rays (`bvh.rs`), where the frame built one: `None`
    /// for a scene without secondary rays or of 48 spheres or less, and in a [`Small`]
    /// storage, which holds none.
    bvh: Option<&'a Bvh<S>>,
}

/// Sphere ids: a row's, a span's or a light's candidates.
type List<const S: usize> = heapless::Vec<SphereId, S>;

impl<'a, const S: usize, const L: usize> Frame<'a, S, L> {
    /// Sphere ids are two bytes, two values kept as markers.
    const FITS: () = assert!(S < SphereId::REST.index(), "sphere capacity above 65533");

    /// Whether shadow rays find their candidates through sorted sweeps, or test every sphere
    /// against a span's bound: decided by the capacity, at compile time, so that a scene of a
    /// few spheres (a microcontroller's) links none of the sweep code (sorting, `atan2f`),
    /// where a scan of all its spheres per span costs about as much.
    const SWEEPS: bool = S > 8;

    /// Prepares a frame, its tables in `storage` (whatever it held is overwritten); fails only
    /// for invalid options (`samples` outside 1..=16), and then leaves `storage` as it was.
    ///
    /// ```
    /// # use microray::{Camera, Error, Frame, FrameStorage, RenderOptions, Scene, Vec3};
    /// let scene: Scene<1, 0> = Scene::new();
    /// let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 4, 4)?;
    /// let bad = RenderOptions { samples: 0, ..RenderOptions::default() };
    /// let mut storage = FrameStorage::new();
    /// assert_eq!(Frame::new(&scene, &cam, bad, &mut storage).err(), Some(Error::InvalidSamples));
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn new<P: Place>(
        scene: &'a Scene<S, L>,
        camera: &'a Camera,
        options: RenderOptions,
        storage: &'a mut FrameStorage<S, L, P>,
    ) -> Result<Self, Error> {
        #[allow(clippy::let_unit_value)]
        let () = Self::FITS;
        if !(1..=16).contains(&options.samples) {
            return Err(Error::InvalidSamples);
        }
        storage.fill(scene, camera);
        Ok(Frame {
            scene,
            camera,
            samples: options.samples as u32,
            encoding: options.encoding,
            tables: Tables {
                eye: &storage.eye,
                boxes: &storage.boxes,
                lights: &storage.lights,
                sweeps: storage.built_sweeps(),
                all: &storage.all,
                near: &storage.near,
                #[cfg(lanes)]
                pile: &storage.pile,
                #[cfg(lanes)]
                box_rows: &storage.box_rows,
                bvh: storage.bvh().filter(|b| b.built()),
            },
            shadow_rays: scene.shadows() && !scene.lights().is_empty(),
        })
    }

    /// Image width in pixels.
    ///
    /// ```
    /// # use microray::{Camera, Frame, RenderOptions, Scene, Vec3};
    /// # let scene: Scene<1, 0> = Scene::new();
    /// # let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 4, 3)?;
    /// let mut storage = microray::FrameStorage::new();
    /// let frame = Frame::new(&scene, &cam, RenderOptions::default(), &mut storage)?;
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
    /// let mut storage = microray::FrameStorage::new();
    /// let frame = Frame::new(&scene, &cam, RenderOptions::default(), &mut storage)?;
    /// assert_eq!(frame.height(), 3);
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn height(&self) -> u32 {
        self.camera.height()
    }

    /// The screen box of every sphere, in scene order: a primary ray through pixel `(i, j)`
    /// can hit sphere `s` only if `boxes()[s]` contains `(i, j)`.
    ///
    /// ```
    /// # use microray::{Camera, Frame, Material, RenderOptions, Scene, Sphere, Vec3};
    /// let mut scene: Scene<2, 0> = Scene::new();
    /// scene.add_sphere(Sphere::new(Vec3::ZERO, 0.5), Material::default())?;
    /// scene.add_sphere(Sphere::new(Vec3::new(0.0, 0.0, 9.0), 1.0), Material::default())?; // behind
    /// let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 64, 64)?;
    /// let mut storage = microray::FrameStorage::new();
    /// let frame = Frame::new(&scene, &cam, RenderOptions::default(), &mut storage)?;
    /// let b = frame.boxes()[0];
    /// assert!(b.contains(32, 32) && !b.contains(0, 0));
    /// assert!(frame.boxes()[1].is_empty());
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn boxes(&self) -> &[PixelBox] {
        self.tables.boxes
    }
}
