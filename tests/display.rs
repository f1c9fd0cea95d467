//! Drawing onto displays, checked against `Frame::render` bit for bit with a display that
//! records every call: one window per frame, `Image` and `sub_image` placement, clipping at the
//! display's edge, colour conversion, dithering to each display colour, and the progressive
//! path (its passes, its final image, its progress and its early stop).

mod common;

use core::ops::ControlFlow;

use embedded_graphics::image::{Image, ImageDrawableExt};
use embedded_graphics::pixelcolor::{
    BinaryColor, Gray2, Gray4, Gray8, PixelColor, Rgb555, Rgb565, Rgb666, Rgb888,
};
use embedded_graphics::prelude::*;
use embedded_graphics::primitives::Rectangle;
use microray::output::{Dither, Progress};
use microray::scene_file::{self, Desktop};
use microray::{Frame, FrameStorage};

/// One call a display received.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Call {
    Contiguous(Rectangle),
    Solid(Rectangle),
    Iter,
}

/// A display of `size` that records its calls and keeps its pixels (clipped to its edges,
/// as embedded-graphics asks of a display).
struct Recorder<C> {
    size: Size,
    px: Vec<Option<C>>,
    calls: Vec<Call>,
    /// Pixels written, counting overdraw.
    writes: usize,
}

impl<C: PixelColor> Recorder<C> {
    fn new(w: u32, h: u32) -> Self {
        Recorder {
            size: Size::new(w, h),
            px: vec![None; (w * h) as usize],
            calls: Vec::new(),
            writes: 0,
        }
    }

    fn set(&mut self, p: Point, c: C) {
        if self.bounding_box().contains(p) {
            self.px[(p.y as u32 * self.size.width + p.x as u32) as usize] = Some(c);
        }
        self.writes += 1;
    }

    fn get(&self, x: u32, y: u32) -> Option<C> {
        self.px[(y * self.size.width + x) as usize]
    }
}

impl<C> OriginDimensions for Recorder<C> {
    fn size(&self) -> Size {
        self.size
    }
}

impl<C: PixelColor> DrawTarget for Recorder<C> {
    type Color = C;
    type Error = core::convert::Infallible;

    fn draw_iter<I: IntoIterator<Item = Pixel<C>>>(&mut self, it: I) -> Result<(), Self::Error> {
        self.calls.push(Call::Iter);
        for Pixel(p, c) in it {
            self.set(p, c);
        }
        Ok(())
    }

    fn fill_contiguous<I: IntoIterator<Item = C>>(
        &mut self,
        area: &Rectangle,
        colors: I,
    ) -> Result<(), Self::Error> {
        self.calls.push(Call::Contiguous(*area));
        let mut n = 0;
        for (p, c) in area.points().zip(colors) {
            self.set(p, c);
            n += 1;
        }
        assert_eq!(
            n,
            area.size.width * area.size.height,
            "{area:?}: as many colours as points"
        );
        Ok(())
    }

    fn fill_solid(&mut self, area: &Rectangle, c: C) -> Result<(), Self::Error> {
        self.calls.push(Call::Solid(*area));
        for p in area.points() {
            self.set(p, c);
        }
        Ok(())
    }
}

/// The scenes: the conformance scenes (supersampled, sRGB, mirrors, glass) and a hard case.
fn scenes() -> Vec<(String, Box<Desktop>)> {
    let mut names: Vec<String> = common::CONFORMANCE
        .iter()
        .map(|n| format!("tests/data/{n}.toml"))
        .collect();
    names.push("tests/hard/glass_grazing.toml".into());
    names
        .into_iter()
        .map(|path| {
            let file = scene_file::load(&path).unwrap_or_else(|e| panic!("{e}"));
            (path, file)
        })
        .collect()
}

/// Runs `f` on each scene's frame and its whole image from `Frame::render`.
fn each_frame(
    mut f: impl FnMut(&str, &Frame<'_, { scene_file::SPHERES }, { scene_file::LIGHTS }>, &[Rgb888]),
) {
    for (path, file) in scenes() {
        let mut storage = FrameStorage::on_heap();
        let frame = Frame::new(&file.scene, &file.camera, file.options, &mut storage).unwrap();
        let mut whole = vec![Rgb888::BLACK; (frame.width() * frame.height()) as usize];
        frame.render(&mut whole).unwrap();
        f(&path, &frame, &whole);
    }
}

#[test]
fn draw_is_one_window_over_the_frame() {
    each_frame(|path, frame, whole| {
        let (w, h) = (frame.width(), frame.height());
        let mut d = Recorder::<Rgb888>::new(w, h);
        frame.draw(&mut d).unwrap();
        assert_eq!(d.calls, [Call::Contiguous(frame.bounding_box())], "{path}");
        assert_eq!(d.writes, whole.len(), "{path}: each pixel once");
        for (k, p) in whole.iter().enumerate() {
            assert_eq!(d.px[k], Some(*p), "{path}: pixel {k}");
        }
        // The same through `Image` at the origin, and on a larger display.
        let mut big = Recorder::<Rgb888>::new(w + 7, h + 3);
        Image::new(frame, Point::zero()).draw(&mut big).unwrap();
        assert_eq!(
            big.calls,
            [Call::Contiguous(frame.bounding_box())],
            "{path}"
        );
        assert_eq!(
            big.get(w - 1, h - 1),
            Some(whole[whole.len() - 1]),
            "{path}"
        );
        assert_eq!(
            big.get(w, h),
            None,
            "{path}: nothing drawn outside the frame"
        );
    });
}

#[test]
fn images_and_sub_images_are_placed_and_clipped() {
    each_frame(|path, frame, whole| {
        let (w, h) = (frame.width() as i32, frame.height() as i32);
        let at = |x: i32, y: i32| whole[(y * w + x) as usize];
        // A display smaller than the frame, the image at an offset that pushes it past the
        // right and bottom edges, then past the left and top ones.
        let (dw, dh) = (w * 2 / 3, h * 3 / 4);
        for offset in [
            Point::new(dw / 2, dh / 3),
            Point::new(-w / 3, -h / 5),
            Point::new(w, 0),
        ] {
            let mut d = Recorder::<Rgb888>::new(dw as u32, dh as u32);
            Image::new(frame, offset).draw(&mut d).unwrap();
            let visible = Rectangle::new(offset, frame.size()).intersection(&d.bounding_box());
            if visible.is_zero_sized() {
                assert!(d.calls.is_empty(), "{path}: nothing visible, nothing drawn");
                continue;
            }
            assert_eq!(d.calls, [Call::Contiguous(visible)], "{path} at {offset:?}");
            assert_eq!(
                d.writes as u32,
                visible.size.width * visible.size.height,
                "{path}: only the visible pixels traced"
            );
            for p in visible.points() {
                let q = p - offset;
                assert_eq!(
                    d.get(p.x as u32, p.y as u32),
                    Some(at(q.x, q.y)),
                    "{path}: {p:?}"
                );
            }
        }
        // A sub-image, itself placed at an offset; and one reaching past the frame's corner.
        let area = Rectangle::new(
            Point::new(w / 5, h / 4),
            Size::new((w / 2) as u32, (h / 3) as u32),
        );
        let off = Point::new(3, 2);
        let mut d = Recorder::<Rgb888>::new(w as u32, h as u32);
        Image::new(&frame.sub_image(&area), off)
            .draw(&mut d)
            .unwrap();
        assert_eq!(
            d.calls,
            [Call::Contiguous(Rectangle::new(off, area.size))],
            "{path}"
        );
        for p in area.points() {
            let q = p - area.top_left + off;
            assert_eq!(
                d.get(q.x as u32, q.y as u32),
                Some(at(p.x, p.y)),
                "{path}: sub-image {p:?}"
            );
        }
        let corner = Rectangle::new(Point::new(w - 5, h - 4), Size::new(20, 20));
        let mut d = Recorder::<Rgb888>::new(w as u32, h as u32);
        Image::new(&frame.sub_image(&corner), Point::zero())
            .draw(&mut d)
            .unwrap();
        assert_eq!(
            d.calls,
            [Call::Contiguous(Rectangle::new(
                Point::zero(),
                Size::new(5, 4)
            ))],
            "{path}"
        );
        assert_eq!(d.get(4, 3), Some(at(w - 1, h - 1)), "{path}");
    });
}

#[test]
fn color_converted_images_reach_rgb565_panels() {
    each_frame(|path, frame, whole| {
        let (w, h) = (frame.width(), frame.height());
        let mut d = Recorder::<Rgb565>::new(w, h);
        Image::new(frame, Point::zero())
            .draw(&mut d.color_converted())
            .unwrap();
        assert_eq!(d.calls, [Call::Contiguous(frame.bounding_box())], "{path}");
        for (k, p) in whole.iter().enumerate() {
            assert_eq!(d.px[k], Some(Rgb565::from(*p)), "{path}: pixel {k}");
        }
    });
}

/// `draw_dithered` and `render_rows_dithered` onto colour `C`: each pixel `C::dither` of the
/// rendered pixel, by its place in the frame; one window.
fn check_dithered<C: Dither + core::fmt::Debug>(
    frame: &Frame<'_, { scene_file::SPHERES }, { scene_file::LIGHTS }>,
    whole: &[Rgb888],
    path: &str,
) {
    let (w, h) = (frame.width(), frame.height());
    let expected: Vec<C> = whole
        .iter()
        .enumerate()
        .map(|(k, &c)| C::dither(c, k as u32 % w, k as u32 / w))
        .collect();
    let mut d = Recorder::<C>::new(w, h);
    frame.draw_dithered(&mut d).unwrap();
    assert_eq!(d.calls, [Call::Contiguous(frame.bounding_box())], "{path}");
    assert!(
        d.px.iter().zip(&expected).all(|(a, b)| *a == Some(*b)),
        "{path}: draw_dithered"
    );
    let mut rows = vec![expected[0]; whole.len()];
    let band = (3 * w) as usize;
    for (b, chunk) in rows.chunks_mut(band).enumerate() {
        frame.render_rows_dithered(b as u32 * 3, chunk).unwrap();
    }
    assert!(rows == expected, "{path}: render_rows_dithered");
}

#[test]
fn dithering_onto_every_display_colour() {
    each_frame(|path, frame, whole| {
        check_dithered::<Rgb565>(frame, whole, path);
        check_dithered::<Rgb555>(frame, whole, path);
        check_dithered::<Rgb666>(frame, whole, path);
        check_dithered::<Rgb888>(frame, whole, path);
        check_dithered::<BinaryColor>(frame, whole, path);
        check_dithered::<Gray2>(frame, whole, path);
        check_dithered::<Gray4>(frame, whole, path);
        check_dithered::<Gray8>(frame, whole, path);
    });
}

#[test]
fn dithered_1_bit_keeps_gradients_that_a_threshold_loses() {
    // A smooth gradient: the plain conversion turns it into two flat areas; the dithered one
    // follows it, 16 × 16 tile by tile, within one pixel of a tile.
    let w = 64u32;
    let grey = |x: u32| (x * 255 / (w - 1)) as u8;
    let mut plain_levels = std::collections::BTreeSet::new();
    for x0 in (0..w).step_by(4) {
        let mut on = 0;
        for y in 0..4 {
            for x in x0..x0 + 4 {
                let c = Rgb888::new(grey(x), grey(x), grey(x));
                on += BinaryColor::dither(c, x, y).is_on() as u32;
                plain_levels.insert(BinaryColor::from(c).is_on());
            }
        }
        let mean: f64 = (x0..x0 + 4)
            .map(|x| grey(x) as f64 / 255.0 * 16.0)
            .sum::<f64>()
            / 4.0;
        assert!(
            (on as f64 - mean).abs() <= 1.0,
            "tile at {x0}: {on} on, expected about {mean}"
        );
    }
    assert_eq!(plain_levels.len(), 2);
}

#[test]
fn progressive_passes_end_in_the_plain_image() {
    each_frame(|path, frame, whole| {
        let (w, h) = (frame.width(), frame.height());
        let mut d = Recorder::<Rgb888>::new(w, h);
        let mut seen: Vec<Progress> = Vec::new();
        let mut after_pass0: Option<Vec<Option<Rgb888>>> = None;
        let last = frame
            .draw_progressive(&mut d, |d, p| {
                // The last call of pass 0 comes when its blocks are all drawn.
                if p.pass == 0 {
                    after_pass0 = Some(d.px.clone());
                }
                seen.push(p);
                ControlFlow::Continue(())
            })
            .unwrap();
        assert!(
            last.is_complete() && last.traced == w * h,
            "{path}: {last:?}"
        );
        for (k, p) in whole.iter().enumerate() {
            assert_eq!(d.px[k], Some(*p), "{path}: final pixel {k}");
        }
        // Progress: after each row of samples, monotone, the passes in order.
        assert!(
            seen.windows(2)
                .all(|p| p[0].traced < p[1].traced && p[0].pass <= p[1].pass),
            "{path}"
        );
        assert_eq!(
            seen.first().map(|p| (p.pass, p.traced)),
            Some((0, w.div_ceil(8))),
            "{path}"
        );
        // Pass 0 alone: 8 × 8 blocks, each of its top-left pixel's final colour, after 1/64
        // of the pixels are traced.
        let coarse = after_pass0.unwrap();
        let traced0 = seen.iter().rfind(|p| p.pass == 0).unwrap().traced;
        assert_eq!(traced0, w.div_ceil(8) * h.div_ceil(8), "{path}");
        for y in 0..h {
            for x in 0..w {
                let (bx, by) = (x & !7, y & !7);
                assert_eq!(
                    coarse[(y * w + x) as usize],
                    Some(whole[(by * w + bx) as usize]),
                    "{path}: pass 0 at ({x}, {y})"
                );
            }
        }
        // Blocks for the coarse passes, whole rows for the last: no pixel traced twice.
        let solid: u32 = d
            .calls
            .iter()
            .filter(|c| matches!(c, Call::Solid(_)))
            .count() as u32;
        let rows: Vec<Rectangle> = d
            .calls
            .iter()
            .filter_map(|c| match c {
                Call::Contiguous(r) => Some(*r),
                _ => None,
            })
            .collect();
        assert!(!d.calls.contains(&Call::Iter), "{path}");
        assert_eq!(rows.len() as u32, h / 2, "{path}: the odd rows streamed");
        assert!(
            rows.iter()
                .all(|r| r.size == Size::new(w, 1) && r.top_left.y % 2 == 1),
            "{path}"
        );
        assert_eq!(
            solid + rows.len() as u32 * w,
            w * h,
            "{path}: each pixel traced once"
        );
    });
}

#[test]
fn progressive_stops_when_asked_and_resumes_nothing() {
    each_frame(|path, frame, whole| {
        let (w, h) = (frame.width(), frame.height());
        for stop_after in [1, 7, 40] {
            let mut d = Recorder::<Rgb888>::new(w, h);
            let mut calls = 0;
            let last = frame
                .draw_progressive(&mut d, |_, _| {
                    calls += 1;
                    if calls == stop_after {
                        ControlFlow::Break(())
                    } else {
                        ControlFlow::Continue(())
                    }
                })
                .unwrap();
            assert_eq!(calls, stop_after, "{path}: no callback after the stop");
            assert!(!last.is_complete(), "{path}");
            let drawn_after_stop = d.calls.len();
            assert!(drawn_after_stop > 0);
            // Every pixel drawn so far shows a traced pixel's colour from the final image:
            // its block's top-left one.
            let finals: std::collections::HashSet<Rgb888> = whole.iter().copied().collect();
            assert!(d.px.iter().flatten().all(|c| finals.contains(c)), "{path}");
        }
    });
}

#[test]
fn progressive_reaches_grey_and_rgb565_displays() {
    each_frame(|path, frame, whole| {
        let (w, h) = (frame.width(), frame.height());
        let mut d = Recorder::<Rgb565>::new(w, h);
        frame
            .draw_progressive(&mut d, |_, _| ControlFlow::Continue(()))
            .unwrap();
        assert!(
            d.px.iter()
                .zip(whole)
                .all(|(a, b)| *a == Some(Rgb565::from(*b))),
            "{path}"
        );
        let mut g = Recorder::<Gray8>::new(w, h);
        frame
            .draw_progressive(&mut g, |_, _| ControlFlow::Continue(()))
            .unwrap();
        assert!(
            g.px.iter()
                .zip(whole)
                .all(|(a, b)| *a == Some(Gray8::from(*b))),
            "{path}"
        );
    });
}

#[test]
fn tiny_frames_and_odd_sizes() {
    // 1 × 1 up to sizes that are not multiples of 8: blocks clipped to the frame.
    let file: Box<Desktop> = scene_file::load("tests/data/lit.toml").unwrap();
    for (w, h) in [(1, 1), (1, 9), (9, 1), (13, 7), (17, 18)] {
        // The file's scene seen by a camera of this size (no copy of the file: at the desktop
        // capacity it is 1.3 MB, which an unoptimised clone moves through the stack).
        let camera = microray::Camera::new(
            file.camera.eye(),
            file.camera.eye() - file.camera.basis().2,
            microray::Vec3::new(0.0, 1.0, 0.0),
            40.0,
            w,
            h,
        )
        .unwrap();
        let mut storage = FrameStorage::on_heap();
        let frame = Frame::new(&file.scene, &camera, file.options, &mut storage).unwrap();
        let mut whole = vec![Rgb888::BLACK; (w * h) as usize];
        frame.render(&mut whole).unwrap();
        let mut d = Recorder::<Rgb888>::new(w, h);
        let p = frame
            .draw_progressive(&mut d, |_, _| ControlFlow::Continue(()))
            .unwrap();
        assert!(p.is_complete(), "{w}×{h}");
        assert!(
            d.px.iter().zip(&whole).all(|(a, b)| *a == Some(*b)),
            "{w}×{h}"
        );
        assert!(
            d.calls.iter().all(|c| match c {
                Call::Solid(r) | Call::Contiguous(r) =>
                    frame.bounding_box().contains(r.bottom_right().unwrap()),
                Call::Iter => false,
            }),
            "{w}×{h}: every block inside the frame"
        );
        let mut d = Recorder::<Rgb888>::new(w, h);
        frame.draw(&mut d).unwrap();
        assert!(
            d.px.iter().zip(&whole).all(|(a, b)| *a == Some(*b)),
            "{w}×{h}"
        );
    }
}
