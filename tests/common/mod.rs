//! Helpers shared by the integration tests: rendering scene files and comparing images.
#![allow(dead_code)]

pub mod cli;
pub mod rng;

/// The conformance scenes in tests/data (NAME.toml with its expected NAME.png).
pub const CONFORMANCE: [&str; 9] = [
    "flat",
    "lit",
    "mirror",
    "room",
    "supersampled_srgb",
    "tilted",
    "glass",
    "glass_inside",
    "glass_mirror",
];

use embedded_graphics::pixelcolor::{Rgb888, RgbColor};
use microray::scene_file::{self, Desktop};
use microray::Frame;

/// An 8-bit RGB image.
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<[u8; 3]>,
}

/// Reads a PNG into RGB (it must be opaque).
pub fn read_png(path: &str) -> Image {
    let pixmap = tiny_skia::Pixmap::load_png(path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let pixels = pixmap
        .pixels()
        .iter()
        .map(|p| {
            assert_eq!(p.alpha(), 255, "{path}: expected an opaque image");
            [p.red(), p.green(), p.blue()]
        })
        .collect();
    Image {
        width: pixmap.width(),
        height: pixmap.height(),
        pixels,
    }
}

/// Renders a scene file the way the desktop renderer does (same parser, same band API).
pub fn render_file(path: &str) -> Image {
    let file: Box<Desktop> = scene_file::load(path).unwrap_or_else(|e| panic!("{e}"));
    render(&file)
}

pub fn render(file: &Desktop) -> Image {
    let mut storage = microray::FrameStorage::on_heap();
    let frame = Frame::new(&file.scene, &file.camera, file.options, &mut storage).unwrap();
    let (w, h) = (file.camera.width(), file.camera.height());
    let mut buf = vec![Rgb888::BLACK; (w * h) as usize];
    frame.render(&mut buf).unwrap();
    Image {
        width: w,
        height: h,
        pixels: buf.iter().map(|p| [p.r(), p.g(), p.b()]).collect(),
    }
}

/// How many pixels differ by more than 1 and by more than 8 levels in some channel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Diff {
    pub total: usize,
    pub over1: usize,
    pub over8: usize,
    pub max: u8,
}

pub fn diff(a: &Image, b: &Image) -> Diff {
    assert_eq!(
        (a.width, a.height),
        (b.width, b.height),
        "image sizes differ"
    );
    let mut d = Diff {
        total: a.pixels.len(),
        over1: 0,
        over8: 0,
        max: 0,
    };
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        let m = (0..3).map(|c| p[c].abs_diff(q[c])).max().unwrap();
        d.max = d.max.max(m);
        d.over1 += (m > 1) as usize;
        d.over8 += (m > 8) as usize;
    }
    d
}

pub mod reference;

/// The f32 image against the f64 reference, with the edges and tangents excused.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Agreement {
    pub total: usize,
    /// Pixels that differ by more than 1 level but change in f64 when the ray moves by 2 ulp.
    pub excused: usize,
    /// Pixels, not excused, off by more than 1 and by more than 8 levels, and the largest error.
    pub over1: usize,
    pub over8: usize,
    pub max: u8,
    /// Pixels that are not the background colour in the reference (the scene is not empty).
    pub covered: usize,
}

impl Agreement {
    /// The goal: no pixel off by more than 8, ≥ 99.5% within 1 (excused pixels left out).
    pub fn holds(&self) -> bool {
        let n = (self.total - self.excused) as f64;
        self.over8 == 0 && self.over1 as f64 <= 0.005 * n
    }
}

/// Compares microray's image with the reference's for the same scene.
pub fn agreement(file: &Desktop, got: &Image) -> Agreement {
    let r = reference::Reference::new(file);
    let want = r.render();
    let bg = r.pixel_background();
    let mut a = Agreement {
        total: want.len(),
        excused: 0,
        over1: 0,
        over8: 0,
        max: 0,
        covered: want.iter().filter(|p| **p != bg).count(),
    };
    for (k, (p, q)) in got.pixels.iter().zip(&want).enumerate() {
        let m = (0..3).map(|c| p[c].abs_diff(q[c])).max().unwrap();
        if m <= 1 {
            continue;
        }
        let (i, j) = (k as u32 % r.width, k as u32 / r.width);
        if r.sensitive(i, j) {
            a.excused += 1;
            continue;
        }
        a.max = a.max.max(m);
        a.over1 += 1;
        a.over8 += (m > 8) as usize;
    }
    a
}

/// Writes an image as a PNG (for looking at a failing case).
pub fn write_png(img: &Image, path: &str) {
    let mut pm = tiny_skia::Pixmap::new(img.width, img.height).unwrap();
    for (dst, p) in pm.pixels_mut().iter_mut().zip(&img.pixels) {
        *dst = tiny_skia::PremultipliedColorU8::from_rgba(p[0], p[1], p[2], 255).unwrap();
    }
    pm.save_png(path).unwrap();
}
