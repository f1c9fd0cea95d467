//! `c = |o − m|² − r²` compensated where f32 cancels: rebuilt from error-free pieces (TwoSum,
//! Dekker's exact squares) in plain f32, scalar or in lanes from one generic definition.

use super::*;

/// f32 `c = ff − rr` is kept only when `|c| > CANCEL (ff + rr)`, that is when the origin is more
/// than √3 radii from the centre (or inside, less than 1/√3). The f32 error of c is about
/// 2⁻²⁴ (ff + rr) from the squares plus as much again from rounding `f`, and the near root
/// `c/q` (used within ~2 radii, see `near_root`; farther it does not depend on c) is
/// proportional to c, so `(ff + rr) / |c| ≤ 2` keeps that root within a few ulp. A threshold
/// of 2⁻¹¹ would let c lose 10 bits, and a mirror ray leaving a sphere that rests on a ground
/// sphere of radius 1000 would meet the ground 700 ulp off, enough to flip its shadow.
pub(super) const CANCEL: f32 = 0.5;

/// `c = |f|² − r²` for the origin `base + offset` (`offset` zero for a plain origin) where its
/// f32 value cancels (an origin near the surface), from error-free pieces: `f` as `h + l` per
/// coordinate (`h` the f32 `(base − m) + offset`, `l` the errors of both sums), each square of
/// `h` as its rounded value and error, and the sum of the rounded squares with its errors.
/// Only the error terms, each ~2⁻²⁴ of `|f|² + r²`, are added with rounding, so the result is
/// good to ~2⁻⁴⁵ (|f|² + r²) plus its own rounding: ~2⁻²⁴ |c| even where `|f|²` and `r²`
/// agree in 20 bits (the eye 1 above a ground of radius 10⁶). Where `|base − m|` is much more
/// than `|f|` (a base far away for the sphere's size), `l`'s error grows with their ratio.
///
/// f32 rather than f64, which is software on every Cortex-M, and plain f32 operations on every
/// target, so every target computes the same bits.
/// Where the squares overflow (|f| or r from ~1.8·10¹⁹) the result is not finite.
#[inline(always)]
pub(super) fn c_near(base: Vec3, offset: Vec3, sphere: &Sphere) -> f32 {
    let (b, o, m) = (base, offset, sphere.center);
    c_near_xyz::<true>(b.x, b.y, b.z, o.x, o.y, o.z, m.x, m.y, m.z, sphere.radius)
}

/// [`c_near`] for a plain origin (no offset), the same bits with less work: for the per-ray
/// constants of [`ray_intersect`] and [`Prepared::new`]. Those built once per frame keep
/// `c_near`, so that a firmware that does not call these links one copy.
#[inline(always)]
pub(super) fn c_origin(origin: Vec3, sphere: &Sphere) -> f32 {
    let (b, m) = (origin, sphere.center);
    c_near_xyz::<false>(b.x, b.y, b.z, 0.0, 0.0, 0.0, m.x, m.y, m.z, sphere.radius)
}

/// [`c_near`] on the coordinates of base, offset and centre. Out of line: the rare call costs
/// less than its long body inlined into every ray loop, and on Arm s16–s31 keep the caller's
/// values across it. Scalars, not `Vec3`s (nor an array): an aggregate goes to a call by
/// address, and callers would then keep it in memory for every test, not only for the few that
/// call this.
///
/// `OFFSET` false: for a plain origin (`offset` zero), where the sum with the offset is exact and
/// is left out (the same bits, fewer operations; for `ray_intersect` and [`Prepared::new`]).
#[inline(never)]
#[allow(clippy::too_many_arguments)]
pub(super) fn c_near_xyz<const OFFSET: bool>(
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
    c_near_target::<OFFSET>([bx, by, bz], [ox, oy, oz], [mx, my, mz], radius)
}

/// [`c_near_of`] as this target computes it fastest, the same bits: across vector lanes on
/// hosts ([`c_near_across`]).
#[cfg(lanes)]
#[inline(always)]
fn c_near_target<const OFFSET: bool>(b: [f32; 3], o: [f32; 3], m: [f32; 3], radius: f32) -> f32 {
    c_near_across::<OFFSET>(b, o, m, radius)
}

/// [`c_near_of`] as this target computes it: one f32 at a time, without lanes.
#[cfg(not(lanes))]
#[inline(always)]
fn c_near_target<const OFFSET: bool>(b: [f32; 3], o: [f32; 3], m: [f32; 3], radius: f32) -> f32 {
    c_near_of::<f32, OFFSET>(b, o, m, radius)
}

/// [`c_near_of`] for one origin with the coordinates in vector lanes (hosts, `cfg(lanes)`): the
/// per-coordinate pieces (the sums' errors, the squares and their errors) in lanes 0–2 and the
/// radius's square in lane 3, then the running sum over the coordinates in `c_near_of`'s order.
/// The same operations on the same values, so the same bits, in fewer instructions than the
/// scalar sequence.
#[cfg(lanes)]
#[inline(always)]
pub(super) fn c_near_across<const OFFSET: bool>(
    b: [f32; 3],
    o: [f32; 3],
    m: [f32; 3],
    radius: f32,
) -> f32 {
    use crate::simd::F;
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

/// [`c_near_of`] of a point `base` from a sphere about the origin, with no offset (`m` and
/// `offset` zero): `|base|² − r²` compensated, for the far hit points in lanes
/// (`hit_point_far_lanes`). For a finite `base` the two sums with zero there only copy each
/// coordinate (and its error term is zero), so they are left out: the same value but for the
/// sign of a zero, which its caller only compares with zero; a coordinate whose square
/// overflows makes both NaN. `c_origin_is_c_near` pins it down.
#[cfg(lanes)]
#[inline(always)]
pub(super) fn c_origin_of<T: Ieee>(base: [T; 3], radius: T) -> T {
    let (pr, er) = two_square_of(radius);
    let (mut big, mut small) = (pr.flip(), er.flip());
    for h in base {
        let (p, ep) = two_square_of(h);
        let (sum, t) = two_sum_of(big, p);
        big = sum;
        small = small + (t + ep);
    }
    big + small
}

/// [`c_near_xyz`]'s operations on any [`Ieee`] type (one f32, or four lanes on hosts).
/// Hosts compute it across lanes (`c_near_across`), and their tests compare the two.
#[cfg_attr(all(lanes, not(test)), allow(dead_code))]
#[inline(always)]
pub(super) fn c_near_of<T: Ieee, const OFFSET: bool>(
    base: [T; 3],
    offset: [T; 3],
    m: [T; 3],
    radius: T,
) -> T {
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
