//! # microray
//!
//! A sphere ray tracer for microcontrollers that desktops can use too: `#![no_std]`, no heap,
//! every float function from [`libm`] so that a Cortex-M computes the same pixels as the host.
//! The exceptions are instructions that return the same bits: `vsqrt.f32` on a Cortex-M4F, and
//! on x86-64 and AArch64 the vector lanes (`wide`'s f32x4: IEEE add, multiply, divide and
//! square root, no fused multiply-add) in which the renderer traces four primary rays at once.
//!
//! The layers, each one module: [`math`] → `simd` (the vector lanes, hosts only) →
//! [`geometry`] (rays, spheres, intersection) → [`scene`] → [`camera`] and [`raster`] (screen
//! bounds) → [`shading`] (the shading model) → [`render`] (frames, bands, pixels) → [`output`]
//! (embedded-graphics displays). With the `scene-file` feature (std), [`scene_file`] reads the
//! TOML scene format. ARCHITECTURE.md in the repository says where each part lives.
//!
//! ```
//! use embedded_graphics::pixelcolor::Rgb888;
//! use microray::{Camera, Color, Frame, FrameStorage, Light, Material, RenderOptions, Scene, Sphere, Vec3};
//!
//! // Capacities are the caller's choice: here 4 spheres and 2 lights, no heap.
//! let mut scene: Scene<4, 2> = Scene::new();
//! scene.set_ambient(Color::splat(0.05))?;
//! scene.add_sphere(Sphere::new(Vec3::new(0.0, -1000.0, 0.0), 1000.0), Material::default())?;
//! scene.add_sphere(
//!     Sphere::new(Vec3::new(0.0, 1.0, 0.0), 1.0),
//!     Material { diffuse: Color::new(0.8, 0.2, 0.2), specular: Color::splat(0.5), ..Material::default() },
//! )?;
//! scene.add_light(Light::Point { position: Vec3::new(3.0, 5.0, 4.0), intensity: Color::splat(0.8) })?;
//!
//! let camera = Camera::new(Vec3::new(0.0, 1.0, 6.0), Vec3::new(0.0, 0.5, 0.0), Vec3::new(0.0, 1.0, 0.0), 45.0, 64, 48)?;
//! let mut storage = FrameStorage::new(); // the per-frame tables, small at this capacity
//! let frame = Frame::new(&scene, &camera, RenderOptions::default(), &mut storage)?;
//! let mut row = [Rgb888::new(0, 0, 0); 64]; // one row at a time: no framebuffer needed
//! for j in 0..48 {
//!     frame.render_rows(j, &mut row)?;
//! }
//! # Ok::<(), microray::Error>(())
//! ```
#![no_std]
#![deny(unsafe_code)]
#![deny(missing_docs)]
// `!(x > 0.0)` is deliberate throughout: NaN must fail every validity check.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

#[cfg(feature = "std")]
extern crate std;

pub mod camera;
pub mod error;
pub mod geometry;
pub mod math;
pub mod output;
pub mod raster;
pub mod render;
pub mod scene;
#[cfg(feature = "scene-file")]
pub mod scene_file;
pub mod shading;
pub(crate) mod simd;

pub use camera::Camera;
pub use error::Error;
pub use geometry::{ray_intersect, Prepared, Ray, Sphere};
pub use math::{Color, Vec3};
pub use render::{Encoding, Frame, FrameStorage, RenderOptions};
pub use scene::{Hit, Light, Material, Scene};
pub use shading::{shade, trace};

/// The README's examples, compiled and run as doctests so they cannot drift from the API.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
