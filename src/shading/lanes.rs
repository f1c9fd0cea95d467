//! The shadow tests of four neighbouring hits on one sphere at once in vector lanes
//! (`cfg(lanes)`), each lane the scalar test's operations in the scalar order.

use super::*;
use crate::scene::SphereId;

/// Four hits on one sphere, in vector lanes (`cfg(lanes)`): [`Hit`]'s fields, for
/// [`in_shadow4`].
#[cfg(lanes)]
#[derive(Debug, Clone, Copy)]
pub(crate) struct Hits4 {
    pub t: F,
    pub sphere: usize,
    pub normal: V,
    pub offset: V,
    pub anchor: V,
    pub rel: V,
}

#[cfg(lanes)]
use crate::simd::{bits, ones, F, V};

#[cfg(lanes)]
impl Hits4 {
    /// Lane `l` as a [`Hit`], for the scalar shadow test.
    #[inline]
    pub(crate) fn hit(&self, l: usize) -> Hit {
        Hit {
            t: self.t.as_array_ref()[l & 3],
            sphere: self.sphere,
            normal: self.normal.lane(l),
            offset: self.offset.lane(l),
            anchor: self.anchor.lane(l),
            rel: self.rel.lane(l),
        }
    }
}

/// [`in_shadow_among`] for the lanes `ask` of four hits on one sphere (`to` their
/// [`LightKind::to_light`] vectors): the bits of those in shadow. For one kind of light `K`,
/// so that the loop over the candidates matches on no kind ([`in_shadow4_of`] matches once
/// for a [`Light`]). Each candidate is weighed for the four lanes at once as far as lanes
/// decide it (`fused`'s steps lane by lane, and the point light's constants through
/// [`Prepared::hit4`]); the lanes that remain get the scalar test of that sphere, so every
/// answer is the scalar one. Lanes that see their sphere from inside take the whole scalar
/// test.
#[cfg(lanes)]
#[inline(always)]
pub(crate) fn in_shadow4<const S: usize, const L: usize, K: LightKind>(
    scene: &Scene<S, L>,
    h: &Hits4,
    light: &K,
    to: &V,
    ask: u32,
    light_c: impl Fn(usize) -> Option<f32>,
    candidates: &[SphereId],
) -> u32 {
    use crate::geometry::leaving_blocks4;
    use crate::simd::CmpLt;
    let spheres = scene.spheres();
    let inside = bits(h.normal.dot(h.offset).cmp_lt(F::ZERO));
    // The lanes whose shadow ray `shadow_ray` scales up take the scalar test too.
    let small = light.scalar_lanes(to);
    let inside = inside | small;
    let mut out = 0;
    for l in ones(ask & inside) {
        let cands = candidates.iter().map(|j| j.index());
        if in_shadow_among(scene, &h.hit(l), light, to.lane(l), &light_c, cands) {
            out |= 1 << l;
        }
    }
    let mut open = ask & !inside;
    // `leaving_blocks` of the lanes in `open`: in lanes, the undecided ones scalar.
    let leaving = |s: &Sphere, d: &V, tmax: f32, open: u32| {
        let (mut hit, maybe) = leaving_blocks4(h.anchor, h.rel, s, *d, tmax, open);
        for l in ones(maybe) {
            let (anchor, rel) = (h.anchor.lane(l), h.rel.lane(l));
            if Prepared::leaving_blocks(anchor, rel, s, d.lane(l), tmax) {
                hit |= 1 << l;
            }
        }
        hit
    };
    for &j in candidates {
        if open == 0 {
            break;
        }
        let j = j.index();
        let Some(s) = spheres.get(j) else { continue };
        if j == h.sphere {
            continue;
        }
        let hit = light.blocks4(s, || light_c(j), to, open, leaving);
        out |= hit;
        open &= !hit;
    }
    out
}
