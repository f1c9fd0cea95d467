//! The TOML scene format (feature `scene-file`, needs std): all of it is in this file.
//!
//! ```toml
//! [camera]            # eye, look_at required; up = [0,1,0]; vfov = 60 (0 < vfov < 180)
//! eye = [0, 1, 6]
//! look_at = [0, 0.5, 0]
//! [render]            # all optional: width = 640, height = 480 (1..=16384), background = 0,
//! width = 320         # ambient = 0, shadows = true, max_depth = 3 (0..=16),
//! height = 240        # samples = 1 (1..=16, per axis), encoding = "linear" | "srgb"
//! [[sphere]]          # center, radius (> 0) required; diffuse = 1, specular = 0,
//! center = [0, 0, 0]  # shininess = 32 (> 0), mirror = 0
//! radius = 1.0
//! diffuse = [0.8, 0.2, 0.2]
//! [[light]]           # kind = "point" + position, or kind = "directional" + direction (≠ 0);
//! kind = "point"      # intensity = 1
//! position = [3, 5, 4]
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

use std::fmt;
use std::ops::Range;
use std::path::Path;
use std::string::{String, ToString};
use std::vec::Vec;
use std::{format, vec};

use serde::de::{self, Deserializer, SeqAccess, Visitor};
use serde::Deserialize;
use toml::Spanned;

use crate::camera::{Camera, MAX_SIZE};
use crate::error::Error;
use crate::geometry::Sphere;
use crate::math::{Color, Vec3};
use crate::render::{Encoding, RenderOptions};
use crate::scene::{Light, Material, Scene};

/// The desktop renderer's scene: 1024 spheres and 32 lights.
pub type Desktop = SceneFile<1024, 32>;

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
}

/// The camera's placement, independent of the image size.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    /// The eye point.
    pub eye: Vec3,
    /// The point looked at.
    pub look_at: Vec3,
    /// The up direction.
    pub up: Vec3,
    /// Full vertical field of view in degrees.
    pub vfov: f32,
}

impl View {
    /// The camera for a `width` × `height` image.
    ///
    /// ```
    /// # use microray::scene_file::parse;
    /// let file = parse::<4, 1>("[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\n")?;
    /// assert_eq!(file.view.camera(32, 16)?.width(), 32);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn camera(&self, width: u32, height: u32) -> Result<Camera, Error> {
        Camera::new(self.eye, self.look_at, self.up, self.vfov, width, height)
    }
}

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

/// Reads and checks a scene file; the error names the file.
///
/// ```
/// let err = microray::scene_file::load::<4, 1>("no/such/scene.toml").unwrap_err();
/// assert!(err.io && err.to_string().starts_with("no/such/scene.toml: "));
/// ```
pub fn load<const S: usize, const L: usize>(
    path: impl AsRef<Path>,
) -> Result<SceneFile<S, L>, SceneError> {
    let path = path.as_ref();
    let name = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| SceneError {
        file: Some(name.clone()),
        line: None,
        field: None,
        message: e.to_string(),
        io: true,
    })?;
    parse(&text).map_err(|mut e| {
        e.file = Some(name);
        e
    })
}

/// Parses and checks scene text.
///
/// ```
/// use microray::scene_file::parse;
/// let text = "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\n[[sphere]]\ncenter = [0, 0, 0]\nradius = -1\n";
/// assert_eq!(parse::<4, 1>(text).unwrap_err().to_string(),
///            "line 6: sphere[0].radius: radius must be finite and > 0");
/// ```
pub fn parse<const S: usize, const L: usize>(text: &str) -> Result<SceneFile<S, L>, SceneError> {
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

// ---- raw TOML shapes -------------------------------------------------------------------------

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawFile {
    camera: Spanned<RawCamera>,
    render: Option<Spanned<RawRender>>,
    #[serde(default)]
    sphere: Vec<Spanned<RawSphere>>,
    #[serde(default)]
    light: Vec<Spanned<RawLight>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawCamera {
    eye: Spanned<Vector>,
    look_at: Spanned<Vector>,
    up: Option<Spanned<Vector>>,
    vfov: Option<Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRender {
    width: Option<Spanned<i64>>,
    height: Option<Spanned<i64>>,
    background: Option<Spanned<Rgb>>,
    ambient: Option<Spanned<Rgb>>,
    shadows: Option<bool>,
    max_depth: Option<Spanned<i64>>,
    samples: Option<Spanned<i64>>,
    encoding: Option<Spanned<String>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSphere {
    center: Spanned<Vector>,
    radius: Spanned<f64>,
    diffuse: Option<Spanned<Rgb>>,
    specular: Option<Spanned<Rgb>>,
    shininess: Option<Spanned<f64>>,
    mirror: Option<Spanned<Rgb>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawLight {
    kind: Spanned<String>,
    position: Option<Spanned<Vector>>,
    direction: Option<Spanned<Vector>>,
    intensity: Option<Spanned<Rgb>>,
}

/// Three numbers, integers or floats.
struct Vector([f64; 3]);
/// A colour: three numbers, or one for all channels.
struct Rgb([f64; 3]);

fn three<'de, A: SeqAccess<'de>>(mut seq: A, what: &str) -> Result<[f64; 3], A::Error> {
    let mut out = [0.0; 3];
    for (i, slot) in out.iter_mut().enumerate() {
        *slot = seq
            .next_element::<f64>()?
            .ok_or_else(|| de::Error::invalid_length(i, &what))?;
    }
    if seq.next_element::<f64>()?.is_some() {
        return Err(de::Error::invalid_length(4, &what));
    }
    Ok(out)
}

impl<'de> Deserialize<'de> for Vector {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Vector;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("an array of 3 numbers")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<Vector, A::Error> {
                three(seq, "an array of 3 numbers").map(Vector)
            }
        }
        d.deserialize_seq(V)
    }
}

impl<'de> Deserialize<'de> for Rgb {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Rgb;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a number or an array of 3 numbers [r, g, b]")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Rgb, E> {
                Ok(Rgb([v; 3]))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Rgb, E> {
                Ok(Rgb([v as f64; 3]))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Rgb, E> {
                Ok(Rgb([v as f64; 3]))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<Rgb, A::Error> {
                three(seq, "an array of 3 numbers [r, g, b]").map(Rgb)
            }
        }
        d.deserialize_any(V)
    }
}

// ---- checking and building -------------------------------------------------------------------

/// Byte offsets to lines, and the key written on a line.
struct LineIndex<'a> {
    text: &'a str,
    starts: Vec<usize>,
}

impl<'a> LineIndex<'a> {
    fn new(text: &'a str) -> Self {
        let mut starts = vec![0];
        starts.extend(text.match_indices('\n').map(|(i, _)| i + 1));
        LineIndex { text, starts }
    }

    fn line(&self, offset: usize) -> usize {
        self.starts.partition_point(|&s| s <= offset)
    }

    fn text_of(&self, line: usize) -> Option<&'a str> {
        let start = *self.starts.get(line.checked_sub(1)?)?;
        let end = self.starts.get(line).copied().unwrap_or(self.text.len());
        Some(self.text[start..end].trim())
    }

    /// The table a line belongs to, as `camera` or `sphere[2]`, and the header's own key.
    fn table_of(&self, line: usize) -> Option<String> {
        let header = (1..=line)
            .rev()
            .find(|&l| self.text_of(l).is_some_and(|t| t.starts_with('[')))?;
        let h = self.text_of(header)?;
        let name = h
            .trim_start_matches('[')
            .split(']')
            .next()?
            .trim()
            .to_string();
        if !h.starts_with("[[") {
            return Some(name);
        }
        let index = (1..header)
            .filter(|&l| {
                self.text_of(l).is_some_and(|t| {
                    t.starts_with("[[")
                        && t.trim_start_matches('[').split(']').next().map(str::trim) == Some(&name)
                })
            })
            .count();
        Some(format!("{name}[{index}]"))
    }

    /// The field written on a line: `sphere[1].radius` for `radius = …` in the second
    /// `[[sphere]]`, or the table itself for a header line.
    fn key_on(&self, line: usize) -> Option<String> {
        let l = self.text_of(line)?;
        let table = self.table_of(line);
        match (l.split_once('='), table) {
            (Some((k, _)), Some(t)) if !l.starts_with('[') => Some(format!("{t}.{}", k.trim())),
            (Some((k, _)), None) => Some(k.trim().to_string()),
            (_, t) => t,
        }
    }
}

struct Builder<'a> {
    lines: &'a LineIndex<'a>,
}

impl Builder<'_> {
    fn err(&self, span: Range<usize>, field: &str, message: impl ToString) -> SceneError {
        SceneError {
            file: None,
            line: Some(self.lines.line(span.start)),
            field: Some(field.to_string()),
            message: message.to_string(),
            io: false,
        }
    }

    fn num(&self, v: &Spanned<f64>, field: &str) -> Result<f32, SceneError> {
        let x = *v.get_ref() as f32;
        if x.is_finite() {
            Ok(x)
        } else {
            Err(self.err(v.span(), field, "must be a finite number (in f32 range)"))
        }
    }

    fn vector(&self, v: &Spanned<Vector>, field: &str) -> Result<Vec3, SceneError> {
        let [x, y, z] = v.get_ref().0.map(|c| c as f32);
        let out = Vec3::new(x, y, z);
        if out.is_finite() {
            Ok(out)
        } else {
            Err(self.err(v.span(), field, "must be finite numbers (in f32 range)"))
        }
    }

    fn color(
        &self,
        v: Option<&Spanned<Rgb>>,
        default: f32,
        field: &str,
    ) -> Result<Color, SceneError> {
        let Some(v) = v else {
            return Ok(Color::splat(default));
        };
        let [r, g, b] = v.get_ref().0.map(|c| c as f32);
        let out = Color::new(r, g, b);
        if out.is_finite() && r >= 0.0 && g >= 0.0 && b >= 0.0 {
            Ok(out)
        } else {
            Err(self.err(v.span(), field, Error::InvalidColor))
        }
    }

    fn int(
        &self,
        v: Option<&Spanned<i64>>,
        default: i64,
        range: Range<i64>,
        field: &str,
    ) -> Result<i64, SceneError> {
        match v {
            None => Ok(default),
            Some(v) if range.contains(v.get_ref()) => Ok(*v.get_ref()),
            Some(v) => Err(self.err(
                v.span(),
                field,
                format!("must be in {}..={}", range.start, range.end - 1),
            )),
        }
    }

    fn build<const S: usize, const L: usize>(
        &self,
        raw: RawFile,
    ) -> Result<SceneFile<S, L>, SceneError> {
        let mut scene: Scene<S, L> = Scene::new();

        let (width, height, options) = match &raw.render {
            None => (640, 480, RenderOptions::default()),
            Some(r) => {
                let r = r.get_ref();
                let size = 1..MAX_SIZE as i64 + 1;
                let width = self.int(r.width.as_ref(), 640, size.clone(), "render.width")?;
                let height = self.int(r.height.as_ref(), 480, size, "render.height")?;
                let bg = self.color(r.background.as_ref(), 0.0, "render.background")?;
                let amb = self.color(r.ambient.as_ref(), 0.0, "render.ambient")?;
                scene.set_background(bg).expect("checked above");
                scene.set_ambient(amb).expect("checked above");
                scene.set_shadows(r.shadows.unwrap_or(true));
                let depth = self.int(r.max_depth.as_ref(), 3, 0..17, "render.max_depth")?;
                scene.set_max_depth(depth as u8).expect("checked above");
                let samples = self.int(r.samples.as_ref(), 1, 1..17, "render.samples")?;
                let encoding = match &r.encoding {
                    None => Encoding::Linear,
                    Some(e) => match e.get_ref().as_str() {
                        "linear" => Encoding::Linear,
                        "srgb" => Encoding::Srgb,
                        other => {
                            return Err(self.err(
                                e.span(),
                                "render.encoding",
                                format!("must be \"linear\" or \"srgb\", not {other:?}"),
                            ))
                        }
                    },
                };
                let options = RenderOptions {
                    samples: samples as u8,
                    encoding,
                };
                (width as u32, height as u32, options)
            }
        };

        let cam = raw.camera.get_ref();
        let eye = self.vector(&cam.eye, "camera.eye")?;
        let look_at = self.vector(&cam.look_at, "camera.look_at")?;
        let up = match &cam.up {
            Some(u) => self.vector(u, "camera.up")?,
            None => Vec3::new(0.0, 1.0, 0.0),
        };
        let vfov = match &cam.vfov {
            Some(v) => self.num(v, "camera.vfov")?,
            None => 60.0,
        };
        let view = View {
            eye,
            look_at,
            up,
            vfov,
        };
        let camera = view.camera(width, height).map_err(|e| {
            let (span, field) = match e {
                Error::EyeAtLookAt => (cam.look_at.span(), "camera.look_at"),
                Error::UpParallelToView => match &cam.up {
                    Some(u) => (u.span(), "camera.up"),
                    None => (raw.camera.span(), "camera.up"),
                },
                Error::InvalidFov => match &cam.vfov {
                    Some(v) => (v.span(), "camera.vfov"),
                    None => (raw.camera.span(), "camera.vfov"),
                },
                _ => (raw.camera.span(), "camera"),
            };
            self.err(span, field, e)
        })?;

        if raw.sphere.len() > S {
            let s = &raw.sphere[S];
            return Err(self.err(
                s.span(),
                "sphere",
                format!(
                    "{} spheres, more than the capacity of {S}",
                    raw.sphere.len()
                ),
            ));
        }
        for (i, s) in raw.sphere.iter().enumerate() {
            let f = |name: &str| format!("sphere[{i}].{name}");
            let r = s.get_ref();
            let center = self.vector(&r.center, &f("center"))?;
            let radius = self.num(&r.radius, &f("radius"))?;
            let shininess = match &r.shininess {
                Some(v) => self.num(v, &f("shininess"))?,
                None => 32.0,
            };
            let material = Material {
                diffuse: self.color(r.diffuse.as_ref(), 1.0, &f("diffuse"))?,
                specular: self.color(r.specular.as_ref(), 0.0, &f("specular"))?,
                shininess,
                mirror: self.color(r.mirror.as_ref(), 0.0, &f("mirror"))?,
            };
            scene
                .add_sphere(Sphere::new(center, radius), material)
                .map_err(|e| {
                    let (span, name) = match e {
                        Error::InvalidRadius => (r.radius.span(), "radius"),
                        Error::InvalidShininess => (
                            r.shininess.as_ref().map_or(s.span(), |v| v.span()),
                            "shininess",
                        ),
                        _ => (s.span(), ""),
                    };
                    self.err(span, f(name).trim_end_matches('.'), e)
                })?;
        }

        if raw.light.len() > L {
            let l = &raw.light[L];
            return Err(self.err(
                l.span(),
                "light",
                format!("{} lights, more than the capacity of {L}", raw.light.len()),
            ));
        }
        for (i, l) in raw.light.iter().enumerate() {
            let f = |name: &str| format!("light[{i}].{name}");
            let r = l.get_ref();
            let intensity = self.color(r.intensity.as_ref(), 1.0, &f("intensity"))?;
            let light = match r.kind.get_ref().as_str() {
                "point" => {
                    if let Some(d) = &r.direction {
                        return Err(self.err(
                            d.span(),
                            &f("direction"),
                            "not allowed for a point light",
                        ));
                    }
                    let p = r.position.as_ref().ok_or_else(|| {
                        self.err(
                            l.span(),
                            &f("position"),
                            "missing (a point light needs a position)",
                        )
                    })?;
                    Light::Point {
                        position: self.vector(p, &f("position"))?,
                        intensity,
                    }
                }
                "directional" => {
                    if let Some(p) = &r.position {
                        return Err(self.err(
                            p.span(),
                            &f("position"),
                            "not allowed for a directional light",
                        ));
                    }
                    let d = r.direction.as_ref().ok_or_else(|| {
                        self.err(
                            l.span(),
                            &f("direction"),
                            "missing (a directional light needs a direction)",
                        )
                    })?;
                    let direction = self.vector(d, &f("direction"))?;
                    if direction == Vec3::ZERO {
                        return Err(self.err(d.span(), &f("direction"), Error::ZeroDirection));
                    }
                    Light::Directional {
                        direction,
                        intensity,
                    }
                }
                other => {
                    return Err(self.err(
                        r.kind.span(),
                        &f("kind"),
                        format!("must be \"point\" or \"directional\", not {other:?}"),
                    ))
                }
            };
            scene
                .add_light(light)
                .map_err(|e| self.err(l.span(), &format!("light[{i}]"), e))?;
        }

        Ok(SceneFile {
            scene,
            camera,
            view,
            width,
            height,
            options,
        })
    }
}
