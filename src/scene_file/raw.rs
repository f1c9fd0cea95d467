//! The file as TOML sees it: each table's keys, types and defaults, before validation.

use super::*;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawFile {
    pub(super) camera: Spanned<RawCamera>,
    pub(super) render: Option<Spanned<RawRender>>,
    #[serde(default)]
    pub(super) sphere: Vec<Spanned<RawSphere>>,
    #[serde(default)]
    pub(super) light: Vec<Spanned<RawLight>>,
    #[serde(default)]
    pub(super) keyframe: Vec<Spanned<RawKeyframe>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawKeyframe {
    pub(super) at: Spanned<f64>,
    pub(super) eye: Option<Spanned<Vector>>,
    pub(super) look_at: Option<Spanned<Vector>>,
    pub(super) up: Option<Spanned<Vector>>,
    pub(super) vfov: Option<Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawCamera {
    pub(super) eye: Spanned<Vector>,
    pub(super) look_at: Spanned<Vector>,
    pub(super) up: Option<Spanned<Vector>>,
    pub(super) vfov: Option<Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawRender {
    pub(super) width: Option<Spanned<i64>>,
    pub(super) height: Option<Spanned<i64>>,
    pub(super) background: Option<Spanned<Rgb>>,
    pub(super) ambient: Option<Spanned<Rgb>>,
    pub(super) shadows: Option<bool>,
    pub(super) max_depth: Option<Spanned<i64>>,
    pub(super) samples: Option<Spanned<i64>>,
    pub(super) encoding: Option<Spanned<String>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawSphere {
    pub(super) center: Spanned<Vector>,
    pub(super) radius: Spanned<f64>,
    pub(super) diffuse: Option<Spanned<Rgb>>,
    pub(super) specular: Option<Spanned<Rgb>>,
    pub(super) shininess: Option<Spanned<f64>>,
    pub(super) mirror: Option<Spanned<Rgb>>,
    pub(super) refraction: Option<Spanned<Rgb>>,
    pub(super) ior: Option<Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawLight {
    pub(super) kind: Spanned<String>,
    pub(super) position: Option<Spanned<Vector>>,
    pub(super) direction: Option<Spanned<Vector>>,
    pub(super) intensity: Option<Spanned<Rgb>>,
}

/// Three numbers, integers or floats.
pub(super) struct Vector(pub(super) [f64; 3]);
/// A colour: three numbers, or one for all channels.
pub(super) struct Rgb(pub(super) [f64; 3]);

pub(super) fn three<'de, A: SeqAccess<'de>>(mut seq: A, what: &str) -> Result<[f64; 3], A::Error> {
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
