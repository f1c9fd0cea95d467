//! Hit points and their offsets from the centre, rebuilt from exact products where `f + t·d`
//! would lose the low bits of r; the exit root of a ray leaving a sphere from inside.

use super::*;

/// Where a ray that hit `sphere` at parameter `t` meets it: the point and the point's offset from
/// the centre (the outward normal times the radius). `f` is the ray origin minus the centre, as
/// [`Prepared`] has it (for rays leaving a surface more accurate than `ray.origin − centre`).
///
/// `f + t·d` loses the offset's low bits when the sphere is small for its distance (|f| ≫ r):
/// with `t` right to half an ulp, a sphere of radius 10⁻⁴ seen from 10 units would still get
/// normals wrong by 1%. From 16 radii away the offset is therefore recomputed from the foot of
/// the perpendicular from the centre to the ray, `l = f − (b/a) d`, with the cancellation done
/// in exact products (good to ~2⁻⁴⁸ |f|), and the point as `centre + offset`: within 4.5 ulp of
/// r, measured out to 10⁵ radii. Nearer, `f + t·d` errs by a few ulp of |f| (up to 47 ulp of r
/// at 16 radii).
///
/// ```
/// use microray::geometry::hit_point;
/// use microray::{Ray, Sphere, Vec3};
/// let tiny = Sphere::new(Vec3::ZERO, 1e-4);
/// let ray = Ray::new(Vec3::new(0.0, 6e-5, 10.0), Vec3::new(0.0, 0.0, -1.0));
/// let t = microray::ray_intersect(&ray, &tiny, 0.0, f32::INFINITY).unwrap();
/// let (p, offset) = hit_point(&ray, t, ray.origin - tiny.center, &tiny);
/// assert_eq!(offset, Vec3::new(0.0, 6e-5, 8e-5)); // exact to the last bit
/// assert_eq!(p, offset);
/// // whereas f + t·d is off in the 3rd digit:
/// assert!(((ray.origin + ray.dir * t).z - 8e-5).abs() > 1e-7);
/// ```
#[inline]
pub fn hit_point(ray: &Ray, t: f32, f: Vec3, sphere: &Sphere) -> (Vec3, Vec3) {
    hit_point_within(ray, t, f, sphere, NEAR2_MIN)
}

/// `(distance/radius)²` within which [`hit_point()`] keeps `f + t·d`: 16 radii, the least any
/// material gets (`scene::near2`).
pub(crate) const NEAR2_MIN: f32 = 256.0;

/// [`hit_point()`] with f32 up to `√near2` radii away instead of 16: the renderer's choice per
/// material (`scene::near2`), which a diffuse or dull sphere lets go much farther.
#[inline]
pub(crate) fn hit_point_within(
    ray: &Ray,
    t: f32,
    f: Vec3,
    sphere: &Sphere,
    near2: f32,
) -> (Vec3, Vec3) {
    hit_point_near(ray, t, f, sphere, offset_is_near(f, sphere.radius, near2))
}

/// [`hit_point_within`] with [`offset_is_near`]'s answer given: for primary rays, whose
/// renderer decides it once per sphere and frame.
#[inline]
pub(crate) fn hit_point_near(
    ray: &Ray,
    t: f32,
    f: Vec3,
    sphere: &Sphere,
    near: bool,
) -> (Vec3, Vec3) {
    let d = ray.dir;
    if near {
        return (ray.at(t), f + d * t);
    }
    hit_point_far(d.x, d.y, d.z, t, f.x, f.y, f.z, sphere).unwrap_or((ray.at(t), f + d * t))
}

/// Whether [`hit_point_within`] keeps `f + t·d` for rays from `f` (origin − centre) to a sphere
/// of `radius`: within `√near2` radii. The same for every ray from one origin, so the lane paths
/// decide it once per sphere and frame.
#[inline(always)]
pub(crate) fn offset_is_near(f: Vec3, radius: f32, near2: f32) -> bool {
    f.dot(f) <= near2 * (radius * radius)
}

/// [`hit_point()`] from afar: the offset as `l ± s·d`, with `l = f − (b/a) d` the foot of the
/// perpendicular from the centre and `s = √((r² − |l|²)/a)`, the sign that of the root that `t`
/// approximates (`−b/a ∓ s`). `l` is computed as `d × (f × d) / a`: the cross product `f × d`
/// is where the cancellation is (f nearly along d, |l| ≪ |f|), so each of its components is
/// taken from exact products ([`two_product`](crate::math::two_product)), whose difference is
/// then exact or nearly (good to ~2⁻⁴⁸ |f||d| where the plain one errs by 2⁻²⁴ |f||d|); `d × w`
/// and the divide do not cancel. `r² − |l|²` is `c_near`'s (exact squares). All in f32: f64
/// would do as well, but it is software on a Cortex-M. Scalar arguments, as for `c_near_xyz`:
/// `Vec3`s would keep the callers' rays in memory. Hosts take four at a time where they can
/// (`hit_point_far4`).
#[cold]
#[inline(never)]
#[allow(clippy::too_many_arguments)]
pub(super) fn hit_point_far(
    dx: f32,
    dy: f32,
    dz: f32,
    t: f32,
    fx: f32,
    fy: f32,
    fz: f32,
    sphere: &Sphere,
) -> Option<(Vec3, Vec3)> {
    let (d, f) = (Vec3::new(dx, dy, dz), Vec3::new(fx, fy, fz));
    let w = Vec3::new(
        product_difference(f.y, d.z, f.z, d.y),
        product_difference(f.z, d.x, f.x, d.z),
        product_difference(f.x, d.y, f.y, d.x),
    );
    // r² − |l|², the `c` of the origin l for the sphere about 0.
    let centred = Sphere {
        center: Vec3::ZERO,
        radius: sphere.radius,
    };
    let offset = far_offset(d, t, f, w, |l| -c_near(l, Vec3::ZERO, &centred));
    let point = sphere.center + offset;
    if offset.is_finite() && point.is_finite() {
        Some((point, offset))
    } else {
        None
    }
}

/// [`hit_point_far`]'s offset `l ± s·d` from `w = f × d` in exact products and `h2(l)`, which
/// is r² − |l|²: for one f32 and for four lanes (`hit_point_far4`). The callers give `w` and
/// `h2`, out of line for one f32 (a cold path: one copy is small flash), inline in lanes.
#[inline(always)]
fn far_offset<P: Ieee3>(d: P, t: P::S, f: P, w: P, h2: impl FnOnce(P) -> P::S) -> P {
    let zero = <P::S as Ieee>::splat(0.0);
    let a = d.dot(d);
    let l = d.cross(w).div(a);
    let h2 = h2(l);
    let s = <P::S as IeeeCmp>::select(h2.gt(zero), h2 / a, zero).sqrt();
    // The roots are −k ∓ s; the hit is the one that `t` approximates.
    let k = f.dot(d) / a;
    let nearer = (t - (k.flip() - s)).abs().le((t - (k.flip() + s)).abs());
    let s = <P::S as IeeeCmp>::select(nearer, s.flip(), s);
    l.add(d.mul(s))
}

/// [`hit_point_far`] of four rays from one origin (`f` their common `o − m`, as for primary
/// rays) with directions `d` and parameters `t`: [`hit_point_far_lanes`] with `f` and the
/// sphere in every lane; `None` where a lane is not finite (the scalar call then falls back for
/// it). For hosts, where many small far spheres make this path warm.
#[cfg(lanes)]
#[inline(always)]
pub(crate) fn hit_point_far4(
    d: crate::simd::V,
    t: crate::simd::F,
    f: Vec3,
    sphere: &Sphere,
) -> Option<(crate::simd::V, crate::simd::V)> {
    use crate::simd::{F, V};
    let (point, offset, finite) = hit_point_far_lanes(
        d,
        t,
        V::splat(f),
        V::splat(sphere.center),
        F::splat(sphere.radius),
    );
    (finite == 0b1111).then_some((point, offset))
}

/// [`hit_point_far`] lane by lane, each lane its own ray (`f`, `d`, `t`) and sphere (`center`,
/// `radius`): [`far_offset`] in lanes, so a lane whose bit is set in the returned mask is the
/// scalar `Some((point, offset))`, bit for bit, and a lane whose bit is clear the scalar `None`.
#[cfg(lanes)]
#[inline(always)]
pub(crate) fn hit_point_far_lanes(
    d: crate::simd::V,
    t: crate::simd::F,
    f: crate::simd::V,
    center: crate::simd::V,
    radius: crate::simd::F,
) -> (crate::simd::V, crate::simd::V, u32) {
    use crate::simd::{neg, V};
    let w = V {
        x: product_difference_of(f.y, d.z, f.z, d.y),
        y: product_difference_of(f.z, d.x, f.x, d.z),
        z: product_difference_of(f.x, d.y, f.y, d.x),
    };
    let offset = far_offset(d, t, f, w, |l| neg(c_origin_of([l.x, l.y, l.z], radius)));
    let point = center.add(offset);
    (point, offset, offset.finite() & point.finite())
}

/// `a·b − c·e` from the exact products: exact or nearly where the two agree in most bits.
/// Out of line: one copy for the three components of a cold path.
#[inline(never)]
pub(super) fn product_difference(a: f32, b: f32, c: f32, e: f32) -> f32 {
    product_difference_of(a, b, c, e)
}

/// [`product_difference`] on any [`Ieee`] type.
#[inline(always)]
pub(super) fn product_difference_of<T: Ieee>(a: T, b: T, c: T, e: T) -> T {
    let ((p, pe), (q, qe)) = (two_product_of(a, b), two_product_of(c, e));
    (p - q) + (pe - qe)
}

/// For a ray that starts on the surface of a sphere (`f = o − m` with `|f| = r`): the
/// parameter where it leaves the sphere again, or `None` when it heads outwards (or the exit is
/// beyond the f32 range).
///
/// The roots of a quadratic sum to `−2b/a`; one of them is the origin itself, so the other is
/// `−2b/a` exactly as far as b goes. Computing it this way instead of intersecting the sphere
/// the ray starts on is what makes shadow and mirror rays free of self-hits ("acne") without
/// an epsilon.
///
/// ```
/// use microray::geometry::exit_root;
/// use microray::Vec3;
/// // From the top of a unit sphere straight down: out through the bottom at t = 2.
/// assert_eq!(exit_root(Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, -1.0, 0.0)), Some(2.0));
/// assert_eq!(exit_root(Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, 1.0, 0.0)), None);
/// ```
#[inline]
pub fn exit_root(f: Vec3, d: Vec3) -> Option<f32> {
    let t = exit_t(f, d);
    // Beyond the f32 range (a tiny d) there is no exit to return: like a miss.
    if t > 0.0 && t < f32::INFINITY {
        Some(t)
    } else {
        None
    }
}

/// [`exit_root`]'s `t` before its range check, `−2 f·d / d·d`, for one ray or four lanes (the
/// same operations in the same order: a lane computes the scalar bits).
#[inline(always)]
pub(crate) fn exit_t<V: Ieee3>(f: V, d: V) -> V::S {
    V::S::splat(-2.0) * f.dot(d) / d.dot(d)
}
