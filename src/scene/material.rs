//! [`Material`]: how a sphere reflects and transmits light.

use super::*;

/// How a sphere reflects and transmits light.
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
/// assert_eq!((red_plastic.refraction, red_plastic.ior), (Color::ZERO, 1.5));
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
    /// Transmittance `k_t`: the share of the refracted ray's colour that the hit adds (see
    /// `shading::refract`). A scene accepts a non-zero value only with the crate's
    /// `refraction` feature.
    pub refraction: Color,
    /// Index of refraction of the sphere's inside (finite and > 0); outside every sphere is
    /// air, of index 1. Used only where `refraction` is not zero.
    pub ior: f32,
}

impl Default for Material {
    /// White diffuse, no highlight, no mirror, no refraction, shininess 32, index of
    /// refraction 1.5 (the scene format's defaults).
    fn default() -> Self {
        Material {
            diffuse: Color::ONE,
            specular: Color::ZERO,
            shininess: 32.0,
            mirror: Color::ZERO,
            refraction: Color::ZERO,
            ior: 1.5,
        }
    }
}
