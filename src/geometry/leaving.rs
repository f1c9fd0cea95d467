//! Rays leaving a surface (shadow and mirror rays): `f` for another sphere as
//! `(anchor − m) + rel`, and a clear miss or hit decided from the discriminant before any
//! compensated `c`.

use super::*;

impl Prepared {
    /// What `Prepared::from_surface(anchor, rel, sphere).hit(d, tmin, tmax)` returns, with the
    /// `f` it used: for the shadow and mirror rays of a hit, which leave from
    /// `anchor + rel` (see [`Hit::anchor`](crate::Hit::anchor)). Cheaper, because a sphere
    /// certainly behind the ray (origin outside by more than the f32 error of `c`, `f·d ≥ 0`,
    /// `tmin ≥ 0`) is rejected before `c` is finished. That spares the compensated `c`, the costly
    /// part, for, say, the ground under a ball when the shadow ray goes up.
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
    pub(super) fn leaving_test(
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
    pub(super) fn fused<const OFFSET: bool>(
        f: Vec3,
        d: Vec3,
        tmin: f32,
        tmax: f32,
        any_hit: bool,
        (base, offset, sphere): (Vec3, Vec3, &Sphere),
    ) -> Option<(f32, Vec3)> {
        let r = sphere.radius;
        let start = leaving_start(f, r, d);
        if start.clear {
            return None;
        }
        if start.behind() && tmin >= 0.0 {
            return None;
        }
        let Leaving {
            a,
            b,
            c,
            rr,
            sum,
            err_c,
            ..
        } = start;
        let c = if start.keeps() {
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
}

/// The first steps of the test of a ray leaving a surface, for one f32 (`fused`) and for four
/// lanes (`leaving_blocks4`): `a`, `b`, the f32 `c` and the two tests that decide most rays
/// before `c` is finished: `clear`, a miss of the sphere's line, and [`Leaving::behind`].
#[derive(Clone, Copy)]
pub(super) struct Leaving<T: IeeeCmp> {
    pub a: T,
    pub b: T,
    pub c: T,
    pub rr: T,
    pub sum: T,
    pub err_c: T,
    pub clear: T::Mask,
}

impl<T: IeeeCmp> Leaving<T> {
    /// Certainly behind, for `tmin ≥ 0`: outside by more than the f32 error of `c`, heading
    /// away. (Methods, not fields, so that one f32 computes them only past `clear`.)
    #[inline(always)]
    pub fn behind(&self) -> T::Mask {
        self.c.gt(self.err_c) & self.b.ge(T::splat(0.0))
    }

    /// Where the f32 `c` is kept: it does not cancel (`CANCEL`) and is finite.
    #[inline(always)]
    pub fn keeps(&self) -> T::Mask {
        let c = self.c.abs();
        c.gt(self.sum * T::splat(CANCEL)) & c.le(T::splat(f32::MAX))
    }
}

/// [`Leaving`] of the ray along `d` with `f` the origin's offset from the centre of a sphere
/// of radius `r`.
#[inline(always)]
pub(super) fn leaving_start<P: Ieee3>(f: P, r: f32, d: P) -> Leaving<P::S> {
    leaving_start_rr(f, <P::S as Ieee>::splat(r * r), d)
}

/// [`leaving_start`] with the squared radius `rr` given, which lanes may hold per sphere.
#[inline(always)]
pub(super) fn leaving_start_rr<P: Ieee3>(f: P, rr: P::S, d: P) -> Leaving<P::S> {
    let v = <P::S as Ieee>::splat;
    let ff = f.dot(f);
    let c = ff - rr;
    let b = f.dot(d);
    // The f32 c is within ~2⁻²¹ (ff + rr) of the exact one (its rounding and that of f), so
    // b² − ac is off by that times a, plus a few ε (b² + a ff) from b, b² and ac, all below
    // 2⁻²⁰ a (ff + rr) as b² ≤ a ff: below −2⁻¹⁶ a (ff + rr) it misses the sphere's line
    // whatever the rounding. Most tests are such misses, decided before the compensated c,
    // as are spheres certainly behind. (A margin scaled by |c| instead, as `hit_ab`'s with
    // an accurate c, is too small where c cancels: rays from 1 above a ground of radius 10⁶
    // that meet it 1 400 away would miss.) Written `ac − 2⁻¹⁶ a (ff + rr) > b²`, where a or ff
    // overflows is ∞ − ∞ = NaN, never a miss; `a (c − 2⁻¹⁶ (ff + rr))` would reject those
    // (`leaving_overflow_is_no_clear_miss`).
    let sum = ff + rr;
    let a = d.dot(d);
    let clear = (a * c - a * sum * v(1.0 / 65_536.0)).gt(b * b);
    let err_c = sum * v(1.0 / 1_048_576.0);
    Leaving {
        a,
        b,
        c,
        rr,
        sum,
        err_c,
        clear,
    }
}
