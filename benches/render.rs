//! `cargo bench`: frame times of the accelerated renderer (one thread, `Frame::render`).
//!
//! * `spheres/{kind}/{layout}/{n}` at 640×480: `kind` is `primary` (no lights: primary rays
//!   only), `shaded` (a point and a directional light, specular, no shadows) or `shadowed` (the
//!   same with shadows); `layout` is `spread` (small spheres on a grid over the screen) or
//!   `clustered` (packed in a small block at the centre); `n` is 1, 16, 256 or 1024 spheres,
//!   in front of a large back wall sphere.
//! * `pixels/shadowed/spread16/{w}x{h}`: the cost against image size, 160×120 to 1920×1080.
//! * `target/{accelerated,brute}`: bench/scenes/target.toml (ground, 24 spheres, two point lights
//!   and a directional light, shadows, 640×480) with both paths.
//!
//! Small samples keep a full run to a few minutes on two cores; `cargo bench -- spheres/shadowed`
//! runs a part.

use std::time::Duration;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use embedded_graphics::pixelcolor::Rgb888;
use microray::scene_file::{self, Desktop};
use microray::{
    Camera, Color, Frame, FrameStorage, Light, Material, RenderOptions, Scene, Sphere, Vec3,
};

/// Capacity: 1024 spheres and the wall.
type BenchScene = Scene<1025, 4>;

#[derive(Clone, Copy, PartialEq)]
enum Kind {
    Primary,
    Shaded,
    Shadowed,
}

fn scene(kind: Kind, clustered: bool, n: usize) -> Box<BenchScene> {
    let mut s: Box<BenchScene> = Box::new(Scene::new());
    s.set_ambient(Color::splat(0.1)).unwrap();
    s.set_background(Color::new(0.2, 0.3, 0.5)).unwrap();
    s.set_shadows(kind == Kind::Shadowed);
    let wall = Material {
        diffuse: Color::splat(0.7),
        ..Material::default()
    };
    s.add_sphere(Sphere::new(Vec3::new(0.0, 0.0, -1002.0), 1000.0), wall)
        .unwrap();
    let side = (n as f32).sqrt().ceil() as usize;
    let mut seed = 0x2545_F491_4F6C_DD1Du64;
    let mut rnd = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 40) as f32 / (1u64 << 24) as f32
    };
    for k in 0..n {
        let c = if clustered {
            // A block about 1 unit across at the centre: ~1/40 of the screen.
            Vec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5) * 1.2
        } else {
            // A grid over the whole screen (it spans about ±4.8 × ±3.6 at z = 0).
            let (gx, gy) = ((k % side) as f32, (k / side) as f32);
            let cell = 9.0 / side as f32;
            Vec3::new(
                -4.5 + (gx + 0.5) * cell,
                3.4 - (gy + 0.5) * cell * 0.75,
                0.0,
            )
        };
        let m = Material {
            diffuse: Color::new(0.3 + 0.6 * rnd(), 0.3 + 0.6 * rnd(), 0.3 + 0.6 * rnd()),
            specular: if kind == Kind::Primary {
                Color::ZERO
            } else {
                Color::splat(0.4)
            },
            shininess: 32.0,
            ..Material::default()
        };
        s.add_sphere(Sphere::new(c, 0.12), m).unwrap();
    }
    if kind != Kind::Primary {
        s.add_light(Light::Point {
            position: Vec3::new(3.0, 5.0, 8.0),
            intensity: Color::splat(0.6),
        })
        .unwrap();
        s.add_light(Light::Directional {
            direction: Vec3::new(-0.3, -0.5, -1.0),
            intensity: Color::splat(0.3),
        })
        .unwrap();
    }
    s
}

fn camera(w: u32, h: u32) -> Camera {
    Camera::new(
        Vec3::new(0.0, 0.0, 10.0),
        Vec3::ZERO,
        Vec3::new(0.0, 1.0, 0.0),
        40.0,
        w,
        h,
    )
    .unwrap()
}

fn render<const S: usize, const L: usize>(frame: &Frame<'_, S, L>, buf: &mut [Rgb888]) {
    frame.render(buf).unwrap();
}

fn spheres(c: &mut Criterion) {
    let cam = camera(640, 480);
    let mut buf = vec![Rgb888::new(0, 0, 0); 640 * 480];
    for (kind, kname) in [
        (Kind::Primary, "primary"),
        (Kind::Shaded, "shaded"),
        (Kind::Shadowed, "shadowed"),
    ] {
        let mut g = c.benchmark_group(format!("spheres/{kname}"));
        g.sample_size(10)
            .warm_up_time(Duration::from_millis(300))
            .measurement_time(Duration::from_secs(1));
        for (clustered, lname) in [(false, "spread"), (true, "clustered")] {
            for n in [1usize, 16, 256, 1024] {
                let s = scene(kind, clustered, n);
                let mut storage = Box::new(FrameStorage::new());
                let frame = Frame::new(&*s, &cam, RenderOptions::default(), &mut storage).unwrap();
                g.bench_with_input(BenchmarkId::new(lname, n), &n, |b, _| {
                    b.iter(|| render(&frame, &mut buf))
                });
            }
        }
        g.finish();
    }
}

fn pixels(c: &mut Criterion) {
    let s = scene(Kind::Shadowed, false, 16);
    let mut g = c.benchmark_group("pixels/shadowed/spread16");
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(1));
    for (w, h) in [
        (160u32, 120u32),
        (320, 240),
        (640, 480),
        (1280, 720),
        (1920, 1080),
    ] {
        let cam = camera(w, h);
        let mut storage = Box::new(FrameStorage::new());
        let frame = Frame::new(&*s, &cam, RenderOptions::default(), &mut storage).unwrap();
        let mut buf = vec![Rgb888::new(0, 0, 0); (w * h) as usize];
        g.bench_function(format!("{w}x{h}"), |b| b.iter(|| render(&frame, &mut buf)));
    }
    g.finish();
}

fn target(c: &mut Criterion) {
    let file: Box<Desktop> =
        scene_file::parse(include_str!("../bench/scenes/target.toml")).unwrap();
    let mut storage = Box::new(FrameStorage::new());
    let frame = Frame::new(&file.scene, &file.camera, file.options, &mut storage).unwrap();
    let (w, h) = (file.camera.width() as usize, file.camera.height() as usize);
    let mut buf = vec![Rgb888::new(0, 0, 0); w * h];
    let mut g = c.benchmark_group("target");
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(2));
    g.bench_function("accelerated", |b| b.iter(|| render(&frame, &mut buf)));
    g.bench_function("brute", |b| {
        b.iter(|| frame.render_rows_brute(0, &mut buf).unwrap())
    });
    g.finish();
}

criterion_group!(benches, target, spheres, pixels);
criterion_main!(benches);
