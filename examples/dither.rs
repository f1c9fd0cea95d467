//! Writes `docs/dither.png`: the firmware's benchmark scene converted to 16-bit `Rgb565` plainly
//! (left) and with 4×4 ordered dithering (right), each above a 4× zoom of the same crop, where
//! the plain conversion's bands and the dither's fine pattern are visible.
//!
//! `cargo run --example dither [out.png]`

#[allow(dead_code)]
#[path = "firmware/src/scene.rs"]
mod scene;

use embedded_graphics::pixelcolor::{Rgb565, Rgb888, RgbColor};
use microray::{output::dither_rgb565, Frame};
use tiny_skia::{Pixmap, PremultipliedColorU8};

const ZOOM: u32 = 4;
/// The crop that is zoomed: the small yellow sphere, its shadow and the shaded ground.
const CROP: (u32, u32, u32, u32) = (120, 150, 80, 40);

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "docs/dither.png".into());
    let mut scene = scene::BenchScene::new();
    scene::build_scene(&mut scene)?;
    let camera = scene::camera()?;
    let mut storage = microray::FrameStorage::new();
    let frame = Frame::new(&scene, &camera, scene::options(), &mut storage)?;
    let (w, h) = (frame.width(), frame.height());

    let plain = |i, j| Rgb888::from(Rgb565::from(frame.pixel(i, j)));
    let dithered = |i, j| Rgb888::from(dither_rgb565(frame.pixel(i, j), i, j));
    let (cx, cy, cw, ch) = CROP;
    let mut img = Pixmap::new(2 * w, h + ch * ZOOM).ok_or("image size")?;
    let iw = img.width();
    let px = img.pixels_mut();
    let mut put = |x: u32, y: u32, c: Rgb888| {
        px[(y * iw + x) as usize] =
            PremultipliedColorU8::from_rgba(c.r(), c.g(), c.b(), 255).unwrap();
    };
    for (panel, conv) in [&plain as &dyn Fn(u32, u32) -> Rgb888, &dithered]
        .into_iter()
        .enumerate()
    {
        let x0 = panel as u32 * w;
        for j in 0..h {
            for i in 0..w {
                put(x0 + i, j, conv(i, j));
            }
        }
        for j in 0..ch * ZOOM {
            for i in 0..cw * ZOOM {
                put(x0 + i, h + j, conv(cx + i / ZOOM, cy + j / ZOOM));
            }
        }
    }
    img.save_png(&out)?;
    println!("wrote {out}");
    Ok(())
}
