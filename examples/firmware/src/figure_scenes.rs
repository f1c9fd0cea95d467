//! Two well-known small ray tracers' scenes, in microray's spheres-only model, with the CRC-32
//! of each one's frame: FTB's ray tracer (timed on a 240 MHz RX72N) and ssloy's tinyraytracer
//! (timed on an ESP32). The `figures` firmware (`src/bin/figures.rs`) renders them and prints
//! its instructions a pixel beside those published figures.
//!
//! Each scene is also a TOML file, `examples/scenes/ftb.toml` and
//! `examples/scenes/tinyraytracer.toml`, whose comments say what was changed from the original
//! and why. The host test `tests/figure_scenes.rs` compiles this file (through `#[path]`),
//! asserts that each builder here gives the file's scene value for value, and that the file's
//! frame has the CRC committed here, which the firmware checks on both boards: the TOML and
//! this copy cannot drift apart.
//!
//! `no_std`, heap-free; both scenes fit the micro:bit's 16 KiB of RAM.

use microray::{Camera, Color, Error, Light, Material, RenderOptions, Scene, Sphere, Vec3};

/// Image width of both scenes: the figures compared with are for 76 800 pixels.
pub const WIDTH: u32 = 320;
/// Image height of both scenes.
pub const HEIGHT: u32 = 240;
/// Sphere capacity: a ground sphere and four spheres in each scene.
pub const SPHERES: usize = 5;
/// Light capacity: tinyraytracer's three point lights (FTB's scene has one).
pub const LIGHTS: usize = 3;

/// Both scenes' type.
pub type FigureScene = Scene<SPHERES, LIGHTS>;

/// One scene, its file and its checksum.
#[derive(Debug, Clone, Copy)]
pub struct Figure {
    /// Short name, the prefix of the firmware's keys.
    pub name: &'static str,
    /// The scene file, relative to the repository's root.
    pub file: &'static str,
    /// CRC-32 of the `Rgb888` frame (bytes r, g, b per pixel, rows from the top).
    pub crc32: u32,
}

/// The scenes, in the order [`build`] numbers them.
pub const FIGURES: [Figure; 2] = [
    Figure {
        name: "ftb",
        file: "examples/scenes/ftb.toml",
        crc32: 0x5255_a2a6,
    },
    Figure {
        name: "tinyraytracer",
        file: "examples/scenes/tinyraytracer.toml",
        crc32: 0x08ec_5dc4,
    },
];

/// Fills `scene` (which must be empty) with scene `k` of [`FIGURES`] and returns its camera.
pub fn build(k: usize, scene: &mut FigureScene) -> Result<Camera, Error> {
    match k {
        0 => ftb(scene),
        _ => tinyraytracer(scene),
    }
}

/// One sample per pixel, linear encoding: what both originals were timed at.
pub fn options() -> RenderOptions {
    RenderOptions::default()
}

/// `diffuse`, `specular` (white), `shininess` and `mirror` (grey): the four numbers both
/// originals give a material.
fn material(diffuse: Color, specular: f32, shininess: f32, mirror: f32) -> Material {
    Material {
        diffuse,
        specular: Color::splat(specular),
        shininess,
        mirror: Color::splat(mirror),
        ..Material::default()
    }
}

/// FTB's scene (`examples/scenes/ftb.toml`; z is up).
fn ftb(scene: &mut FigureScene) -> Result<Camera, Error> {
    scene.set_background(Color::new(0.4, 0.085, 0.51))?;
    scene.set_ambient(Color::splat(0.05))?;
    scene.set_max_depth(2)?;
    // The plane z = 0.
    scene.add_sphere(
        Sphere::new(Vec3::new(0.0, 0.0, -100000.0), 100000.0),
        Material {
            diffuse: Color::new(0.9, 0.6, 0.6),
            ..Material::default()
        },
    )?;
    let mirror = material(Color::splat(0.8), 1.0, 32.0, 0.5);
    scene.add_sphere(Sphere::new(Vec3::new(5.0, 15.0, 8.0), 5.0), mirror)?;
    scene.add_sphere(Sphere::new(Vec3::new(-6.0, 12.0, 4.0), 3.0), mirror)?;
    scene.add_sphere(
        Sphere::new(Vec3::new(1.0, 10.0, 2.0), 2.0),
        material(Color::new(0.0, 1.0, 0.0), 1.0, 32.0, 0.2),
    )?;
    scene.add_sphere(
        Sphere::new(Vec3::new(0.0, 9.0, 5.0), 1.0),
        material(Color::new(0.0, 0.8, 0.8), 1.0, 32.0, 0.3),
    )?;
    scene.add_light(Light::Point {
        position: Vec3::new(9.0, 6.0, 16.0),
        intensity: Color::ONE,
    })?;
    Camera::new(
        Vec3::new(0.0, 0.0, 3.0),
        Vec3::new(1.0, 8.0, 4.0),
        Vec3::new(0.0, 0.0, 1.0),
        48.4555,
        WIDTH,
        HEIGHT,
    )
}

/// tinyraytracer's final scene (`examples/scenes/tinyraytracer.toml`), the glass made opaque.
fn tinyraytracer(scene: &mut FigureScene) -> Result<Camera, Error> {
    scene.set_background(Color::new(0.2, 0.7, 0.8))?;
    scene.set_max_depth(4)?;
    // The plane y = −4.
    scene.add_sphere(
        Sphere::new(Vec3::new(0.0, -100004.0, 0.0), 100000.0),
        Material {
            diffuse: Color::new(0.3, 0.255, 0.195),
            ..Material::default()
        },
    )?;
    scene.add_sphere(
        Sphere::new(Vec3::new(-3.0, 0.0, -16.0), 2.0),
        material(Color::new(0.24, 0.24, 0.18), 0.3, 50.0, 0.1),
    )?;
    scene.add_sphere(
        Sphere::new(Vec3::new(-1.0, -1.5, -12.0), 2.0),
        material(Color::new(0.48, 0.56, 0.64), 0.5, 125.0, 0.1),
    )?;
    scene.add_sphere(
        Sphere::new(Vec3::new(1.5, -0.5, -18.0), 3.0),
        material(Color::new(0.27, 0.09, 0.09), 0.1, 10.0, 0.0),
    )?;
    scene.add_sphere(
        Sphere::new(Vec3::new(7.0, 5.0, -18.0), 4.0),
        material(Color::ZERO, 10.0, 1425.0, 0.8),
    )?;
    for (position, intensity) in [
        (Vec3::new(-20.0, 20.0, 20.0), 1.5),
        (Vec3::new(30.0, 50.0, -25.0), 1.8),
        (Vec3::new(30.0, 20.0, 30.0), 1.7),
    ] {
        scene.add_light(Light::Point {
            position,
            intensity: Color::splat(intensity),
        })?;
    }
    Camera::new(
        Vec3::ZERO,
        Vec3::new(0.0, 0.0, -1.0),
        Vec3::new(0.0, 1.0, 0.0),
        57.29578,
        WIDTH,
        HEIGHT,
    )
}
