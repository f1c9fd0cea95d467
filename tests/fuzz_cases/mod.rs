//! The cases that the fuzz targets (`fuzz/`), their corpus replay (`tests/fuzz_replay.rs`) and
//! the seeded random tests (`tests/api_values.rs`, `tests/robustness.rs`) run, and the
//! invariants each checks by panicking: a case either fails with an error when it is built, or
//! renders, and then every way of rendering it gives the same pixels.
#![allow(dead_code)]

use arbitrary::{Arbitrary, Unstructured};
use embedded_graphics::mock_display::MockDisplay;
use embedded_graphics::pixelcolor::{Rgb565, Rgb888};
use embedded_graphics::prelude::*;
use embedded_graphics::primitives::Rectangle;
use microray::scene_file::parse;
use microray::{
    Camera, Color, Encoding, Error, Frame, FrameStorage, Light, Material, RenderOptions, Scene,
    Sphere, Vec3,
};

/// Values that break formulas written without care.
const SPECIAL: [f32; 16] = [
    0.0,
    -0.0,
    f32::NAN,
    f32::INFINITY,
    f32::NEG_INFINITY,
    f32::MIN_POSITIVE,
    1e-45,
    -1e-45,
    1e38,
    -1e38,
    f32::MAX,
    f32::MIN,
    1e19,
    1e-19,
    1.0,
    -1.0,
];

/// Any f32, weighted towards what a scene holds: a special value, any bit pattern, a
/// magnitude up to 10⁶, or one up to 5 (scene-sized).
#[derive(Debug, Clone, Copy)]
pub struct V(pub f32);

impl<'a> Arbitrary<'a> for V {
    fn arbitrary(u: &mut Unstructured<'a>) -> arbitrary::Result<Self> {
        Ok(V(match u.arbitrary::<u8>()? % 8 {
            0 => SPECIAL[(u.arbitrary::<u8>()? % 16) as usize],
            1 => f32::from_bits(u.arbitrary()?),
            2 => u.arbitrary::<i32>()? as f32 / 2048.0,
            _ => u.arbitrary::<i16>()? as f32 / 6553.6,
        }))
    }
}

/// A value in `lo..hi` three times in four, any [`V`] otherwise.
fn mostly(u: &mut Unstructured, lo: f32, hi: f32) -> arbitrary::Result<f32> {
    if u.arbitrary::<u8>()? % 4 == 0 {
        Ok(V::arbitrary(u)?.0)
    } else {
        Ok(lo + (hi - lo) * (u.arbitrary::<u16>()? as f32 / 65535.0))
    }
}

fn vec3(u: &mut Unstructured, lo: f32, hi: f32) -> arbitrary::Result<Vec3> {
    Ok(Vec3::new(
        mostly(u, lo, hi)?,
        mostly(u, lo, hi)?,
        mostly(u, lo, hi)?,
    ))
}

fn color(u: &mut Unstructured) -> arbitrary::Result<Color> {
    Ok(Color::new(
        mostly(u, 0.0, 1.0)?,
        mostly(u, 0.0, 1.0)?,
        mostly(u, 0.0, 1.0)?,
    ))
}

/// A library call sequence: a scene of up to 40 spheres and 10 lights (its capacity is 48 and
/// 8), a camera, options, and the bands to render it in.
#[derive(Debug)]
pub struct ApiCase {
    pub spheres: Vec<(Sphere, Material)>,
    pub lights: Vec<Light>,
    pub ambient: Color,
    pub background: Color,
    pub shadows: bool,
    pub max_depth: u8,
    pub camera: (Vec3, Vec3, Vec3, f32, u32, u32),
    pub options: RenderOptions,
    pub bands: Vec<u8>,
}

impl<'a> Arbitrary<'a> for ApiCase {
    fn arbitrary(u: &mut Unstructured<'a>) -> arbitrary::Result<Self> {
        // The camera and options first, so that they take the input's bytes and not the zeros
        // past its end. An ordinary camera three times in four; otherwise any of its values
        // may be wild.
        let wild = u.arbitrary::<u8>()? % 4 == 3;
        let pick = |u: &mut Unstructured<'a>, lo: f32, hi: f32| -> arbitrary::Result<f32> {
            if wild {
                mostly(u, lo, hi)
            } else {
                Ok(lo + (hi - lo) * (u.arbitrary::<u16>()? as f32 / 65535.0))
            }
        };
        let eye = Vec3::new(pick(u, -1.0, 1.0)?, pick(u, -1.0, 1.0)?, pick(u, 3.0, 9.0)?);
        let look = Vec3::new(
            pick(u, -0.5, 0.5)?,
            pick(u, -0.5, 0.5)?,
            pick(u, -0.5, 0.5)?,
        );
        let up = Vec3::new(pick(u, -0.2, 0.2)?, pick(u, 0.5, 1.0)?, pick(u, -0.2, 0.2)?);
        let fov = pick(u, 10.0, 120.0)?;
        let (w, h) = (u.int_in_range(1..=20)?, u.int_in_range(1..=14)?);
        let samples = if u.arbitrary::<u8>()? % 8 == 7 {
            u.arbitrary::<u8>()? % 20
        } else {
            u.int_in_range(1..=4)?
        };
        let srgb: bool = u.arbitrary()?;
        let mut lights = vec![];
        for _ in 0..u.int_in_range(0..=10)? {
            lights.push(if u.arbitrary()? {
                Light::Point {
                    position: vec3(u, -10.0, 10.0)?,
                    intensity: color(u)?,
                }
            } else {
                Light::Directional {
                    direction: vec3(u, -1.0, 1.0)?,
                    intensity: color(u)?,
                }
            });
        }
        let mut spheres = vec![];
        for _ in 0..u.int_in_range(0..=40)? {
            let centre = vec3(u, -4.0, 4.0)? + Vec3::new(0.0, 0.0, -4.0);
            let radius = mostly(u, 0.01, 2.0)?;
            let material = Material {
                diffuse: color(u)?,
                specular: color(u)?,
                shininess: mostly(u, 1.0, 200.0)?,
                mirror: if u.arbitrary::<u8>()? % 3 == 0 {
                    color(u)?
                } else {
                    Color::ZERO
                },
                refraction: if u.arbitrary::<u8>()? % 4 == 0 {
                    color(u)?
                } else {
                    Color::ZERO
                },
                ior: mostly(u, 0.5, 2.5)?,
            };
            spheres.push((Sphere::new(centre, radius), material));
        }
        Ok(ApiCase {
            spheres,
            lights,
            ambient: color(u)?,
            background: color(u)?,
            shadows: u.arbitrary::<u8>()? % 4 != 0,
            max_depth: u.int_in_range(0..=19)?,
            camera: (eye, look, up, fov, w, h),
            options: RenderOptions {
                samples,
                encoding: if srgb {
                    Encoding::Srgb
                } else {
                    Encoding::Linear
                },
            },
            bands: u.arbitrary()?,
        })
    }
}

/// How far a case got.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Reached {
    /// An error when the scene, the camera or the frame was built.
    Refused,
    /// Rendered, with at least one sphere and one light.
    RenderedLit,
    /// Rendered without a sphere or without a light.
    Rendered,
}

/// Builds `case` through the public API and checks what renders (panics on a violation):
/// how far it got, and how many values the scene rejected (a rejected value leaves the scene
/// as it was, so what was accepted still renders).
pub fn check_api(case: &ApiCase) -> (Reached, u32) {
    let mut scene: Scene<48, 8> = Scene::new();
    let mut rejected = 0;
    for &(sphere, material) in &case.spheres {
        rejected += scene.add_sphere(sphere, material).is_err() as u32;
    }
    for &light in &case.lights {
        rejected += scene.add_light(light).is_err() as u32;
    }
    rejected += scene.set_ambient(case.ambient).is_err() as u32;
    rejected += scene.set_background(case.background).is_err() as u32;
    scene.set_shadows(case.shadows);
    rejected += scene.set_max_depth(case.max_depth).is_err() as u32;
    let (eye, look, up, fov, w, h) = case.camera;
    let Ok(camera) = Camera::new(eye, look, up, fov, w, h) else {
        return (Reached::Refused, rejected);
    };
    let mut storage = Box::new(FrameStorage::new());
    let Ok(frame) = Frame::new(&scene, &camera, case.options, &mut storage) else {
        return (Reached::Refused, rejected);
    };
    check_frame(&frame, &case.bands);
    // The scene copied to other capacities renders the same pixels: one with room to spare,
    // and one of 8 spheres (whose frames build no sweeps) where it fits.
    let mut whole = vec![Rgb888::MAGENTA; (camera.width() * camera.height()) as usize];
    frame.render(&mut whole).unwrap();
    let mut roomy: Box<Scene<64, 8>> = Box::new(Scene::new());
    roomy.copy_from(&scene).unwrap();
    same_pixels(&roomy, &camera, case.options, &whole);
    let mut small: Scene<8, 8> = Scene::new();
    match small.copy_from(&scene) {
        Ok(()) => same_pixels(&small, &camera, case.options, &whole),
        Err(e) => {
            assert_eq!(e, Error::TooManySpheres);
            assert!(scene.spheres().len() > 8 && small.spheres().is_empty());
        }
    }
    let lit = !(scene.spheres().is_empty() || scene.lights().is_empty());
    (
        if lit {
            Reached::RenderedLit
        } else {
            Reached::Rendered
        },
        rejected,
    )
}

/// `scene` rendered by `Frame::render` gives the pixels `whole`.
fn same_pixels<const S: usize, const L: usize>(
    scene: &Scene<S, L>,
    camera: &Camera,
    options: RenderOptions,
    whole: &[Rgb888],
) {
    let mut storage = Box::new(FrameStorage::new());
    let frame = Frame::new(scene, camera, options, &mut storage).unwrap();
    let mut image = vec![Rgb888::new(1, 2, 3); whole.len()];
    frame.render(&mut image).unwrap();
    assert!(
        image == whole,
        "a copy at capacity {S} renders other pixels"
    );
}

/// Every way of rendering `frame` gives its pixels: `render` = brute force = bands of the
/// heights `bands` gives = `row` = `draw` = `pixels` of a rectangle = `draw_progressive`'s
/// final image, and the dithered rows = `draw_dithered`.
pub fn check_frame<const S: usize, const L: usize>(frame: &Frame<S, L>, bands: &[u8]) {
    let (w, h) = (frame.width(), frame.height());
    let n = (w * h) as usize;
    let mut whole = vec![Rgb888::MAGENTA; n];
    frame.render(&mut whole).unwrap();
    let mut brute = vec![Rgb888::new(1, 2, 3); n];
    assert_eq!(frame.render_rows_brute(0, &mut brute), Ok(h));
    assert!(whole == brute, "accelerated and brute force differ");
    let (mut first, mut k) = (0, 0);
    while first < h {
        let rows = (1 + bands.get(k).map_or(2, |&b| b % 5) as u32).min(h - first);
        let mut band = vec![Rgb888::MAGENTA; (rows * w) as usize];
        assert_eq!(frame.render_rows(first, &mut band), Ok(rows));
        let (a, b) = ((first * w) as usize, ((first + rows) * w) as usize);
        assert!(band[..] == whole[a..b], "band of {rows} rows at {first}");
        first += rows;
        k += 1;
    }
    let j = bands.first().map_or(0, |&b| b as u32 % h);
    let row: Vec<Rgb888> = frame.row(j).collect();
    assert!(
        row[..] == whole[(j * w) as usize..((j + 1) * w) as usize],
        "row {j}"
    );
    // Past the last row, or not whole rows: an error, nothing written.
    let mut past = vec![Rgb888::MAGENTA; w as usize];
    assert_eq!(frame.render_rows(h, &mut past), Err(Error::BufferSize));
    assert!(past.iter().all(|&p| p == Rgb888::MAGENTA));
    if w > 1 {
        let mut ragged = vec![Rgb888::MAGENTA; w as usize + 1];
        assert_eq!(frame.render_rows(0, &mut ragged), Err(Error::BufferSize));
    }
    let mut display = Recorder {
        size: Size::new(w, h),
        px: vec![None; n],
        drawn: 0,
    };
    frame.draw(&mut display).unwrap();
    assert_eq!(display.drawn as usize, n, "draw drew each pixel once");
    assert!(
        display.px.iter().zip(&whole).all(|(d, p)| *d == Some(*p)),
        "draw's pixels"
    );
    // A rectangle from the band bytes, anywhere (partly outside the frame too): its pixels,
    // row by row, are the rendered ones.
    let b = |k: usize| bands.get(k).copied().unwrap_or(0) as i32;
    let area = Rectangle::new(
        Point::new(b(0) % (w as i32 + 2) - 1, b(1) % (h as i32 + 2) - 1),
        Size::new(1 + b(2) as u32 % w, 1 + b(3) as u32 % h),
    );
    let inside = area.intersection(&Rectangle::new(Point::zero(), Size::new(w, h)));
    let pixels: Vec<Rgb888> = frame.pixels(&area).collect();
    let expected: Vec<Rgb888> = inside
        .points()
        .map(|p| whole[(p.y as u32 * w + p.x as u32) as usize])
        .collect();
    assert!(pixels == expected, "pixels of {area:?}");
    // The progressive path's final image.
    let mut display = Recorder {
        size: Size::new(w, h),
        px: vec![None; n],
        drawn: 0,
    };
    let p = frame
        .draw_progressive(&mut display, |_, _| core::ops::ControlFlow::Continue(()))
        .unwrap();
    assert!(p.is_complete());
    assert!(
        display.px.iter().zip(&whole).all(|(d, p)| *d == Some(*p)),
        "draw_progressive's final pixels"
    );
    let mut dithered = vec![Rgb565::BLACK; n];
    assert_eq!(frame.render_rows_dithered(0, &mut dithered), Ok(h));
    if w <= 64 && h <= 64 {
        let mut d565 = MockDisplay::<Rgb565>::new();
        frame.draw_dithered(&mut d565).unwrap();
        for (k, c) in dithered.iter().enumerate() {
            let p = Point::new((k as u32 % w) as i32, (k as u32 / w) as i32);
            assert_eq!(d565.get_pixel(p), Some(*c), "draw_dithered at {p:?}");
        }
    }
}

/// A display that records every pixel drawn, and how many were.
struct Recorder {
    size: Size,
    px: Vec<Option<Rgb888>>,
    drawn: u32,
}

impl OriginDimensions for Recorder {
    fn size(&self) -> Size {
        self.size
    }
}

impl DrawTarget for Recorder {
    type Color = Rgb888;
    type Error = core::convert::Infallible;
    fn draw_iter<I: IntoIterator<Item = Pixel<Rgb888>>>(
        &mut self,
        it: I,
    ) -> Result<(), Self::Error> {
        for Pixel(p, c) in it {
            let (w, h) = (self.size.width as i32, self.size.height as i32);
            assert!(
                (0..w).contains(&p.x) && (0..h).contains(&p.y),
                "drawn outside: {p:?}"
            );
            self.px[(p.y * w + p.x) as usize] = Some(c);
            self.drawn += 1;
        }
        Ok(())
    }
}

/// Parses scene text and, where it parses, renders a small frame of it every way
/// ([`check_frame`]). `Refused` where the text, the camera or the options are rejected.
pub fn check_scene_text(text: &str) -> Reached {
    let Ok(file) = parse::<64, 8>(text) else {
        return Reached::Refused;
    };
    let (w, h) = (file.width.min(24), file.height.min(16));
    let Ok(camera) = file.view.camera(w, h) else {
        return Reached::Refused;
    };
    let mut storage = Box::new(FrameStorage::new());
    let Ok(frame) = Frame::new(&file.scene, &camera, file.options, &mut storage) else {
        return Reached::Refused;
    };
    check_frame(&frame, &[1, 3, 0, 4]);
    if file.scene.spheres().is_empty() || file.scene.lights().is_empty() {
        Reached::Rendered
    } else {
        Reached::RenderedLit
    }
}

/// The scene file's bytes as the desktop renderer takes them: text or not, never a panic.
pub fn check_scene_bytes(bytes: &[u8]) -> Reached {
    match core::str::from_utf8(bytes) {
        Ok(text) => check_scene_text(text),
        Err(_) => Reached::Refused,
    }
}
