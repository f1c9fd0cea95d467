//! The refracted ray at a hit on glass: Snell's law, and total internal reflection beyond the
//! critical angle.

use super::*;
use crate::math::sqrt;

/// The refracted ray at a hit on a sphere whose inside has index of refraction `ior` (outside
/// every sphere is air, of index 1), or the mirror ray where the light is totally reflected.
///
/// With `d̂ = d/|d|`, `n` the normal facing the ray and `η` the ratio of the indices (`1/ior`
/// entering the sphere, `ior` leaving it), `cos_i = −d̂·n` and `k = 1 − η²(1 − cos_i²)`: for
/// `k ≥ 0` the ray goes along `η d̂ + (η cos_i − √k) n`, for `k < 0` along [`reflect`]'s
/// direction. It starts on the hit, as a mirror ray does: [`find_from`] finds where a ray
/// going into the sphere leaves it.
///
/// The direction is that one times the index of the side the ray goes to, which is the same
/// ray: with `η = a/b` (`a = 1, b = ior` entering, `a = ior, b = 1` leaving), it is
/// `a d̂ + (a cos_i − √((b − a)(b + a) + (a cos_i)²)) n`. So nothing is divided and `η` is not
/// rounded, whose error at an `ior` near 1 would be a large part of `1 − η²`; `b² − a²` is
/// `(b − a)(b + a)`, whose difference is exact (Sterbenz, `ior` within [0.5, 2]) where `b² − a²`
/// would cancel; and going into the denser medium, where no ray is totally reflected, `k` is a
/// sum of two terms ≥ 0 that cannot cancel. For `ior = 1` the direction is `d̂` exactly
/// (`√(c²) = |c|` in binary floating point). Near the critical angle `k` is a difference of
/// nearly equal numbers whatever the formula: an error of a few ε in `cos_i` (from `d` and `n`
/// as f32) becomes one of a few ε in `k`, and of that over `√k` in the direction. An `ior`
/// beyond 2⁶⁰ is taken as 2⁶⁰, which bends every ray as it would in f32, and whose squares do
/// not overflow.
///
/// ```
/// use microray::shading::{reflect, refract};
/// use microray::{Material, Ray, Scene, Sphere, Vec3};
/// let mut scene: Scene<1, 0> = Scene::new();
/// scene.add_sphere(Sphere::new(Vec3::ZERO, 1.0), Material::default())?;
/// // Into the glass at 45°: sin 45° = 1.5 sin θ_t (Snell).
/// let ray = Ray::new(Vec3::new(-2.0, 2.5, 0.0), Vec3::new(1.0, -1.0, 0.0));
/// let hit = scene.find_intersection(&ray, 0.0, 10.0).unwrap();
/// let sin = |d: Vec3| d.normalize_fast().cross(hit.normal).length();
/// let inside = refract(&ray, &hit, 1.5);
/// assert!((1.5 * sin(inside.dir) - sin(ray.dir)).abs() < 1e-6);
/// // Out of the glass at 64°, beyond the critical angle (41.8°): totally reflected.
/// let slanted = Ray::new(Vec3::new(0.0, -0.9, 0.0), Vec3::new(1.0, 0.0, 0.0));
/// let wall = scene.find_intersection(&slanted, 0.0, 10.0).unwrap();
/// assert_eq!(refract(&slanted, &wall, 1.5), reflect(&slanted, &wall));
/// # Ok::<(), microray::Error>(())
/// ```
#[inline]
pub fn refract(ray: &Ray, hit: &Hit, ior: f32) -> Ray {
    const MAX_IOR: f32 = (1u64 << 60) as f32;
    let ior = if ior > MAX_IOR { MAX_IOR } else { ior };
    let n = hit.normal;
    let entering = !hit.from_inside();
    let u = ray.dir.normalize_fast();
    let cos_i = -u.dot(n);
    let (a, b) = if entering { (1.0, ior) } else { (ior, 1.0) };
    let ac = a * cos_i;
    let k = (b - a) * (b + a) + ac * ac;
    // `!(k ≥ 0)`: a NaN (from a NaN input) reflects too, and the walk ends where it meets
    // nothing.
    if !(k >= 0.0) {
        return reflect(ray, hit);
    }
    Ray::new(hit.point(), u * a + n * (ac - sqrt(k)))
}
