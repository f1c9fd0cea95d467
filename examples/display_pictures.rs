//! Writes the README's pictures of the display paths, drawn through embedded-graphics
//! displays kept in memory:
//!
//! - `docs/progressive.png`: `Frame::draw_progressive` after each of its four passes (8 × 8,
//!   4 × 4, 2 × 2 blocks, then the final image) with the share of pixels traced;
//! - `docs/displays.png`: the same frame on a 16-bit panel (dithered `Rgb565`), a 16-level
//!   grey OLED (`Gray4`), and a 1-bit OLED or e-paper (`BinaryColor`), thresholded as a plain
//!   conversion does and dithered.
//!
//! `cargo run --release --example display_pictures [OUT_DIR]` (default `docs`).

#[allow(dead_code)]
#[path = "firmware/src/scene.rs"]
mod scene;

use core::ops::ControlFlow;

use embedded_graphics::mono_font::{ascii::FONT_6X10, MonoTextStyle};
use embedded_graphics::pixelcolor::{BinaryColor, Gray4, Rgb565, Rgb888, RgbColor};
use embedded_graphics::prelude::*;
use embedded_graphics::text::Text;
use microray::{Camera, Frame, FrameStorage, Vec3};
use tiny_skia::{Pixmap, PremultipliedColorU8};

/// The frame's size: a small display's.
const W: u32 = 160;
const H: u32 = 120;
/// Each panel is shown at this zoom, so that the blocks and the dither pattern are visible.
const ZOOM: u32 = 2;
/// Room under each panel for its caption.
const CAPTION: u32 = 14;

/// An in-memory display of any colour, kept as the `Rgb888` it shows.
struct Screen<C> {
    px: Vec<Rgb888>,
    color: core::marker::PhantomData<C>,
}

impl<C> Screen<C> {
    fn new() -> Self {
        Screen {
            px: vec![Rgb888::BLACK; (W * H) as usize],
            color: core::marker::PhantomData,
        }
    }
}

impl<C> OriginDimensions for Screen<C> {
    fn size(&self) -> Size {
        Size::new(W, H)
    }
}

impl<C: PixelColor + Into<Rgb888>> DrawTarget for Screen<C> {
    type Color = C;
    type Error = core::convert::Infallible;

    fn draw_iter<I: IntoIterator<Item = Pixel<C>>>(&mut self, it: I) -> Result<(), Self::Error> {
        for Pixel(p, c) in it {
            if self.bounding_box().contains(p) {
                self.px[(p.y as u32 * W + p.x as u32) as usize] = c.into();
            }
        }
        Ok(())
    }
}

/// A sheet of captioned panels, `cols` wide.
struct Sheet {
    img: Pixmap,
    cols: u32,
    n: u32,
}

impl Sheet {
    fn new(cols: u32, rows: u32) -> Result<Self, &'static str> {
        let (pw, ph) = (W * ZOOM, H * ZOOM + CAPTION);
        let mut img = Pixmap::new(cols * pw, rows * ph).ok_or("image size")?;
        img.fill(tiny_skia::Color::WHITE);
        Ok(Sheet { img, cols, n: 0 })
    }

    fn add(&mut self, px: &[Rgb888], caption: &str) {
        let (pw, ph) = (W * ZOOM, H * ZOOM + CAPTION);
        let (x0, y0) = ((self.n % self.cols) * pw, (self.n / self.cols) * ph);
        self.n += 1;
        let iw = self.img.width();
        let put = |img: &mut Pixmap, x: u32, y: u32, c: Rgb888| {
            img.pixels_mut()[(y * iw + x) as usize] =
                PremultipliedColorU8::from_rgba(c.r(), c.g(), c.b(), 255).unwrap();
        };
        for y in 0..H * ZOOM {
            for x in 0..W * ZOOM {
                put(
                    &mut self.img,
                    x0 + x,
                    y0 + y,
                    px[((y / ZOOM) * W + x / ZOOM) as usize],
                );
            }
        }
        // The caption, drawn with embedded-graphics' own font into a strip.
        let mut strip = Screen::<Rgb888>::new();
        strip.px.iter_mut().for_each(|p| *p = Rgb888::WHITE);
        let style = MonoTextStyle::new(&FONT_6X10, Rgb888::BLACK);
        let _ = Text::new(caption, Point::new(2, 9), style).draw(&mut strip);
        for y in 0..CAPTION.min(H) {
            for x in 0..(W * ZOOM).min(W) {
                put(
                    &mut self.img,
                    x0 + x,
                    y0 + H * ZOOM + y,
                    strip.px[(y * W + x) as usize],
                );
            }
        }
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = std::env::args().nth(1).unwrap_or_else(|| "docs".into());
    let mut scene = scene::BenchScene::new();
    scene::build_scene(&mut scene)?;
    // The firmware's view, at a small display's size.
    let camera = Camera::new(
        Vec3::new(0.0, 1.6, 6.0),
        Vec3::new(0.0, 0.7, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
        45.0,
        W,
        H,
    )?;
    let mut storage = FrameStorage::new();
    let frame = Frame::new(&scene, &camera, scene::options(), &mut storage)?;

    // The progressive passes: a snapshot at the last callback of each.
    let mut screen = Screen::<Rgb565>::new();
    let mut shots: Vec<(u8, u32, Vec<Rgb888>)> = Vec::new();
    let total = W * H;
    frame.draw_progressive(&mut screen, |s, p| {
        match shots.last_mut() {
            Some(last) if last.0 == p.pass => *last = (p.pass, p.traced, s.px.clone()),
            _ => shots.push((p.pass, p.traced, s.px.clone())),
        }
        ControlFlow::Continue(())
    })?;
    let mut sheet = Sheet::new(4, 1)?;
    for (pass, traced, px) in &shots {
        let b = 8 >> pass;
        let share = *traced as f64 / total as f64;
        let label = if *traced == total {
            "final, all traced".to_string()
        } else {
            format!("{b}x{b} blocks, {:.1}% traced", 100.0 * share)
        };
        sheet.add(px, &label);
    }
    let out = format!("{dir}/progressive.png");
    sheet.img.save_png(&out)?;
    println!("wrote {out}");

    // One frame on four kinds of display.
    let mut sheet = Sheet::new(2, 2)?;
    let mut rgb565 = Screen::<Rgb565>::new();
    frame.draw_dithered(&mut rgb565)?;
    sheet.add(&rgb565.px, "Rgb565, dithered");
    let mut gray4 = Screen::<Gray4>::new();
    frame.draw_dithered(&mut gray4)?;
    sheet.add(&gray4.px, "Gray4, dithered");
    let mut threshold = Screen::<BinaryColor>::new();
    frame.draw(&mut threshold)?;
    sheet.add(&threshold.px, "BinaryColor, plain");
    let mut binary = Screen::<BinaryColor>::new();
    frame.draw_dithered(&mut binary)?;
    sheet.add(&binary.px, "BinaryColor, dithered");
    let out = format!("{dir}/displays.png");
    sheet.img.save_png(&out)?;
    println!("wrote {out}");
    Ok(())
}
