//! [`Light`]: point and directional lights.

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
}
