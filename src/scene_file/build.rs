//! From the raw tables to a [`Scene`] and a [`View`]: every value validated through the library's
//! own checks, each error located at its file, line and field.

use super::*;

/// Byte offsets to lines, and the key written on a line.
pub(super) struct LineIndex<'a> {
    pub(super) text: &'a str,
    pub(super) starts: Vec<usize>,
}

impl<'a> LineIndex<'a> {
    pub(super) fn new(text: &'a str) -> Self {
        let mut starts = vec![0];
        starts.extend(text.match_indices('\n').map(|(i, _)| i + 1));
        LineIndex { text, starts }
    }

    pub(super) fn line(&self, offset: usize) -> usize {
        self.starts.partition_point(|&s| s <= offset)
    }

    pub(super) fn text_of(&self, line: usize) -> Option<&'a str> {
        let start = *self.starts.get(line.checked_sub(1)?)?;
        let end = self.starts.get(line).copied().unwrap_or(self.text.len());
        Some(self.text[start..end].trim())
    }

    /// The table a line belongs to, as `camera` or `sphere[2]`, and the header's own key.
    pub(super) fn table_of(&self, line: usize) -> Option<String> {
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
    pub(super) fn key_on(&self, line: usize) -> Option<String> {
        let l = self.text_of(line)?;
        let table = self.table_of(line);
        match (l.split_once('='), table) {
            (Some((k, _)), Some(t)) if !l.starts_with('[') => Some(format!("{t}.{}", k.trim())),
            (Some((k, _)), None) => Some(k.trim().to_string()),
            (_, t) => t,
        }
    }
}

/// The field an error names, `sphere[3].radius` (or `sphere[3]` without a key), written only
/// when there is an error: a scene file of 16 384 spheres names seven fields a sphere.
#[derive(Clone, Copy)]
pub(super) struct Entry<'a>(pub(super) &'a str, pub(super) usize, pub(super) &'a str);

impl core::fmt::Display for Entry<'_> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let Entry(table, i, key) = *self;
        match key {
            "" => write!(f, "{table}[{i}]"),
            _ => write!(f, "{table}[{i}].{key}"),
        }
    }
}

pub(super) struct Builder<'a> {
    pub(super) lines: &'a LineIndex<'a>,
}

impl Builder<'_> {
    pub(super) fn err(
        &self,
        span: Range<usize>,
        field: impl core::fmt::Display,
        message: impl ToString,
    ) -> SceneError {
        SceneError {
            file: None,
            line: Some(self.lines.line(span.start)),
            field: Some(field.to_string()),
            message: message.to_string(),
            io: false,
        }
    }

    pub(super) fn num(
        &self,
        v: &Spanned<f64>,
        field: impl core::fmt::Display,
    ) -> Result<f32, SceneError> {
        let x = *v.get_ref() as f32;
        if x.is_finite() {
            Ok(x)
        } else {
            Err(self.err(v.span(), field, "must be a finite number (in f32 range)"))
        }
    }

    pub(super) fn vector(
        &self,
        v: &Spanned<Vector>,
        field: impl core::fmt::Display,
    ) -> Result<Vec3, SceneError> {
        let [x, y, z] = v.get_ref().0.map(|c| c as f32);
        let out = Vec3::new(x, y, z);
        if out.is_finite() {
            Ok(out)
        } else {
            Err(self.err(v.span(), field, "must be finite numbers (in f32 range)"))
        }
    }

    pub(super) fn color(
        &self,
        v: Option<&Spanned<Rgb>>,
        default: f32,
        field: impl core::fmt::Display,
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

    pub(super) fn int(
        &self,
        v: Option<&Spanned<i64>>,
        default: i64,
        range: Range<i64>,
        field: impl core::fmt::Display,
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

    pub(super) fn build<const S: usize, const L: usize>(
        &self,
        raw: RawFile,
    ) -> Result<Box<SceneFile<S, L>>, SceneError> {
        // The scene's settings, applied once the file is on the heap.
        let mut settings = None;
        let (width, height, options) = match &raw.render {
            None => (640, 480, RenderOptions::default()),
            Some(r) => {
                let r = r.get_ref();
                let size = 1..MAX_SIZE as i64 + 1;
                let width = self.int(r.width.as_ref(), 640, size.clone(), "render.width")?;
                let height = self.int(r.height.as_ref(), 480, size, "render.height")?;
                let bg = self.color(r.background.as_ref(), 0.0, "render.background")?;
                let amb = self.color(r.ambient.as_ref(), 0.0, "render.ambient")?;
                let depth = self.int(r.max_depth.as_ref(), 3, 0..17, "render.max_depth")?;
                settings = Some((bg, amb, r.shadows.unwrap_or(true), depth as u8));
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

        // Built in place on the heap: a scene at the desktop capacity is over a megabyte (1.3
        // MB at 16384 spheres), more than a thread's stack should hold, let alone the copies
        // of a return by value. A constant boxed, then its few small fields set: an
        // unoptimised build holds one copy of it on the stack, where a struct built from
        // `Scene::new()` and the fields would be two or three (more than a test thread's 2 MiB).
        let mut file: Box<SceneFile<S, L>> = Box::new(SceneFile::EMPTY);
        file.camera = camera;
        file.view = view;
        file.width = width;
        file.height = height;
        file.options = options;
        let scene = &mut file.scene;
        if let Some((bg, amb, shadows, depth)) = settings {
            scene.set_background(bg).expect("checked above");
            scene.set_ambient(amb).expect("checked above");
            scene.set_shadows(shadows);
            scene.set_max_depth(depth).expect("checked above");
        }

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
            let f = |name| Entry("sphere", i, name);
            let r = s.get_ref();
            let center = self.vector(&r.center, f("center"))?;
            let radius = self.num(&r.radius, f("radius"))?;
            let shininess = match &r.shininess {
                Some(v) => self.num(v, f("shininess"))?,
                None => 32.0,
            };
            let ior = match &r.ior {
                Some(v) => self.num(v, f("ior"))?,
                None => 1.5,
            };
            let material = Material {
                diffuse: self.color(r.diffuse.as_ref(), 1.0, f("diffuse"))?,
                specular: self.color(r.specular.as_ref(), 0.0, f("specular"))?,
                shininess,
                mirror: self.color(r.mirror.as_ref(), 0.0, f("mirror"))?,
                refraction: self.color(r.refraction.as_ref(), 0.0, f("refraction"))?,
                ior,
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
                        Error::InvalidIor => (r.ior.as_ref().map_or(s.span(), |v| v.span()), "ior"),
                        _ => (s.span(), ""),
                    };
                    self.err(span, f(name), e)
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
            let f = |name| Entry("light", i, name);
            let r = l.get_ref();
            let intensity = self.color(r.intensity.as_ref(), 1.0, f("intensity"))?;
            let light = match r.kind.get_ref().as_str() {
                "point" => {
                    if let Some(d) = &r.direction {
                        return Err(self.err(
                            d.span(),
                            f("direction"),
                            "not allowed for a point light",
                        ));
                    }
                    let p = r.position.as_ref().ok_or_else(|| {
                        self.err(
                            l.span(),
                            f("position"),
                            "missing (a point light needs a position)",
                        )
                    })?;
                    Light::Point {
                        position: self.vector(p, f("position"))?,
                        intensity,
                    }
                }
                "directional" => {
                    if let Some(p) = &r.position {
                        return Err(self.err(
                            p.span(),
                            f("position"),
                            "not allowed for a directional light",
                        ));
                    }
                    let d = r.direction.as_ref().ok_or_else(|| {
                        self.err(
                            l.span(),
                            f("direction"),
                            "missing (a directional light needs a direction)",
                        )
                    })?;
                    let direction = self.vector(d, f("direction"))?;
                    if direction == Vec3::ZERO {
                        return Err(self.err(d.span(), f("direction"), Error::ZeroDirection));
                    }
                    Light::Directional {
                        direction,
                        intensity,
                    }
                }
                other => {
                    return Err(self.err(
                        r.kind.span(),
                        f("kind"),
                        format!("must be \"point\" or \"directional\", not {other:?}"),
                    ))
                }
            };
            scene
                .add_light(light)
                .map_err(|e| self.err(l.span(), f(""), e))?;
        }

        file.keyframes = self.keyframes(&raw.keyframe, &view, (width, height))?;
        Ok(file)
    }

    /// The `[[keyframe]]` tables: none, or 2..=KEYFRAMES keys whose fields default to the
    /// camera's, each a valid camera at the file's size.
    fn keyframes(
        &self,
        raw: &[Spanned<RawKeyframe>],
        camera: &View,
        (width, height): (u32, u32),
    ) -> Result<Keyframes<KEYFRAMES>, SceneError> {
        let mut keys = Keyframes::new();
        match raw {
            [] => return Ok(keys),
            [one] => return Err(self.err(one.span(), "keyframe", Error::TooFewKeyframes)),
            _ if raw.len() > KEYFRAMES => {
                let k = &raw[KEYFRAMES];
                let n = raw.len();
                let message = format!("{n} keyframes, more than the capacity of {KEYFRAMES}");
                return Err(self.err(k.span(), "keyframe", message));
            }
            _ => {}
        }
        for (i, k) in raw.iter().enumerate() {
            let f = |name| Entry("keyframe", i, name);
            let r = k.get_ref();
            let vector = |v: &Option<Spanned<Vector>>, name, default| match v {
                Some(v) => self.vector(v, f(name)),
                None => Ok(default),
            };
            let view = View {
                eye: vector(&r.eye, "eye", camera.eye)?,
                look_at: vector(&r.look_at, "look_at", camera.look_at)?,
                up: vector(&r.up, "up", camera.up)?,
                vfov: match &r.vfov {
                    Some(v) => self.num(v, f("vfov"))?,
                    None => camera.vfov,
                },
            };
            // Where the key's own fields make no camera, say which.
            let span = |v: Option<Range<usize>>| v.unwrap_or(k.span());
            view.camera(width, height).map_err(|e| {
                let (s, name) = match e {
                    Error::EyeAtLookAt => (span(r.look_at.as_ref().map(|v| v.span())), "look_at"),
                    Error::UpParallelToView => (span(r.up.as_ref().map(|v| v.span())), "up"),
                    Error::InvalidFov => (span(r.vfov.as_ref().map(|v| v.span())), "vfov"),
                    _ => (k.span(), ""),
                };
                self.err(s, f(name), e)
            })?;
            let at = *r.at.get_ref() as f32;
            keys.push(Keyframe { at, view })
                .map_err(|e| self.err(r.at.span(), f("at"), e))?;
        }
        Ok(keys)
    }
}

#[cfg(test)]
mod tests {
    use super::Entry;
    use std::string::ToString;

    /// A field of an entry, `sphere[3].radius`, and the entry alone (an error of the whole
    /// `[[light]]` table) without a trailing dot.
    #[test]
    fn entries_are_named_as_the_file_writes_them() {
        assert_eq!(Entry("sphere", 3, "radius").to_string(), "sphere[3].radius");
        assert_eq!(Entry("light", 0, "").to_string(), "light[0]");
    }
}
