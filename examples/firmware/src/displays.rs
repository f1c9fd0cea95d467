//! The display paths on the board: the one-window draw, the progressive draw and the dithered
//! draws to 1-bit and 4-bit grey, each checked against the plain render. Compiled by the
//! `displays` firmware and, unchanged, by the host test (`tests/firmware.rs`).
//!
//! The progressive draw repaints pixels pass after pass, so its final image cannot be folded
//! into a CRC in drawing order without a framebuffer (which the micro:bit has no room for).
//! [`Digest`] sums a hash of each pixel's position and final colour instead, an
//! order-independent digest: a pixel's final colour comes with the `fill_solid` block whose
//! top-left corner it is, or with a `fill_contiguous` row (the progressive path's last pass,
//! and the plain draw). The plain draw's digest must equal the progressive one.

use core::ops::ControlFlow;

use embedded_graphics::pixelcolor::{BinaryColor, Gray4, Rgb888, RgbColor};
use embedded_graphics::prelude::{
    Dimensions, DrawTarget, IntoStorage, OriginDimensions, Pixel, PixelColor, PointsIter, Size,
};
use embedded_graphics::primitives::Rectangle;
use microray::output::{Dither, Progress};
use microray::Frame;

use crate::scene::{Crc32, HEIGHT, LIGHTS, SPHERES, WIDTH};

/// The CRC-32 of the 1-bit dithered frame (one byte a pixel, 0 or 1), as the host computes it.
pub const EXPECTED_CRC32_BINARY: u32 = 0xed6dd2d4;
/// The CRC-32 of the 4-bit grey dithered frame (one byte a pixel, 0..=15).
pub const EXPECTED_CRC32_GRAY4: u32 = 0xb823b0c1;

/// fmix32 of MurmurHash3: every input bit reaches every output bit.
fn mix(mut h: u32) -> u32 {
    h ^= h >> 16;
    h = h.wrapping_mul(0x85eb_ca6b);
    h ^= h >> 13;
    h = h.wrapping_mul(0xc2b2_ae35);
    h ^ (h >> 16)
}

/// An order-independent digest of a frame's final pixels (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Digest {
    /// Sum and xor of the pixels' hashes (two independent folds).
    pub sum: u32,
    pub xor: u32,
    /// Final pixels seen (each once: `W × H` when complete).
    pub pixels: u32,
    /// `fill_contiguous` calls (windows) and `fill_solid` blocks.
    pub windows: u32,
    pub blocks: u32,
}

/// A display that keeps only a [`Digest`].
pub struct DigestDisplay {
    pub digest: Digest,
}

impl DigestDisplay {
    pub const fn new() -> Self {
        DigestDisplay {
            digest: Digest {
                sum: 0,
                xor: 0,
                pixels: 0,
                windows: 0,
                blocks: 0,
            },
        }
    }

    #[inline]
    fn fold(&mut self, x: i32, y: i32, c: Rgb888) {
        let at = y as u32 * WIDTH + x as u32;
        let rgb = (c.r() as u32) << 16 | (c.g() as u32) << 8 | c.b() as u32;
        let h = mix(mix(at.wrapping_mul(0x9e37_79b9)) ^ rgb);
        self.digest.sum = self.digest.sum.wrapping_add(h);
        self.digest.xor ^= mix(h ^ 0x5bd1_e995);
        self.digest.pixels += 1;
    }
}

impl OriginDimensions for DigestDisplay {
    fn size(&self) -> Size {
        Size::new(WIDTH, HEIGHT)
    }
}

impl DrawTarget for DigestDisplay {
    type Color = Rgb888;
    type Error = core::convert::Infallible;

    fn draw_iter<I: IntoIterator<Item = Pixel<Rgb888>>>(
        &mut self,
        it: I,
    ) -> Result<(), Self::Error> {
        for Pixel(p, c) in it {
            self.fold(p.x, p.y, c);
        }
        Ok(())
    }

    fn fill_contiguous<I: IntoIterator<Item = Rgb888>>(
        &mut self,
        area: &Rectangle,
        colors: I,
    ) -> Result<(), Self::Error> {
        self.digest.windows += 1;
        for (p, c) in area.points().zip(colors) {
            self.fold(p.x, p.y, c);
        }
        Ok(())
    }

    fn fill_solid(&mut self, area: &Rectangle, c: Rgb888) -> Result<(), Self::Error> {
        self.digest.blocks += 1;
        self.fold(area.top_left.x, area.top_left.y, c);
        Ok(())
    }
}

/// The plain draw's digest: one window, every pixel.
#[inline(never)]
pub fn plain_digest(frame: &Frame<'_, SPHERES, LIGHTS>) -> Digest {
    let mut d = DigestDisplay::new();
    let _ = frame.draw(&mut d);
    d.digest
}

/// The progressive draw's digest, and its last progress and number of progress calls.
#[inline(never)]
pub fn progressive_digest(frame: &Frame<'_, SPHERES, LIGHTS>) -> (Digest, Progress, u32) {
    let mut d = DigestDisplay::new();
    let mut calls = 0;
    let p = frame.draw_progressive(&mut d, |_, _| {
        calls += 1;
        ControlFlow::Continue(())
    });
    let p = p.unwrap_or(Progress {
        pass: 0,
        traced: 0,
        total: 1,
    });
    (d.digest, p, calls)
}

/// The progressive draw stopped by its callback once the first pass is done.
#[inline(never)]
pub fn progressive_stopped(frame: &Frame<'_, SPHERES, LIGHTS>) -> (Digest, Progress) {
    let mut d = DigestDisplay::new();
    let p = frame.draw_progressive(&mut d, |_, p| {
        if p.pass == 0 {
            ControlFlow::Continue(())
        } else {
            ControlFlow::Break(())
        }
    });
    let p = p.unwrap_or(Progress {
        pass: 0,
        traced: 0,
        total: 1,
    });
    (d.digest, p)
}

/// A display of colour `C` that folds each pixel's raw byte into a CRC-32, in drawing order.
pub struct CrcOf<C> {
    pub crc: Crc32,
    pub pixels: u32,
    pub windows: u32,
    color: core::marker::PhantomData<C>,
}

impl<C> OriginDimensions for CrcOf<C> {
    fn size(&self) -> Size {
        Size::new(WIDTH, HEIGHT)
    }
}

impl<C: PixelColor + IntoStorage<Storage = u8>> DrawTarget for CrcOf<C> {
    type Color = C;
    type Error = core::convert::Infallible;

    fn draw_iter<I: IntoIterator<Item = Pixel<C>>>(&mut self, it: I) -> Result<(), Self::Error> {
        for Pixel(_, c) in it {
            self.crc.update(&[c.into_storage()]);
            self.pixels += 1;
        }
        Ok(())
    }

    fn fill_contiguous<I: IntoIterator<Item = C>>(
        &mut self,
        area: &Rectangle,
        colors: I,
    ) -> Result<(), Self::Error> {
        self.windows += 1;
        if area.intersection(&self.bounding_box()) != *area {
            return Ok(()); // the frame is the display's size: never reached
        }
        for c in colors {
            self.crc.update(&[c.into_storage()]);
            self.pixels += 1;
        }
        Ok(())
    }
}

/// `draw_dithered` onto a display of colour `C`: CRC-32, pixels and windows.
#[inline(never)]
pub fn crc_dithered<C: Dither + IntoStorage<Storage = u8>>(
    frame: &Frame<'_, SPHERES, LIGHTS>,
) -> (u32, u32, u32) {
    let mut d = CrcOf::<C> {
        crc: Crc32::new(),
        pixels: 0,
        windows: 0,
        color: core::marker::PhantomData,
    };
    let _ = frame.draw_dithered(&mut d);
    (d.crc.value(), d.pixels, d.windows)
}

/// The 1-bit draw ([`crc_dithered`] for `BinaryColor`): a root of the panic check.
#[inline(never)]
pub fn crc_binary(frame: &Frame<'_, SPHERES, LIGHTS>) -> (u32, u32, u32) {
    crc_dithered::<BinaryColor>(frame)
}

/// The 4-bit grey draw ([`crc_dithered`] for `Gray4`): a root of the panic check.
#[inline(never)]
pub fn crc_gray4(frame: &Frame<'_, SPHERES, LIGHTS>) -> (u32, u32, u32) {
    crc_dithered::<Gray4>(frame)
}
