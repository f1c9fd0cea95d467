//! The accelerated renderer (screen boxes, span lists, shadow culling) must compute exactly the
//! brute-force pixels: on the conformance and demo scenes, and on random scenes built to stress
//! the bounds (spheres behind, around and enclosing the eye, tiny and huge ones, grazing views,
//! point lights inside spheres, supersampling).

mod common;

/// Scene values drawn in f32.
trait Draw {
    fn vec(&mut self, s: f32) -> Vec3;
    fn color(&mut self) -> Color;
}

impl Draw for Rng {
    fn vec(&mut self, s: f32) -> Vec3 {
        Vec3::new(
            self.range_f32(-s, s),
            self.range_f32(-s, s),
            self.range_f32(-s, s),
        )
    }
    fn color(&mut self) -> Color {
        Color::new(
            self.range_f32(0.0, 1.0),
            self.range_f32(0.0, 1.0),
            self.range_f32(0.0, 1.0),
        )
    }
}

use common::rng::Rng;
use embedded_graphics::pixelcolor::{Rgb565, Rgb888};
use microray::output::dither_rgb565;
use microray::scene_file::{self, Desktop};
use microray::{
    Camera, Color, Frame, FrameStorage, Light, Material, Prepared, Ray, RenderOptions, Scene,
    Sphere, Vec3,
};

/// Renders with both paths and reports the first differing pixel.
fn same<const S: usize, const L: usize>(
    scene: &Scene<S, L>,
    camera: &Camera,
    options: RenderOptions,
) {
    let mut storage = FrameStorage::on_heap();
    let frame = Frame::new(scene, camera, options, &mut storage).unwrap();
    let (w, h) = (camera.width() as usize, camera.height() as usize);
    let mut fast = vec![Rgb888::new(0, 0, 0); w * h];
    let mut brute = fast.clone();
    frame.render(&mut fast).unwrap();
    frame.render_rows_brute(0, &mut brute).unwrap();
    if let Some(k) = (0..w * h).find(|&k| fast[k] != brute[k]) {
        let (i, j) = ((k % w) as u32, (k / w) as u32);
        panic!(
            "pixel ({i}, {j}): accelerated {:?} != brute force {:?}; pixel_color {:?} vs {:?}",
            fast[k],
            brute[k],
            frame.pixel_color(i, j),
            frame.pixel_color_brute(i, j)
        );
    }
    // The single-pixel path too, on a sample of pixels.
    for k in (0..w * h).step_by(7) {
        let (i, j) = ((k % w) as u32, (k / w) as u32);
        assert_eq!(frame.pixel(i, j), brute[k], "pixel({i}, {j})");
    }
}

/// A random stress scene of up to `min(S, 80)` spheres (capacity `S`: up to 8 renders without
/// the shadow sweeps, `Frame::SWEEPS`; above 48 spheres with mirrors or glass, the frame walks
/// secondary rays through its hierarchy).
fn random_scene<const S: usize>(seed: u64) -> (Box<Scene<S, 4>>, Camera, RenderOptions) {
    let mut rng = Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1);
    let mut scene: Box<Scene<S, 4>> = Box::new(Scene::new());
    scene
        .set_ambient(Color::splat(rng.range_f32(0.0, 0.2)))
        .unwrap();
    scene.set_background(rng.color()).unwrap();
    scene.set_shadows(!rng.next().is_multiple_of(4));
    scene.set_max_depth((rng.next() % 3) as u8).unwrap();
    let eye = rng.vec(6.0);
    let look = rng.vec(2.0);
    let n = 1 + rng.next() % (S as u64).min(80);
    for _ in 0..n {
        let kind = rng.next() % 10;
        let (c, r) = match kind {
            // tiny and far
            0 => (rng.vec(40.0), rng.range_f32(0.001, 0.05)),
            // huge ground-like sphere, often just below the eye
            1 => {
                let r = [1e3, 1e5, 1e6][(rng.next() % 3) as usize];
                (
                    Vec3::new(
                        rng.range_f32(-1.0, 1.0),
                        eye.y - r - rng.range_f32(0.01, 3.0),
                        rng.range_f32(-1.0, 1.0),
                    ),
                    r,
                )
            }
            // around the eye (the eye inside, or just outside)
            2 => (eye + rng.vec(1.0), rng.range_f32(0.5, 3.0)),
            // enclosing the whole scene
            3 => (rng.vec(1.0), rng.range_f32(20.0, 60.0)),
            _ => (rng.vec(5.0), rng.range_f32(0.1, 1.5)),
        };
        let specular = if rng.next().is_multiple_of(2) {
            Color::ZERO
        } else {
            rng.color()
        };
        let mirror = if rng.next().is_multiple_of(4) {
            rng.color() * 0.8
        } else {
            Color::ZERO
        };
        let m = Material {
            diffuse: rng.color(),
            specular,
            shininess: rng.range_f32(1.0, 200.0),
            mirror,
            // Glass (its rays are shaded by the scalar path on every target), with an index
            // below 1 at times, which totally reflects rays entering it.
            refraction: if rng.next().is_multiple_of(5) {
                rng.color()
            } else {
                Color::ZERO
            },
            ior: rng.range_f32(0.6, 2.5),
        };
        scene.add_sphere(Sphere::new(c, r), m).unwrap();
    }
    for _ in 0..(rng.next() % 5) {
        let light = if rng.next().is_multiple_of(3) {
            Light::Directional {
                direction: rng.vec(1.0) + Vec3::new(0.0, -0.3, 0.0),
                intensity: rng.color(),
            }
        } else {
            Light::Point {
                position: rng.vec(8.0),
                intensity: rng.color(),
            }
        };
        let _ = scene.add_light(light);
    }
    let up = if rng.next().is_multiple_of(2) {
        Vec3::new(0.0, 1.0, 0.0)
    } else {
        rng.vec(1.0)
    };
    let (w, h) = (8 + (rng.next() % 90) as u32, 8 + (rng.next() % 70) as u32);
    let camera = match Camera::new(eye, look, up, rng.range_f32(10.0, 150.0), w, h) {
        Ok(c) => c,
        Err(_) => Camera::new(eye, look, Vec3::new(0.3, 1.0, 0.1), 60.0, w, h).unwrap(),
    };
    let samples = if rng.next().is_multiple_of(5) {
        2 + (rng.next() % 2) as u8
    } else {
        1
    };
    (
        scene,
        camera,
        RenderOptions {
            samples,
            ..RenderOptions::default()
        },
    )
}

/// `random_scene::<S>` for seeds `0..MICRORAY_SEEDS` (300 by default), both ways.
fn random_scenes_agree<const S: usize>() {
    let seeds: u64 = std::env::var("MICRORAY_SEEDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(300);
    for seed in 0..seeds {
        let (scene, camera, options) = random_scene::<S>(seed);
        let result = std::panic::catch_unwind(|| same(&*scene, &camera, options));
        if let Err(e) = result {
            panic!("seed {seed}: {:?}", e.downcast_ref::<String>());
        }
    }
}

#[test]
fn accelerated_equals_brute_force_on_random_scenes() {
    random_scenes_agree::<96>();
}

/// The same with a capacity of 8 spheres, which renders without the shadow sweeps: every
/// sphere is weighed against each span's bound.
#[test]
fn accelerated_equals_brute_force_on_small_scenes() {
    random_scenes_agree::<8>();
}

#[test]
fn accelerated_equals_brute_force_on_scene_files() {
    for name in common::CONFORMANCE {
        let file: Box<Desktop> = scene_file::load(format!("tests/data/{name}.toml")).unwrap();
        same(&file.scene, &file.camera, file.options);
    }
    let demo: Box<Desktop> =
        scene_file::parse(include_str!("../examples/scenes/demo.toml")).unwrap();
    let camera = demo.view.camera(160, 120).unwrap();
    same(&demo.scene, &camera, demo.options);
}

/// Many spheres: the benchmark's scenes of 256 small spheres on a grid in front of a wall
/// (`bench/scenes/spread256_*.toml`, written by `bench/spread_scenes.py`), where the sweeps
/// hold long sorted lists and both keys cut the candidates (the random scenes have up to 80
/// spheres), at a quarter of their pixels. It fails when a sweep's search band is halved.
/// (Shifting a point light's second keys by half their half-widths passes here, whose
/// spans' slack covers it; the random scenes catch that.)
#[test]
fn accelerated_equals_brute_force_with_256_spheres() {
    const W: u32 = 320;
    const H: u32 = 240;
    for kind in ["shadowed", "shaded", "primary"] {
        let file: Box<Desktop> =
            scene_file::load(format!("bench/scenes/spread256_{kind}.toml")).unwrap();
        assert_eq!(file.scene.spheres().len(), 257);
        let camera = file.view.camera(W, H).unwrap();
        same(&file.scene, &camera, file.options);
    }
}

/// The scaling scenes (`bench/scenes/{spread,cluster,mirrors}1024.toml`,
/// `bench/scale_scenes.py`): a thousand spheres spread over the screen, and packed about 32
/// deep at its centre, where a span's hits fall on many spheres and fill every hit group; the
/// spread spheres as mirrors, whose rays and their shadow rays go through the frame's
/// hierarchy; and the mirror scene at 640×480. At a quarter of their pixels (the mirrors at a
/// sixteenth: their brute force tests every sphere at every bounce).
#[test]
fn accelerated_equals_brute_force_on_the_scaling_scenes() {
    for (name, n, (w, h)) in [
        ("spread1024", 1024, (320, 240)),
        ("cluster1024", 1024, (320, 240)),
        ("mirrors1024", 1024, (160, 120)),
        ("mirror640", 4, (320, 240)),
    ] {
        let file: Box<Desktop> = scene_file::load(format!("bench/scenes/{name}.toml")).unwrap();
        assert_eq!(file.scene.spheres().len(), n, "{name}");
        let camera = file.view.camera(w, h).unwrap();
        same(&file.scene, &camera, file.options);
    }
}

/// The set-up of the scaling scenes (`bench/scale_scenes.py`): a grey wall of radius 1000
/// behind the origin in a scene of ambient light `ambient`, with the material `m` makes of a
/// colour; and the camera at (0, 0, 10) facing it, of vertical field `vfov`, `w`×`h`.
fn walled<const S: usize, const L: usize>(
    ambient: f32,
    m: impl Fn(Color) -> Material,
    (vfov, w, h): (f32, u32, u32),
) -> (Box<Scene<S, L>>, Camera) {
    let mut scene: Box<Scene<S, L>> = Box::new(Scene::new());
    scene.set_ambient(Color::splat(ambient)).unwrap();
    scene
        .add_sphere(
            Sphere::new(Vec3::new(0.0, 0.0, -1002.0), 1000.0),
            m(Color::splat(0.7)),
        )
        .unwrap();
    let eye = Vec3::new(0.0, 0.0, 10.0);
    let camera = Camera::new(eye, Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), vfov, w, h).unwrap();
    (scene, camera)
}

/// Thousands of spheres, where hosts narrow crowded spans, skip spheres behind a deep pile's
/// first hits, and keep their shadow sweeps in slabs (from 512 spheres a light): a wall, a
/// grid of 4096 small spheres over the screen, and 400 packed in a ball at its centre, under a
/// point and a directional light with shadows.
#[test]
fn accelerated_equals_brute_force_with_4500_spheres() {
    let m = |c: Color| Material {
        diffuse: c,
        specular: Color::splat(0.3),
        shininess: 16.0,
        ..Material::default()
    };
    let (mut scene, camera) = walled::<4600, 4>(0.1, m, (40.0, 96, 72));
    scene.set_shadows(true);
    let mut rng = Rng(0x4500);
    for k in 0..4096 {
        let (x, y) = ((k % 64) as f32, (k / 64) as f32);
        let c = Vec3::new(
            -4.5 + (x + 0.5) * 0.140625,
            3.4 - (y + 0.5) * 0.10546875,
            0.0,
        );
        scene
            .add_sphere(Sphere::new(c, 0.05), m(rng.color()))
            .unwrap();
    }
    for _ in 0..400 {
        let c = rng.vec(0.6) + Vec3::new(0.0, 0.0, 1.0);
        scene
            .add_sphere(Sphere::new(c, 0.08), m(rng.color()))
            .unwrap();
    }
    scene
        .add_light(Light::Point {
            position: Vec3::new(3.0, 5.0, 8.0),
            intensity: Color::splat(0.6),
        })
        .unwrap();
    scene
        .add_light(Light::Directional {
            direction: Vec3::new(-0.3, -0.5, -1.0),
            intensity: Color::splat(0.3),
        })
        .unwrap();
    same(&scene, &camera, RenderOptions::default());
}

/// A deep pile whose spheres come in pairs at one place, each of another colour: their roots
/// tie, and the brute-force loop gives every tie to the later sphere. Hosts trace a pile's
/// spheres nearest first, not in scene order, and must pick the same ones: with shadows (one
/// sample a pixel, its hits kept), without, with 2×2 samples (kept) and 3×3 (traced again
/// one by one).
#[test]
fn a_deep_pile_of_tied_spheres_keeps_the_brute_force_hits() {
    let m = |c: Color| Material {
        diffuse: c,
        ..Material::default()
    };
    let (mut scene, camera) = walled::<700, 2>(0.2, m, (12.0, 64, 48));
    let mut rng = Rng(0x7_1E5);
    for _ in 0..300 {
        let s = Sphere::new(rng.vec(0.8) + Vec3::new(0.0, 0.0, 1.0), 0.1);
        scene.add_sphere(s, m(Color::new(1.0, 0.1, 0.1))).unwrap();
        scene.add_sphere(s, m(Color::new(0.1, 0.1, 1.0))).unwrap();
    }
    scene
        .add_light(Light::Point {
            position: Vec3::new(3.0, 5.0, 8.0),
            intensity: Color::splat(0.8),
        })
        .unwrap();
    for (shadows, samples) in [(true, 1), (false, 1), (true, 2), (true, 3)] {
        scene.set_shadows(shadows);
        let options = RenderOptions {
            samples,
            ..RenderOptions::default()
        };
        same(&scene, &camera, options);
    }
}

/// `render_rows` gathers a span's rows several at a time (with one sample a pixel and
/// shadows): bands of any height, starting at any row, render the pixels of the whole frame,
/// and so do the row iterator's pixels (`Frame::row`, one row at a time).
#[test]
fn bands_of_any_height_render_the_whole_frame() {
    let mut scenes: Vec<(Box<Desktop>, Camera)> = vec![];
    for path in [
        "tests/data/lit.toml",
        "tests/data/room.toml",
        "bench/scenes/target.toml",
    ] {
        let file: Box<Desktop> = scene_file::load(path).unwrap();
        let camera = file.view.camera(97, 61).unwrap();
        scenes.push((file, camera));
    }
    let file: Box<Desktop> = scene_file::load("bench/scenes/spread256_shadowed.toml").unwrap();
    let camera = file.view.camera(160, 120).unwrap();
    scenes.push((file, camera));
    for (file, camera) in &scenes {
        let mut storage = FrameStorage::on_heap();
        let frame = Frame::new(&file.scene, camera, file.options, &mut storage).unwrap();
        let (w, h) = (camera.width() as usize, camera.height() as usize);
        let mut whole = vec![Rgb888::new(0, 0, 0); w * h];
        frame.render(&mut whole).unwrap();
        let mut brute = whole.clone();
        frame.render_rows_brute(0, &mut brute).unwrap();
        assert!(whole == brute, "the whole frame differs from brute force");
        for height in [1, 2, 3, 5, 7, 8, 11] {
            let mut banded = vec![Rgb888::new(0, 0, 0); w * h];
            for (b, band) in banded.chunks_mut(w * height).enumerate() {
                assert_eq!(
                    frame.render_rows((b * height) as u32, band),
                    Ok((band.len() / w) as u32)
                );
            }
            assert!(banded == whole, "bands of {height} rows differ");
        }
        // Bands that do not start on a multiple of four.
        let mut odd = vec![Rgb888::new(0, 0, 0); w * h];
        let (top, rest) = odd.split_at_mut(w * 3);
        frame.render_rows(0, top).unwrap();
        frame.render_rows(3, rest).unwrap();
        assert!(odd == whole, "a band from row 3 differs");
        let rows: Vec<Rgb888> = (0..h as u32).flat_map(|j| frame.row(j)).collect();
        assert!(rows == whole, "the row iterator differs");
        // The dithered bands are the dithered pixels, whatever the band's height.
        let dithered: Vec<Rgb565> = (0..w * h)
            .map(|k| dither_rgb565(whole[k], (k % w) as u32, (k / w) as u32))
            .collect();
        for height in [1, 3, 8, 13] {
            let mut banded = vec![Rgb565::new(0, 0, 0); w * h];
            for (b, band) in banded.chunks_mut(w * height).enumerate() {
                frame
                    .render_rows_dithered((b * height) as u32, band)
                    .unwrap();
            }
            assert!(banded == dithered, "dithered bands of {height} rows differ");
        }
    }
}

/// The comparison can fail: the frame of a slightly different scene is told apart.
#[test]
fn a_different_scene_is_detected() {
    let camera = Camera::new(
        Vec3::new(0.0, 0.0, 5.0),
        Vec3::ZERO,
        Vec3::new(0.0, 1.0, 0.0),
        45.0,
        32,
        32,
    )
    .unwrap();
    let mut scene: Scene<1, 0> = Scene::new();
    scene.set_ambient(Color::splat(0.5)).unwrap();
    scene
        .add_sphere(Sphere::new(Vec3::ZERO, 1.0), Material::default())
        .unwrap();
    let mut other: Scene<1, 0> = Scene::new();
    other.set_ambient(Color::splat(0.5)).unwrap();
    other
        .add_sphere(Sphere::new(Vec3::ZERO, 1.05), Material::default())
        .unwrap();
    let options = RenderOptions::default();
    let (mut sa, mut sb) = (FrameStorage::new(), FrameStorage::new());
    let (a, b) = (
        Frame::new(&scene, &camera, options, &mut sa).unwrap(),
        Frame::new(&other, &camera, options, &mut sb).unwrap(),
    );
    let (mut x, mut y) = (
        vec![Rgb888::new(0, 0, 0); 32 * 32],
        vec![Rgb888::new(0, 0, 0); 32 * 32],
    );
    a.render(&mut x).unwrap();
    b.render_rows_brute(0, &mut y).unwrap();
    assert!(x != y, "the two scenes rendered the same image");
}

/// Every primary ray that the f32 test reports as a hit passes through its sphere's screen box,
/// ray by ray (one sample and a 3×3 grid per pixel), on spheres built to be hard to bound: tiny
/// and far ones through fields of view down to 0.01°, grounds of radius up to 10⁶ just below
/// the eye, spheres around, enclosing and grazing the eye, reaching behind it, and scenes
/// 10⁴ from the origin.
#[test]
fn screen_boxes_hold_every_hit() {
    let seeds: u64 = std::env::var("MICRORAY_SEEDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(300);
    let (mut hits, mut tested) = (0u64, 0u64);
    for seed in 0..seeds {
        let mut rng = Rng(seed.wrapping_mul(0xD1B5_4A32_D192_ED03) | 1);
        let shift = if rng.next().is_multiple_of(4) {
            rng.vec(1e4)
        } else {
            Vec3::ZERO
        };
        let eye = shift + rng.vec(5.0);
        let look = shift + rng.vec(5.0);
        let fov = libm::powf(10.0, rng.range_f32(-6.0, 2.23));
        let up = rng.vec(1.0);
        let (w, h) = (8 + (rng.next() % 40) as u32, 8 + (rng.next() % 40) as u32);
        let Ok(camera) = Camera::new(eye, look, up, fov, w, h) else {
            continue;
        };
        let mut scene: Box<Scene<24, 0>> = Box::new(Scene::new());
        for _ in 0..24 {
            // Towards a random image point, at a random distance.
            let toward = camera
                .direction(
                    rng.range_f32(-0.5, w as f32 + 0.5),
                    rng.range_f32(-0.5, h as f32 + 0.5),
                )
                .normalized()
                .unwrap();
            let dist = libm::powf(10.0, rng.range_f32(-1.0, 4.0));
            let (c, r) = match rng.next() % 6 {
                // Tiny to ordinary, anywhere from 0.1 to 10⁴ away, often just off the view.
                0 | 1 => {
                    let r = dist * libm::powf(10.0, rng.range_f32(-7.5, -0.5));
                    let off = rng.vec(r * 2.0);
                    (eye + toward * dist + off, r)
                }
                // A ground just below (or above) the eye.
                2 => {
                    let r = libm::powf(10.0, rng.range_f32(2.0, 6.0));
                    let n = rng
                        .vec(1.0)
                        .normalized()
                        .unwrap_or(Vec3::new(0.0, 1.0, 0.0));
                    let gap = libm::powf(10.0, rng.range_f32(-3.0, 0.5));
                    (eye - n * (r + gap), r)
                }
                // Around the eye: inside, outside, or within rounding of the surface.
                3 => {
                    let r = rng.range_f32(0.1, 5.0);
                    let n = rng
                        .vec(1.0)
                        .normalized()
                        .unwrap_or(Vec3::new(1.0, 0.0, 0.0));
                    let k = [1.0, 1.0 + 1e-6, 1.0 - 1e-6, rng.range_f32(0.5, 2.0)];
                    (eye + n * (r * k[(rng.next() % 4) as usize]), r)
                }
                // Beside the eye and reaching behind it.
                4 => {
                    let r = rng.range_f32(1.0, 50.0);
                    (eye + rng.vec(1.0) * (r * 1.5), r)
                }
                _ => (eye + toward * dist, dist * rng.range_f32(0.01, 0.9)),
            };
            scene
                .add_sphere(Sphere::new(c, r), Material::default())
                .unwrap();
        }
        let mut storage = FrameStorage::on_heap();
        let frame = Frame::new(&*scene, &camera, RenderOptions::default(), &mut storage).unwrap();
        for (s, sphere) in scene.spheres().iter().enumerate() {
            let k = Prepared::exact(camera.eye(), sphere);
            let b = frame.boxes()[s];
            for j in 0..h {
                for i in 0..w {
                    let rays = (0..9)
                        .map(|q| camera.view_ray(i, j, q % 3, q / 3, 3))
                        .chain([camera.view_ray(i, j, 0, 0, 1)]);
                    // The renderer's own primary rays: the same points, the direction not
                    // normalised (`Camera::direction`).
                    let (x, y) = (i as f32, j as f32);
                    let raw = (0..9)
                        .map(|q| {
                            let (a, b) = ((q % 3) as f32, (q / 3) as f32);
                            camera.direction(x + (a + 0.5) / 3.0, y + (b + 0.5) / 3.0)
                        })
                        .chain([camera.direction(x + 0.5, y + 0.5)])
                        .map(|d| Ray::new(camera.eye(), d));
                    for ray in rays.chain(raw) {
                        tested += 1;
                        if k.hit(ray.dir, f32::MIN_POSITIVE, f32::INFINITY).is_some() {
                            hits += 1;
                            assert!(
                                b.contains(i, j),
                                "seed {seed}: sphere {s} ({sphere:?}) hit through pixel \
                                 ({i}, {j}) outside its box {b:?}"
                            );
                        }
                    }
                }
            }
        }
    }
    // The test has something to check: a good share of the rays hit.
    assert!(hits * 20 > tested, "{hits} hits of {tested} rays");
}
