//! [`Prepared`]: the constants of one ray origin against one sphere, and the tests of rays from
//! that origin (primary rays from the eye, shadow rays from a point light).

use super::*;

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
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Prepared {
    /// `o − m`, rounded to f32.
    pub f: Vec3,
    /// `|o − m|² − r²`, accurate to a few ulp even where the subtraction cancels.
    pub c: f32,
    /// The sphere's radius.
    pub r: f32,
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
    pub(super) fn finish(f: Vec3, r: f32, exact: impl FnOnce() -> f32) -> Self {
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
        self.hit4_lanes(d, tmin, tmax)
            .unwrap_or_else(|| core::array::from_fn(|l| self.hit(d[l], tmin, tmax[l])))
    }

    /// [`Prepared::hit4`] in the lanes of one vector, where there are lanes and `c` is finite.
    #[cfg(lanes)]
    #[inline(always)]
    fn hit4_lanes(&self, d: &[Vec3; 4], tmin: f32, tmax: [f32; 4]) -> Option<[Option<f32>; 4]> {
        if !finite(self.c) {
            return None;
        }
        let h = self.hit_lanes_of(d, tmin, tmax);
        Some(core::array::from_fn(|l| {
            if h.redo & (1 << l) != 0 {
                self.hit(d[l], tmin, tmax[l])
            } else {
                (h.hit & (1 << l) != 0).then_some(h.t[l])
            }
        }))
    }

    /// No lanes here: [`Prepared::hit4`] tests one direction after another.
    #[cfg(not(lanes))]
    #[inline(always)]
    fn hit4_lanes(&self, _: &[Vec3; 4], _: f32, _: [f32; 4]) -> Option<[Option<f32>; 4]> {
        None
    }

    /// Which of the lanes `ask` of four directions (by coordinate) `hit` finds a root for in
    /// `[tmin, tmax]`, as bits: `hit4`'s answers without their roots, for shadow rays from a
    /// point light (its per-frame constants): the lanes' test where it decides, the scalar one
    /// where it does not, so the same answers. Without the arrays of `Vec3` and `Option` that
    /// `hit4` goes through, which the shadow loop would build for every candidate sphere.
    #[cfg(lanes)]
    #[inline(always)]
    pub(crate) fn hit_bits4(&self, d: &crate::simd::V, tmin: f32, tmax: f32, ask: u32) -> u32 {
        let (x, y, z) = (d.x.to_array(), d.y.to_array(), d.z.to_array());
        let (hit, redo) = if finite(self.c) {
            let h = self.hit_lanes(self.hearn_baker(), x, y, z, tmin, [tmax; LANES]);
            (h.hit & !h.redo & ask, h.redo & ask)
        } else {
            (0, ask)
        };
        let mut bits = hit;
        for l in crate::simd::ones(redo) {
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
    pub(super) fn hit_lanes_of(&self, d: &[Vec3; 4], tmin: f32, tmax: [f32; 4]) -> LaneHits {
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
///
/// [`hit_core`] on one f32, written out with a branch for each exit: with `hit_core` in its
/// place the M4F takes about 1.5 % more instructions a pixel at opt 3 and 250 bytes more flash
/// at "s" (`examples/firmware/run.sh m4f`); `hit_ab_xyz_is_hit_core` pins the two, bit for bit.
#[inline]
#[allow(clippy::too_many_arguments)]
pub(super) fn hit_ab_xyz(
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
    // The same roots as `roots`, with early exits that bring its cost near the textbook
    // quadratic's: most tests are misses.
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
/// const parameter of `hit_ab_xyz`, which made generic compiles to a longer general test; what
/// it saves the M4F is `OUTSIDE_TEST`'s figure (`render/config.rs`). `hit_outside_is_hit` pins
/// the two together, bit for bit.
#[cfg(any(test, not(lanes)))]
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(super) fn hit_outside_xyz(
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
    // `0 ≤ disc ≤ f32::MAX` as a bit test (on a Cortex-M4F cheaper than two float
    // comparisons, as `vsqrt` takes the bits in a core register); −0, which the float test
    // lets through, takes the general test with the negatives, NaN and ∞.
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
    // `tmax` is finite, so `t0 ≤ tmax` also rules out t0 = ∞: no test against infinity.
    if t0 >= tmin && t0 <= tmax {
        return Some(t0);
    }
    let t1 = q / a;
    select(if t0 <= t1 { (t0, t1) } else { (t1, t0) }, tmin, tmax)
}
