//! The intersection tests four rays at a time in vector lanes (hosts with `cfg(lanes)`): each
//! lane does the scalar path's IEEE operations in the scalar order, so its answer is the scalar
//! answer, bit for bit.

use super::*;

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
    anchor: crate::simd::V,
    rel: crate::simd::V,
    sphere: &Sphere,
    d: crate::simd::V,
    tmax: f32,
    open: u32,
) -> (u32, u32) {
    use crate::simd::{bits, F, V};
    use crate::simd::{CmpGe, CmpGt, CmpLe};
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
        use crate::simd::{F, V};
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
pub(super) fn lanes_hit(
    f: crate::simd::V,
    cv: crate::simd::F,
    rr: crate::simd::F,
    hb: bool,
    d: crate::simd::V,
    tmin: f32,
    tmax: crate::simd::F,
) -> LaneHits {
    use crate::simd::{neg, F as f32x4};
    use crate::simd::{CmpEq, CmpGe, CmpGt, CmpLe, CmpLt};
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
