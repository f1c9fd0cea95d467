//! [`Material`]: how a sphere reflects light.

use super::*;

/// How a sphere reflects light.
///
/// ```
/// use microray::{Color, Material};
/// let red_plastic = Material {
///     diffuse: Color::new(0.8, 0.1, 0.1),
///     specular: Color::splat(0.5),
///     shininess: 64.0,
///     ..Material::default()
/// };
/// assert_eq!(red_plastic.mirror, Color::ZERO);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Material {
    /// Lambert (and ambient) reflectance `k_d`.
    pub diffuse: Color,
    /// Blinn–Phong highlight colour `k_s`.
    pub specular: Color,
    /// Blinn–Phong exponent `s` (> 0).
    pub shininess: f32,
    /// Mirror reflectance `k_m`.
    pub mirror: Color,
}

impl Default for Material {
    /// White diffuse, no highlight, no mirror, shininess 32 (the scene format's defaults).
    fn default() -> Self {
        Material {
            diffuse: Color::ONE,
            specular: Color::ZERO,
            shininess: 32.0,
            mirror: Color::ZERO,
        }
    }
}
