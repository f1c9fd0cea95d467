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
/// `open` a miss. `fused`'s steps lane by lane: its clear-miss and behind tests
/// ([`leaving_start`]), then, where it keeps the f32 `c` (no cancellation) and the origin is
/// outside, `hit_ab` ([`hit_core`] in `lanes_hit`). The undecided lanes (a cancelling `c`, an origin
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
    let f = anchor.sub(V::splat(sphere.center)).add(rel);
    let start = leaving_start(f, sphere.radius, d);
    let (c, rr) = (start.c, start.rr);
    // `tmin ≥ 0` holds: `leaving_blocks` starts at the smallest normal number.
    let maybe = open & !bits(start.clear | start.behind());
    if maybe == 0 {
        return (0, 0);
    }
    // `fused` keeps c where `keeps`; `hit_ab` then takes Hearn–Baker's discriminant where
    // |c| > r², which every kept lane with c > 0 has: c > sum/2 means |f|² > ~3r², so
    // c > ~2r² whatever the rounding of c and sum.
    let kept = maybe & bits(start.keeps() & c.gt(F::ZERO));
    if kept == 0 {
        return (0, maybe);
    }
    let h = lanes_hit(f, c, rr, true, d, f32::MIN_POSITIVE, F::splat(tmax));
    (h.hit & !h.redo & kept, (maybe & !kept) | (h.redo & kept))
}

/// What [`leaving_hit4`] found: bit `l` of `hit` set where lane `l` hits, at `t[l]` with the
/// offset `f` (as [`Prepared::leaving_hit`] returns them); of `undecided` where only the scalar
/// test decides. Every other lane of `open` misses.
#[cfg(lanes)]
#[derive(Clone, Copy)]
pub(crate) struct LeavingHits {
    pub hit: u32,
    pub undecided: u32,
    pub t: [f32; LANES],
    pub f: crate::simd::V,
}

/// [`Prepared::leaving_hit`] from `anchor + rel` along `d`, from `tmin ≥ 0` to each lane's
/// `tmax`, for the lanes `open` of four mirror rays, as far as lanes decide it. The steps of
/// `leaving_blocks4`: most lanes miss the sphere's line clearly or have it behind them; an
/// origin outside whose f32 `c` is kept takes `hit_ab` in lanes, with the scalar root. The
/// rest (a cancelling `c`, an origin inside, a rare path of the roots) are undecided.
#[cfg(lanes)]
#[inline(always)]
pub(crate) fn leaving_hit4(
    (anchor, rel): (crate::simd::V, crate::simd::V),
    sphere: &Sphere,
    d: crate::simd::V,
    (tmin, tmax): (f32, crate::simd::F),
    open: u32,
) -> LeavingHits {
    use crate::simd::{bits, F, V};
    let f = anchor.sub(V::splat(sphere.center)).add(rel);
    let start = leaving_start(f, sphere.radius, d);
    let (c, rr) = (start.c, start.rr);
    let none = |undecided| LeavingHits {
        hit: 0,
        undecided,
        t: [0.0; LANES],
        f,
    };
    let maybe = open & !bits(start.clear | start.behind());
    if maybe == 0 {
        return none(0);
    }
    // As in `leaving_blocks4`: a kept `c > 0` has |c| > r², Hearn–Baker's discriminant.
    let kept = maybe & bits(start.keeps() & c.gt(F::ZERO));
    if kept == 0 {
        return none(maybe);
    }
    let h = lanes_hit(f, c, rr, true, d, tmin, tmax);
    LeavingHits {
        hit: h.hit & !h.redo & kept,
        undecided: (maybe & !kept) | (h.redo & kept),
        t: h.t,
        f,
    }
}

/// [`leaving_hit4`]'s first tests turned about: the spheres `spheres` (bits `0..4` of `open`) that one ray
/// from `anchor + rel` along `d` does not reject at once, each lane the scalar test's first
/// steps against its sphere (`r²` rounded per lane as the scalar `r * r`). A leaf of the
/// hierarchy asked at once: most of its spheres are clear misses, and a ray that would test
/// them one by one mispredicts the loop's branches.
#[cfg(lanes)]
#[inline(always)]
pub(crate) fn leaving_open_among(
    anchor: Vec3,
    rel: Vec3,
    spheres: [&Sphere; 4],
    d: Vec3,
    open: u32,
) -> u32 {
    use crate::simd::{bits, F, V};
    let r = F::from(spheres.map(|s| s.radius));
    let centre = V::from_lanes(spheres.map(|s| s.center));
    let f = V::splat(anchor).sub(centre).add(V::splat(rel));
    let start = leaving_start_rr(f, r * r, V::splat(d));
    open & !bits(start.clear | start.behind())
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
/// the shadow rays of four pixels have towards one sphere: [`hit_core`] in lanes, each lane
/// [`hit_ab_xyz`] on its values or marked to redo. `hb` (Hearn–Baker's discriminant) is one
/// choice for all lanes; every lane's `c` is finite.
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
    let (a, b) = (d.dot(d), f.dot(d));
    let h = hit_core(f, cv, rr, hb, true, d, a, b, tmin, tmax);
    LaneHits {
        hit: h.hit,
        redo: h.scaled | h.tangent,
        t: h.t.to_array(),
    }
}
