//! Rays, spheres and their intersection: all of microray's intersection code is in this file.
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
//!    of r when `|f| ≫ r`, even with t exact. [`hit_point`] recomputes it from exact products
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

use crate::math::{finite, sqrt, two_product_of, two_square_of, two_sum_of, Ieee, Vec3};

/// A ray `origin + t·dir`; `dir` need not be unit length.
///
/// ```
/// use microray::{Ray, Vec3};
/// let ray = Ray::new(Vec3::ZERO, Vec3::new(0.0, 0.0, -2.0));
/// assert_eq!(ray.at(1.5), Vec3::new(0.0, 0.0, -3.0));
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
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
/// This is the lecture's `ray_intersect(ray, sphere, tmin, tmax)`, written to stay accurate in
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

/// What a ray origin and a sphere share, whatever the ray's direction: `f = o − m` and
/// `c = |f|² − r²` (negative when the origin is inside).
///
/// Build it once per origin and sphere (see [`Prepared::exact`]) and intersect many directions
/// with [`Prepared::hit`]: this is how primary rays and point-light shadow rays are traced.
///
/// ```
/// use microray::{Prepared, Sphere, Vec3};
/// let ground = Sphere::new(Vec3::new(0.0, -1e6, 0.0), 1e6);
/// let eye = Vec3::new(0.0, 1.0, 0.0);
/// let k = Prepared::exact(eye, &ground);
/// assert_eq!(k.c, 2_000_001.0); // (1e6 + 1)² − 1e12, exact; plain f32 says 2_031_616
/// let t = k.hit(Vec3::new(0.0, -1.0, 1.0), 0.0, f32::INFINITY).unwrap();
/// assert!((t - 1.0).abs() < 1e-6);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Prepared {
    /// `o − m`, rounded to f32.
    pub f: Vec3,
    /// `|o − m|² − r²`, accurate to a few ulp even where the subtraction cancels.
    pub c: f32,
    /// The sphere's radius.
    pub r: f32,
}

/// f32 `c = ff − rr` is kept only when `|c| > CANCEL (ff + rr)`, that is when the origin is more
/// than √3 radii from the centre (or inside, less than 1/√3). The f32 error of c is about
/// 2⁻²⁴ (ff + rr) from the squares plus as much again from rounding `f`, and the near root
/// `c/q` (used within ~2 radii, see `near_root`; farther it does not depend on c) is
/// proportional to c, so `(ff + rr) / |c| ≤ 2` keeps that root within a few ulp. An earlier
/// threshold of 2⁻¹¹ let c lose 10 bits, and a mirror ray leaving a sphere that rests on a
/// ground sphere of radius 1000 met the ground 700 ulp off, enough to flip its shadow.
const CANCEL: f32 = 0.5;

/// `c = |f|² − r²` for the origin `base + offset` (`offset` zero for a plain origin) where its
/// f32 value cancels (an origin near the surface), from error-free pieces: `f` as `h + l` per
/// coordinate (`h` the f32 `(base − m) + offset`, `l` the errors of both sums), each square of
/// `h` as its rounded value and error, and the sum of the rounded squares with its errors.
/// Only the error terms, each ~2⁻²⁴ of `|f|² + r²`, are added with rounding, so the result is
/// good to ~2⁻⁴⁵ (|f|² + r²) plus its own rounding: ~2⁻²⁴ |c| even where `|f|²` and `r²`
/// agree in 20 bits (the eye 1 above a ground of radius 10⁶). Where `|base − m|` is much more
/// than `|f|` (a base far away for the sphere's size), `l`'s error grows with their ratio.
///
/// f32 rather than f64, which is software on every Cortex-M (~1 000 instructions here against
/// ~130), and plain f32 operations on every target, so every target computes the same bits.
/// Where the squares overflow (|f| or r from ~1.8·10¹⁹) the result is not finite.
#[inline(always)]
fn c_near(base: Vec3, offset: Vec3, sphere: &Sphere) -> f32 {
    let (b, o, m) = (base, offset, sphere.center);
    c_near_xyz::<true>(b.x, b.y, b.z, o.x, o.y, o.z, m.x, m.y, m.z, sphere.radius)
}

/// [`c_near`] for a plain origin (no offset), the same bits with less work: for the per-ray
/// constants of [`ray_intersect`] and [`Prepared::new`]. Those built once per frame keep
/// `c_near`, so that a firmware that does not call these links one copy.
#[inline(always)]
fn c_origin(origin: Vec3, sphere: &Sphere) -> f32 {
    let (b, m) = (origin, sphere.center);
    c_near_xyz::<false>(b.x, b.y, b.z, 0.0, 0.0, 0.0, m.x, m.y, m.z, sphere.radius)
}

/// [`c_near`] on the coordinates of base, offset and centre. Out of line: the rare call costs
/// less than its ~120 operations inlined into every ray loop (on x86-64, 7% of the renderer's
/// time), and on Arm s16–s31 keep the caller's values across it. Scalars, not `Vec3`s (nor an
/// array): an aggregate goes to a call by address, and callers then kept it in memory for
/// every test, not only for the few that call this.
///
/// `OFFSET` false: for a plain origin (`offset` zero), where the sum with the offset is exact and
/// is left out (the same bits, ~15% fewer operations; `ray_intersect`, [`Prepared::new`]).
#[inline(never)]
#[allow(clippy::too_many_arguments)]
fn c_near_xyz<const OFFSET: bool>(
    bx: f32,
    by: f32,
    bz: f32,
    ox: f32,
    oy: f32,
    oz: f32,
    mx: f32,
    my: f32,
    mz: f32,
    radius: f32,
) -> f32 {
    #[cfg(lanes)]
    return c_near_across::<OFFSET>([bx, by, bz], [ox, oy, oz], [mx, my, mz], radius);
    #[cfg(not(lanes))]
    c_near_of::<f32, OFFSET>([bx, by, bz], [ox, oy, oz], [mx, my, mz], radius)
}

/// [`c_near_of`] for one origin with the coordinates in vector lanes (hosts, `cfg(lanes)`): the
/// per-coordinate pieces (the sums' errors, the squares and their errors) in lanes 0–2 and the
/// radius's square in lane 3, then the running sum over the coordinates in `c_near_of`'s order.
/// The same operations on the same values, so the same bits, in 93 x86-64 instructions instead
/// of 162 (91 instead of 133 without an offset).
#[cfg(lanes)]
#[inline(always)]
fn c_near_across<const OFFSET: bool>(b: [f32; 3], o: [f32; 3], m: [f32; 3], radius: f32) -> f32 {
    use crate::math::lanes::F;
    let lanes = |v: [f32; 3], w: f32| F::from([v[0], v[1], v[2], w]);
    // Lane 3: `radius − 0 (+ 0)`, which is `radius` with no error, squared as `c_near_of`
    // squares it.
    let (g, gl) = two_sum_of(lanes(b, radius), lanes(m, 0.0).flip());
    let (h, e) = if OFFSET {
        two_sum_of(g, lanes(o, 0.0))
    } else {
        (g + F::splat(0.0), F::splat(0.0))
    };
    let l = gl + e;
    let (p, ep) = two_square_of(h);
    let q = l * (F::splat(2.0) * h + l);
    let (p, ep, q) = (p.to_array(), ep.to_array(), q.to_array());
    let (mut big, mut small) = (-p[3], -ep[3]);
    for k in 0..3 {
        let (sum, t) = two_sum_of(big, p[k]);
        big = sum;
        small += (t + ep[k]) + q[k];
    }
    big + small
}

/// [`c_near_xyz`]'s operations on any [`Ieee`] type (one f32, or four lanes on hosts).
#[inline(always)]
fn c_near_of<T: Ieee, const OFFSET: bool>(base: [T; 3], offset: [T; 3], m: [T; 3], radius: T) -> T {
    let (pr, er) = two_square_of(radius);
    // `big` the rounded sum of the squares; `small` every error term, each ~2⁻²⁴ of the total.
    let (mut big, mut small) = (pr.flip(), er.flip());
    // A loop, not three copies: flash is scarce, and at opt-level 3 LLVM unrolls it anyway.
    for (b, (o, m)) in base.into_iter().zip(offset.into_iter().zip(m)) {
        let (g, gl) = two_sum_of(b, m.flip());
        // `two_sum(g, 0.0)` is `(g + 0.0, +0.0)` for every finite g.
        let (h, e) = if OFFSET {
            two_sum_of(g, o)
        } else {
            (g + T::splat(0.0), T::splat(0.0))
        };
        let l = gl + e;
        let (p, ep) = two_square_of(h);
        let (sum, t) = two_sum_of(big, p);
        big = sum;
        // (h + l)² − h² = l (2h + l): small, and rounded only relative to itself.
        small = small + ((t + ep) + l * (T::splat(2.0) * h + l));
    }
    big + small
}

impl Prepared {
    /// The constants for rays from `origin`, with `c` always computed the compensated way
    /// (`c_near`), not only where the f32 value cancels: for origins that many rays share (the
    /// eye, a point light), where it is worth its cost.
    ///
    /// ```
    /// # use microray::{Prepared, Sphere, Vec3};
    /// let k = Prepared::exact(Vec3::ZERO, &Sphere::new(Vec3::new(0.0, 0.0, -3.0), 1.0));
    /// assert_eq!((k.f, k.c), (Vec3::new(0.0, 0.0, 3.0), 8.0));
    /// ```
    pub fn exact(origin: Vec3, sphere: &Sphere) -> Self {
        let (f, r) = (origin - sphere.center, sphere.radius);
        let c = c_near(origin, Vec3::ZERO, sphere);
        // Where the squares overflow f32 (|f| or r from ~1.8·10¹⁹) `c_near` is not finite: the
        // plain value then, infinite or NaN, for which the roots take their scaled path
        // (`roots_scaled`).
        let c = if finite(c) { c } else { f.dot(f) - r * r };
        Prepared { f, c, r }
    }

    /// The constants for one ray from `origin`: `c` in f32, redone the compensated way where the
    /// f32 subtraction cancels more than a bit (an origin within 0.73 radii of the surface) or
    /// overflows.
    ///
    /// ```
    /// # use microray::{Prepared, Sphere, Vec3};
    /// let ground = Sphere::new(Vec3::new(0.0, -1e6, 0.0), 1e6);
    /// assert_eq!(Prepared::new(Vec3::new(0.0, 1.0, 0.0), &ground).c, 2_000_001.0);
    /// ```
    #[inline]
    pub fn new(origin: Vec3, sphere: &Sphere) -> Self {
        let f = origin - sphere.center;
        Prepared::finish(f, sphere.radius, || c_origin(origin, sphere))
    }

    /// `c` for `f` in f32, or `exact()` where the f32 value cancels or overflows.
    #[inline]
    fn finish(f: Vec3, r: f32, exact: impl FnOnce() -> f32) -> Self {
        let (ff, rr) = (f.dot(f), r * r);
        let c = ff - rr;
        let c = if libm::fabsf(c) > (ff + rr) * CANCEL && finite(c) {
            c
        } else {
            exact()
        };
        Prepared { f, c, r }
    }

    /// The constants for a ray that starts on the surface of the sphere centred at `base`, at
    /// `base + offset` (a [`Hit`](crate::Hit)'s centre and offset): `f = (base − m) + offset`.
    ///
    /// The hit point itself, rounded to f32, is off by half an ulp of its coordinates: 5·10⁻⁴
    /// for a scene 10⁴ from the origin, a large part of a unit sphere's shading. Centres near
    /// each other subtract exactly, and the offset is small and accurate, so `f` is good to an
    /// ulp of `|f|` wherever the scene is. `c` is compensated as in [`Prepared::new`].
    ///
    /// ```
    /// # use microray::{Prepared, Sphere, Vec3};
    /// let base = Vec3::new(1e4, 1e4, 1e4);
    /// let offset = Vec3::new(0.0, 1.0, 1e-4); // a point on a unit sphere at `base`
    /// let other = Sphere::new(Vec3::new(1e4, 1e4 + 3.0, 1e4), 1.0);
    /// let k = Prepared::from_surface(base, offset, &other);
    /// assert_eq!(k.f, Vec3::new(0.0, -2.0, 1e-4)); // (base + offset) − m would say z = 0
    /// ```
    #[inline]
    pub fn from_surface(base: Vec3, offset: Vec3, sphere: &Sphere) -> Self {
        let f = (base - sphere.center) + offset;
        Prepared::finish(f, sphere.radius, || c_near(base, offset, sphere))
    }

    /// `Prepared::new(ray.origin, sphere).hit(ray.dir, tmin, tmax)` with the `f` it used, a
    /// clear miss decided before `c` is finished (see `fused`): [`ray_intersect`].
    #[inline]
    pub(crate) fn ray_hit(ray: &Ray, sphere: &Sphere, tmin: f32, tmax: f32) -> Option<(f32, Vec3)> {
        let (o, m) = (ray.origin, sphere.center);
        Prepared::fused::<false>(o - m, ray.dir, tmin, tmax, false, (o, Vec3::ZERO, sphere))
    }

    /// What `Prepared::from_surface(anchor, rel, sphere).hit(d, tmin, tmax)` returns, with the
    /// `f` it used: for the shadow and mirror rays of a hit, which leave from
    /// `anchor + rel` (see [`Hit::anchor`](crate::Hit::anchor)). Cheaper, because a sphere
    /// certainly behind the ray (origin outside by more than the f32 error of `c`, `f·d ≥ 0`,
    /// `tmin ≥ 0`) is rejected before `c` is finished. That spares the compensated `c` (~100
    /// instructions) for, say, the ground under a ball when the shadow ray goes up.
    ///
    /// ```
    /// # use microray::{Prepared, Sphere, Vec3};
    /// let ground = Sphere::new(Vec3::new(0.0, -1000.0, 0.0), 1000.0);
    /// // the foot of a ball floating 1 above the ground
    /// let (base, offset) = (Vec3::new(0.0, 1.5, 0.0), Vec3::new(0.0, -0.5, 0.0));
    /// let up = Vec3::new(0.0, 1.0, 0.0);
    /// assert_eq!(Prepared::leaving_hit(base, offset, &ground, up, 0.0, f32::INFINITY), None);
    /// let (t, f) = Prepared::leaving_hit(base, offset, &ground, -up, 0.0, 10.0).unwrap();
    /// assert_eq!((t, f), (1.0, Vec3::new(0.0, 1001.0, 0.0)));
    /// ```
    #[inline]
    pub fn leaving_hit(
        anchor: Vec3,
        rel: Vec3,
        sphere: &Sphere,
        d: Vec3,
        tmin: f32,
        tmax: f32,
    ) -> Option<(f32, Vec3)> {
        Prepared::leaving_test(anchor, rel, sphere, d, tmin, tmax, false)
    }

    /// Whether the shadow ray from `anchor + rel` along `d` meets `sphere` at some
    /// `0 < t ≤ tmax`: `leaving_hit(anchor, rel, sphere, d, f32::MIN_POSITIVE, tmax).is_some()`,
    /// without the root where the answer is clear. Where `leaving_hit` needs the compensated
    /// `c` (an origin near the surface, typically a ground point next to a ball resting on it)
    /// the sign of Hearn–Baker's discriminant, which does not use `c`, decides a clear miss, and
    /// for `tmax = ∞` a clear hit too; only rays that graze the sphere within ~2⁻¹⁹ of its size
    /// pay for `c`.
    ///
    /// ```
    /// # use microray::{Prepared, Sphere, Vec3};
    /// let ball = Sphere::new(Vec3::new(0.0, 1.0, 0.0), 1.0);
    /// let (ground_centre, foot) = (Vec3::new(0.0, -1000.0, 0.0), Vec3::new(0.3, 1000.0, 0.0));
    /// let up = Vec3::new(0.0, 1.0, 0.0);
    /// assert!(Prepared::leaving_blocks(ground_centre, foot, &ball, up, f32::INFINITY));
    /// assert!(!Prepared::leaving_blocks(ground_centre, foot, &ball, -up, f32::INFINITY));
    /// ```
    #[inline]
    pub fn leaving_blocks(anchor: Vec3, rel: Vec3, sphere: &Sphere, d: Vec3, tmax: f32) -> bool {
        Prepared::leaving_test(anchor, rel, sphere, d, f32::MIN_POSITIVE, tmax, true).is_some()
    }

    /// [`Prepared::leaving_hit`]; with `any_hit`, [`Prepared::leaving_blocks`], where a clear
    /// hit may come back with a NaN `t`: only whether there is one is asked.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn leaving_test(
        anchor: Vec3,
        rel: Vec3,
        sphere: &Sphere,
        d: Vec3,
        tmin: f32,
        tmax: f32,
        any_hit: bool,
    ) -> Option<(f32, Vec3)> {
        let f = (anchor - sphere.center) + rel;
        Prepared::fused::<true>(f, d, tmin, tmax, any_hit, (anchor, rel, sphere))
    }

    /// `Prepared { f, c, r }.hit(d, tmin, tmax)` for the origin `base + offset` and `sphere`
    /// (`f` their difference), with the compensated `c` only where the f32 value cancels and
    /// the answer is not clear without it (see `leaving_test`).
    ///
    /// `OFFSET` false when `offset` is zero (see `c_near_xyz`).
    #[inline(always)]
    fn fused<const OFFSET: bool>(
        f: Vec3,
        d: Vec3,
        tmin: f32,
        tmax: f32,
        any_hit: bool,
        (base, offset, sphere): (Vec3, Vec3, &Sphere),
    ) -> Option<(f32, Vec3)> {
        let r = sphere.radius;
        let (ff, rr) = (f.dot(f), r * r);
        let c = ff - rr;
        let b = f.dot(d);
        // The f32 c is within ~2⁻²¹ (ff + rr) of the exact one (its rounding and that of f), so
        // b² − ac is off by that times a, plus a few ε (b² + a ff) from b, b² and ac, all below
        // 2⁻²⁰ a (ff + rr) as b² ≤ a ff: below −2⁻¹⁶ a (ff + rr) it misses the sphere's line
        // whatever the rounding. Most tests are such misses, decided before the compensated c,
        // as are spheres certainly behind. (A margin scaled by |c| instead, as `hit_ab`'s with
        // an accurate c, is too small where c cancels: rays from 1 above a ground of radius 10⁶
        // that meet it 1 400 away missed.) Written `ac − 2⁻¹⁶ a (ff + rr) > b²`, where a or ff
        // overflows is ∞ − ∞ = NaN, never a miss; `a (c − 2⁻¹⁶ (ff + rr))` would reject those
        // (`leaving_overflow_is_no_clear_miss`).
        let sum = ff + rr;
        let a = d.dot(d);
        let bb = b * b;
        if a * c - a * sum * (1.0 / 65_536.0) > bb {
            return None;
        }
        let err_c = sum * (1.0 / 1_048_576.0);
        if c > err_c && b >= 0.0 && tmin >= 0.0 {
            return None;
        }
        let c = if libm::fabsf(c) > sum * CANCEL && finite(c) {
            c
        } else {
            if any_hit {
                // Hearn–Baker's a (r² − |l|²) is within ~8ε a (r² + |f|²) of the exact b² − ac
                // (the rounding of b/a, l and its square): 2⁻²⁰ of that is a clear sign.
                let l = f - d * (b / a);
                let disc = a * (rr - l.dot(l));
                let margin = a * sum * (1.0 / 1_048_576.0);
                if finite(disc) && finite(margin) {
                    if disc < -margin {
                        return None;
                    }
                    // Outside, heading in, meeting it: both roots are positive.
                    if disc > margin && c > err_c && b < 0.0 && tmax == f32::INFINITY {
                        return Some((f32::NAN, f));
                    }
                }
            }
            // `c_near`, or `c_origin` (without the offset's sums) when `OFFSET` is false.
            let (b, o, m) = (base, offset, sphere.center);
            c_near_xyz::<OFFSET>(b.x, b.y, b.z, o.x, o.y, o.z, m.x, m.y, m.z, r)
        };
        let k = Prepared { f, c, r };
        k.hit_ab(d, a, b, tmin, tmax).map(|t| (t, f))
    }

    /// The closest root in `[tmin, tmax]` of the ray from this origin along `d` (any length).
    ///
    /// ```
    /// # use microray::{Prepared, Sphere, Vec3};
    /// let k = Prepared::exact(Vec3::ZERO, &Sphere::new(Vec3::new(0.0, 0.0, -3.0), 1.0));
    /// assert_eq!(k.hit(Vec3::new(0.0, 0.0, -2.0), 0.0, 10.0), Some(1.0)); // unnormalised d
    /// ```
    #[inline]
    pub fn hit(&self, d: Vec3, tmin: f32, tmax: f32) -> Option<f32> {
        self.hit_ab(d, d.dot(d), self.f.dot(d), tmin, tmax)
    }

    /// [`Prepared::hit`] of four directions at once, each with its own `tmax`: the same
    /// results, bit for bit. On x86-64 and on AArch64 with NEON the four run in the lanes of
    /// one vector register (how the renderer traces primary rays there); elsewhere one by one.
    ///
    /// ```
    /// # use microray::{Prepared, Sphere, Vec3};
    /// let k = Prepared::exact(Vec3::ZERO, &Sphere::new(Vec3::new(0.0, 0.0, -3.0), 1.0));
    /// let d = [Vec3::new(0.0, 0.0, -1.0), Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, 0.1, -1.0), Vec3::ZERO];
    /// let hits = k.hit4(&d, 0.0, [10.0, 10.0, 1.0, 10.0]);
    /// assert_eq!(hits, [Some(2.0), None, None, None]); // the third is beyond its tmax
    /// assert_eq!(hits[0], k.hit(d[0], 0.0, 10.0));
    /// ```
    #[inline]
    pub fn hit4(&self, d: &[Vec3; 4], tmin: f32, tmax: [f32; 4]) -> [Option<f32>; 4] {
        #[cfg(lanes)]
        if finite(self.c) {
            let h = self.hit_lanes_of(d, tmin, tmax);
            return core::array::from_fn(|l| {
                if h.redo & (1 << l) != 0 {
                    self.hit(d[l], tmin, tmax[l])
                } else {
                    (h.hit & (1 << l) != 0).then_some(h.t[l])
                }
            });
        }
        core::array::from_fn(|l| self.hit(d[l], tmin, tmax[l]))
    }

    /// Which of the lanes `ask` of four directions (by coordinate) `hit` finds a root for in
    /// `[tmin, tmax]`, as bits: `hit4`'s answers without their roots, for shadow rays from a
    /// point light (its per-frame constants): the lanes' test where it decides, the scalar one
    /// where it does not, so the same answers. Without the arrays of `Vec3` and `Option` that
    /// `hit4` goes through, which were 6% of a shadowed scene's time.
    #[cfg(lanes)]
    #[inline(always)]
    pub(crate) fn hit_bits4(
        &self,
        d: &crate::math::lanes::V,
        tmin: f32,
        tmax: f32,
        ask: u32,
    ) -> u32 {
        let (x, y, z) = (d.x.to_array(), d.y.to_array(), d.z.to_array());
        let (hit, redo) = if finite(self.c) {
            let h = self.hit_lanes(self.hearn_baker(), x, y, z, tmin, [tmax; LANES]);
            (h.hit & !h.redo & ask, h.redo & ask)
        } else {
            (0, ask)
        };
        let mut bits = hit;
        for l in crate::math::lanes::ones(redo) {
            let dl = Vec3::new(x[l & 3], y[l & 3], z[l & 3]);
            if self.hit(dl, tmin, tmax).is_some() {
                bits |= 1 << l;
            }
        }
        bits
    }

    /// [`Prepared::hit_lanes`] of four directions given as vectors, its discriminant choice
    /// made here: for `hit4` and the lanes' test (the renderer's loop makes the choice once per
    /// sphere and keeps its directions by coordinate).
    #[cfg(lanes)]
    #[inline(always)]
    fn hit_lanes_of(&self, d: &[Vec3; 4], tmin: f32, tmax: [f32; 4]) -> LaneHits {
        let [x, y, z] = [d.map(|v| v.x), d.map(|v| v.y), d.map(|v| v.z)];
        self.hit_lanes(self.hearn_baker(), x, y, z, tmin, tmax)
    }

    /// The scalar test's choice of discriminant for these constants, the same for every
    /// direction: Hearn–Baker's where `|c| > r²` (see `roots`), for the lanes' `hit_lanes`.
    #[cfg(lanes)]
    #[inline(always)]
    pub(crate) fn hearn_baker(&self) -> bool {
        libm::fabsf(self.c) > self.r * self.r
    }

    /// [`Prepared::hit`] with `a = d·d` and `b = f·d` already computed.
    #[inline(always)]
    pub(crate) fn hit_ab(&self, d: Vec3, a: f32, b: f32, tmin: f32, tmax: f32) -> Option<f32> {
        let (f, c, r) = (self.f, self.c, self.r);
        hit_ab_xyz(f.x, f.y, f.z, c, r, d.x, d.y, d.z, a, b, tmin, tmax)
    }

    /// [`Prepared::hit`] for constants of an origin outside the sphere (`c > 0`, finite),
    /// `tmin ≥ 0` and a finite `tmax` (`f32::MAX` for no limit: a root is finite), as the
    /// eye's are for most spheres: the same result, bit for bit, without the tests that these
    /// conditions decide (the sign of `c`, its overflow, `q`'s sign and zero, a root beyond the
    /// f32 range). For primary rays on Cortex-M, where every test is scalar: the caller checks
    /// the condition once per sphere, not per ray.
    #[cfg(any(test, not(lanes)))]
    #[inline(always)]
    pub(crate) fn hit_outside(&self, d: Vec3, tmin: f32, tmax: f32) -> Option<f32> {
        let (f, c, r) = (self.f, self.c, self.r);
        let (a, b) = (d.dot(d), f.dot(d));
        hit_outside_xyz(f.x, f.y, f.z, c, r, d.x, d.y, d.z, a, b, tmin, tmax)
    }

    /// Whether [`Prepared::hit_outside`] applies to these constants.
    #[cfg(any(test, not(lanes)))]
    #[inline(always)]
    pub(crate) fn outside(&self) -> bool {
        self.c > 0.0 && finite(self.c)
    }
}

/// [`Prepared::hit_ab`] on scalars: where it is not inlined (the shadow loops), a `Prepared` or
/// `Vec3` argument would go by address, and the loop would build it in memory for every test.
#[inline]
#[allow(clippy::too_many_arguments)]
fn hit_ab_xyz(
    fx: f32,
    fy: f32,
    fz: f32,
    c: f32,
    r: f32,
    dx: f32,
    dy: f32,
    dz: f32,
    a: f32,
    b: f32,
    tmin: f32,
    tmax: f32,
) -> Option<f32> {
    let (f, d) = (Vec3::new(fx, fy, fz), Vec3::new(dx, dy, dz));
    // The same roots as `roots`, with the early exits that make it cost about what the
    // lecture's formula costs: most tests are misses.
    // b² − ac is off by a few ε (b² + a|c|) (its rounding, and that of b and c); a value
    // below −2⁻¹⁸ of that misses the sphere's whole line whatever the rounding. Most tests
    // are such misses: one branch first, and no Hearn–Baker divide for them. The margin is
    // written with `ac`, not `a|c|`: they differ only for c < 0, where b² − ac ≥ 0 is never
    // below a margin of either sign, so the same tests are rejected, and `ac` is computed once.
    let bb = b * b;
    let ac = a * c;
    let disc0 = bb - ac;
    if disc0 < -(bb + ac) * (1.0 / 262_144.0) {
        return None;
    }
    // Outside (c > 0) and heading away (b ≥ 0): both roots are negative.
    if c > 0.0 && b >= 0.0 && tmin >= 0.0 {
        return None;
    }
    let rr = r * r;
    let disc = if libm::fabsf(c) <= rr {
        disc0
    } else {
        let l = f - d * (b / a);
        a * (rr - l.dot(l))
    };
    if !((0.0..=f32::MAX).contains(&disc) && finite(c)) {
        // Overflow shows as ±∞ or NaN somewhere on the way to disc (or in c).
        if disc < 0.0 && finite(disc) {
            return None;
        }
        return select(roots_scaled(f.x, f.y, f.z, d.x, d.y, d.z, r)?, tmin, tmax);
    }
    let s = sqrt(disc);
    let q = if b > 0.0 { -(b + s) } else { s - b };
    if q == 0.0 {
        return select((0.0, 0.0), tmin, tmax);
    }
    let t0 = near_root(a, b, c, q, s);
    // With q > 0 and c > 0, c/q is the near root (c/q ≤ q/a since q² ≥ b² ≥ ac): when it is
    // in range the far root's divide is not needed.
    if q > 0.0 && c > 0.0 && t0 >= tmin && t0 <= tmax && t0 < f32::INFINITY {
        return Some(t0);
    }
    let t1 = q / a;
    select(if t0 <= t1 { (t0, t1) } else { (t1, t0) }, tmin, tmax)
}

/// [`hit_ab_xyz`]'s steps for `c > 0` finite, `tmin ≥ 0` and `tmax` finite
/// ([`Prepared::hit_outside`]), with the tests whose outcome that fixes left out: `c > 0` in the
/// behind test and in the early return, the early return's `t0 < ∞`, `c`'s overflow check,
/// `q`'s sign (b < 0 once the behind test has passed: b ≥ 0 left, and a NaN b makes disc NaN,
/// which the range check hands to the general test with any other overflow), `q = 0`
/// (q ≥ −b > 0), and `near_root`'s `c > 0 && b < 0`. A copy rather than a
/// const parameter of `hit_ab_xyz`: made generic, the general test's Cortex-M code grew by 4–5
/// instructions a test (numbench) and the host's renderer by 3.4 a pixel.
/// `hit_outside_is_hit` pins the two together, bit for bit.
#[cfg(any(test, not(lanes)))]
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn hit_outside_xyz(
    fx: f32,
    fy: f32,
    fz: f32,
    c: f32,
    r: f32,
    dx: f32,
    dy: f32,
    dz: f32,
    a: f32,
    b: f32,
    tmin: f32,
    tmax: f32,
) -> Option<f32> {
    let (f, d) = (Vec3::new(fx, fy, fz), Vec3::new(dx, dy, dz));
    let bb = b * b;
    let ac = a * c;
    let disc0 = bb - ac;
    if disc0 < -(bb + ac) * (1.0 / 262_144.0) {
        return None;
    }
    if b >= 0.0 && tmin >= 0.0 {
        return None;
    }
    let rr = r * r;
    let disc = if libm::fabsf(c) <= rr {
        disc0
    } else {
        let l = f - d * (b / a);
        a * (rr - l.dot(l))
    };
    // `0 ≤ disc ≤ f32::MAX` as a bit test (M4F: for two float comparisons, as `vsqrt` takes
    // the bits in a core register); −0, which the float test lets through, takes the general
    // test with the negatives, NaN and ∞.
    if !crate::math::plus_finite(disc) {
        if disc < 0.0 && finite(disc) {
            return None;
        }
        // Overflow (or −0), rare: the general test, which gives this test's answer too.
        return hit_ab_xyz(fx, fy, fz, c, r, dx, dy, dz, a, b, tmin, tmax);
    }
    let s = sqrt(disc);
    let q = s - b;
    let t0 = if s < -0.5 * b { (-b - s) / a } else { c / q };
    // `tmax` is finite: no test of t0 against infinity (a `tmax` of ∞ made the M4F code test
    // t0's exponent range, 13 instructions a test).
    if t0 >= tmin && t0 <= tmax {
        return Some(t0);
    }
    let t1 = q / a;
    select(if t0 <= t1 { (t0, t1) } else { (t1, t0) }, tmin, tmax)
}

/// Directions that [`Prepared::hit_lanes`] takes at once: four f32 lanes, one SSE or NEON
/// register.
#[cfg(lanes)]
pub(crate) const LANES: usize = 4;

/// What [`Prepared::hit_lanes`] found: bit `l` of `hit` set where lane `l` hits (at `t[l]`), of
/// `redo` where the lane took a rare path (an overflow, `q = 0`) that only the scalar
/// [`Prepared::hit`] decides.
#[cfg(lanes)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct LaneHits {
    pub hit: u32,
    pub redo: u32,
    pub t: [f32; LANES],
}

/// [`Prepared::leaving_blocks`] from `anchor + rel` along `d` for the lanes `open` of four
/// rays, as far as lanes decide it: `(blocked, undecided)` as bits `0..4`, every other lane of
/// `open` a miss. `fused`'s steps lane by lane, the same IEEE operations in its order: its
/// clear-miss and behind tests, then, where it keeps the f32 `c` (no cancellation) and the
/// origin is outside, `hit_ab` (`lanes_hit`). The undecided lanes (a cancelling `c`, an origin
/// inside the sphere, a rare path of the roots) need the scalar test. Shadow rays of four
/// pixels meet most candidates this way.
#[cfg(lanes)]
#[inline(always)]
pub(crate) fn leaving_blocks4(
    anchor: crate::math::lanes::V,
    rel: crate::math::lanes::V,
    sphere: &Sphere,
    d: crate::math::lanes::V,
    tmax: f32,
    open: u32,
) -> (u32, u32) {
    use crate::math::lanes::{bits, F, V};
    use wide::{CmpGe, CmpGt, CmpLe};
    let f = anchor.sub(V::splat(sphere.center)).add(rel);
    let r = sphere.radius;
    let (ff, rr) = (f.dot(f), F::splat(r * r));
    let c = ff - rr;
    let b = f.dot(d);
    let sum = ff + rr;
    let a = d.dot(d);
    let bb = b * b;
    let clear = (a * c - a * sum * F::splat(1.0 / 65_536.0)).cmp_gt(bb);
    let err_c = sum * F::splat(1.0 / 1_048_576.0);
    // `tmin ≥ 0` holds: `leaving_blocks` starts at the smallest normal number.
    let behind = c.cmp_gt(err_c) & b.cmp_ge(F::ZERO);
    let maybe = open & !bits(clear | behind);
    if maybe == 0 {
        return (0, 0);
    }
    // `fused` keeps c where `|c| > sum·CANCEL` and c is finite; `hit_ab` then takes Hearn–Baker's
    // discriminant where |c| > r², which every kept lane with c > 0 has: c > sum/2 means
    // |f|² > ~3r², so c > ~2r² whatever the rounding of c and sum.
    let cabs = c.abs();
    let keeps = cabs.cmp_gt(sum * F::splat(CANCEL)) & cabs.cmp_le(F::splat(f32::MAX));
    let kept = maybe & bits(keeps & c.cmp_gt(F::ZERO));
    if kept == 0 {
        return (0, maybe);
    }
    let h = lanes_hit(f, c, rr, true, d, f32::MIN_POSITIVE, F::splat(tmax));
    (h.hit & !h.redo & kept, (maybe & !kept) | (h.redo & kept))
}

#[cfg(lanes)]
impl Prepared {
    /// [`Prepared::hit`] of `LANES` directions at once (coordinates `dx`, `dy`, `dz`, each lane
    /// with its own `tmax`), in one vector register: on hosts, where primary rays are most of
    /// the tests. Each lane does the scalar path's IEEE operations on the same values in the
    /// same order (no fused multiply-add; negation flips the sign bit, as `-x` does, rather than
    /// `0 − x`, which differs at zero), and each branch of the scalar path is a selection
    /// between both arms, so a lane's hit is the scalar hit, bit for bit. Where the scalar path
    /// leaves its common case (the scaled roots of an overflow, `q = 0`) the lane is marked to
    /// redo. For constants with a finite `c` and for `tmin ≥ 0`; `hb` is `|c| > r²`, the scalar
    /// path's choice of discriminant, the same for every lane.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn hit_lanes(
        &self,
        hb: bool,
        dx: [f32; LANES],
        dy: [f32; LANES],
        dz: [f32; LANES],
        tmin: f32,
        tmax: [f32; LANES],
    ) -> LaneHits {
        use crate::math::lanes::{F, V};
        let v = F::splat;
        let f = V::splat(self.f);
        let d = V {
            x: F::from(dx),
            y: F::from(dy),
            z: F::from(dz),
        };
        let r = self.r;
        lanes_hit(f, v(self.c), v(r * r), hb, d, tmin, F::from(tmax))
    }
}

/// [`Prepared::hit_lanes`] with constants of their own in each lane (`f`, `c`; `rr` = r²), as
/// the shadow rays of four pixels have towards one sphere: each lane is `hit_ab_xyz` on its
/// values, or marked to redo. `hb` (Hearn–Baker's discriminant) is one choice for all lanes.
#[cfg(lanes)]
#[inline(always)]
fn lanes_hit(
    f: crate::math::lanes::V,
    cv: crate::math::lanes::F,
    rr: crate::math::lanes::F,
    hb: bool,
    d: crate::math::lanes::V,
    tmin: f32,
    tmax: crate::math::lanes::F,
) -> LaneHits {
    use crate::math::lanes::{neg, F as f32x4};
    use wide::{CmpEq, CmpGe, CmpGt, CmpLe, CmpLt};
    let v = f32x4::splat;
    let (fx, fy, fz) = (f.x, f.y, f.z);
    let (dx, dy, dz) = (d.x, d.y, d.z);
    let (tmin, zero, max) = (v(tmin), v(0.0), v(f32::MAX));
    // `d.dot(d)`, `f.dot(d)`: the same association as `Vec3::dot`.
    let a = dx * dx + dy * dy + dz * dz;
    let b = fx * dx + fy * dy + fz * dz;
    // `hit_ab_xyz`'s steps, in its order.
    let bb = b * b;
    let ac = a * cv;
    let disc0 = bb - ac;
    let clear_miss = disc0.cmp_lt(neg(bb + ac) * v(1.0 / 262_144.0));
    let cpos = cv.cmp_gt(zero);
    let behind = cpos & b.cmp_ge(zero) & tmin.cmp_ge(zero);
    let open = !(clear_miss | behind);
    // Every lane a clear miss or behind: the rest, divides and a root, is not needed.
    if open.move_mask() == 0 {
        return LaneHits {
            hit: 0,
            redo: 0,
            t: [0.0; LANES],
        };
    }
    let disc = if hb {
        let k = b / a;
        let (lx, ly, lz) = (fx - dx * k, fy - dy * k, fz - dz * k);
        a * (rr - (lx * lx + ly * ly + lz * lz))
    } else {
        disc0
    };
    let in_range = zero.cmp_le(disc) & disc.cmp_le(max);
    let negative = disc.cmp_lt(zero) & disc.abs().cmp_le(max);
    let s = disc.sqrt();
    let q = b.cmp_gt(zero).blend(neg(b + s), s - b);
    // `near_root`
    let far_ahead = cpos & b.cmp_lt(zero) & s.cmp_lt(v(-0.5) * b);
    let q_zero = q.cmp_eq(zero);
    let redo = open & ((!(in_range | negative)) | (in_range & q_zero));
    // The lanes whose answer this test gives: their other lanes' `t` is never read.
    let live = open & in_range & !q_zero;
    let lives = live.move_mask();
    // Neighbouring rays mostly take the same arm of `near_root` (small spheres the first,
    // a ground below the eye the second) and have their near root in range: then one
    // divide, not three.
    let ahead = far_ahead.move_mask() & lives;
    let t0 = if ahead == 0 {
        cv / q
    } else if ahead == lives {
        (neg(b) - s) / a
    } else {
        far_ahead.blend((neg(b) - s) / a, cv / q)
    };
    let ok = |t: f32x4| t.cmp_ge(tmin) & t.cmp_le(tmax) & t.cmp_lt(v(f32::INFINITY));
    let early = q.cmp_gt(zero) & cpos & ok(t0);
    if early.move_mask() & lives == lives {
        return LaneHits {
            hit: lives as u32,
            redo: redo.move_mask() as u32,
            t: t0.to_array(),
        };
    }
    let t1 = q / a;
    let ordered = t0.cmp_le(t1);
    let (near, far) = (ordered.blend(t0, t1), ordered.blend(t1, t0));
    let take_near = early | ok(near);
    let t = early.blend(t0, take_near.blend(near, far));
    let found = take_near | ok(far);
    let hit = live & found;
    LaneHits {
        hit: hit.move_mask() as u32,
        redo: redo.move_mask() as u32,
        t: t.to_array(),
    }
}

impl Prepared {
    /// Both roots `(near, far)` of the ray along `d`, or `None` when it misses the sphere.
    ///
    /// ```
    /// # use microray::{Prepared, Sphere, Vec3};
    /// let k = Prepared::exact(Vec3::ZERO, &Sphere::new(Vec3::new(0.0, 0.0, -3.0), 1.0));
    /// assert_eq!(k.roots(Vec3::new(0.0, 0.0, -1.0)), Some((2.0, 4.0)));
    /// assert_eq!(k.roots(Vec3::new(0.0, 1.0, 0.0)), None);
    /// ```
    #[inline]
    pub fn roots(&self, d: Vec3) -> Option<(f32, f32)> {
        self.roots_or::<true>(d)
    }

    /// [`Prepared::roots`]; with `CHECKED` false, for inputs known to be in range
    /// (`roots_scaled`'s), without the overflow check and fallback.
    #[inline]
    fn roots_or<const CHECKED: bool>(&self, d: Vec3) -> Option<(f32, f32)> {
        let f = self.f;
        let (a, b, c, r) = (d.dot(d), f.dot(d), self.c, self.r);
        // Where the origin is within ~0.4 r of the surface (|c| ≤ r²), b² − a c does not
        // cancel badly and is the more accurate for huge spheres; elsewhere Hearn–Baker.
        let disc = if libm::fabsf(c) <= r * r {
            b * b - a * c
        } else {
            let l = f - d * (b / a);
            a * (r * r - l.dot(l))
        };
        if CHECKED && !(a.is_finite() && b.is_finite() && c.is_finite() && disc.is_finite()) {
            return roots_scaled(f.x, f.y, f.z, d.x, d.y, d.z, r);
        }
        if !(disc >= 0.0) {
            return None;
        }
        let s = sqrt(disc);
        // q has the sign of −b, so −b and ∓s never cancel.
        let q = if b > 0.0 { -(b + s) } else { s - b };
        if q == 0.0 {
            // b = 0 and a tangent: both roots at t = 0 (origin on the surface, d along it).
            return Some((0.0, 0.0));
        }
        let (t0, t1) = (near_root(a, b, c, q, s), q / a);
        Some(if t0 <= t1 { (t0, t1) } else { (t1, t0) })
    }
}

/// The root `c/q`, or for a sphere ahead of an origin more than ~2 radii away (`c > 0`,
/// `b < 0`, `s < −b/2`) the same root as `(−b − s)/a`, which then does not cancel and does
/// not depend on `c`: b is good to an ulp or two, while `c = |f|² − r²` in f32 carries the
/// rounding of three squares and of f (per-ray constants) and would add as much again.
#[inline]
fn near_root(a: f32, b: f32, c: f32, q: f32, s: f32) -> f32 {
    if c > 0.0 && b < 0.0 && s < -0.5 * b {
        (-b - s) / a
    } else {
        c / q
    }
}

/// The near root if it is in `[tmin, tmax]`, else the far one if it is, else `None`. A root
/// beyond the f32 range (a tiny `d` towards a huge sphere) is a miss, not a hit at infinity.
#[inline]
fn select((near, far): (f32, f32), tmin: f32, tmax: f32) -> Option<f32> {
    let ok = |t: f32| t >= tmin && t <= tmax && t < f32::INFINITY;
    if ok(near) {
        Some(near)
    } else if ok(far) {
        Some(far)
    } else {
        None
    }
}

/// The same roots for inputs whose squares overflow f32 (centres or radii from ~10¹⁹, a huge
/// `d`): `f` and `r` scaled by one power of two and `d` by another, so that `max(|f|, r)` is
/// near 2²⁰ and `|d|` near 1. Scaling by powers of two is exact, and so is scaling the roots
/// back (`t` of `(σf, τd, σr)` is `σ/τ` times that of `(f, d, r)`) unless it leaves the f32
/// range: the roots are those of the f32 path, exactly scaled, and no f64 is needed (software
/// on a Cortex-M). `None` for non-finite inputs or a zero `d`.
///
/// Scalar arguments, not `Vec3`s: an aggregate goes to a call by address, and for that the hot
/// paths that call this (inlined in ray loops) kept `f` and `d` in memory, storing and reloading
/// them in every test (on x86 a store-forwarding stall each; `ray_intersect` cost 3.2× the
/// lecture's formula per test instead of 1.5×).
#[cold]
#[inline(never)]
fn roots_scaled(
    fx: f32,
    fy: f32,
    fz: f32,
    dx: f32,
    dy: f32,
    dz: f32,
    r: f32,
) -> Option<(f32, f32)> {
    let (f, d) = (Vec3::new(fx, fy, fz), Vec3::new(dx, dy, dz));
    let m = f.max_abs();
    let (m, n) = (if r > m { r } else { m }, d.max_abs());
    if !(finite(m) && finite(n) && n > 0.0 && r >= 0.0) {
        return None;
    }
    // `e` the unbiased exponent of a normal x (a subnormal counts as 2⁻¹²⁷); `pow2(k)` = 2^k for
    // |k| ≤ 126, so that the scales and both halves of the way back are normal numbers.
    let e = |x: f32| ((x.to_bits() >> 23) & 0xff) as i32 - 127;
    let pow2 = |k: i32| f32::from_bits(((k + 127) as u32) << 23);
    let (ks, kt) = ((20 - e(m)).clamp(-126, 126), (-e(n)).clamp(-126, 126));
    let (f, d, r) = (f * pow2(ks), d * pow2(kt), r * pow2(ks));
    let origin = Sphere {
        center: Vec3::ZERO,
        radius: r,
    };
    // `c_near` of f itself (the centre at 0): compensated, as for any origin.
    let k = Prepared {
        f,
        c: c_near(f, Vec3::ZERO, &origin),
        r,
    };
    // Finite now: no second fallback (and no recursion).
    let (t0, t1) = k.roots_or::<false>(d)?;
    // t·2^(kt − ks) in two steps of the same sign, neither of which leaves the range on its
    // own: exact unless the result does.
    let k = kt - ks;
    let back = |t: f32| t * pow2(k / 2) * pow2(k - k / 2);
    Some((back(t0), back(t1)))
}

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

/// `(distance/radius)²` within which [`hit_point`] keeps `f + t·d`: 16 radii, the least any
/// material gets (`scene::near2`).
pub(crate) const NEAR2_MIN: f32 = 256.0;

/// [`hit_point`] with f32 up to `√near2` radii away instead of 16: the renderer's choice per
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

/// [`hit_point`] from afar: the offset as `l ± s·d`, with `l = f − (b/a) d` the foot of the
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
fn hit_point_far(
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
    let a = d.dot(d);
    let l = d.cross(w) / a;
    // r² − |l|², the `c` of the origin l for the sphere about 0.
    let centred = Sphere {
        center: Vec3::ZERO,
        radius: sphere.radius,
    };
    let h2 = -c_near(l, Vec3::ZERO, &centred);
    let s = sqrt(if h2 > 0.0 { h2 / a } else { 0.0 });
    // The roots are −k ∓ s; the hit is the one that `t` approximates.
    let k = f.dot(d) / a;
    let s = if libm::fabsf(t - (-k - s)) <= libm::fabsf(t - (-k + s)) {
        -s
    } else {
        s
    };
    let offset = l + d * s;
    let point = sphere.center + offset;
    if offset.is_finite() && point.is_finite() {
        Some((point, offset))
    } else {
        None
    }
}

/// [`hit_point_far`] of four rays from one origin (`f` their common `o − m`, as for primary
/// rays) with directions `d` and parameters `t`: its operations lane by lane, so each lane is
/// the scalar `Some((point, offset))`, bit for bit; `None` where a lane is not finite (the
/// scalar call then falls back for it). On hosts, where many small far spheres make this path
/// warm (~70 x86 instructions a pixel at 256 spheres when it was scalar).
#[cfg(lanes)]
#[inline(always)]
pub(crate) fn hit_point_far4(
    d: crate::math::lanes::V,
    t: crate::math::lanes::F,
    f: Vec3,
    sphere: &Sphere,
) -> Option<(crate::math::lanes::V, crate::math::lanes::V)> {
    use crate::math::lanes::{neg, F, V};
    use wide::{CmpGt, CmpLe};
    let fv = V::splat(f);
    let w = V {
        x: product_difference_of(fv.y, d.z, fv.z, d.y),
        y: product_difference_of(fv.z, d.x, fv.x, d.z),
        z: product_difference_of(fv.x, d.y, fv.y, d.x),
    };
    let a = d.dot(d);
    let l = d.cross(w).div(a);
    let zero = F::splat(0.0);
    let h2 = c_near_of::<F, true>(
        [l.x, l.y, l.z],
        [zero; 3],
        [zero; 3],
        F::splat(sphere.radius),
    );
    let h2 = neg(h2);
    let s = h2.cmp_gt(zero).blend(h2 / a, zero).sqrt();
    let k = fv.dot(d) / a;
    let nearer = (t - (neg(k) - s)).abs().cmp_le((t - (neg(k) + s)).abs());
    let s = nearer.blend(neg(s), s);
    let offset = l.add(d.mul(s));
    let point = V::splat(sphere.center).add(offset);
    (offset.finite() & point.finite() == 0b1111).then_some((point, offset))
}

/// `a·b − c·e` from the exact products: exact or nearly where the two agree in most bits.
/// Out of line: one copy for the three components of a cold path.
#[inline(never)]
fn product_difference(a: f32, b: f32, c: f32, e: f32) -> f32 {
    product_difference_of(a, b, c, e)
}

/// [`product_difference`] on any [`Ieee`] type.
#[inline(always)]
fn product_difference_of<T: Ieee>(a: T, b: T, c: T, e: T) -> T {
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
    let t = -2.0 * f.dot(d) / d.dot(d);
    // Beyond the f32 range (a tiny d) there is no exit to return: like a miss.
    if t > 0.0 && t < f32::INFINITY {
        Some(t)
    } else {
        None
    }
}

#[cfg(all(test, lanes))]
mod lane_tests {
    use super::*;

    use crate::math::TestRng;

    /// Magnitudes over many decades, for the test's spheres and rays.
    trait Decades {
        /// ±(1 … 10) · 10^e for e in lo..hi.
        fn mag(&mut self, lo: i32, hi: i32) -> f32;
        fn decades(&mut self, lo: i32, hi: i32) -> Vec3;
    }
    impl Decades for TestRng {
        fn mag(&mut self, lo: i32, hi: i32) -> f32 {
            let e = lo + (self.next() % (hi - lo) as u64) as i32;
            let v = (1.0 + 9.0 * self.unit()) * libm::powf(10.0, e as f32);
            if self.next() & 1 == 0 {
                v
            } else {
                -v
            }
        }
        fn decades(&mut self, lo: i32, hi: i32) -> Vec3 {
            Vec3::new(self.mag(lo, hi), self.mag(lo, hi), self.mag(lo, hi))
        }
    }

    /// `c_near_across` (coordinates in lanes) is `c_near_of` on scalars, bit for bit, with and
    /// without an offset: origins on, near and far from spheres of every size, coordinates
    /// where the squares overflow, zeros, infinities and NaNs.
    #[test]
    fn c_across_lanes_is_the_scalar_c() {
        let mut g = TestRng(0x1319_8a2e_0370_7344);
        let special = [0.0, -0.0, f32::INFINITY, f32::NAN, 3e19, f32::MIN_POSITIVE];
        let bits = |x: f32| if x.is_nan() { u32::MAX } else { x.to_bits() };
        let mut cancelled = 0;
        for case in 0..200_000u32 {
            let r = g.mag(-4, 7).abs();
            let m = g.decades(-4, 7);
            let offset = Vec3::new(r, 0.0, 0.0) * (1.0 + 1e-3 * (g.unit() - 0.5));
            let (mut b, mut o) = match case % 3 {
                0 => (m + g.decades(-3, 1) * r, offset),
                1 => (g.decades(-4, 7), g.decades(-4, 3)),
                _ => (m - offset, offset),
            };
            let mut m = [m.x, m.y, m.z];
            let mut r = r;
            if case % 64 == 7 {
                let v = special[(case / 64) as usize % special.len()];
                match (case / 7) % 4 {
                    0 => b.y = v,
                    1 => o.z = v,
                    2 => m[0] = v,
                    _ => r = v,
                }
            }
            let (b, o) = ([b.x, b.y, b.z], [o.x, o.y, o.z]);
            let scalar = c_near_of::<f32, true>(b, o, m, r);
            assert_eq!(
                bits(c_near_across::<true>(b, o, m, r)),
                bits(scalar),
                "case {case}"
            );
            let plain = c_near_of::<f32, false>(b, [0.0; 3], m, r);
            let across = c_near_across::<false>(b, [0.0; 3], m, r);
            assert_eq!(bits(across), bits(plain), "case {case}, no offset");
            let (f, rr) = (Vec3::from(b) - Vec3::from(m) + Vec3::from(o), r * r);
            cancelled += (libm::fabsf(f.dot(f) - rr) < 1e-3 * (f.dot(f) + rr)) as u32;
        }
        assert!(
            cancelled > 2_000,
            "{cancelled} cases where the f32 c cancels"
        );
    }

    /// `hit_bits4` answers as the scalar `hit` does for every asked lane and leaves the others
    /// out: spheres of every size, origins on, near and far from them, overflowing constants,
    /// zero, huge and tangent directions, and `tmax` at a root.
    #[test]
    fn hit_bits_are_the_scalar_hits() {
        let mut g = TestRng(0x243f_6a88_85a3_08d3);
        let (mut yes, mut asked) = (0, 0);
        for case in 0..100_000u32 {
            let r = g.mag(-4, 5).abs();
            let m = g.decades(-4, 5);
            let origin = match case % 4 {
                0 => m + Vec3::new(0.0, r, 0.0) * (1.0 + 0.01 * (g.unit() - 0.5)),
                1 => m + g.decades(-5, 2),
                2 if case % 32 == 2 => Vec3::new(3e19, -2e19, 1e19),
                _ => g.decades(-4, 6),
            };
            let k = Prepared::exact(origin, &Sphere::new(m, r));
            let aim = m - origin;
            let d: [Vec3; LANES] = core::array::from_fn(|l| match (case + l as u32) % 5 {
                0 => Vec3::ZERO,
                1 => aim,
                2 => g.decades(15, 20),
                _ => aim + g.decades(-6, 1) * aim.length(),
            });
            let tmin = [f32::MIN_POSITIVE, 0.0][case as usize % 2];
            let tmax = match case % 3 {
                0 => 1.0 - f32::EPSILON / 2.0,
                1 => k.hit(d[0], tmin, f32::INFINITY).unwrap_or(f32::INFINITY),
                _ => f32::INFINITY,
            };
            let v = crate::math::lanes::V::from_lanes(d);
            let ask = (case / 3) % 16;
            let bits = k.hit_bits4(&v, tmin, tmax, ask);
            for (l, &dl) in d.iter().enumerate() {
                let scalar = ask & (1 << l) != 0 && k.hit(dl, tmin, tmax).is_some();
                assert_eq!(
                    bits & (1 << l) != 0,
                    scalar,
                    "case {case} lane {l}: {k:?} {dl:?}"
                );
                yes += scalar as u32;
                asked += (ask >> l) & 1;
            }
        }
        assert!(yes > asked / 10, "{yes} hits of {asked} asked lanes");
    }

    /// Every lane of `hit_lanes` is the scalar `hit`, bit for bit, or marked to redo, on rays
    /// of every scale: far and tiny spheres, origins on, near and inside the surface
    /// (both discriminants), tangents, zero and huge directions, overflowing constants, and
    /// `tmax` at the root itself.
    #[test]
    fn lanes_are_the_scalar_hit() {
        let mut g = TestRng(0x9e37_79b9_7f4a_7c15);
        let (mut hits, mut redos, mut near, mut lanes) = (0, 0, 0, 0);
        let mut ordinary_redos = 0;
        for case in 0..200_000u32 {
            let r = g.mag(-4, 5).abs();
            let m = g.decades(-4, 5);
            let origin = match case % 4 {
                // on or just off the surface, where `|c| ≤ r²`
                0 => m + Vec3::new(r, 0.0, 0.0) * (1.0 + 0.01 * (g.unit() - 0.5)),
                1 => m + g.decades(-5, 2),
                // centres near 10¹⁹ (squares overflow) now and then
                2 if case % 64 == 2 => Vec3::new(3e19, -2e19, 1e19),
                _ => g.decades(-4, 6),
            };
            let k = Prepared::exact(origin, &Sphere::new(m, r));
            // (An origin that rounded onto the centre has no direction to aim along.)
            if !finite(k.c) || k.f == Vec3::ZERO {
                continue;
            }
            let hb = libm::fabsf(k.c) > k.r * k.r;
            near += !hb as u32;
            let aim = m - origin;
            let d: [Vec3; LANES] = core::array::from_fn(|l| match (case + l as u32) % 7 {
                0 => Vec3::ZERO,
                1 => aim,
                // towards the rim: tangent or nearly
                // along a tangent, give or take up to 10⁻⁴ of r: where the two roots, the two
                // discriminants and the margins of the clear-miss test part ways
                2 | 4 => {
                    let (dd, u) = (aim.length(), aim.cross(Vec3::new(0.3, 1.0, 0.1)));
                    let side = libm::sqrtf(libm::fabsf(dd * dd - r * r)) / dd;
                    let off = 1.0 + libm::powf(10.0, -4.0 - 3.0 * g.unit()) * (g.unit() - 0.5);
                    aim * side + u.normalized().unwrap_or(Vec3::ZERO) * (r * off)
                }
                3 => g.decades(15, 20),
                _ => aim + g.decades(-6, 1) * aim.length(),
            });
            // (`hit_lanes` takes any tmin; the renderer's is `f32::MIN_POSITIVE`.)
            let tmin = [0.0, f32::MIN_POSITIVE, -1e3][case as usize % 3];
            let tmax: [f32; LANES] = core::array::from_fn(|l| match (case / 7 + l as u32) % 4 {
                0 => f32::INFINITY,
                // exactly the root: `t ≤ tmax` must hold as in the scalar test
                1 => k.hit(d[l], tmin, f32::INFINITY).unwrap_or(1.0),
                2 => g.mag(-3, 4).abs(),
                _ => f32::NAN,
            });
            let h = k.hit_lanes_of(&d, tmin, tmax);
            for l in 0..LANES {
                lanes += 1;
                if h.redo & (1 << l) != 0 {
                    redos += 1;
                    // Zero and huge directions aside, redoing is the exception.
                    ordinary_redos += !matches!((case + l as u32) % 7, 0 | 3) as u32;
                    continue;
                }
                let lane = (h.hit & (1 << l) != 0).then(|| h.t[l].to_bits());
                let scalar = k.hit(d[l], tmin, tmax[l]).map(f32::to_bits);
                assert_eq!(
                    lane, scalar,
                    "case {case} lane {l}: {k:?} d {:?} tmax {}",
                    d[l], tmax[l]
                );
                hits += scalar.is_some() as u32;
            }
        }
        // The sets reach every path: hits, redos (overflow, q = 0) and both discriminants.
        assert!(
            hits > lanes / 10 && redos > 0 && near > 1000,
            "{hits} {redos} {near} {lanes}"
        );
        assert!(
            ordinary_redos < lanes / 1000,
            "{ordinary_redos} of {lanes} lanes redone"
        );
    }

    /// `hit_outside` is `hit`, bit for bit, for constants of an origin outside the sphere
    /// (`c > 0`) and `tmin ≥ 0`: near the surface and far, both discriminants, tangents, huge
    /// and zero directions (overflow and the scaled roots), `tmax` at the root itself.
    #[test]
    fn hit_outside_is_hit() {
        let mut g = TestRng(0x5851_f42d_4c95_7f2d);
        let (mut tested, mut hits, mut near, mut far_roots) = (0u32, 0u32, 0u32, 0u32);
        for case in 0..200_000u32 {
            let r = g.mag(-4, 5).abs();
            let m = g.decades(-4, 5);
            let origin = match case % 3 {
                0 => m + Vec3::new(r, 0.0, 0.0) * (1.0 + 0.01 * g.unit()),
                1 => m + g.decades(-5, 2),
                _ => g.decades(-4, 6),
            };
            let k = Prepared::exact(origin, &Sphere::new(m, r));
            if !k.outside() {
                continue;
            }
            near += (k.c <= k.r * k.r) as u32;
            let aim = m - origin;
            let d = match case % 5 {
                0 => Vec3::ZERO,
                1 => aim,
                2 => {
                    let (dd, u) = (aim.length(), aim.cross(Vec3::new(0.3, 1.0, 0.1)));
                    let side = libm::sqrtf(libm::fabsf(dd * dd - r * r)) / dd;
                    let off = 1.0 + libm::powf(10.0, -4.0 - 3.0 * g.unit()) * (g.unit() - 0.5);
                    aim * side + u.normalized().unwrap_or(Vec3::ZERO) * (r * off)
                }
                3 if case % 50 == 3 => g.decades(15, 20),
                _ => aim + g.decades(-6, 1) * aim.length(),
            };
            let tmin = [0.0, f32::MIN_POSITIVE, 1e-3][(case / 3) as usize % 3];
            let root = k.hit(d, tmin, f32::INFINITY);
            let tmax = match case / 5 % 4 {
                0 => f32::INFINITY,
                1 => root.unwrap_or(1.0),
                // below the near root: only the far one (or none) can answer
                2 => root.map_or(1.0, |t| t * 0.999),
                _ => g.mag(-3, 4).abs(),
            };
            let scalar = k.hit(d, tmin, tmax);
            assert_eq!(
                // Its `tmax` finite: `f32::MAX` for ∞.
                k.hit_outside(d, tmin, tmax.min(f32::MAX)).map(f32::to_bits),
                scalar.map(f32::to_bits),
                "case {case}: {k:?} d {d:?} tmin {tmin} tmax {tmax}"
            );
            tested += 1;
            hits += scalar.is_some() as u32;
            far_roots += (scalar.is_some() && k.hit(d, 0.0, f32::INFINITY) != scalar) as u32;
        }
        // Hits, far roots and both discriminants are reached.
        assert!(
            tested > 100_000 && hits > tested / 10 && far_roots > 0 && near > 1000,
            "{tested} {hits} {far_roots} {near}"
        );
    }

    /// A Hearn–Baker discriminant that underflows to −0 (a tiny direction grazing a sphere):
    /// `hit_outside` hands it to the general test, whose float range check lets −0 through,
    /// and answers as that test does, bit for bit.
    #[test]
    fn hit_outside_takes_a_negative_zero_discriminant_as_hit_does() {
        const T_MIN: f32 = f32::MIN_POSITIVE; // the renderer's primary rays'
        type Test = fn(f32, f32, f32, f32, f32, f32, f32, f32, f32, f32, f32, f32) -> Option<f32>;
        let (f, r) = (Vec3::new(10.0, 0.0, 0.0), 1.0f32);
        let c = f.dot(f) - r * r;
        let mut negative_zeros = 0;
        for k in -200..200 {
            // a = |d|² ≈ 10⁻⁴⁰ (subnormal): a·(r² − |l|²) underflows near the tangent.
            let y = 1.005_037_8e-21 * (1.0 + k as f32 * f32::EPSILON);
            let d = Vec3::new(-1e-20, y, 0.0);
            let (a, b) = (d.dot(d), f.dot(d));
            let l = f - d * (b / a);
            let disc = a * (r * r - l.dot(l));
            negative_zeros += (disc == 0.0 && disc.is_sign_negative()) as u32;
            for tmax in [f32::MAX, 1e21, 1e20] {
                let run = |test: Test| {
                    let t = test(f.x, f.y, f.z, c, r, d.x, d.y, d.z, a, b, T_MIN, tmax);
                    t.map(f32::to_bits)
                };
                assert_eq!(
                    run(hit_outside_xyz),
                    run(hit_ab_xyz),
                    "k {k} d {d:?} disc {disc:e} tmax {tmax}"
                );
            }
        }
        assert!(negative_zeros > 0, "no case reached a discriminant of -0");
    }

    /// Every lane that `leaving_blocks4` decides is the scalar `leaving_blocks`, for shadow rays
    /// from just above spheres of radius 10⁻² … 10⁶ (the hit given as an anchor and an offset,
    /// as shading gives it), many of them grazing the sphere to within 10⁻¹² … 10⁻³ of its
    /// radius, where the clear-miss margin must cover the error of an f32 `c` that cancels; and
    /// it decides most lanes, misses and blocks (a function that decides nothing would pass
    /// the first check alone).
    #[test]
    fn leaving_blocks4_decides_as_the_scalar_test() {
        use crate::math::lanes::V;
        let mut g = TestRng(0x2545_f491_4f6c_dd1d);
        let (mut claimed, mut misses, mut grazing) = (0u32, 0u32, 0u32);
        let (mut open_claimed, mut open_misses) = (0u32, 0u32);
        let (mut blocks_decided, mut blocks_all) = (0u32, 0u32);
        let unit = |g: &mut TestRng| loop {
            let v = [g.unit() - 0.5, g.unit() - 0.5, g.unit() - 0.5].map(f64::from);
            let n = libm::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
            if n > 0.1 {
                break v.map(|x| x / n);
            }
        };
        let v32 = |v: [f64; 3]| Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32);
        for case in 0..50_000u32 {
            let r = libm::pow(10.0, -2.0 + 8.0 * f64::from(g.unit()));
            let shift = if case % 2 == 0 { 0.0 } else { 1e4 };
            let m = [shift + f64::from(g.unit()), shift - r, -shift];
            let s = Sphere::new(v32(m), r as f32);
            let c = s.center;
            let (r, m) = (f64::from(s.radius), [c.x, c.y, c.z].map(f64::from));
            let lane = |g: &mut TestRng| {
                let u = unit(g);
                // From just above (the hit's own sphere) to 100 radii away (another's).
                let h = r * libm::pow(10.0, -7.0 + 9.0 * f64::from(g.unit()));
                let p = [0, 1, 2].map(|i| m[i] + u[i] * (r + h));
                // A direction whose closest approach to the centre is r (1 ± δ), or any.
                let mut close = f64::INFINITY;
                let d = if g.next() % 4 != 0 {
                    let w = unit(g);
                    let wu = w[0] * u[0] + w[1] * u[1] + w[2] * u[2];
                    let q = [0, 1, 2].map(|i| w[i] - u[i] * wu);
                    let ql = libm::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
                    let delta = libm::pow(10.0, -12.0 + 9.0 * f64::from(g.unit()));
                    close = if g.next() % 2 == 0 { delta } else { -delta };
                    let rd = r * (1.0 + close);
                    let dist = r + h;
                    let t = rd * dist / libm::sqrt(dist * dist - rd * rd);
                    [0, 1, 2].map(|i| m[i] + q[i] / ql * t - p[i])
                } else {
                    unit(g)
                };
                // The hit's own ball (anchor) of radius up to 2 holds p.
                let (w, k) = (unit(g), 2.0 * f64::from(g.unit()));
                let anchor = v32([0, 1, 2].map(|i| p[i] + w[i] * k));
                let a = [anchor.x, anchor.y, anchor.z].map(f64::from);
                let rel = v32([0, 1, 2].map(|i| p[i] - a[i]));
                (anchor, rel, v32(d), close, h > r)
            };
            let ls: [(Vec3, Vec3, Vec3, f64, bool); 4] = core::array::from_fn(|_| lane(&mut g));
            let tmax = if case % 3 == 0 { 1.0 } else { f32::INFINITY };
            let (hit, undecided) = leaving_blocks4(
                V::from_lanes(ls.map(|l| l.0)),
                V::from_lanes(ls.map(|l| l.1)),
                &s,
                V::from_lanes(ls.map(|l| l.2)),
                tmax,
                0b1111,
            );
            for (l, &(anchor, rel, d, close, far)) in ls.iter().enumerate() {
                let blocks = Prepared::leaving_blocks(anchor, rel, &s, d, tmax);
                let decided = undecided & (1 << l) == 0;
                let lane = hit & (1 << l) != 0;
                assert!(
                    !decided || lane == blocks,
                    "case {case} lane {l}: {s:?} anchor {anchor:?} rel {rel:?} d {d:?} tmax {tmax}"
                );
                if far {
                    blocks_all += blocks as u32;
                    blocks_decided += (blocks && decided) as u32;
                }
                let claim = decided && !lane;
                misses += !blocks as u32;
                claimed += claim as u32;
                // Passing within 10⁻⁴ radii of the sphere, and claimed: near the margin's edge.
                grazing += (claim && close > 0.0 && close < 1e-4) as u32;
                if close.is_infinite() {
                    open_misses += !blocks as u32;
                    open_claimed += claim as u32;
                }
            }
        }
        // Rays in any direction from above a surface: the first steps decide most misses
        // (not those from within ~10⁻⁶ radii, where c is within its error of zero). Grazing
        // ones are often left to the scalar test.
        assert!(
            open_claimed > open_misses - open_misses / 5 && grazing > 1000,
            "{open_claimed} of {open_misses} open misses claimed ({claimed} of {misses} in \
             all), {grazing} grazing"
        );
        // Blocks from origins more than a radius away (another sphere's shadow rays): the
        // lanes decide them, but for those that graze within the margins.
        assert!(
            blocks_decided > blocks_all - blocks_all / 10,
            "{blocks_decided} of {blocks_all} blocks from afar decided in lanes"
        );
    }

    /// Where `fused` computes the compensated `c` (an origin within √3 radii of the centre,
    /// where f32 `c` cancels), the lanes must leave the answer to it: shadow rays that reach
    /// the sphere near their `tmax`, from origins √2 … 2 radii from the centre, where `c`'s
    /// rounding moves the near root by ~10 ulp. With the lanes keeping f32 `c` a little
    /// further in (`CANCEL` 0.5 → 0.2, c > r²/2 instead of c > 2r²), 514 of the 42 247 lanes
    /// within √3 radii answer differently: this fails then, while the random rays above pass.
    #[test]
    fn leaving_blocks4_leaves_cancelling_c_to_the_scalar_test() {
        use crate::math::lanes::V;
        let mut g = TestRng(0x9e37_79b9_7f4a_7c15);
        let (mut scalar_zone, mut lanes) = (0u32, 0u32);
        for case in 0..20_000u32 {
            let r = libm::powf(10.0, -1.0 + 3.0 * g.unit());
            let m = Vec3::new(g.unit() * 10.0, g.unit() * 10.0 - r, g.unit() * 10.0);
            let s = Sphere::new(m, r);
            let unit = |g: &mut TestRng| loop {
                let v = Vec3::new(g.unit() - 0.5, g.unit() - 0.5, g.unit() - 0.5);
                if let Some(u) = v.normalized() {
                    break u;
                }
            };
            // Each lane from √2 … 2 radii out towards a point of the near cap, so that its
            // near root is 1 up to the rounding of `d`; `tmax` within ±16 ulp of 1.
            let lane = |g: &mut TestRng| {
                let u = unit(g);
                let p = m + u * (r * (1.414 + 0.6 * g.unit()));
                let aim = (u + unit(g) * 0.3).normalized().unwrap_or(u);
                let target = m + aim * r;
                (p, target - p)
            };
            let ls: [(Vec3, Vec3); 4] = core::array::from_fn(|_| lane(&mut g));
            let tmax = 1.0 + (case % 33) as f32 * f32::EPSILON - 16.0 * f32::EPSILON;
            let (hit, undecided) = leaving_blocks4(
                V::from_lanes(ls.map(|l| l.0)),
                V::splat(Vec3::ZERO),
                &s,
                V::from_lanes(ls.map(|l| l.1)),
                tmax,
                0b1111,
            );
            for (l, &(p, d)) in ls.iter().enumerate() {
                let blocks = Prepared::leaving_blocks(p, Vec3::ZERO, &s, d, tmax);
                let decided = undecided & (1 << l) == 0;
                assert!(
                    !decided || (hit & (1 << l) != 0) == blocks,
                    "case {case} lane {l}: {s:?} from {p:?} along {d:?}, tmax {tmax}"
                );
                let f = p - m;
                let cancels = (f.dot(f) - r * r) <= 2.0 * r * r;
                scalar_zone += (cancels && !decided) as u32;
                lanes += cancels as u32;
            }
        }
        // The origins within √3 radii are the scalar test's (those beyond it the lanes').
        assert!(
            scalar_zone > lanes - lanes / 50,
            "{scalar_zone} of {lanes} left to the scalar test"
        );
        assert!(lanes > 20_000, "{lanes} lanes within √3 radii");
    }

    /// `hit_point_far4` is `hit_point_far` lane by lane, bit for bit: primary rays from one
    /// origin 30 … 10⁵ radii from spheres of radius 10⁻⁴ … 10², centres up to 10⁴ away from
    /// the origin of coordinates, hitting near the rim and the middle, both roots, and `t`
    /// perturbed as a rounded root is; `None` only where a lane's scalar answer is not finite.
    #[test]
    fn hit_point_far4_is_the_scalar_offset() {
        use crate::math::lanes::{F, V};
        let mut g = TestRng(0x5851_f42d_4c95_7f2d);
        let (mut some, mut cases) = (0u32, 0u32);
        for case in 0..50_000u32 {
            let r = g.mag(-4, 3).abs();
            let m = g.decades(-2, 5);
            let dist = r * libm::powf(10.0, 1.5 + 3.5 * g.unit());
            let u = g.vec(2.0).normalized().unwrap_or(Vec3::new(0.0, 0.0, 1.0));
            let origin = m + u * dist;
            let s = Sphere::new(m, r);
            let k = Prepared::exact(origin, &s);
            let ds: [Vec3; 4] = core::array::from_fn(|_| {
                // Aim at a point of the disc the sphere shows, out to its rim.
                let aim = m + g.vec(2.0 * r) * (0.5 + 0.5 * g.unit()) - origin;
                aim * g.mag(-2, 2).abs()
            });
            let ts: [f32; 4] = core::array::from_fn(|l| {
                let t = match k.roots(ds[l]) {
                    Some((near, far)) => {
                        if case % 5 == 0 {
                            far
                        } else {
                            near
                        }
                    }
                    None => 1.0,
                };
                // a rounded root: a few ulp either way
                f32::from_bits((t.to_bits() as i64 + (g.next() % 9) as i64 - 4) as u32)
            });
            let scalar: [Option<(Vec3, Vec3)>; 4] = core::array::from_fn(|l| {
                let (d, f) = (ds[l], k.f);
                hit_point_far(d.x, d.y, d.z, ts[l], f.x, f.y, f.z, &s)
            });
            cases += 1;
            let bits = |v: Vec3| [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()];
            match hit_point_far4(V::from_lanes(ds), F::from(ts), k.f, &s) {
                Some((p, o)) => {
                    some += 1;
                    for l in 0..4 {
                        let (sp, so) = scalar[l].expect("a lane the scalar call rejects");
                        assert_eq!(
                            (bits(p.lane(l)), bits(o.lane(l))),
                            (bits(sp), bits(so)),
                            "case {case} lane {l}: {s:?} from {origin:?} along {:?} t {}",
                            ds[l],
                            ts[l]
                        );
                    }
                }
                None => assert!(scalar.iter().any(Option::is_none), "case {case}"),
            }
        }
        assert!(some > cases - cases / 100, "{some} of {cases}");
    }
}
