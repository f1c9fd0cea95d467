//! microray in a browser. The page (`index.html`, `main.js`) runs this crate built for
//! `wasm32-unknown-unknown` through the plain exports of `exports.rs`; the host's `reference`
//! binary calls the same [`render_rgba`], so that `test/canvas.mjs` can compare the canvas
//! with the host's pixels byte for byte.
//!
//! A scene file is read at a fixed capacity, [`SPHERES`] spheres and [`LIGHTS`] lights; frame
//! `k` of `n` follows the scene's keyframes if it has any, else an orbit about its look-at
//! point, as the desktop renderer's `--frames` does.

#![deny(unsafe_code)]

use embedded_graphics::pixelcolor::{Rgb888, RgbColor};
use microray::animation::{Orbit, View};
use microray::scene_file::{self, SceneFile};
use microray::{Frame, FrameStorage};

#[cfg(target_arch = "wasm32")]
mod exports;

/// The most spheres a scene may have here.
pub const SPHERES: usize = 64;
/// The most lights a scene may have here.
pub const LIGHTS: usize = 8;

/// A scene read from its file, ready to render any frame of its animation.
#[derive(Debug)]
pub struct Animation {
    file: Box<SceneFile<SPHERES, LIGHTS>>,
    storage: Box<FrameStorage<SPHERES, LIGHTS>>,
    pixels: Vec<Rgb888>,
}

impl Animation {
    /// Reads a scene file's text; the error is microray's one-line message (line and field).
    pub fn parse(toml: &str) -> Result<Animation, String> {
        let file = scene_file::parse::<SPHERES, LIGHTS>(toml).map_err(|e| e.to_string())?;
        let len = file.width as usize * file.height as usize;
        // An allocation that fails is an error to show, not a trap that ends the module.
        let mut pixels = Vec::new();
        pixels
            .try_reserve_exact(len)
            .map_err(|_| format!("no memory for a {}×{} image", file.width, file.height))?;
        pixels.resize(len, Rgb888::BLACK);
        Ok(Animation {
            file,
            storage: Box::new(FrameStorage::new()),
            pixels,
        })
    }

    /// Image width in pixels.
    pub fn width(&self) -> u32 {
        self.file.width
    }

    /// Image height in pixels.
    pub fn height(&self) -> u32 {
        self.file.height
    }

    /// The view of frame `k` of `n`: the scene's keyframes if it has any (`degrees` unused),
    /// else the file's view turned by `degrees · k / n` about the look-at point.
    pub fn view(&self, k: u32, n: u32, degrees: f32) -> Result<View, String> {
        if self.file.keyframes.keys().is_empty() {
            let orbit = Orbit {
                view: self.file.view,
                degrees,
            };
            Ok(orbit.view(k, n))
        } else {
            self.file.keyframes.view(k, n).map_err(|e| e.to_string())
        }
    }

    /// Renders frame `k` of `n` into `rgba`, replacing its contents: width × height × 4 bytes,
    /// rows from the top, alpha 255.
    pub fn render_rgba(
        &mut self,
        k: u32,
        n: u32,
        degrees: f32,
        rgba: &mut Vec<u8>,
    ) -> Result<(), String> {
        let camera = self
            .view(k, n, degrees)?
            .camera(self.file.width, self.file.height)
            .map_err(|e| format!("frame {k} of {n}: {e}"))?;
        let frame = Frame::new(
            &self.file.scene,
            &camera,
            self.file.options,
            &mut self.storage,
        )
        .map_err(|e| e.to_string())?;
        frame.render(&mut self.pixels).map_err(|e| e.to_string())?;
        rgba.clear();
        rgba.try_reserve_exact(self.pixels.len() * 4)
            .map_err(|_| "no memory for the RGBA image".to_string())?;
        rgba.extend(self.pixels.iter().flat_map(|p| [p.r(), p.g(), p.b(), 255]));
        Ok(())
    }
}

/// Frame `k` of `n` of a scene file's animation (an orbit of `degrees` without keyframes) as
/// (width, height, RGBA bytes): what the page draws on its canvas.
pub fn render_rgba(
    toml: &str,
    k: u32,
    n: u32,
    degrees: f32,
) -> Result<(u32, u32, Vec<u8>), String> {
    let mut animation = Animation::parse(toml)?;
    let mut rgba = Vec::new();
    animation.render_rgba(k, n, degrees, &mut rgba)?;
    Ok((animation.width(), animation.height(), rgba))
}
