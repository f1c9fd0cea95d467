//! The one error type: everything that can go wrong is found while a scene, camera or frame is
//! built, never in the pixel loop.

use core::fmt;

/// Why a scene, camera, frame or buffer was rejected.
///
/// ```
/// use microray::{Error, Material, Scene, Sphere, Vec3};
/// let mut scene: Scene<1, 0> = Scene::new();
/// let ball = Sphere::new(Vec3::ZERO, 1.0);
/// scene.add_sphere(ball, Material::default()).unwrap();
/// assert_eq!(scene.add_sphere(ball, Material::default()), Err(Error::TooManySpheres));
/// assert_eq!(Error::TooManySpheres.to_string(), "more spheres than the scene's capacity");
///
/// // A `core::error::Error`: `?` takes it into a `Box<dyn std::error::Error>`.
/// fn tiny() -> Result<Scene<1, 0>, Box<dyn std::error::Error>> {
///     let mut scene = Scene::new();
///     scene.add_sphere(Sphere::new(Vec3::ZERO, -1.0), Material::default())?;
///     Ok(scene)
/// }
/// assert_eq!(tiny().unwrap_err().to_string(), "radius must be finite and > 0");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum Error {
    /// More spheres than the scene's capacity `S`.
    TooManySpheres,
    /// More lights than the scene's capacity `L`.
    TooManyLights,
    /// A position or vector with a NaN or infinite component.
    NotFinite,
    /// A radius that is not finite and > 0.
    InvalidRadius,
    /// A colour (diffuse, specular, mirror, refraction, intensity, ambient, background) with a
    /// negative, NaN or infinite channel.
    InvalidColor,
    /// A shininess that is not finite and > 0.
    InvalidShininess,
    /// An index of refraction that is not finite and > 0.
    InvalidIor,
    /// A material with refraction, in a build without the `refraction` feature.
    RefractionNotEnabled,
    /// A directional light whose direction is the zero vector.
    ZeroDirection,
    /// The camera's eye and look-at points coincide.
    EyeAtLookAt,
    /// The camera's up vector is zero or parallel to the view direction.
    UpParallelToView,
    /// A vertical field of view outside (0, 180) degrees.
    InvalidFov,
    /// An image width or height outside 1..=16384.
    InvalidSize,
    /// Samples per axis outside 1..=16.
    InvalidSamples,
    /// A reflection and refraction depth above 16.
    InvalidMaxDepth,
    /// A pixel buffer whose length is not a whole number of rows inside the image.
    BufferSize,
    /// A keyframe time that is NaN, outside [0, 1], not after the previous key's, or a first
    /// key not at 0.
    InvalidKeyframe,
    /// More keyframes than the capacity.
    TooManyKeyframes,
    /// An animation by keyframes with fewer than two.
    TooFewKeyframes,
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Error::TooManySpheres => "more spheres than the scene's capacity",
            Error::TooManyLights => "more lights than the scene's capacity",
            Error::NotFinite => "a coordinate is NaN or infinite",
            Error::InvalidRadius => "radius must be finite and > 0",
            Error::InvalidColor => "colour channels must be finite and >= 0",
            Error::InvalidShininess => "shininess must be finite and > 0",
            Error::InvalidIor => "ior must be finite and > 0",
            Error::RefractionNotEnabled => "refraction needs microray's `refraction` feature",
            Error::ZeroDirection => "light direction must not be zero",
            Error::EyeAtLookAt => "eye and look_at must differ",
            Error::UpParallelToView => "up must not be zero or parallel to the view direction",
            Error::InvalidFov => "vfov must be in (0, 180) degrees",
            Error::InvalidSize => "width and height must be in 1..=16384",
            Error::InvalidSamples => "samples must be in 1..=16",
            Error::InvalidMaxDepth => "max_depth must be in 0..=16",
            Error::BufferSize => "buffer length must be a whole number of rows inside the image",
            Error::InvalidKeyframe => {
                "keyframe times must start at 0, increase, and stay within [0, 1]"
            }
            Error::TooManyKeyframes => "more keyframes than the capacity",
            Error::TooFewKeyframes => "an animation by keyframes needs at least two",
        })
    }
}

/// In every build, `no_std` included: `?` turns an [`Error`] into a `Box<dyn Error>` or an
/// error type of the caller's.
impl core::error::Error for Error {}
