//! The host path's shading: a span's stored hits four neighbouring pixels at a time, one lane
//! pass per sphere, each lane the scalar shading's operations in the scalar order.

use super::*;

impl<'a, const S: usize, const L: usize> Frame<'a, S, L> {
    /// Shades the span's stored primary hits four neighbouring pixels at a time, one lane pass
    /// for each sphere that sends no secondary ray among the four ([`shade_model`](crate::shading)),
    /// into `cull.hits.path.px`, marking them in `cull.hits.path.done`: the pixels `next_pixel` would compute one
    /// by one, bit for bit (the hit records built lane by lane as `make_hit` builds them, the
    /// shadow tests the scalar ones, asked for the same lanes and lights). Misses are marked
    /// done too (`px` starts as the background); mirrors and glass then take a pass of their
    /// own ([`Frame::shade_span4_secondary`]), and every other pixel is left to the scalar path.
    #[inline(never)]
    pub(super) fn shade_span4(&self, cull: &mut Cull<S, L>) {
        let len = cull.span_len();
        let (mut done, mut px) = (0u32, [cull.miss; SPAN]);
        let mut m = 0;
        while m + 4 <= len {
            // Pixels `k0..k0 + 4`, whose hits are in slots `q..q + 4`.
            let (k0, q) = (m, cull.slot(m));
            m += 4;
            let [dx, dy, dz] = &cull.hits.path.hit_dc;
            let lanes = |a: &[f32; DPAD]| -> Option<[f32; 4]> { a.get(q..q + 4)?.try_into().ok() };
            let (Some(ss), Some(ts), Some(x), Some(y), Some(z)) = (
                cull.hits.s.get(q..q + 4),
                cull.hits.t.get(q..q + 4),
                lanes(dx),
                lanes(dy),
                lanes(dz),
            ) else {
                break;
            };
            // Misses show the background, which `px` already holds: done, whatever the rest.
            let none = (0..4).fold(0u32, |b, l| b | ((ss[l] == SphereId::NONE) as u32) << l);
            done |= none << k0;
            let hits = !none & 0b1111;
            if hits == 0b1111 && ss.iter().all(|&x| x == ss[0]) {
                let colour =
                    self.shade4::<true, false>(cull, q, ss[0].index(), hits, ts, [x, y, z]);
                keep4(self, &mut px, &mut done, k0, hits, colour);
            } else if hits != 0 {
                self.shade4_mixed(cull, (k0, q), ss, hits, ts, [x, y, z], &mut px, &mut done);
            }
        }
        cull.hits.path.px = px;
        cull.hits.path.done = done;
        if self.scene.has_secondary() {
            self.shade_span4_secondary(cull);
        }
    }

    /// [`Frame::shade_span4`]'s groups of four whose hits are not all on one sphere (an edge):
    /// one lane pass per sphere, each keeping the lanes that hit it, rather than leaving such a
    /// group to the scalar path pixel by pixel (scenes of many small spheres have many edges).
    /// Out of line, so that the common group's code keeps its values in registers.
    #[inline(never)]
    #[allow(clippy::too_many_arguments)]
    pub(super) fn shade4_mixed(
        &self,
        cull: &Cull<S, L>,
        (k0, q): (usize, usize),
        ss: &[SphereId],
        hits: u32,
        ts: &[f32],
        xyz: [[f32; 4]; 3],
        px: &mut [Rgb888; SPAN],
        done: &mut u32,
    ) {
        let mut todo = hits;
        while let Some(&s) = ss.get(todo.trailing_zeros() as usize) {
            let active = (0..4).fold(0u32, |b, l| b | ((ss.get(l) == Some(&s)) as u32) << l) & todo;
            todo &= !active;
            let colour = self.shade4::<false, false>(cull, q, s.index(), active, ts, xyz);
            keep4(self, px, done, k0, active, colour);
        }
    }

    /// The colours of the lanes `active` of the span's four stored hits from slot `q`, all on
    /// sphere `si` (`ts` their t, `dir` their view directions by coordinate), shaded in lanes
    /// as `shade_span4` describes; the other lanes' values are meaningless. `None` where the
    /// scalar path must shade them (a mirror or glass without `SECONDARY`). `ALL`: all four lanes
    /// (the common group); a parameter so that the common group and `shade4_mixed` each get a
    /// copy of their own, whose shadow-test closure is inlined (shared, it goes out of line).
    /// `SECONDARY`: shade a mirror's or glass's lanes too, their secondary rays walked one by
    /// one (`follow4`); else leave them (`None`). A parameter so that the copies in the pixel
    /// loop stay without the walk: [`Frame::shade_span4_secondary`] has its own.
    #[inline(always)]
    pub(super) fn shade4<const ALL: bool, const SECONDARY: bool>(
        &self,
        cull: &Cull<S, L>,
        q: usize,
        si: usize,
        active: u32,
        ts: &[f32],
        [x, y, z]: [[f32; 4]; 3],
    ) -> Option<crate::simd::V> {
        use crate::scene::hit_vectors;
        use crate::shading::Hits4;
        use crate::simd::{F, V};
        let scene = self.scene;
        let active = if ALL { 0b1111 } else { active };
        let (k, sphere) = (self.tables.eye.get(si)?, scene.spheres().get(si)?);
        let secondary = scene.sends_secondary(si) && scene.max_depth() > 0;
        if secondary && !SECONDARY {
            return None;
        }
        let dir = V {
            x: F::from(x),
            y: F::from(y),
            z: F::from(z),
        };
        let t = F::from(<[f32; 4]>::try_from(ts).ok()?);
        // `hit_point_within`'s offset: `f + t·d` within near2 radii, else the one the span's
        // bounds kept, or without them (no shadow rays) `hit_point_far`'s, in lanes here.
        let offset = if self.offset_near(si) {
            V::splat(k.f).add(dir.mul(t))
        } else {
            match cull.hits.o.get(q..q + 4) {
                Some(o) if cull.shadow.culled => V::from_lanes([o[0], o[1], o[2], o[3]]),
                _ => crate::geometry::hit_point_far4(dir, t, k.f, sphere)?.1,
            }
        };
        // `hit_from_offset` for rays from the eye (`path` zero).
        let (eye, zero) = (V::splat(self.camera.eye()), V::splat(Vec3::ZERO));
        let [normal, anchor, rel] = hit_vectors(dir, t, sphere, offset, eye, zero);
        let h = Hits4 {
            t,
            sphere: si,
            normal,
            offset,
            anchor,
            rel,
        };
        let group = if cull.shadow.culled {
            cull.lists(si)
        } else {
            None
        };
        let colour = self.lit4::<ALL, SECONDARY>(&h, dir, active, group)?;
        if SECONDARY && secondary {
            return Some(self.follow4(&h, dir, colour, active));
        }
        Some(colour)
    }

    /// The local colours of the lanes `active` of the hits `h`, seen along `dir`, their shadow
    /// rays tested against the spheres of the span lists `group` (a primary hit's), or every
    /// sphere: [`shade_model`](crate::shading) in lanes, `None` where lanes leave some lane
    /// to the scalar shading. `ALL` and `SECONDARY` name the copy: each instance of `shade4`
    /// passes its own, and `mirror4` `<true, true>`, which no `shade4` takes, so that each
    /// caller's shadow-test closure is a type of its own and is inlined there (one shared
    /// closure goes out of line: 2 % more instructions on the target scene).
    #[inline(always)]
    pub(super) fn lit4<const ALL: bool, const SECONDARY: bool>(
        &self,
        h: &crate::shading::Hits4,
        dir: crate::simd::V,
        active: u32,
        group: Option<Lists<'_, L>>,
    ) -> Option<crate::simd::V> {
        use crate::shading::{in_shadow4_of, shade_model};
        use crate::simd::{bits, CmpLt, F, V};
        let scene = self.scene;
        let inside = bits(h.normal.dot(h.offset).cmp_lt(F::ZERO));
        let blocked = |i: usize, light: &Light, ask: u32, to: &V| {
            if !scene.shadows() {
                return 0;
            }
            // No candidate: only lanes that see the sphere from inside need the test
            // (`Frame::blocked`'s shortcut, four lanes at a time).
            let cands = self.candidates(group, i);
            let ask = if cands.is_empty() { ask & inside } else { ask };
            if ask == 0 {
                return 0;
            }
            let cs = self.light_consts(i, light);
            let consts = |j: usize| cs.and_then(|c| c.get(j)).copied();
            in_shadow4_of(scene, h, light, to, ask, consts, cands)
        };
        let [n, anchor, rel] = [h.normal, h.anchor, h.rel];
        shade_model(scene, h.sphere, [n, anchor, rel, dir], active, blocked)
    }

    /// The groups of four that [`Frame::shade_span4`] left to the scalar path because they hit
    /// a mirror or glass: their local colours in lanes, one pass per such sphere, then each
    /// lane's walk of secondary rays (`follow4`). A pass of its own after `shade_span4`, whose
    /// loop stays as it is for the scenes without secondary rays.
    #[inline(never)]
    pub(super) fn shade_span4_secondary(&self, cull: &mut Cull<S, L>) {
        let len = cull.span_len();
        let (mut done, mut px) = (cull.hits.path.done, cull.hits.path.px);
        let mut m = 0;
        while m + 4 <= len {
            let (k0, q) = (m, cull.slot(m));
            m += 4;
            let left = !(done >> k0) & 0b1111;
            if left == 0 {
                continue;
            }
            let [dx, dy, dz] = &cull.hits.path.hit_dc;
            let lanes = |a: &[f32; DPAD]| -> Option<[f32; 4]> { a.get(q..q + 4)?.try_into().ok() };
            let (Some(ss), Some(ts), Some(x), Some(y), Some(z)) = (
                cull.hits.s.get(q..q + 4),
                cull.hits.t.get(q..q + 4),
                lanes(dx),
                lanes(dy),
                lanes(dz),
            ) else {
                break;
            };
            let mut todo = left;
            while let Some(&s) = ss.get(todo.trailing_zeros() as usize) {
                let active =
                    (0..4).fold(0u32, |b, l| b | ((ss.get(l) == Some(&s)) as u32) << l) & todo;
                todo &= !active;
                let si = s.index();
                if !self.scene.sends_secondary(si) {
                    continue;
                }
                let colour = self.shade4::<false, true>(cull, q, si, active, ts, [x, y, z]);
                keep4(self, &mut px, &mut done, k0, active, colour);
            }
        }
        cull.hits.path.px = px;
        cull.hits.path.done = done;
    }

    /// The secondary rays of the lanes `active` of four primary hits on a mirror or glass,
    /// whose local colours the lanes shaded: each walked on its own, as the scalar path walks
    /// it from the same hit record (`Hits4::hit`) and colour, so the same bits. Out of line:
    /// the walk stays out of the lanes' loop.
    #[inline(never)]
    fn follow4(
        &self,
        h: &crate::shading::Hits4,
        dir: crate::simd::V,
        colour: crate::simd::V,
        active: u32,
    ) -> crate::simd::V {
        let eye = self.camera.eye();
        let mut out = [Vec3::ZERO; 4];
        // The first mirror rays in lanes where the walk tests every sphere.
        let left = if Self::SWEEPS && self.culls {
            active & 0b1111
        } else {
            self.mirror4(h, dir, colour, active & 0b1111, &mut out)
        };
        for l in crate::simd::ones(left) {
            if let Some(o) = out.get_mut(l) {
                let (ray, hit, c) = (Ray::new(eye, dir.lane(l)), h.hit(l), colour.lane(l));
                // The scalar path's walks, out of line: a copy of the walk of its own here
                // would cost the scalar path's (`Frame::follow_every`).
                *o = if Self::SWEEPS && self.culls {
                    self.follow_culled(&ray, &hit, c)
                } else {
                    self.follow_every(&ray, &hit, c)
                };
            }
        }
        crate::simd::V::from_lanes(out)
    }
}

/// Stores the encoded `colour` of the lanes `active` of the group at `k0` into `px`, marking
/// them done; nothing when the lanes could not shade them (`None`: the scalar path will).
#[inline(always)]
pub(super) fn keep4<const S: usize, const L: usize>(
    frame: &Frame<'_, S, L>,
    px: &mut [Rgb888; SPAN],
    done: &mut u32,
    k0: usize,
    active: u32,
    colour: Option<crate::simd::V>,
) {
    let Some(colour) = colour else { return };
    for (l, &c) in frame.encode4(&colour).iter().enumerate() {
        if active & (1 << l) != 0 {
            if let Some(p) = px.get_mut(k0 + l) {
                *p = c;
                *done |= 1 << (k0 + l);
            }
        }
    }
}
