//! # microray
//!
//! A sphere ray tracer for microcontrollers that desktops can use too: `#![no_std]`, no heap,
//! every float function from [`libm`] so that a Cortex-M computes the same pixels as the host.
//! The exceptions are instructions that return the same bits: `vsqrt.f32` on a Cortex-M4F, and
//! on x86-64, AArch64 and wasm32 with simd128 the vector lanes (`wide`'s f32x4: IEEE add, multiply, divide and
//! square root, no fused multiply-add) in which the renderer traces four primary rays at once.
//!
//! The layers, each one module: [`math`] → `simd` (the vector lanes, hosts only) →
//! [`geometry`] (rays, spheres, intersection) → [`scene`] → [`camera`], [`animation`] and [`raster`] (screen
//! bounds) → [`shading`] (the shading model, mirrors and glass) → [`render`] (frames, bands,
//! pixels) → [`output`] (embedded-graphics displays). With the `scene-file` feature (std),
//! [`scene_file`](scene_file/index.html) reads the TOML scene format. ARCHITECTURE.md in the
//! repository says where each part lives.
//!
//! ## On a microcontroller: a scene in code, a row at a time
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
//! let mut storage = FrameStorage::small(); // the per-frame tables of at most 8 spheres
//! let frame = Frame::new(&scene, &camera, RenderOptions::default(), &mut storage)?;
//! let mut row = [Rgb888::new(0, 0, 0); 64]; // one row at a time: no framebuffer needed
//! for j in 0..48 {
//!     frame.render_rows(j, &mut row)?;
//! }
//! # Ok::<(), microray::Error>(())
//! ```
//!
//! On a display, [`Frame::draw`] streams the frame in one window with no buffer at all, a
//! [`Frame`] is an embedded-graphics image (`Image::new(&frame, point)`), and
//! [`Frame::draw_progressive`] shows a coarse image first on chips that take seconds a frame;
//! [`Frame::draw_dithered`] keeps gradients on 16-bit, grey and 1-bit displays
//! ([`output::Dither`]).
//!
//! ## On a desktop: a scene file in, an image out
//!
//! With the `scene-file` feature; the repository's `render` example does this on all cores
//! and writes a PNG.
//!
//! ```
//! # #[cfg(feature = "scene-file")]
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! use embedded_graphics::pixelcolor::Rgb888;
//! use microray::scene_file::{self, Desktop};
//! use microray::{Frame, FrameStorage};
//!
//! // Or scene_file::load("scene.toml"). Every error names the field (and line) at fault.
//! let file: Box<Desktop> = scene_file::parse(
//!     r#"
//!     [camera]
//!     eye = [0, 1, 6]
//!     look_at = [0, 0.5, 0]
//!     [render]
//!     width = 64
//!     height = 48
//!     [[sphere]]
//!     center = [0, 0.5, 0]
//!     radius = 1.0
//!     [[light]]
//!     kind = "point"
//!     position = [3, 5, 4]
//!     "#,
//! )?;
//! // The desktop capacity (16 384 spheres, 32 lights) takes 15.4 MB of tables: each
//! // boxed on the heap.
//! let mut storage = FrameStorage::on_heap();
//! let frame = Frame::new(&file.scene, &file.camera, file.options, &mut storage)?;
//! let mut image = vec![Rgb888::new(0, 0, 0); (file.width * file.height) as usize];
//! frame.render(&mut image)?; // or a band of rows per thread: `render_rows`
//! // `image` holds the rows top to bottom, ready for a PNG encoder.
//! # assert!(image.iter().any(|p| *p != image[0]));
//! # Ok(())
//! # }
//! # #[cfg(not(feature = "scene-file"))]
//! # fn main() {}
//! ```
//!
//! ## Features
//!
//! None is on by default: the crate is `no_std` and allocates nothing.
//!
// Plain links to `scene_file`: without the feature there is no module for rustdoc to resolve.
//! - `scene-file`: [`scene_file`](scene_file/index.html), the TOML scene reader; turns on
//!   `std` and `refraction` and adds `serde` and `toml`.
//! - `refraction`: glass ([`Material::refraction`], [`Material::ior`],
//!   `shading::refract`). Without it a scene with glass is
//!   [`Error::RefractionNotEnabled`], and no refraction code is in the binary.
//! - `std`: links the standard library, which the scene reader needs. Nothing else depends
//!   on it: [`Error`] is a `core::error::Error` in every build.
//! - `defmt`: `defmt::Format` for [`Error`] and the small `Copy` types ([`Vec3`], [`Sphere`],
//!   [`Material`], [`Light`], [`Camera`], [`RenderOptions`], …), to log them from firmware.
//! - `outside-test`, `inline-shading`: size builds (`size_opt` below) keep the second primary
//!   test for an eye outside a sphere, and the shading inlined into the pixel loop, which they
//!   otherwise leave out for flash: speed for flash, the same pixels.
//!
//! ## Build-time cfgs
//!
//! `build.rs` sets these from the target and the profile, never by hand; none changes a
//! pixel (every target computes the same bits) or the API.
//!
//! - `lanes` on x86-64, on AArch64 with NEON and on wasm32 with simd128: primary rays, hit records and shading four
//!   pixels at a time in vector registers (`wide`'s `f32x4`).
//! - `no_dirs` on soft-float Arm (Cortex-M0): spans keep no view directions.
//! - `size_opt` at opt-level `"s"` or `"z"`: the scalar path keeps its shading out of line
//!   and has one primary test, unless features `inline-shading` and `outside-test` say
//!   otherwise.
//!
//! `MICRORAY_HOST_AS=m4f` (or `m0`) in the environment builds a host with that board's render
//! path, so that the host's tests check it.
//!
//! The oldest Rust that builds the crate is 1.87 (`rust-version`).
#![no_std]
#![cfg_attr(docsrs, feature(doc_cfg))]
#![deny(unsafe_code)]
#![deny(missing_docs)]
// `!(x > 0.0)` is deliberate throughout: NaN must fail every validity check.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

#[cfg(feature = "std")]
extern crate std;

pub mod animation;
pub mod camera;
pub mod error;
pub mod geometry;
pub mod math;
pub mod output;
pub mod raster;
pub mod render;
pub mod scene;
#[cfg(feature = "scene-file")]
#[cfg_attr(docsrs, doc(cfg(feature = "scene-file")))]
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
