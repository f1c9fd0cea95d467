//! Rays, spheres and their intersection: all of microray's intersection code is in this module
//! (`prepared.rs`: rays sharing an origin; `compensated.rs`: the compensated `c`; `roots.rs`;
//! `leaving.rs`: rays leaving a surface; `hit_point.rs`; `lanes.rs`: four rays at once).
//!
//! A ray `o + t·d` meets a sphere (centre `m`, radius `r`) where `a t² + 2 b t + c = 0` with
//! `f = o − m`, `a = d·d`, `b = f·d`, `c = f·f − r²`. The textbook formula
//! `(−b ± √(b² − a c)) / a` fails in f32 in three ways, each answered below:
//!
//! 1. **Far or small spheres** (`|f| ≫ r`): `b²` and `a c` agree in almost every bit, so
//!    `b² − a c` is noise. We use Hearn and Baker's form `a (r² − |f − (b/a) d|²)`, whose error
//!    scales with `ε |f| r` instead of `ε |f|²`.
//! 2. **The root near zero** (`−b + √…` with `√… ≈ b`): computed as `c / q` with
//!    `q = −(b + sign(b) √…)`, which never subtracts nearly equal numbers (the "stable roots" of
//!    Press et al., Ray Tracing Gems ch. 7).
//! 3. **Huge spheres seen from nearby** (a ground of radius 10⁶ one unit below the eye):
//!    `c = |f|² − r²` cancels; in f32 it is off by percents. Where the f32 value would lose
//!    more than about a bit (an origin within 0.73 r of the surface) we recompute it from
//!    error-free pieces (TwoSum, Dekker's exact squares), still in f32, good to ~2⁻⁴⁵ of
//!    `|f|²`: f64 would do as well, but it is software on a Cortex-M. For rays that share an
//!    origin (primary rays, shadow rays cast from a point light) [`Prepared::exact`] does this
//!    once per frame.
//!
//! Two more losses come after the root, and are answered here too:
//!
//! 4. **The hit's offset from the centre** (the normal times r): `f + t·d` loses the low bits
//!    of r when `|f| ≫ r`, even with t exact. [`hit_point()`] recomputes it from exact products
//!    from 16 radii away (from 2048 for dull materials, whose shading the lost bits do not
//!    reach).
//! 5. **Rays leaving a hit far from the origin**: the hit point rounded to f32 is off by half an
//!    ulp of its coordinates (5·10⁻⁴ at 10⁴). Shadow and mirror rays therefore take `f` for
//!    another sphere as `(anchor − m) + rel`: the hit's centre and offset, or the eye and the
//!    path travelled from it, whichever vector is shorter ([`Hit::anchor`](crate::Hit::anchor)).
//!    `anchor − m` is exact or nearly, so the error scales with the scene's size, not with its
//!    distance from the origin: a scene moved by an exact vector renders the same bits.
//!
//! All of it is f32, in plain IEEE operations (no fused multiply-add, no f64, which is software
//! on a Cortex-M): every target, soft-float included, computes the host's bits. Inputs whose
//! squares overflow f32 are scaled by powers of two first, which is exact.
//! docs/numerics.md measures what each of these costs and buys.

use crate::math::{
    finite, sqrt, two_product_of, two_square_of, two_sum_of, Ieee, Ieee3, IeeeCmp, Vec3,
};

mod compensated;
mod hit_point;
#[cfg(lanes)]
mod lanes;
mod leaving;
mod prepared;
mod roots;
#[cfg(test)]
mod tests;

use compensated::*;
pub use hit_point::*;
#[cfg(lanes)]
pub(crate) use lanes::*;
#[cfg(lanes)]
use leaving::*;
pub use prepared::*;
use roots::*;

/// A ray `origin + t·dir`; `dir` need not be unit length.
///
/// ```
/// use microray::{Ray, Vec3};
/// let ray = Ray::new(Vec3::ZERO, Vec3::new(0.0, 0.0, -2.0));
/// assert_eq!(ray.at(1.5), Vec3::new(0.0, 0.0, -3.0));
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Ray {
    /// Where the ray starts.
    pub origin: Vec3,
    /// Its direction; any finite non-zero length.
    pub dir: Vec3,
}

impl Ray {
    /// A ray from its origin and direction.
    ///
    /// ```
    /// # use microray::{Ray, Vec3};
    /// let ray = Ray::new(Vec3::ZERO, Vec3::new(1.0, 0.0, 0.0));
    /// assert_eq!(ray.dir.x, 1.0);
    /// ```
    #[inline]
    pub const fn new(origin: Vec3, dir: Vec3) -> Self {
        Ray { origin, dir }
    }

    /// The point at parameter `t`.
    ///
    /// ```
    /// # use microray::{Ray, Vec3};
    /// let ray = Ray::new(Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0));
    /// assert_eq!(ray.at(2.0), Vec3::new(1.0, 2.0, 0.0));
    /// ```
    #[inline]
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + self.dir * t
    }
}

/// A sphere: the only shape microray knows.
///
/// ```
/// use microray::{Sphere, Vec3};
/// let s = Sphere::new(Vec3::new(0.0, -1000.0, 0.0), 1000.0); // a ground plane, nearly
/// assert_eq!(s.radius, 1000.0);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Sphere {
    /// Its centre.
    pub center: Vec3,
    /// Its radius; the scene accepts only finite values > 0.
    pub radius: f32,
}

impl Sphere {
    /// A sphere from its centre and radius (checked when added to a [`Scene`](crate::Scene)).
    ///
    /// ```
    /// # use microray::{Sphere, Vec3};
    /// let s = Sphere::new(Vec3::ZERO, 1.0);
    /// assert_eq!(s.center, Vec3::ZERO);
    /// ```
    #[inline]
    pub const fn new(center: Vec3, radius: f32) -> Self {
        Sphere { center, radius }
    }
}

/// The closest root of the ray–sphere equation inside `[tmin, tmax]`, or `None`.
///
/// The textbook quadratic's `ray_intersect(ray, sphere, tmin, tmax)`, written to stay accurate in
/// f32 for tiny, far and huge spheres (see the module documentation). A NaN or infinite input
/// never yields a hit.
///
/// ```
/// use microray::{ray_intersect, Ray, Sphere, Vec3};
/// let sphere = Sphere::new(Vec3::new(0.0, 0.0, -5.0), 1.0);
/// let ray = Ray::new(Vec3::ZERO, Vec3::new(0.0, 0.0, -1.0));
/// assert_eq!(ray_intersect(&ray, &sphere, 0.0, f32::INFINITY), Some(4.0));
/// // the far root, when the near one is outside the interval
/// assert_eq!(ray_intersect(&ray, &sphere, 4.5, f32::INFINITY), Some(6.0));
/// assert_eq!(ray_intersect(&ray, &sphere, 0.0, 3.0), None);
/// ```
#[inline]
pub fn ray_intersect(ray: &Ray, sphere: &Sphere, tmin: f32, tmax: f32) -> Option<f32> {
    Prepared::ray_hit(ray, sphere, tmin, tmax).map(|(t, _)| t)
}
