//! The library API under any `f32`: scenes, lights, cameras and options built from arbitrary
//! values (NaN, infinities, subnormals, ±0, 10³⁸, random bit patterns, ordinary magnitudes)
//! either fail with an `Error` when they are built or render without a panic, and what renders
//! is consistent: bands of any height, rows, `draw`, the brute-force reference and the dithered
//! paths all give the whole frame's pixels.

mod common;

use common::rng::Rng;
use embedded_graphics::pixelcolor::{Rgb565, Rgb888};
use embedded_graphics::prelude::*;
use microray::{
    Camera, Color, Encoding, Frame, FrameStorage, Light, Material, RenderOptions, Scene, Sphere,
    Vec3,
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

/// One value: special, any bit pattern, or an ordinary magnitude.
fn value(g: &mut Rng) -> f32 {
    match g.next() % 8 {
        0 => SPECIAL[(g.next() % SPECIAL.len() as u64) as usize],
        1 => f32::from_bits(g.next() as u32),
        2 => g.range_f32(-1e6, 1e6),
        _ => g.range_f32(-5.0, 5.0),
    }
}

fn vec3(g: &mut Rng) -> Vec3 {
    Vec3::new(value(g), value(g), value(g))
}

/// A colour, mostly in range.
fn color(g: &mut Rng) -> Color {
    if g.next() % 4 == 0 {
        Color::new(value(g), value(g), value(g))
    } else {
        Color::new(
            g.range_f32(0.0, 1.0),
            g.range_f32(0.0, 1.0),
            g.range_f32(0.0, 1.0),
        )
    }
}

type S = Scene<48, 8>;

/// What the case came to.
#[derive(Default, Debug)]
struct Outcomes {
    sphere_errors: u32,
    light_errors: u32,
    camera_errors: u32,
    option_errors: u32,
    rendered: u32,
    lit_spheres: u32,
}

/// A display that records every pixel drawn, and how often.
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

fn case(g: &mut Rng, out: &mut Outcomes) {
    let mut scene = S::new();
    for _ in 0..g.next() % 40 {
        let centre = if g.next() % 2 == 0 {
            vec3(g)
        } else {
            Vec3::new(
                g.range_f32(-4.0, 4.0),
                g.range_f32(-3.0, 3.0),
                g.range_f32(-8.0, 0.0),
            )
        };
        let radius = if g.next() % 3 == 0 {
            value(g)
        } else {
            g.range_f32(0.01, 2.0)
        };
        let material = Material {
            diffuse: color(g),
            specular: color(g),
            shininess: if g.next() % 4 == 0 {
                value(g)
            } else {
                g.range_f32(1.0, 200.0)
            },
            mirror: if g.next() % 3 == 0 {
                color(g)
            } else {
                Color::ZERO
            },
        };
        if scene
            .add_sphere(Sphere::new(centre, radius), material)
            .is_err()
        {
            out.sphere_errors += 1;
        }
    }
    for _ in 0..g.next() % 7 {
        let light = if g.next() % 2 == 0 {
            Light::Point {
                position: vec3(g),
                intensity: color(g),
            }
        } else {
            Light::Directional {
                direction: vec3(g),
                intensity: color(g),
            }
        };
        if scene.add_light(light).is_err() {
            out.light_errors += 1;
        }
    }
    let _ = scene.set_ambient(color(g));
    let _ = scene.set_background(color(g));
    scene.set_shadows(g.next() % 4 != 0);
    let _ = scene.set_max_depth((g.next() % 20) as u8);
    out.lit_spheres += (!scene.lights().is_empty() && !scene.spheres().is_empty()) as u32;

    let (w, h) = (1 + (g.next() % 20) as u32, 1 + (g.next() % 14) as u32);
    let eye = if g.next() % 3 == 0 {
        vec3(g)
    } else {
        Vec3::new(
            g.range_f32(-1.0, 1.0),
            g.range_f32(-1.0, 1.0),
            g.range_f32(3.0, 9.0),
        )
    };
    let look = if g.next() % 4 == 0 {
        vec3(g)
    } else {
        Vec3::ZERO
    };
    let up = if g.next() % 4 == 0 {
        vec3(g)
    } else {
        Vec3::new(0.0, 1.0, 0.0)
    };
    let fov = if g.next() % 4 == 0 {
        value(g)
    } else {
        g.range_f32(10.0, 120.0)
    };
    let Ok(camera) = Camera::new(eye, look, up, fov, w, h) else {
        out.camera_errors += 1;
        return;
    };
    let options = RenderOptions {
        samples: (g.next() % 5) as u8,
        encoding: if g.next() % 2 == 0 {
            Encoding::Linear
        } else {
            Encoding::Srgb
        },
    };
    let mut storage = Box::new(FrameStorage::new());
    let Ok(frame) = Frame::new(&scene, &camera, options, &mut storage) else {
        out.option_errors += 1;
        return;
    };
    let n = (w * h) as usize;
    let mut whole = vec![Rgb888::MAGENTA; n];
    frame.render(&mut whole).unwrap();
    let mut brute = vec![Rgb888::new(1, 2, 3); n];
    assert_eq!(frame.render_rows_brute(0, &mut brute), Ok(h));
    assert!(whole == brute, "accelerated and brute force differ");
    // Bands of random heights, and single rows through `row`.
    let mut first = 0;
    while first < h {
        let rows = (1 + g.next() % 5).min((h - first) as u64) as u32;
        let mut band = vec![Rgb888::MAGENTA; (rows * w) as usize];
        assert_eq!(frame.render_rows(first, &mut band), Ok(rows));
        assert!(
            band[..] == whole[(first * w) as usize..((first + rows) * w) as usize],
            "band at {first}"
        );
        first += rows;
    }
    let j = (g.next() % h as u64) as u32;
    let row: Vec<Rgb888> = frame.row(j).collect();
    assert!(
        row[..] == whole[(j * w) as usize..((j + 1) * w) as usize],
        "row {j}"
    );
    // Past the last row, or not whole rows: an error, nothing written.
    let mut past = vec![Rgb888::MAGENTA; w as usize];
    assert_eq!(
        frame.render_rows(h, &mut past),
        Err(microray::Error::BufferSize)
    );
    assert!(past.iter().all(|&p| p == Rgb888::MAGENTA));
    if w > 1 {
        let mut ragged = vec![Rgb888::MAGENTA; w as usize + 1];
        assert_eq!(
            frame.render_rows(0, &mut ragged),
            Err(microray::Error::BufferSize)
        );
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
    let mut dithered = vec![Rgb565::BLACK; n];
    assert_eq!(frame.render_rows_dithered(0, &mut dithered), Ok(h));
    let mut d565 = embedded_graphics::mock_display::MockDisplay::<Rgb565>::new();
    d565.set_allow_overdraw(false);
    if w <= 64 && h <= 64 {
        frame.draw_dithered(&mut d565).unwrap();
        for (k, c) in dithered.iter().enumerate() {
            let p = Point::new((k as u32 % w) as i32, (k as u32 / w) as i32);
            assert_eq!(d565.get_pixel(p), Some(*c), "draw_dithered at {p:?}");
        }
    }
    out.rendered += 1;
}

/// A few thousand cases from a fixed seed (`MICRORAY_API_CASES` for more).
#[test]
fn arbitrary_values_fail_cleanly_or_render_consistently() {
    let cases: u32 = std::env::var("MICRORAY_API_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(3000);
    let mut g = Rng(0x2545_f491_4f6c_dd1d);
    let mut out = Outcomes::default();
    for k in 0..cases {
        let state = g.0;
        let result =
            std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| case(&mut g, &mut out)));
        assert!(result.is_ok(), "case {k} (Rng({state:#x})) panicked");
    }
    eprintln!("{out:?}");
    // Every way out is taken, and most cases reach the renderer with lights and spheres.
    assert!(out.rendered > cases / 3, "{out:?}");
    assert!(out.lit_spheres > cases / 2, "{out:?}");
    for n in [
        out.sphere_errors,
        out.light_errors,
        out.camera_errors,
        out.option_errors,
    ] {
        assert!(n > cases / 50, "{out:?}");
    }
}
