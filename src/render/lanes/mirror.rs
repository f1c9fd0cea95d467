//! The mirror rays of four neighbouring primary hits on one mirror, found and shaded in lanes,
//! and those of their hits where these mirror too: each lane takes the scalar walk's steps
//! ([`find_from`](crate::shading::find_from), then the shading of the hit) with the scalar
//! operations in the scalar order, so each pixel gets the scalar walk's colour, bit for bit.
//! Most mirror rays of a scene meet nothing or the same sphere as their neighbours'.

use super::*;
use crate::geometry::{exit_t, leaving_hit4, offset_is_near, Prepared};
use crate::math::IeeeCmp;
use crate::scene::hit_vectors;
use crate::shading::{Hits4, T_EPS};
use crate::simd::{ones, F, V};

/// A lane's closest hit so far: `t`, the sphere and its `f` (the ray's origin less the centre).
type Found = Option<(f32, usize, Vec3)>;

impl<'a, const S: usize, const L: usize> Frame<'a, S, L> {
    /// The colours of the lanes `active` of the primary hits `h`, seen along `dir` with local
    /// colours `colour`, into `out`, where their sphere mirrors and does not refract: the
    /// mirror rays found together (sphere by sphere, misses and most hits decided in lanes) and
    /// shaded in lanes, one pass per sphere they hit, and so on down their paths
    /// ([`Frame::mirror_step`]). Returns the lanes left to the scalar walk: all of them for
    /// glass, and those whose ray meets its own sphere again, whose hit point is far from the
    /// sphere (`hit_point_far`) or whose shading lanes do not decide.
    #[inline(always)]
    pub(super) fn mirror4(
        &self,
        h: &Hits4,
        dir: V,
        colour: V,
        active: u32,
        out: &mut [Vec3; 4],
    ) -> u32 {
        self.mirror_step(h, dir, colour, (Color::ONE, 0), active, out)
    }

    /// [`Frame::mirror_step`] out of line, for the steps below the first: it calls itself.
    #[inline(never)]
    fn mirror_from(
        &self,
        h: &Hits4,
        dir: V,
        colour: V,
        (weight, depth): (Color, u8),
        active: u32,
        out: &mut [Vec3; 4],
    ) -> u32 {
        self.mirror_step(h, dir, colour, (weight, depth), active, out)
    }

    /// [`Frame::mirror4`] from the hits `h` at `depth` (0 for primary hits) on paths of weight
    /// `weight`, their colours so far `colour`: the walk's step (`walk`: the mirror ray of
    /// weight `weight ⊙ k`, its hit's local colour added) in lanes, then, where the hit
    /// mirrors too and the depth allows, the next step, whose undecided lanes take the scalar
    /// walk from that hit. Inline in the first step, where most groups end: a call for every
    /// group costs more than the second copy.
    #[inline(always)]
    fn mirror_step(
        &self,
        h: &Hits4,
        dir: V,
        colour: V,
        (weight, depth): (Color, u8),
        active: u32,
        out: &mut [Vec3; 4],
    ) -> u32 {
        let (scene, si) = (self.scene, h.sphere);
        let Some(m) = scene.materials().get(si) else {
            return active;
        };
        if m.mirror.is_zero() || (cfg!(feature = "refraction") && !m.refraction.is_zero()) {
            return active;
        }
        // `reflect`: d − n (2 d·n).
        let d = dir.sub(h.normal.mul(F::splat(2.0) * dir.dot(h.normal)));
        // `find_from`: the way out of the own sphere, then every other sphere with the
        // closest hit so far as the limit.
        let mut found: [Found; 4] = [None; 4];
        let mut tmax = [f32::INFINITY; 4];
        // `exit_root` in lanes: those whose ray leaves its sphere ahead (none off a ground
        // seen from above).
        let t = exit_t(h.offset, d);
        let ahead = F::bits(t.gt(F::splat(0.0)) & t.lt(F::splat(f32::INFINITY)));
        let ts = t.to_array();
        for l in ones(ahead & active) {
            let t = ts[l & 3];
            tmax[l & 3] = t;
            found[l & 3] = Some((t, si, h.offset.lane(l)));
        }
        let spheres = scene.spheres();
        for (j, s) in spheres.iter().enumerate() {
            if j == si {
                continue;
            }
            let lanes = leaving_hit4((h.anchor, h.rel), s, d, (T_EPS, F::from(tmax)), active);
            for l in ones(lanes.hit) {
                let t = lanes.t[l & 3];
                tmax[l & 3] = t;
                found[l & 3] = Some((t, j, lanes.f.lane(l)));
            }
            for l in ones(lanes.undecided) {
                let (anchor, rel) = (h.anchor.lane(l), h.rel.lane(l));
                let hit = Prepared::leaving_hit(anchor, rel, s, d.lane(l), T_EPS, tmax[l & 3]);
                if let Some((t, f)) = hit {
                    tmax[l & 3] = t;
                    found[l & 3] = Some((t, j, f));
                }
            }
        }
        // `walk`'s sum: the branch's weight is the path's `⊙ k`.
        let weight = weight.mul_elem(m.mirror);
        let depth = depth + 1;
        let (mut left, mut todo) = (0u32, 0u32);
        for l in ones(active) {
            match found[l & 3] {
                None => {
                    let mut c = colour.lane(l);
                    c += weight.mul_elem(scene.background());
                    out[l & 3] = c;
                }
                Some((_, j, f)) => {
                    let near = spheres
                        .get(j)
                        .is_some_and(|s| offset_is_near(f, s.radius, scene.near2(j)));
                    if j == si || !near {
                        left |= 1 << l;
                    } else {
                        todo |= 1 << l;
                    }
                }
            }
        }
        // One lane pass per sphere hit.
        while let Some(&Some((_, j, _))) = found.get(todo.trailing_zeros() as usize) {
            let group = ones(todo).fold(0, |g, l| {
                g | (found[l & 3].is_some_and(|(_, k, _)| k == j) as u32) << l
            });
            todo &= !group;
            let Some(sphere) = spheres.get(j) else {
                left |= group;
                continue;
            };
            // The other lanes repeat the first one's hit: finite values, never read.
            let first = group.trailing_zeros() as usize;
            let lane = |l: usize| {
                let k = if group & (1 << l) != 0 { l } else { first };
                found[k & 3].map_or((0.0, Vec3::ZERO), |(t, _, f)| (t, f))
            };
            let [(t0, f0), (t1, f1), (t2, f2), (t3, f3)] = [lane(0), lane(1), lane(2), lane(3)];
            let t = F::from([t0, t1, t2, t3]);
            // `make_hit` of a near hit: the offset `f + d·t`, on the path from the primary
            // hit's anchor.
            let offset = V::from_lanes([f0, f1, f2, f3]).add(d.mul(t));
            let [normal, anchor, rel] = hit_vectors(d, t, sphere, offset, h.anchor, h.rel);
            let hit = Hits4 {
                t,
                sphere: j,
                normal,
                offset,
                anchor,
                rel,
            };
            let Some(local) = self.lit4::<true, true>(&hit, d, group, None) else {
                left |= group;
                continue;
            };
            let mut sums = [Vec3::ZERO; 4];
            for l in ones(group) {
                let mut c = colour.lane(l);
                c += weight.mul_elem(local.lane(l));
                sums[l & 3] = c;
                out[l & 3] = c;
            }
            // `walk_on`: the rays of hits short of the deepest.
            if scene.sends_secondary(j) && depth < scene.max_depth() {
                let sums = V::from_lanes(sums);
                let rest = self.mirror_from(&hit, d, sums, (weight, depth), group, out);
                for l in ones(rest) {
                    let (from, to) = (h.hit(l), hit.hit(l));
                    let ray = Ray::new(from.point(), d.lane(l));
                    out[l & 3] = self.follow_on(&ray, &to, sums.lane(l), (weight, depth));
                }
            }
        }
        left
    }
}
