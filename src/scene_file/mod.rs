//! The TOML scene format (feature `scene-file`, needs std): all of it is in this module
//! (`raw.rs`: the tables as TOML reads them; `build.rs`: validation into a scene).
//!
//! ```toml
//! [camera]            # eye, look_at required; up = [0,1,0]; vfov = 60 (0 < vfov < 180)
//! eye = [0, 1, 6]
//! look_at = [0, 0.5, 0]
//! [render]            # all optional: width = 640, height = 480 (1..=16384), background = 0,
//! width = 320         # ambient = 0, shadows = true, max_depth = 3 (0..=16),
//! height = 240        # samples = 1 (1..=16, per axis), encoding = "linear" | "srgb"
//! [[sphere]]          # center, radius (> 0) required; diffuse = 1, specular = 0,
//! center = [0, 0, 0]  # shininess = 32 (> 0), mirror = 0, refraction = 0,
//! radius = 1.0        # ior = 1.5 (> 0)
//! diffuse = [0.8, 0.2, 0.2]
//! [[light]]           # kind = "point" + position, or kind = "directional" + direction (≠ 0);
//! kind = "point"      # intensity = 1
//! position = [3, 5, 4]
//! [[keyframe]]        # optional, none or 2..=64: at (0 first, increasing, ≤ 1) required;
//! at = 0.0            # eye, look_at, up and vfov default to the camera's. The renderer's
//! [[keyframe]]        # --frames N interpolates them linearly (frame k at k / (N − 1)).
//! at = 1.0
//! eye = [4, 1, 4]
//! ```
//!
//! Colours take `[r, g, b]` or one number for all three; integers and floats both work. Every
//! error names the field, and the line where the parser knows it.
//!
//! ```
//! use microray::scene_file::{parse, Desktop};
//! let file = parse::<1024, 32>("[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\n")?;
//! assert_eq!((file.width, file.height), (640, 480));
//! let err = parse::<1024, 32>("[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 5]\n").unwrap_err();
//! assert_eq!(err.to_string(), "line 3: camera.look_at: eye and look_at must differ");
//! # let _: Option<Desktop> = None;
//! # Ok::<(), microray::scene_file::SceneError>(())
//! ```

use std::boxed::Box;
use std::fmt;
use std::ops::Range;
use std::path::Path;
use std::string::{String, ToString};
use std::vec::Vec;
use std::{format, vec};

use serde::de::{self, Deserializer, SeqAccess, Visitor};
use serde::Deserialize;
use toml::Spanned;

use crate::animation::{Keyframe, Keyframes};
use crate::camera::{Camera, MAX_SIZE};
use crate::error::Error;
use crate::geometry::Sphere;
use crate::math::{Color, Vec3};
use crate::render::{Encoding, RenderOptions};
use crate::scene::{Light, Material, Scene};

mod build;
mod raw;

use build::*;
use raw::*;

/// The desktop renderer's sphere capacity ([`Desktop`]); a scene file with more spheres is
/// [`SceneError`] naming the sphere that does not fit.
pub const SPHERES: usize = 16384;

/// The desktop renderer's light capacity ([`Desktop`]).
pub const LIGHTS: usize = 32;

/// The desktop renderer's scene: [`SPHERES`] spheres and [`LIGHTS`] lights.
pub type Desktop = SceneFile<SPHERES, LIGHTS>;

/// A scene file, read and checked: the scene, its camera and how to render it.
#[derive(Debug, Clone)]
pub struct SceneFile<const S: usize, const L: usize> {
    /// Spheres, lights and global shading settings.
    pub scene: Scene<S, L>,
    /// The camera for the file's `width` × `height`.
    pub camera: Camera,
    /// Eye, look-at, up and vertical field of view, to rebuild the camera at another size.
    pub view: View,
    /// Image width from the file (or 640).
    pub width: u32,
    /// Image height from the file (or 480).
    pub height: u32,
    /// Samples and encoding.
    pub options: RenderOptions,
    /// The camera's keyframes, if the file has any (then at least two).
    pub keyframes: Keyframes<KEYFRAMES>,
}

impl<const S: usize, const L: usize> SceneFile<S, L> {
    /// An empty file to fill in place (`build.rs`): its camera and view are placeholders.
    const EMPTY: Self = SceneFile {
        scene: Scene::new(),
        camera: Camera::PLACEHOLDER,
        view: View {
            eye: Vec3::ZERO,
            look_at: Vec3::ZERO,
            up: Vec3::ZERO,
            vfov: 0.0,
        },
        width: 0,
        height: 0,
        options: RenderOptions {
            samples: 1,
            encoding: Encoding::Linear,
        },
        keyframes: Keyframes::new(),
    };
}

pub use crate::animation::View;

/// The keyframe capacity of a scene file.
pub const KEYFRAMES: usize = 64;

/// Why a scene file was rejected: where (file, line), which field, and what is wrong.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SceneError {
    /// The file, once known (set by [`load`]).
    pub file: Option<String>,
    /// 1-based line, where the parser knows it.
    pub line: Option<usize>,
    /// The field, such as `sphere[2].radius`, where one is to blame.
    pub field: Option<String>,
    /// What is wrong.
    pub message: String,
    /// Whether reading the file failed (as opposed to its contents being invalid).
    pub io: bool,
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut sep = "";
        if let Some(file) = &self.file {
            write!(f, "{file}")?;
            sep = ":";
        }
        if let Some(line) = self.line {
            write!(
                f,
                "{sep}{}line {line}",
                if sep.is_empty() { "" } else { " " }
            )?;
            sep = ":";
        }
        if let Some(field) = &self.field {
            write!(f, "{sep}{}{field}", if sep.is_empty() { "" } else { " " })?;
            sep = ":";
        }
        write!(
            f,
            "{sep}{}{}",
            if sep.is_empty() { "" } else { " " },
            self.message
        )
    }
}

impl std::error::Error for SceneError {}

/// Reads and checks a scene file; the error names the file. A file that cannot be read is an
/// I/O error (`io`); one that is not UTF-8 text is invalid input, located by line and byte
/// offset.
///
/// The file comes boxed: it is built in place on the heap, since a [`Desktop`] file is over a
/// megabyte, which a thread's stack should not hold.
///
/// ```
/// let err = microray::scene_file::load::<4, 1>("no/such/scene.toml").unwrap_err();
/// assert!(err.io && err.to_string().starts_with("no/such/scene.toml: "));
///
/// let path = std::env::temp_dir().join("microray-doc-not-text.toml");
/// std::fs::write(&path, b"[camera]\neye = \xff\n").unwrap();
/// let err = microray::scene_file::load::<4, 1>(&path).unwrap_err();
/// assert!(!err.io);
/// assert!(err.to_string().ends_with("line 2: not UTF-8 text (byte offset 15)"));
/// # std::fs::remove_file(&path).unwrap();
/// ```
pub fn load<const S: usize, const L: usize>(
    path: impl AsRef<Path>,
) -> Result<Box<SceneFile<S, L>>, SceneError> {
    let path = path.as_ref();
    let name = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| SceneError {
        file: Some(name.clone()),
        line: None,
        field: None,
        message: e.to_string(),
        io: true,
    })?;
    // Bytes that are not text are invalid input, not a failure to read.
    let text = core::str::from_utf8(&bytes).map_err(|e| {
        let at = e.valid_up_to();
        SceneError {
            file: Some(name.clone()),
            line: Some(1 + bytes[..at].iter().filter(|&&b| b == b'\n').count()),
            field: None,
            message: format!("not UTF-8 text (byte offset {at})"),
            io: false,
        }
    })?;
    parse(text).map_err(|mut e| {
        e.file = Some(name);
        e
    })
}

/// Parses and checks scene text, into a file built in place on the heap (see [`load`]).
///
/// ```
/// use microray::scene_file::parse;
/// let text = "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\n[[sphere]]\ncenter = [0, 0, 0]\nradius = -1\n";
/// assert_eq!(parse::<4, 1>(text).unwrap_err().to_string(),
///            "line 6: sphere[0].radius: radius must be finite and > 0");
/// ```
pub fn parse<const S: usize, const L: usize>(
    text: &str,
) -> Result<Box<SceneFile<S, L>>, SceneError> {
    let lines = LineIndex::new(text);
    let raw: RawFile = toml::from_str(text).map_err(|e| {
        let line = e.span().map(|s| lines.line(s.start));
        SceneError {
            file: None,
            line,
            field: line.and_then(|l| lines.key_on(l)),
            message: e.message().trim().replace('\n', "; "),
            io: false,
        }
    })?;
    Builder { lines: &lines }.build(raw)
}
