//! What each kind of light does, one impl per kind: the direction towards it, its shadow ray and
//! the test of that ray, and the bounds by which the span culling keys and keeps the spheres
//! that can block it. Shading and culling ask a [`Light`] through [`LightKind`] and never match
//! on its kind: a new kind is a variant of [`Light`] (with its validation in `scene/light.rs`),
//! a struct here with its `impl LightKind`, and its arm in `per_kind!`.

use super::*;
use crate::geometry::Sphere;
use crate::math::{Ieee3, IeeeCmp};
use crate::raster::ETA;
#[cfg(lanes)]
use crate::simd::{bits, F, V};

/// A point light at `position`, as [`LightKind`] sees it.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Point {
    pub(crate) position: Vec3,
}

/// A directional light shining along the unit vector `direction`, as [`LightKind`] sees it.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Directional {
    pub(crate) direction: Vec3,
}

/// Angular margin of a point light's sweep keys (radians): far above the rounding of `atan2f`
/// and of the unit directions' components.
const ANGLE_MARGIN: f32 = 1e-4;

/// The relative pad of [`LightKind::near_depth`] and [`LightKind::far_depth`]: far above the
/// rounding of a distance or a dot product (a few ε of it, or of `|m|₁`).
const DEPTH_PAD: f32 = 1e-5;

/// The sum of the absolute coordinates, `|w|₁ ≥ |w|`: a pad without a square root.
#[inline(always)]
fn l1(w: Vec3) -> f32 {
    libm::fabsf(w.x) + libm::fabsf(w.y) + libm::fabsf(w.z)
}

/// The behaviour of one kind of light.
pub(crate) trait LightKind {
    /// Where the light comes from at the hit point `anchor + rel` (see [`Hit::anchor`]), for one
    /// hit or four in lanes: the vector from the hit to a point light (the shadow ray,
    /// `0 < t < 1`) or the unit vector towards a directional one.
    fn to_light<P: Ieee3>(&self, anchor: P, rel: P) -> P;

    /// The unit vector `l` along [`LightKind::to_light`]'s `v`, or `None` where a lane of
    /// `active` needs the guarded form that only one f32 computes ([`Ieee3::normalized_or_zero`]).
    fn unit_towards<P: Ieee3>(&self, v: P, active: u32) -> Option<P>;

    /// The point every shadow ray of this light starts from, when there is one (a point
    /// light's position): the frame keeps [`Prepared::exact`]'s `c` from it for every sphere.
    fn origin(&self) -> Option<Vec3>;

    /// Whether one of the spheres `others` (never the hit's own) or, seen from `inside`, the
    /// hit's own sphere blocks the shadow ray along `v` ([`LightKind::to_light`]) from `hit`;
    /// `light_c(j)` is sphere `j`'s `c` from [`LightKind::origin`], where the frame keeps it.
    fn blocked(
        &self,
        spheres: &[Sphere],
        hit: &Hit,
        inside: bool,
        v: Vec3,
        light_c: impl Fn(usize) -> Option<f32>,
        others: impl Iterator<Item = usize>,
    ) -> bool;

    /// The direction across which a sweep keys this light's spheres: where the keys spread
    /// them the most. `None` when there is none (the caller then takes the view's).
    fn sweep_along(&self, spheres: &[Sphere]) -> Option<Vec3>;

    /// The sweep entry of a sphere (centre `m`, radius `r`): its key along `axis`, the key's
    /// half-width (infinite: the sphere is kept apart and always tested) and its key along
    /// `axis2`.
    fn sweep_entry(&self, m: Vec3, r: f32, axis: Vec3, axis2: Vec3) -> (f32, f32, f32);

    /// The keys of the ball `(q, rho)` along `axis` and `axis2`, with the slack its bound adds
    /// to every half-width, or `None` when a sweep cannot bound it (the light inside the ball).
    fn band(&self, q: Vec3, rho: f32, axis: Vec3, axis2: Vec3) -> Option<(f32, f32, f32)>;

    /// How far along the light's rays the ball `(q, rho)` reaches, plus a pad (see
    /// [`LightKind::near_depth`]).
    fn far_depth(&self, q: Vec3, rho: f32) -> f32;

    /// How far along the light's rays the sphere (centre `m`, radius `r`) begins: its least
    /// distance from a point light, its least position along a directional light's direction,
    /// less a pad. A blocker's points on a shadow ray lie nearer the light than the ray's
    /// origin, so a sphere can block a ray from the ball `(q, rho)` only where this is at most
    /// [`LightKind::far_depth`]`(q, rho)`: a sweep's third filter, which drops the spheres
    /// behind a span's hits (most of a cluster, seen from its lit side).
    fn near_depth(&self, m: Vec3, r: f32) -> f32;

    /// Whether spheres (centres `m` by coordinate, radii `r`) can block a shadow ray towards the
    /// light from some point of the ball `(q, rho)`: a conservative test, padded well beyond the
    /// rounding of the shadow test itself and of this one. One definition for one f32 and for
    /// four lanes, so the lanes' answers are the scalar ones (`lane_blockers_are_may_block`).
    fn may_block_of<T: IeeeCmp>(&self, m: [T; 3], r: T, q: Vec3, rho: f32) -> T::Mask;

    /// [`LightKind::may_block_of`] of one sphere: what the Cortex-M span culling filters by.
    #[cfg_attr(lanes, allow(dead_code))]
    #[inline]
    fn may_block(&self, m: Vec3, r: f32, q: Vec3, rho: f32) -> bool {
        self.may_block_of([m.x, m.y, m.z], r, q, rho)
    }

    /// [`LightKind::may_block_of`] of four spheres at once in vector lanes, as bits `0..4`: what
    /// hosts filter by.
    #[cfg(lanes)]
    #[inline(always)]
    fn may_block4(&self, m: [Vec3; 4], r: [f32; 4], q: Vec3, rho: f32) -> u32 {
        let (x, y, z) = lanes3(m);
        bits(self.may_block_of([x, y, z], F::from(r), q, rho))
    }

    /// The lanes whose shadow ray along `to` only the scalar test takes (a point light's
    /// [`shadow_ray`] scaled up).
    #[cfg(lanes)]
    fn scalar_lanes(&self, to: &V) -> u32;

    /// The lanes of `open` whose shadow ray along `to` sphere `s` blocks (`c()` its `light_c`),
    /// `leaving(s, d, tmax, open)` being [`Prepared::leaving_blocks`] in lanes.
    #[cfg(lanes)]
    fn blocks4(
        &self,
        s: &Sphere,
        c: impl FnOnce() -> Option<f32>,
        to: &V,
        open: u32,
        leaving: impl Fn(&Sphere, &V, f32, u32) -> u32,
    ) -> u32;
}

impl Point {
    /// [`Prepared::exact`]'s constants from the light for sphere `s`, rebuilt from its kept `c`,
    /// where a shadow ray cast from the light applies: within 32 radii of the light (see
    /// [`in_shadow`]); `None` elsewhere, where the ray is tested from the hit.
    #[inline(always)]
    fn constants(&self, s: &Sphere, c: Option<f32>) -> Option<Prepared> {
        match c {
            Some(c) if c <= NEAR_LIGHT * (s.radius * s.radius) => Some(Prepared {
                f: self.position - s.center,
                c,
                r: s.radius,
            }),
            _ => None,
        }
    }
}

impl LightKind for Point {
    #[inline(always)]
    fn to_light<P: Ieee3>(&self, anchor: P, rel: P) -> P {
        P::splat(self.position).sub(anchor).sub(rel)
    }

    #[inline(always)]
    fn unit_towards<P: Ieee3>(&self, v: P, active: u32) -> Option<P> {
        let ll = v.dot(v);
        // |v|² overflows beyond ~10¹⁹ and underflows below ~10⁻¹⁹: then the guarded form
        // (and no light at all from a light exactly at p).
        if <P::S as IeeeCmp>::bits(ll.positive_normal()) & active == active {
            Some(v.div(ll.sqrt()))
        } else {
            v.normalized_or_zero()
        }
    }

    #[inline(always)]
    fn origin(&self) -> Option<Vec3> {
        Some(self.position)
    }

    #[inline(always)]
    fn blocked(
        &self,
        spheres: &[Sphere],
        hit: &Hit,
        inside: bool,
        v: Vec3,
        light_c: impl Fn(usize) -> Option<f32>,
        mut others: impl Iterator<Item = usize>,
    ) -> bool {
        // `a`: `|d|²` for `d = −to_light`, the same bits. `t < 1` is `t ≤ below_one`.
        let (to_light, a, below_one) = shadow_ray(v);
        if inside && exit_root(hit.offset, to_light).is_some_and(|t| t <= below_one) {
            return true;
        }
        let d = -to_light;
        // `get`, not `[j]`: no bounds-check panic linked into the render path.
        others.any(|j| {
            let Some(s) = spheres.get(j) else {
                return false;
            };
            match self.constants(s, light_c(j)) {
                Some(k) => k.hit_ab(d, a, k.f.dot(d), T_EPS, below_one).is_some(),
                None => Prepared::leaving_blocks(hit.anchor, hit.rel, s, to_light, below_one),
            }
        })
    }

    fn sweep_along(&self, spheres: &[Sphere]) -> Option<Vec3> {
        // The mean direction from the light to the spheres: a point light's keys are the
        // components of the unit direction to each sphere, which two directions at an angle θ
        // differ in by at most 2 sin(θ/2) ≤ θ, so angular half-widths bound them.
        spheres
            .iter()
            .filter_map(|s| (s.center - self.position).normalized())
            .fold(Vec3::ZERO, |sum, d| sum + d)
            .normalized()
    }

    fn sweep_entry(&self, m: Vec3, r: f32, axis: Vec3, axis2: Vec3) -> (f32, f32, f32) {
        // The same padded radius as `may_block`.
        let w = m - self.position;
        let big = r * (1.0 + 2e-4) + 2.0 * ETA * (l1(w) + r);
        let ww = w.dot(w);
        if !(ww > big * big * 1.01) {
            // The light inside or near: wide.
            (0.0, f32::INFINITY, 0.0)
        } else {
            let hw = libm::atan2f(big, libm::sqrtf(ww - big * big));
            let len = libm::sqrtf(ww);
            (axis.dot(w) / len, hw, axis2.dot(w) / len)
        }
    }

    #[inline]
    fn band(&self, q: Vec3, rho: f32, axis: Vec3, axis2: Vec3) -> Option<(f32, f32, f32)> {
        let v = q - self.position;
        let vv = v.dot(v);
        if !(vv > rho * rho * 1.01) {
            return None;
        }
        let len = libm::sqrtf(vv);
        let (key, key2) = (axis.dot(v) / len, axis2.dot(v) / len);
        // The ball's half-angle seen from the light is atan of this, and atan x ≤ x: a wider
        // band, never a narrower one, without an `atan2f` per span.
        let tan_theta = rho / libm::sqrtf(vv - rho * rho);
        Some((key, tan_theta + ANGLE_MARGIN, key2))
    }

    fn far_depth(&self, q: Vec3, rho: f32) -> f32 {
        let v = q - self.position;
        let len = libm::sqrtf(v.dot(v));
        len + rho + DEPTH_PAD * (len + rho)
    }

    fn near_depth(&self, m: Vec3, r: f32) -> f32 {
        // |w| rounds within a few ε of itself (w = m − light is one rounding per coordinate);
        // the radius padded as `may_block` pads it, and 10⁻⁵ of the distance.
        let w = m - self.position;
        let len = libm::sqrtf(w.dot(w));
        let big = r * (1.0 + 2e-4) + 2.0 * ETA * (l1(w) + r);
        len - big - DEPTH_PAD * (len + big)
    }

    #[inline(always)]
    fn may_block_of<T: IeeeCmp>(&self, [mx, my, mz]: [T; 3], r: T, q: Vec3, rho: f32) -> T::Mask {
        // Shadow rays run from the light to points of the ball: the segments fill the cone
        // hull of the light and the ball, whose section at λ ∈ [0, 1] along v = q − light is
        // the ball (light + λ v, λ ρ). The sphere misses it iff g(λ) = |w − λ v|² − (R + λ ρ)²
        // > 0 on [0, 1], w = m − light.
        let v = T::splat;
        let p = self.position;
        let (wx, wy, wz) = (mx - v(p.x), my - v(p.y), mz - v(p.z));
        let qv = q - p;
        // |x| + |y| + |z| ≥ |w|: a wider pad without a square root.
        let big = r * v(1.0 + 2e-4) + v(2.0 * ETA) * (wx.abs() + wy.abs() + wz.abs() + r);
        let (ww, vv) = (wx * wx + wy * wy + wz * wz, v(qv.dot(qv)));
        let wv = wx * v(qv.x) + wy * v(qv.y) + wz * v(qv.z);
        let a = vv - v(rho * rho);
        let b = wv + big * v(rho);
        let g0 = ww - big * big;
        let g1 = a - v(2.0) * b + g0;
        let gmin = T::select(g0.lt(g1), g0, g1);
        // The minimum inside (0, 1), where there is one.
        let inner = a.gt(v(0.0)) & b.gt(v(0.0)) & b.lt(a);
        let gmin = T::select_lazy(
            inner,
            || {
                let gv = g0 - b * (b / a);
                T::select(gv.lt(gmin), gv, gmin)
            },
            gmin,
        );
        let tol = v(1e-5) * (ww + vv + big * big + v(rho * rho));
        gmin.not_gt(tol)
    }

    #[cfg(lanes)]
    #[inline(always)]
    fn scalar_lanes(&self, to: &V) -> u32 {
        use crate::simd::CmpLt;
        bits(to.dot(*to).cmp_lt(F::splat(f32::from_bits(SMALL_VV))))
    }

    #[cfg(lanes)]
    #[inline(always)]
    fn blocks4(
        &self,
        s: &Sphere,
        c: impl FnOnce() -> Option<f32>,
        to: &V,
        open: u32,
        leaving: impl Fn(&Sphere, &V, f32, u32) -> u32,
    ) -> u32 {
        match self.constants(s, c()) {
            Some(k) => k.hit_bits4(&to.neg(), T_EPS, T_BELOW_ONE, open),
            None => leaving(s, to, T_BELOW_ONE, open),
        }
    }
}

impl LightKind for Directional {
    #[inline(always)]
    fn to_light<P: Ieee3>(&self, _anchor: P, _rel: P) -> P {
        P::splat(-self.direction)
    }

    #[inline(always)]
    fn unit_towards<P: Ieee3>(&self, v: P, _active: u32) -> Option<P> {
        Some(v)
    }

    #[inline(always)]
    fn origin(&self) -> Option<Vec3> {
        None
    }

    #[inline(always)]
    fn blocked(
        &self,
        spheres: &[Sphere],
        hit: &Hit,
        inside: bool,
        v: Vec3,
        _light_c: impl Fn(usize) -> Option<f32>,
        mut others: impl Iterator<Item = usize>,
    ) -> bool {
        let l = v;
        let blocks = |s| Prepared::leaving_blocks(hit.anchor, hit.rel, s, l, f32::INFINITY);
        (inside && exit_root(hit.offset, l).is_some())
            || others.any(|j| spheres.get(j).is_some_and(blocks))
    }

    fn sweep_along(&self, _spheres: &[Sphere]) -> Option<Vec3> {
        Some(self.direction)
    }

    fn sweep_entry(&self, m: Vec3, r: f32, axis: Vec3, axis2: Vec3) -> (f32, f32, f32) {
        // `may_block` pads with 2η|m − q|₁ ≤ 2η(|m|₁ + |q|₁); the |q|₁ part and the rounding
        // of keys (1e-5 of |m|₁, |q|₁) are added per span.
        let big = r * (1.0 + 2e-4) + 2.0 * ETA * (l1(m) + r) + 1e-5 * l1(m);
        (axis.dot(m), big, axis2.dot(m))
    }

    #[inline]
    fn band(&self, q: Vec3, rho: f32, axis: Vec3, axis2: Vec3) -> Option<(f32, f32, f32)> {
        // The same bound holds along any unit axis across a directional light.
        let l1 = l1(q);
        Some((
            axis.dot(q),
            rho + 2.0 * ETA * (l1 + rho) + rho + 1e-5 * l1,
            axis2.dot(q),
        ))
    }

    fn far_depth(&self, q: Vec3, rho: f32) -> f32 {
        q.dot(self.direction) + rho + DEPTH_PAD * (l1(q) + rho)
    }

    fn near_depth(&self, m: Vec3, r: f32) -> f32 {
        // m·u rounds within a few ε of |m|₁ (u = `direction`, unit within a few ε: the scene
        // normalises it): 10⁻⁵ of it pads that, and the radius is padded as `may_block` pads
        // it.
        let big = r * (1.0 + 2e-4) + 2.0 * ETA * (l1(m) + r);
        m.dot(self.direction) - big - DEPTH_PAD * (l1(m) + big)
    }

    #[inline(always)]
    fn may_block_of<T: IeeeCmp>(&self, [mx, my, mz]: [T; 3], r: T, q: Vec3, rho: f32) -> T::Mask {
        // Shadow rays leave points of the ball along l = −direction: the sphere misses them
        // iff it stays farther than R + ρ from the half-line q + t l, t ≥ 0.
        let v = T::splat;
        let l = -self.direction;
        let (wx, wy, wz) = (mx - v(q.x), my - v(q.y), mz - v(q.z));
        let s = wx * v(l.x) + wy * v(l.y) + wz * v(l.z);
        let ahead = s.gt(v(0.0));
        let (ex, ey, ez) = (
            T::select_lazy(ahead, || wx - v(l.x) * s, wx),
            T::select_lazy(ahead, || wy - v(l.y) * s, wy),
            T::select_lazy(ahead, || wz - v(l.z) * s, wz),
        );
        let big = r * v(1.0 + 2e-4)
            + v(2.0 * ETA) * (wx.abs() + wy.abs() + wz.abs() + v(rho) + r)
            + v(rho);
        let d2 = ex * ex + ey * ey + ez * ez;
        let tol = v(1e-5) * (wx * wx + wy * wy + wz * wz + big * big);
        (d2 - big * big).not_gt(tol)
    }

    #[cfg(lanes)]
    #[inline(always)]
    fn scalar_lanes(&self, _to: &V) -> u32 {
        0
    }

    #[cfg(lanes)]
    #[inline(always)]
    fn blocks4(
        &self,
        s: &Sphere,
        _c: impl FnOnce() -> Option<f32>,
        to: &V,
        open: u32,
        leaving: impl Fn(&Sphere, &V, f32, u32) -> u32,
    ) -> u32 {
        leaving(s, to, f32::INFINITY, open)
    }
}

/// The coordinates of four points, each in the lanes of one vector.
#[cfg(lanes)]
#[inline(always)]
fn lanes3(m: [Vec3; 4]) -> (F, F, F) {
    (
        F::from(m.map(|c| c.x)),
        F::from(m.map(|c| c.y)),
        F::from(m.map(|c| c.z)),
    )
}

/// `$body` with `$k` bound to the light's kind: the one place that matches on it.
macro_rules! per_kind {
    ($light:expr, $k:ident => $body:expr) => {
        match *$light {
            Light::Point { position, .. } => {
                let $k = Point { position };
                $body
            }
            Light::Directional { direction, .. } => {
                let $k = Directional { direction };
                $body
            }
        }
    };
}

impl LightKind for Light {
    #[inline(always)]
    fn to_light<P: Ieee3>(&self, anchor: P, rel: P) -> P {
        per_kind!(self, k => k.to_light(anchor, rel))
    }
    #[inline(always)]
    fn unit_towards<P: Ieee3>(&self, v: P, active: u32) -> Option<P> {
        per_kind!(self, k => k.unit_towards(v, active))
    }
    #[inline(always)]
    fn origin(&self) -> Option<Vec3> {
        per_kind!(self, k => k.origin())
    }
    #[inline(always)]
    fn blocked(
        &self,
        spheres: &[Sphere],
        hit: &Hit,
        inside: bool,
        v: Vec3,
        light_c: impl Fn(usize) -> Option<f32>,
        others: impl Iterator<Item = usize>,
    ) -> bool {
        per_kind!(self, k => k.blocked(spheres, hit, inside, v, light_c, others))
    }
    fn sweep_along(&self, spheres: &[Sphere]) -> Option<Vec3> {
        per_kind!(self, k => k.sweep_along(spheres))
    }
    fn sweep_entry(&self, m: Vec3, r: f32, axis: Vec3, axis2: Vec3) -> (f32, f32, f32) {
        per_kind!(self, k => k.sweep_entry(m, r, axis, axis2))
    }
    #[inline]
    fn band(&self, q: Vec3, rho: f32, axis: Vec3, axis2: Vec3) -> Option<(f32, f32, f32)> {
        per_kind!(self, k => k.band(q, rho, axis, axis2))
    }
    fn far_depth(&self, q: Vec3, rho: f32) -> f32 {
        per_kind!(self, k => k.far_depth(q, rho))
    }
    fn near_depth(&self, m: Vec3, r: f32) -> f32 {
        per_kind!(self, k => k.near_depth(m, r))
    }
    #[inline(always)]
    fn may_block_of<T: IeeeCmp>(&self, m: [T; 3], r: T, q: Vec3, rho: f32) -> T::Mask {
        per_kind!(self, k => k.may_block_of(m, r, q, rho))
    }
    #[cfg(lanes)]
    #[inline(always)]
    fn scalar_lanes(&self, to: &V) -> u32 {
        per_kind!(self, k => k.scalar_lanes(to))
    }
    #[cfg(lanes)]
    #[inline(always)]
    fn blocks4(
        &self,
        s: &Sphere,
        c: impl FnOnce() -> Option<f32>,
        to: &V,
        open: u32,
        leaving: impl Fn(&Sphere, &V, f32, u32) -> u32,
    ) -> u32 {
        per_kind!(self, k => k.blocks4(s, c, to, open, leaving))
    }
}

/// [`in_shadow4`] for `light`, its kind matched here, once, rather than for each candidate.
#[cfg(lanes)]
#[inline(always)]
pub(crate) fn in_shadow4_of<const S: usize, const L: usize>(
    scene: &Scene<S, L>,
    h: &crate::shading::Hits4,
    light: &Light,
    to: &V,
    ask: u32,
    light_c: impl Fn(usize) -> Option<f32>,
    candidates: &[crate::scene::SphereId],
) -> u32 {
    per_kind!(light, k => crate::shading::in_shadow4(scene, h, &k, to, ask, light_c, candidates))
}

#[cfg(all(test, lanes))]
mod lane_tests {
    use super::*;
    use crate::math::Color;

    /// `LightKind::may_block4` answers as `may_block` does, lane by lane, for both kinds of light, on
    /// spheres and balls of every size and distance, near the edge of the test especially.
    #[test]
    fn lane_blockers_are_may_block() {
        let mut g = crate::math::TestRng(0x9e37_79b9_7f4a_7c15);
        let (mut yes, mut no) = (0, 0);
        for case in 0..50_000 {
            let scale = [1e-3f32, 1.0, 1e3][case % 3];
            let (q, rho) = (g.vec(8.0 * scale), g.unit() * scale);
            let light = if case % 2 == 0 {
                Light::Point {
                    position: g.vec(8.0 * scale),
                    intensity: Color::ONE,
                }
            } else {
                let d = g.vec(1.0).normalized().unwrap_or(Vec3::new(0.0, -1.0, 0.0));
                Light::Directional {
                    direction: d,
                    intensity: Color::ONE,
                }
            };
            let r: [f32; 4] = core::array::from_fn(|_| g.unit() * scale);
            // Half the spheres anywhere, half about as far from the shadow rays' axis as the
            // test's edge, where it decides by a hair.
            let far_end = match light {
                Light::Point { position, .. } => position,
                Light::Directional { direction, .. } => q - direction * (8.0 * scale),
            };
            let m: [Vec3; 4] = core::array::from_fn(|l| {
                if l % 2 == 0 {
                    return g.vec(8.0 * scale);
                }
                let u = g.unit();
                let axis = q + (far_end - q) * u;
                let side = g.vec(1.0).normalized().unwrap_or(Vec3::new(1.0, 0.0, 0.0));
                if l == 1 {
                    return axis + side * ((r[l] + rho * u) * (0.9 + 0.2 * g.unit()));
                }
                // Within half the test's pad either side of its edge: the cone's radius there
                // (ρ at the ball, 0 at a point light; ρ all along a directional light's sweep)
                // plus r and the pad's estimate, 2·10⁻⁴ r + 2 ETA |w|₁.
                let (w, reach) = match light {
                    Light::Point { position, .. } => (axis - position, rho * (1.0 - u)),
                    Light::Directional { .. } => (axis - q, rho),
                };
                let l1 = w.x.abs() + w.y.abs() + w.z.abs();
                let pad = 2e-4 * r[l] + 2.0 * ETA * (l1 + r[l] + reach);
                axis + side * (r[l] + reach + pad * (0.5 + g.unit()))
            });
            let lanes = light.may_block4(m, r, q, rho);
            for l in 0..4 {
                let scalar = light.may_block(m[l], r[l], q, rho);
                assert_eq!(
                    lanes & (1 << l) != 0,
                    scalar,
                    "{light:?} {:?} {} {q:?} {rho}",
                    m[l],
                    r[l]
                );
                if scalar {
                    yes += 1
                } else {
                    no += 1
                }
            }
        }
        assert!(yes > 10_000 && no > 10_000, "{yes} {no}");
    }
}
