//! Primary rays: the closest hit of a ray from the eye among all spheres or a span's candidates,
//! and the hit records built from what a span kept. A span's own tracing is each render path's
//! `trace_span` (`lanes/`, `scalar.rs`).

use super::*;

impl<'a, const S: usize, const L: usize> Frame<'a, S, L> {
    /// The closest hit of a primary ray (one that starts at the eye), against every sphere.
    #[inline]
    pub(super) fn primary_hit(&self, ray: &Ray) -> Option<Hit> {
        let mut best: Option<(f32, usize)> = None;
        let mut tmax = f32::INFINITY;
        for (i, k) in self.tables.eye.iter().enumerate() {
            if let Some(t) = k.hit(ray.dir, T_EPS, tmax) {
                tmax = t;
                best = Some((t, i));
            }
        }
        let (t, i) = best?;
        self.eye_hit(ray, t, i)
    }

    /// The closest hit of the primary ray through column `i`, as `(t, sphere)`, against the
    /// spheres of `cands` whose box holds that column (the row is the caller's): the closest
    /// of scene order, where equal roots go to the greater index, in whatever order `cands`
    /// come (hosts sort a tile's spheres at its first deep pile, `Frame::sort_piles`). Inlined in [`Frame::gather`]'s pixel loop where spans cannot keep every view
    /// direction (soft-float Arm; elsewhere [`Frame::trace_span`] finds the same hits sphere by
    /// sphere); the other callers share [`Frame::primary_hit_among`].
    #[inline]
    pub(super) fn primary_among(
        &self,
        ray: &Ray,
        i: u32,
        cands: &[SphereId],
    ) -> Option<(f32, usize)> {
        let mut best: Option<(f32, usize)> = None;
        let mut tmax = f32::INFINITY;
        for &id in cands {
            let s = id.index();
            let (Some(b), Some(k)) = (self.tables.boxes.get(s), self.tables.eye.get(s)) else {
                continue;
            };
            if i < b.i0 as u32 || i > b.i1 as u32 {
                continue;
            }
            if let Some(t) = k.hit(ray.dir, T_EPS, tmax) {
                // In scene order a later sphere always takes an equal root (Cortex-M's spans
                // keep that order: no test there).
                #[cfg(lanes)]
                if !wins(
                    t,
                    id,
                    tmax,
                    best.map_or(SphereId::NONE, |b| SphereId::new(b.1)),
                ) {
                    continue;
                }
                tmax = t;
                best = Some((t, s));
            }
        }
        best
    }

    /// [`Frame::primary_among`] as a hit record. Out of line: one copy for the callers off
    /// the hot path (several samples per pixel, no shadow rays, single pixels).
    #[inline(never)]
    pub(super) fn primary_hit_among(&self, ray: &Ray, i: u32, cands: &[SphereId]) -> Option<Hit> {
        let (t, s) = self.primary_among(ray, i, cands)?;
        self.eye_hit(ray, t, s)
    }

    /// What a primary hit record on sphere `s` takes besides its ray and `t`: the eye's
    /// constants for `s`, the sphere, and whether its offset is `f + t·d` ([`Frame::offset_near`]).
    #[inline(always)]
    pub(super) fn eye_record(&self, s: usize) -> Option<(&Prepared, &crate::Sphere, bool)> {
        Some((
            self.tables.eye.get(s)?,
            self.scene.spheres().get(s)?,
            self.offset_near(s),
        ))
    }

    /// The hit record of a primary ray at `t` on sphere `s`: a pure function of them.
    #[inline]
    pub(super) fn eye_hit(&self, ray: &Ray, t: f32, s: usize) -> Option<Hit> {
        let (k, sphere, near) = self.eye_record(s)?;
        Some(make_hit(
            ray,
            t,
            s,
            k.f,
            sphere,
            near,
            ray.origin,
            Vec3::ZERO,
        ))
    }

    /// The hit record of the span's kept primary hit in `slot` along `ray` where spans keep
    /// offsets (`OFFS`, hosts): [`Frame::eye_hit`], with the hit's offset from the centre taken
    /// from the span's bounds where they were built (shadow rays: `culled`), which computed
    /// `hit_point_within` of the same arguments, so the same hit record. One copy of the rest
    /// of `make_hit` for both cases. Its callers test `OFFS` first, so that Cortex-M, where it
    /// is 0, compiles the plain `eye_hit` alone.
    #[inline]
    pub(super) fn kept_hit(
        &self,
        ray: &Ray,
        t: f32,
        s: usize,
        slot: usize,
        cull: &Cull<S, L>,
    ) -> Option<Hit> {
        let (k, sphere, near) = self.eye_record(s)?;
        // Within near2 (`near`) the offset is `f + t·d`, cheaper to redo than to keep
        // (`hit_points_lanes` does not store it there).
        let offset = match cull.hits.o.get(slot) {
            Some(&offset) if cull.shadow.culled && !near => offset,
            _ => hit_point_near(ray, t, k.f, sphere, near).1,
        };
        Some(hit_from_offset(
            ray.dir,
            t,
            s,
            sphere,
            offset,
            ray.origin,
            Vec3::ZERO,
        ))
    }
}

/// Whether a root `t` on `sphere`, at most the closest so far (`best`, on `on`), takes its
/// place: the closest hit of scene order, where equal roots go to the greater index, whatever
/// order the spheres come in (hosts sort a tile's spheres at its first deep pile,
/// `Frame::sort_piles`).
#[cfg(lanes)]
#[inline(always)]
pub(super) fn wins(t: f32, sphere: SphereId, best: f32, on: SphereId) -> bool {
    t < best || on == SphereId::NONE || sphere.index() > on.index()
}
