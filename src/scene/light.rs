//! [`Light`]: point and directional lights, and their validation. What each kind does in shading
//! and culling is its `LightKind` impl in `shading/lights.rs`.

use super::*;

/// A light source.
///
/// ```
/// use microray::{Color, Light, Vec3};
/// let sun = Light::Directional { direction: Vec3::new(1.0, -1.0, 0.0), intensity: Color::ONE };
/// let bulb = Light::Point { position: Vec3::new(0.0, 5.0, 0.0), intensity: Color::splat(0.7) };
/// assert_ne!(sun, bulb);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Light {
    /// Light from a point; no fall-off with distance.
    Point {
        /// Where it is.
        position: Vec3,
        /// Its colour and strength `I`.
        intensity: Color,
    },
    /// Parallel light from infinitely far away.
    Directional {
        /// Where the light travels (from the light towards the scene); any non-zero length.
        direction: Vec3,
        /// Its colour and strength `I`.
        intensity: Color,
    },
}

impl Light {
    /// The light's intensity.
    ///
    /// ```
    /// # use microray::{Color, Light, Vec3};
    /// let l = Light::Point { position: Vec3::ZERO, intensity: Color::splat(0.5) };
    /// assert_eq!(l.intensity(), Color::splat(0.5));
    /// ```
    pub fn intensity(&self) -> Color {
        match *self {
            Light::Point { intensity, .. } | Light::Directional { intensity, .. } => intensity,
        }
    }

    /// The light with its values checked (finite, colours non-negative) and a directional
    /// light's direction normalised: what [`Scene::add_light`] stores.
    pub(super) fn checked(self) -> Result<Light, Error> {
        Ok(match self {
            Light::Point {
                position,
                intensity,
            } => Light::Point {
                position: check_point(position)?,
                intensity: check_color(intensity)?,
            },
            Light::Directional {
                direction,
                intensity,
            } => Light::Directional {
                direction: check_point(direction)?
                    .normalized()
                    .ok_or(Error::ZeroDirection)?,
                intensity: check_color(intensity)?,
            },
        })
    }
}
