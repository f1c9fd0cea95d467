//! The span culling: the span's primary hits grouped by sphere and bounded, and for each group
//! and light the spheres that can block a shadow ray from it.

use super::*;

impl<'a, const S: usize, const L: usize> Frame<'a, S, L> {
    /// Joins the span's hits in `slots` (column `i0` first, sample offset `ox`, all along
    /// `row`) to their groups' bounds run by run, where the span keeps no hit points
    /// (Cortex-M): a run of hits on one sphere as the box of the row's ray fan over the run's
    /// columns and range of `t` (`RowRays::fan_box`, the range found in one tight loop), or for
    /// a sphere beyond near2 as the sphere's box (`hit_point_far` puts those points on the
    /// sphere, not at `eye + t·d`, which is off where a grazing ray's `t` is ill-conditioned).
    /// One box and one join a run, not a point and a join a pixel.
    #[inline(always)]
    pub(super) fn bound_runs(
        &self,
        row: &crate::camera::RowRays,
        (i0, ox): (u32, f32),
        slots: core::ops::Range<usize>,
        cull: &mut Cull<S, L>,
        bounds: &mut Bounds,
    ) {
        let mut slot = slots.start;
        while slot < slots.end {
            let Some((t, s)) = cull.hit(slot) else {
                slot += 1;
                continue;
            };
            // The run's least and greatest `t` by their bits: a hit's `t` is positive (at least
            // `T_EPS`), where the bits order as the values do (M4F: integer compares, no
            // moves to and from the FPU's flags).
            let (mut t0, mut t1, mut next) = (t.to_bits(), t.to_bits(), slot + 1);
            if let (Some(ss), Some(ts)) =
                (cull.hits.s.get(..slots.end), cull.hits.t.get(..slots.end))
            {
                while let (Some(&s2), Some(&t)) = (ss.get(next), ts.get(next)) {
                    if s2 != s {
                        break;
                    }
                    let t = t.to_bits();
                    if t < t0 {
                        t0 = t;
                    }
                    if t > t1 {
                        t1 = t;
                    }
                    next += 1;
                }
            }
            let (t0, t1) = (f32::from_bits(t0), f32::from_bits(t1));
            let s = s.index();
            let join = if self.offset_near(s) {
                // `column` is monotonic: the run's ends have its least and greatest.
                let x = |k: usize| (i0 + (k - slots.start) as u32) as f32 + ox;
                let columns = (row.column(x(slot)), row.column(x(next - 1)));
                Some(row.fan_box((t0, t1), columns))
            } else {
                self.scene.spheres().get(s).map(|sp| {
                    let r = Vec3::splat(sp.radius);
                    (sp.center - r, sp.center + r)
                })
            };
            if let Some(join) = join {
                let g = bounds.join::<false>(s, join);
                cull.set_group(slot..next, g);
            }
            slot = next;
        }
    }

    /// Gathers the span `[span_start, span_end)` of row `j`: its spheres from the row's, then
    /// (with shadow rays, or one sample a pixel) its primary hits, and with shadow rays the
    /// ball bounding their points and each light's possible blockers.
    #[inline(never)]
    pub(super) fn gather(&self, j: u32, cull: &mut Cull<S, L>) {
        let i0 = cull.span_start;
        self.span_spheres(cull);
        self.narrow_span(cull);
        let i1 = cull.span_end;
        cull.shadow.culled = false;
        cull.hits.kept = Kept::Nothing;
        // No group until this span's: `lists` finds none where the span builds no lists.
        cull.shadow.groups = [SphereId::NONE; GROUPS];
        // Without shadow rays the span needs no bounds, but with one sample a pixel its hits
        // are still traced here, in one tight loop over the span, and kept for shading.
        let kept = (self.samples * self.samples) as usize <= KEPT;
        if !self.shadow_rays && !kept {
            return;
        }
        // The span's primary hits (kept for shading when one sample per pixel), grouped by
        // the sphere hit (a sphere and the wall behind it make poor company in one bound),
        // and the box of each group's points.
        let mut bounds = Bounds::new();
        // Slots whose hit joins no group (a miss, or no point) get no lists: every sphere.
        cull.hits.g.fill(NO_GROUP);
        if self.samples == 1 && cull.spheres.span.is_empty() {
            // No sphere's box meets the span (the sky above the scene): every ray misses, and
            // none needs building.
            cull.hits.s.fill(SphereId::NONE);
            cull.hits.kept = Kept::Pixels;
        } else {
            // Every sample's hit joins the bounds; the hits are also kept for shading where
            // there is room (`KEPT`), the samples outermost so that their offsets (the divides
            // of `Camera::primary_ray`) are hoisted.
            let n = self.samples;
            // Rows of a tile (hosts, one sample a pixel), or the samples of one row.
            for rs in 0..cull.rows() * n {
                // (Several rows come with one sample a pixel only; Cortex-M has one row.)
                let (r, sy) = if cull.rows() == 1 { (0, rs) } else { (rs, 0) };
                let y = (j + r) as f32 + sample_offset(sy, n);
                for sx in 0..n {
                    let ox = sample_offset(sx, n);
                    // The sample's slots (see `KEPT`), or the row's.
                    let base = if KEPT > 1 {
                        (r * n * n + sy * n + sx) as usize * SPAN
                    } else {
                        0
                    };
                    if SPHERE_MAJOR {
                        // Scratch slots where this sample's hits are not kept.
                        let base = if kept { base } else { 0 };
                        self.trace_span(i0, i1, ox, (j + r, y), base, cull);
                        if self.shadow_rays && KEEPS_OFFSETS {
                            // The points `trace_span` computed with its hits (`cfg(lanes)`), four
                            // at a time where four neighbours hit one sphere: their box, in
                            // registers, joins the group once.
                            let end = base + (i1 - i0) as usize;
                            let mut slot = base;
                            while slot < end {
                                let four = (slot + 4 <= end)
                                    .then(|| {
                                        let s = cull.hits.s.get(slot..slot + 4)?;
                                        let p = cull.hits.p.get(slot..slot + 4)?;
                                        let same =
                                            s[0] != SphereId::NONE && s.iter().all(|&x| x == s[0]);
                                        same.then(|| (s[0], box4(p)))
                                    })
                                    .flatten();
                                if let Some((s, b)) = four {
                                    cull.set_group(
                                        slot..slot + 4,
                                        bounds.join::<true>(s.index(), b),
                                    );
                                    slot += 4;
                                    continue;
                                }
                                if let (Some((_, s)), Some(&p)) =
                                    (cull.hit(slot), cull.hits.p.get(slot))
                                {
                                    cull.set_group(
                                        slot..slot + 1,
                                        bounds.join::<true>(s.index(), (p, p)),
                                    );
                                }
                                slot += 1;
                            }
                        } else if self.shadow_rays {
                            let row = self.camera.row(y);
                            let slots = base..base + (i1 - i0) as usize;
                            self.bound_runs(&row, (i0, ox), slots, cull, &mut bounds);
                        }
                        continue;
                    }
                    // Pixel by pixel (soft-float Arm, see `SPHERE_MAJOR`).
                    let row = self.camera.row(y);
                    for (k, i) in (i0..i1).enumerate() {
                        let slot = base + k;
                        // `primary_ray(i, j, sx, sy, n)`, the same bits.
                        let ray = row.ray(i as f32 + ox);
                        let h = self.primary_among(&ray, i, &cull.spheres.span);
                        if h.is_some() {
                            // Only a hit is shaded with its ray.
                            cull.set_dir(slot, ray.dir);
                        }
                        let (t, s) = (cull.hits.t.get_mut(slot), cull.hits.s.get_mut(slot));
                        if let (Some(t), Some(s)) = (t, s) {
                            (*t, *s) =
                                h.map_or((0.0, SphereId::NONE), |(t, s)| (t, SphereId::new(s)));
                        }
                    }
                    if self.shadow_rays {
                        let slots = base..base + (i1 - i0) as usize;
                        self.bound_runs(&row, (i0, ox), slots, cull, &mut bounds);
                    }
                }
            }
            cull.hits.kept = if n == 1 {
                Kept::Pixels
            } else if kept {
                Kept::Samples
            } else {
                Kept::Nothing
            };
        }
        if !self.shadow_rays {
            return;
        }
        cull.shadow.culled = true;
        cull.shadow.pool.clear();
        for g in 0..GROUPS {
            let (Some(slot), Some(ranges)) =
                (cull.shadow.groups.get_mut(g), cull.shadow.ranges.get_mut(g))
            else {
                continue;
            };
            let Some(group) = bounds.groups.get(g) else {
                *slot = SphereId::NONE;
                continue;
            };
            *slot = group.sphere;
            let (lo, hi) = (group.lo, group.hi);
            let q = (lo + hi) * 0.5;
            let half = (hi - lo) * 0.5;
            // Rounding of q and of the length: a relative pad far above it. Shadow rays leave
            // from the hit's `anchor + rel`, not from these points: the two differ by the f32
            // error of the hit offset, ~4ε of the distance from the eye (f32 offsets are kept
            // out to 2048 radii, `scene::near2`), which 2⁻²⁰ of that distance covers. It covers
            // as well the few ε by which a ray fan's box (`bound_runs`) and the rounded points
            // `eye + t·d` it stands for may differ (`camera::fan_tests` checks 2⁻²²).
            let reach = (q - self.camera.eye()).length() + half.length();
            let rho = half.length() * (1.0 + 1e-5)
                + 1e-5 * q.max_abs()
                + reach * (1.0 / 1_048_576.0)
                + f32::MIN_POSITIVE;
            let bounded = rho.is_finite() && q.is_finite();
            // The scene's lights only: the ranges of light slots past them are never asked.
            for (li, (range, light)) in ranges.iter_mut().zip(self.scene.lights()).enumerate() {
                *range = Candidates::ALL;
                if !bounded {
                    continue;
                }
                let start = cull.shadow.pool.len() as u16;
                let spheres = self.scene.spheres();
                let pool = &mut cull.shadow.pool;
                let mut blockers = Blockers::new(light, spheres, (q, rho), group.sphere, pool);
                let band = match self.tables.sweeps.get(li) {
                    Some(w) if Self::SWEEPS => w.band(light, q, rho),
                    _ => None,
                };
                match band {
                    // Only the spheres whose key is near the span's, and the wide ones.
                    Some((sweep, band)) => {
                        // The entries beyond the ball's reach dropped (none where it is NaN).
                        let far = light.far_depth(q, rho);
                        sweep.each::<true>(Band { far, ..band }, &mut blockers);
                    }
                    None => {
                        for s in 0..spheres.len() {
                            // The own sphere, which `one` drops, skipped here too: so the
                            // Cortex-M code at opt "s" is 4 bytes smaller.
                            let s = SphereId::new(s);
                            if s != group.sphere {
                                blockers.one(s);
                            }
                        }
                    }
                }
                let full = blockers.finish();
                if full {
                    // Out of room: this light tests every sphere for this group.
                    cull.shadow.pool.truncate(start as usize);
                } else {
                    // Where lists can be long (a capacity of 8 or less links none of it).
                    if let Some(list) = cull.shadow.pool.get_mut(start as usize..) {
                        if Self::SWEEPS && list.len() > LONG {
                            nearest_first(list, spheres, q, light);
                        }
                    }
                    *range = Candidates::listed(start, cull.shadow.pool.len() as u16);
                }
            }
        }
    }
}

/// The spheres kept as one light's shadow candidates for one hit group, as the sweep or the scan
/// names them, into the span's pool: each render path weighs them its own way (`consider` and
/// `finish` in `lanes/`, four at a time; in `scalar.rs`, one by one as they come).
pub(super) struct Blockers<'c, const S: usize> {
    pub(super) light: &'c Light,
    pub(super) spheres: &'c [crate::Sphere],
    pub(super) q: Vec3,
    pub(super) rho: f32,
    /// The group's own sphere, never listed: the shadow test skips the hit's sphere among its
    /// candidates (it finds the ray's exit from it analytically), so listing it would only
    /// cost a skip per pixel. `SphereId::REST` is no sphere's id (`FITS`).
    pub(super) own: SphereId,
    pub(super) pool: &'c mut List<S>,
    /// The candidates collected so far (hosts; `()` on Cortex-M, never read there).
    #[cfg_attr(not(lanes), allow(dead_code))]
    pub(super) found: Found<S>,
    pub(super) full: bool,
}

impl<'c, const S: usize> Blockers<'c, S> {
    /// For shadow rays towards `light` from the ball `(q, rho)` about the hits on sphere
    /// `own`, appending to `pool`.
    #[inline(always)]
    pub(super) fn new(
        light: &'c Light,
        spheres: &'c [crate::Sphere],
        (q, rho): (Vec3, f32),
        own: SphereId,
        pool: &'c mut List<S>,
    ) -> Self {
        Blockers {
            light,
            spheres,
            q,
            rho,
            own,
            pool,
            found: Default::default(),
            full: false,
        }
    }
}

/// Whether the box `b` meets the columns `i0..i1` (a span's). Its right column is read only
/// where its left one passes, as a literal `&&` would (eager, both loads grew the M4F's
/// `gather` by 300 bytes).
#[inline(always)]
pub(super) fn meets_columns(b: &PixelBox, i0: u32, i1: u32) -> bool {
    (b.i0 as u32) < i1 && b.i1 as u32 >= i0
}

/// The box of four points (a coordinate that is NaN skipped, as `Frame::gather`'s bounds skip
/// it): selections in registers, one group update for four neighbouring hits instead of four.
#[inline(always)]
pub(super) fn box4(p: &[Vec3]) -> (Vec3, Vec3) {
    let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
    for q in p {
        for (k, v) in [q.x, q.y, q.z].into_iter().enumerate() {
            if let (Some(l), Some(h)) = (lo.get_mut(k), hi.get_mut(k)) {
                *l = if v < *l { v } else { *l };
                *h = if v > *h { v } else { *h };
            }
        }
    }
    (Vec3::from(lo), Vec3::from(hi))
}

/// Hit groups per span: hits on up to `GROUPS − 1` spheres get their own bound, the rest share
/// the last. A host's 32×8 tile over many small spheres hits more than three of them, and the
/// shared group's box (and so its shadow candidates) then spans the tile; Cortex-M bounds one
/// row's span, which rarely does, and keeps the smaller `Cull`.
pub(super) const GROUPS: usize = if cfg!(lanes) { 8 } else { 4 };
/// A slot's hit in no group (`Cull::hit_g`).
pub(super) const NO_GROUP: u8 = u8::MAX;

/// The bound of one group's hit points.
#[derive(Debug, Clone, Copy)]
pub(super) struct Group {
    pub(super) sphere: SphereId,
    pub(super) lo: Vec3,
    pub(super) hi: Vec3,
}

impl Group {
    /// Grows the box to hold `[lo, hi]`. Comparisons, not `f32::min`/`max` (calls to
    /// `fminf`/`fmaxf` without an FPU instruction for them); a NaN coordinate is skipped as
    /// `min`/`max` skip it. Each bound is written whatever the outcome, a select (`minss`,
    /// `maxss` on x86) rather than a branch, which points scattered over many small spheres
    /// mispredict.
    #[inline(always)]
    pub(super) fn add_box(&mut self, p_lo: Vec3, p_hi: Vec3) {
        let widen = |l: &mut f32, h: &mut f32, a: f32, b: f32| {
            *l = if a < *l { a } else { *l };
            *h = if b > *h { b } else { *h };
        };
        let (lo, hi) = (&mut self.lo, &mut self.hi);
        widen(&mut lo.x, &mut hi.x, p_lo.x, p_hi.x);
        widen(&mut lo.y, &mut hi.y, p_lo.y, p_hi.y);
        widen(&mut lo.z, &mut hi.z, p_lo.z, p_hi.z);
    }
}

/// A span's hit groups while [`Frame::gather`] collects their bounds.
#[derive(Debug, Clone)]
pub(super) struct Bounds {
    /// The groups in the order they were made, each with its sphere's hits; the last of
    /// `GROUPS` takes every other sphere (`SphereId::REST`). A list, not an array of empty groups:
    /// each span starts with none, and an array's boxes would be written for every span.
    pub(super) groups: heapless::Vec<Group, GROUPS>,
    /// The group of the previous hit's sphere: a sphere keeps its group once it has one, and
    /// neighbouring pixels mostly hit the same sphere.
    pub(super) last: (usize, usize),
}

impl Bounds {
    #[inline(always)]
    pub(super) fn new() -> Self {
        Bounds {
            groups: heapless::Vec::new(),
            last: (usize::MAX, 0),
        }
    }

    /// The box `(lo, hi)` (a point, or several points' box) joins sphere `sphere`'s group,
    /// which it returns. `LAST`: look at the previous join's sphere first (for pixels one by
    /// one; runs of one sphere, `Frame::bound_runs`, follow each other's sphere only after
    /// another sphere's run).
    #[inline(always)]
    pub(super) fn join<const LAST: bool>(&mut self, sphere: usize, (lo, hi): (Vec3, Vec3)) -> u8 {
        let g = if LAST && sphere == self.last.0 {
            self.last.1
        } else {
            // The sphere's group, or else a new one, or the last, which takes every other
            // sphere (`SphereId::REST`).
            let groups = &self.groups;
            let open = groups.len().min(GROUPS - 1);
            let g = (0..open)
                .find(|&k| groups.get(k).is_some_and(|gr| gr.sphere.index() == sphere))
                .unwrap_or(open);
            if LAST {
                self.last = (sphere, g);
            }
            g
        };
        match self.groups.get_mut(g) {
            Some(gr) => gr.add_box(lo, hi),
            // A new group (`g` is the number of groups, below `GROUPS`), whose box is the
            // first. A NaN coordinate stays in it, where `add_box` skips one: the group's
            // lists are then every sphere's (`gather`: not `bounded`), which holds.
            None => {
                let sphere = if g + 1 < GROUPS {
                    SphereId::new(sphere)
                } else {
                    SphereId::REST
                };
                let _ = self.groups.push(Group { sphere, lo, hi });
            }
        }
        g as u8
    }
}

/// Moves the [`NEAREST`] of a group's shadow candidates that lie nearest the shadow ray from the
/// group's centre `q` to `light` to the front of its list (a selection, not a sort), so that a
/// shadowed pixel meets its blocker early: a lit pixel asks every candidate, in any order, a
/// shadowed one stops at the first that blocks. The key is `perp² − r²`, `perp` the distance
/// of the sphere's centre from that ray's line (`|v|² − (v·u)²`, `v` from `q` to the centre,
/// `u` the unit direction to the light): negative for a sphere across the line, which blocks
/// the group's central ray, and the spheres nearest it block its other rays likeliest. The
/// keys are computed once where the list fits [`KEYED`], else at each comparison.
#[inline(never)]
pub(super) fn nearest_first(
    list: &mut [SphereId],
    spheres: &[crate::Sphere],
    q: Vec3,
    light: &Light,
) {
    // The light's own vector towards it from `q`: a new kind of light needs nothing here.
    let u = light
        .to_light(q, Vec3::ZERO)
        .normalized()
        .unwrap_or(Vec3::ZERO);
    let d2 = |s: &SphereId| {
        spheres.get(s.index()).map_or(0.0, |b| {
            let v = b.center - q;
            let along = v.dot(u);
            v.dot(v) - along * along - b.radius * b.radius
        })
    };
    if list.len() <= NEAREST {
        return;
    }
    if list.len() > KEYED {
        list.select_nth_unstable_by(NEAREST - 1, |a, b| d2(a).total_cmp(&d2(b)));
        return;
    }
    let mut keyed: heapless::Vec<(f32, SphereId), KEYED> = heapless::Vec::new();
    for s in list.iter() {
        let _ = keyed.push((d2(s), *s));
    }
    keyed.select_nth_unstable_by(NEAREST - 1, |a, b| a.0.total_cmp(&b.0));
    for (s, &(_, id)) in list.iter_mut().zip(keyed.iter()) {
        *s = id;
    }
}

/// How many candidates [`nearest_first`] moves to the front: two sets of four lanes.
pub(super) const NEAREST: usize = 8;
/// Lists of more candidates than this are ordered by [`nearest_first`]: in a shorter one a
/// shadowed pixel meets its blocker soon enough, and most lists are short.
const LONG: usize = 32;
/// The longest list whose keys [`nearest_first`] keeps on the stack (8 KiB).
pub(super) const KEYED: usize = 1024;
