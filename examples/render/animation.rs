//! The renderer's animations: a view per frame (an orbit about the look-at point, or the scene
//! file's keyframes), each frame rendered as a still is, and the frames encoded as they come
//! into an animated PNG (exact pixels) or a GIF (256 colours a frame).

use std::cell::RefCell;
use std::io::Write;
use std::rc::Rc;

use embedded_graphics::pixelcolor::{Rgb888, RgbColor};
use microray::animation::{Orbit, View};
use microray::scene_file::Desktop;
use microray::Camera;

use crate::{Failure, Fallible};

/// Frames a second of the animations written.
pub const FPS: u16 = 15;

/// The output formats.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Format {
    Png,
    Gif,
}

/// How the camera moves over `n` frames.
pub enum Path<'a> {
    /// Frame `k` turned by `degrees · k / n`.
    Orbit(Orbit),
    /// The scene file's keyframes, frame `k` at time `k / (n − 1)`.
    Keyframes(&'a Desktop),
    /// The scene's own view in every frame (a still written as a one-frame GIF).
    Still(View),
}

impl Path<'_> {
    /// The camera of every frame, or the first frame whose view makes none (exit 2).
    pub fn cameras(&self, n: u32, (w, h): (u32, u32)) -> Result<Vec<Camera>, Failure> {
        (0..n)
            .map(|k| {
                let view = match self {
                    Path::Orbit(orbit) => Ok(orbit.view(k, n)),
                    Path::Keyframes(file) => file.keyframes.view(k, n),
                    Path::Still(view) => Ok(*view),
                };
                view.and_then(|v| v.camera(w, h))
                    .map_err(|e| Failure(2, format!("--frames: frame {k} of {n}: {e}")))
            })
            .collect()
    }
}

/// An animation encoder writing into memory, one frame at a time: the file is written whole
/// at the end, so a failure leaves no partial file.
pub struct Encoder {
    sink: Sink,
    kind: Kind,
}

enum Kind {
    Png(png::Writer<Sink>),
    Gif(gif::Encoder<Sink>),
}

/// The encoded bytes, shared with the encoder (which keeps its writer to the end).
#[derive(Clone, Default)]
struct Sink(Rc<RefCell<Fallible>>);

impl Write for Sink {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.0.borrow_mut().write(buf)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

impl Encoder {
    /// Starts an animation of `n` frames of `w × h`, looping forever.
    pub fn new(format: Format, n: u32, (w, h): (u32, u32)) -> Result<Self, Failure> {
        let fail = |e: &dyn std::fmt::Display| Failure(1, format!("encoding: {e}"));
        let sink = Sink::default();
        let kind = match format {
            Format::Png => {
                let mut encoder = png::Encoder::new(sink.clone(), w, h);
                encoder.set_color(png::ColorType::Rgb);
                encoder.set_depth(png::BitDepth::Eight);
                // Frames are written once and viewed often: the default level, not the fast one.
                encoder.set_compression(png::Compression::Balanced);
                encoder.set_animated(n, 0).map_err(|e| fail(&e))?;
                encoder.set_frame_delay(1, FPS).map_err(|e| fail(&e))?;
                Kind::Png(encoder.write_header().map_err(|e| fail(&e))?)
            }
            Format::Gif => {
                let (Ok(w), Ok(h)) = (u16::try_from(w), u16::try_from(h)) else {
                    return Err(Failure(
                        2,
                        format!("GIF images stop at 65535 pixels a side, not {w}x{h}"),
                    ));
                };
                let mut encoder =
                    gif::Encoder::new(sink.clone(), w, h, &[]).map_err(|e| fail(&e))?;
                encoder
                    .set_repeat(gif::Repeat::Infinite)
                    .map_err(|e| fail(&e))?;
                Kind::Gif(encoder)
            }
        };
        Ok(Encoder { sink, kind })
    }

    /// Appends a frame.
    pub fn frame(&mut self, (w, h): (u32, u32), image: &[Rgb888]) -> Result<(), Failure> {
        let fail = |e: &dyn std::fmt::Display| Failure(1, format!("encoding: {e}"));
        let rgb: Vec<u8> = image.iter().flat_map(|p| [p.r(), p.g(), p.b()]).collect();
        match &mut self.kind {
            Kind::Png(writer) => writer.write_image_data(&rgb).map_err(|e| fail(&e)),
            Kind::Gif(encoder) => {
                // NeuQuant's palette per frame; speed 10 is the crate's balance of quality
                // and time.
                let mut frame = gif::Frame::from_rgb_speed(w as u16, h as u16, &rgb, 10);
                frame.delay = (100 / FPS).max(1);
                encoder.write_frame(&frame).map_err(|e| fail(&e))
            }
        }
    }

    /// The encoded file.
    pub fn finish(self) -> Result<Vec<u8>, Failure> {
        let fail = |e: &dyn std::fmt::Display| Failure(1, format!("encoding: {e}"));
        match self.kind {
            Kind::Png(writer) => writer.finish().map_err(|e| fail(&e))?,
            // The trailer goes out when the encoder is dropped.
            Kind::Gif(encoder) => drop(encoder),
        }
        let sink = self.sink.0.take();
        if sink.short {
            return Err(Failure(1, "not enough memory for the animation".into()));
        }
        Ok(sink.bytes)
    }
}

/// The median and range of the frames' times, in ms.
pub fn summary(times: &[f64]) -> String {
    let mut t = times.to_vec();
    t.sort_by(|a, b| a.total_cmp(b));
    let Some((first, last)) = t.first().zip(t.last()) else {
        return "no frames".into();
    };
    let mid = t.len() / 2;
    let median = if t.len() % 2 == 1 {
        t[mid]
    } else {
        (t[mid - 1] + t[mid]) / 2.0
    };
    format!("median {median:.2} ms, range {first:.2}–{last:.2} ms")
}
