//! Renders a scene file once through `Frame::render_rows` (one thread, no PNG) and prints an
//! FNV-1a hash of its pixels: the target of `bench/instructions.sh`, which counts the
//! instructions of `render_once` under valgrind's callgrind. Instruction counts repeat exactly
//! for the same binary and scene whatever else the machine is doing, so two builds can be
//! compared on a noisy machine where timings cannot (they are not times: compare both).
//!
//! `cargo run --release --example instructions -- SCENE.toml`

use embedded_graphics::pixelcolor::{Rgb888, RgbColor};
use microray::scene_file;
use microray::{Frame, RenderOptions};

/// The measured part: every pixel of the frame, as the desktop renderer's bands do it.
#[inline(never)]
fn render_once(
    frame: &Frame<'_, { scene_file::SPHERES }, { scene_file::LIGHTS }>,
    pixels: &mut [Rgb888],
) -> Result<u32, microray::Error> {
    frame.render_rows(0, pixels)
}

fn main() -> Result<(), String> {
    let path = std::env::args()
        .nth(1)
        .ok_or("usage: instructions SCENE.toml")?;
    let file = scene_file::load(&path).map_err(|e| e.to_string())?;
    let camera = file
        .view
        .camera(file.width, file.height)
        .map_err(|e| e.to_string())?;
    let options = RenderOptions { ..file.options };
    let mut storage = microray::FrameStorage::on_heap();
    let frame =
        Frame::new(&file.scene, &camera, options, &mut storage).map_err(|e| e.to_string())?;
    let mut pixels = vec![Rgb888::BLACK; file.width as usize * file.height as usize];
    render_once(&frame, &mut pixels).map_err(|e| e.to_string())?;
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    for p in &pixels {
        for b in [p.r(), p.g(), p.b()] {
            hash = (hash ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
        }
    }
    println!("pixels={}", pixels.len());
    println!("pixel_hash={hash:016x}");
    Ok(())
}
