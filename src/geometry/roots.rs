//! The roots: stable (`c/q`, `q/a`) with Hearn–Baker's discriminant, the choice of root within
//! `[tmin, tmax]`, and the scaled path for inputs whose squares overflow f32.

use super::*;

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
    pub(super) fn roots_or<const CHECKED: bool>(&self, d: Vec3) -> Option<(f32, f32)> {
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
pub(super) fn near_root(a: f32, b: f32, c: f32, q: f32, s: f32) -> f32 {
    if c > 0.0 && b < 0.0 && s < -0.5 * b {
        (-b - s) / a
    } else {
        c / q
    }
}

/// The near root if it is in `[tmin, tmax]`, else the far one if it is, else `None`. A root
/// beyond the f32 range (a tiny `d` towards a huge sphere) is a miss, not a hit at infinity.
#[inline]
pub(super) fn select((near, far): (f32, f32), tmin: f32, tmax: f32) -> Option<f32> {
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
/// paths that call this (inlined in ray loops) would keep `f` and `d` in memory, storing and
/// reloading them in every test (on x86 a store-forwarding stall each).
#[cold]
#[inline(never)]
pub(super) fn roots_scaled(
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

/// What [`hit_core`] found, as bits `0..4` of its lanes (one f32: bit 0): `hit` where the ray
/// meets the sphere in `[tmin, tmax]`, at `t`; `scaled` where the squares overflow, which only
/// [`roots_scaled`] decides; `tangent` where `q = 0`, both roots at 0.
#[cfg(any(test, lanes))]
#[derive(Clone, Copy)]
pub(super) struct Found<T> {
    pub hit: u32,
    pub scaled: u32,
    pub tangent: u32,
    pub t: T,
}

/// The closest root in `[tmin, tmax]` along `d` (`a = d·d`, `b = f·d`) for the constants
/// `f`, `c` (finite where `c_finite`), `rr = r²`, with Hearn–Baker's discriminant where `hb`
/// (both one choice for all lanes): the definition of the ray–sphere test, for four lanes
/// (`lanes_hit`) and for one f32, which [`hit_ab_xyz`] writes out with a branch at each of
/// its early exits. The roots of [`Prepared::roots`], with exits that bring its cost near the
/// textbook quadratic's where every lane takes them.
#[cfg(any(test, lanes))]
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(super) fn hit_core<P: Ieee3>(
    f: P,
    c: P::S,
    rr: P::S,
    hb: bool,
    c_finite: bool,
    d: P,
    a: P::S,
    b: P::S,
    tmin: f32,
    tmax: P::S,
) -> Found<P::S> {
    type T<P> = <P as Ieee3>::S;
    let v = <T<P> as Ieee>::splat;
    let (zero, max) = (v(0.0), v(f32::MAX));
    let miss = |scaled, tangent| Found {
        hit: 0,
        scaled,
        tangent,
        t: zero,
    };
    // b² − ac is off by a few ε (b² + a|c|) (its rounding, and that of b and c); a value
    // below −2⁻¹⁸ of that misses the sphere's whole line whatever the rounding. Most tests
    // are such misses: one branch first, and no Hearn–Baker divide for them. The margin is
    // written with `ac`, not `a|c|`: they differ only for c < 0, where b² − ac ≥ 0 is never
    // below a margin of either sign, so the same tests are rejected, and `ac` is computed once.
    let bb = b * b;
    let ac = a * c;
    let disc0 = bb - ac;
    let open = !disc0.lt((bb + ac).flip() * v(1.0 / 262_144.0));
    // Outside (c > 0) and heading away (b ≥ 0): both roots are negative.
    let cpos = c.gt(zero);
    let open = if tmin >= 0.0 {
        open & !(cpos & b.ge(zero))
    } else {
        open
    };
    if T::<P>::bits(open) == 0 {
        return miss(0, 0);
    }
    let disc = if hb {
        let l = f.sub(d.mul(b / a));
        a * (rr - l.dot(l))
    } else {
        disc0
    };
    // Overflow shows as ±∞ or NaN somewhere on the way to disc (or in c).
    let in_range = if c_finite {
        zero.le(disc) & disc.le(max)
    } else {
        T::<P>::mask(0)
    };
    let negative = disc.lt(zero) & disc.abs().le(max);
    let scaled = T::<P>::bits(open & !(in_range | negative));
    let open = open & in_range;
    let s = disc.sqrt();
    // q has the sign of −b, so −b and ∓s never cancel.
    let q = T::<P>::select(b.gt(zero), (b + s).flip(), s - b);
    let q_zero = q.eq(zero);
    let tangent = T::<P>::bits(open & q_zero);
    let live = open & !q_zero;
    let lives = T::<P>::bits(live);
    // `near_root`, one divide where every live lane takes the same arm, as neighbouring rays
    // mostly do (small spheres the first, a ground below the eye the second).
    let far_ahead = cpos & b.lt(zero) & s.lt(v(-0.5) * b);
    let t0 = T::<P>::choose(far_ahead, lives, || (b.flip() - s) / a, || c / q);
    let ok = |t: T<P>| t.ge(v(tmin)) & t.le(tmax) & t.lt(v(f32::INFINITY));
    // With q > 0 and c > 0, c/q is the near root (c/q ≤ q/a since q² ≥ b² ≥ ac): when it is
    // in range the far root's divide is not needed.
    let early = q.gt(zero) & cpos & ok(t0);
    if T::<P>::bits(early & live) == lives {
        return Found {
            hit: lives,
            scaled,
            tangent,
            t: t0,
        };
    }
    let t1 = q / a;
    let ordered = t0.le(t1);
    let (near, far) = (
        T::<P>::select(ordered, t0, t1),
        T::<P>::select(ordered, t1, t0),
    );
    let take_near = early | ok(near);
    Found {
        hit: T::<P>::bits(live & (take_near | ok(far))),
        scaled,
        tangent,
        t: T::<P>::select(early, t0, T::<P>::select(take_near, near, far)),
    }
}
