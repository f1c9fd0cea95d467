//! Primary rays over a span: the closest hit of each pixel's ray among the span's candidates,
//! scalar or four columns at a time, and the hit records built from what the span kept.

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
    /// spheres of `cands` (in scene order) whose box holds that column (the row is the
    /// caller's). Inlined in [`Frame::gather`]'s pixel loop where spans cannot keep every view
    /// direction (soft-float Arm; elsewhere [`Frame::trace_span`] finds the same hits sphere by
    /// sphere); the other callers share [`Frame::primary_hit_among`].
    #[inline]
    pub(super) fn primary_among(&self, ray: &Ray, i: u32, cands: &[u16]) -> Option<(f32, usize)> {
        let mut best: Option<(f32, usize)> = None;
        let mut tmax = f32::INFINITY;
        for &s in cands {
            let s = s as usize;
            let (Some(b), Some(k)) = (self.tables.boxes.get(s), self.tables.eye.get(s)) else {
                continue;
            };
            if i < b.i0 as u32 || i > b.i1 as u32 {
                continue;
            }
            if let Some(t) = k.hit(ray.dir, T_EPS, tmax) {
                tmax = t;
                best = Some((t, s));
            }
        }
        best
    }

    /// [`Frame::primary_among`] as a hit record. Out of line: one copy for the callers off
    /// the hot path (several samples per pixel, no shadow rays, single pixels).
    #[inline(never)]
    pub(super) fn primary_hit_among(&self, ray: &Ray, i: u32, cands: &[u16]) -> Option<Hit> {
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
        let offset = match cull.hit_o.get(slot) {
            Some(&offset) if cull.culled && !near => offset,
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

    /// The closest primary hits of the span's pixels `i0..i1` for one sample (`ox`, row
    /// coordinate `y`) into the slots `base..`: view directions in `hit_d`, `(t, sphere)` in
    /// `hit_t`/`hit_s` (`NONE`: a miss). Sphere by sphere in scene order, each over the columns of
    /// its box: every pixel sees its candidates in the order and with the `tmax` of
    /// [`Frame::primary_among`], so the hits are its hits, bit for bit, while a sphere's
    /// constants and box stay in registers across its columns.
    #[inline]
    pub(super) fn trace_span(
        &self,
        i0: u32,
        i1: u32,
        ox: f32,
        (row, y): (u32, f32),
        base: usize,
        cull: &mut Cull<S, L>,
    ) {
        // Hosts with f32 vector registers: `LANES` columns at a time, and with shadow rays the
        // hit points for the span's bounds too.
        #[cfg(lanes)]
        {
            const PAD: usize = SPAN + crate::geometry::LANES - 1;
            let len = (i1 - i0) as usize;
            let [dx, dy, dz] = &mut cull.hit_dc;
            fn lanes<const N: usize>(a: &mut [f32; DPAD], base: usize) -> Option<&mut [f32; N]> {
                a.get_mut(base..base + N)?.try_into().ok()
            }
            let (Some(ts), Some(ss), Some(ps), Some(os)) = (
                cull.hit_t.get_mut(base..base + len),
                cull.hit_s.get_mut(base..base + len),
                cull.hit_p.get_mut(base..base + len),
                cull.hit_o.get_mut(base..base + len),
            ) else {
                return;
            };
            let (Some(dx), Some(dy), Some(dz)) = (
                lanes::<PAD>(dx, base),
                lanes::<PAD>(dy, base),
                lanes::<PAD>(dz, base),
            ) else {
                return;
            };
            let points = self.shadow_rays.then_some((ps, os));
            self.trace_lanes(
                [dx, dy, dz],
                ts,
                ss,
                points,
                &cull.span,
                (i0, i1, ox, y, row),
            );
        }
        #[cfg(not(lanes))]
        {
            // One row at a time on Cortex-M: the row's spheres are the span's.
            let _ = row;
            self.trace_scalar(i0, i1, ox, y, base, cull);
        }
    }

    /// `trace_span` one column at a time.
    #[cfg(not(lanes))]
    #[inline(always)]
    pub(super) fn trace_scalar(
        &self,
        i0: u32,
        i1: u32,
        ox: f32,
        y: f32,
        base: usize,
        cull: &mut Cull<S, L>,
    ) {
        let len = (i1 - i0) as usize;
        let (Some(dirs), Some(ts), Some(ss)) = (
            cull.hit_d.get_mut(base..base + len),
            cull.hit_t.get_mut(base..base + len),
            cull.hit_s.get_mut(base..base + len),
        ) else {
            return;
        };
        let row = self.camera.row(y);
        // The column `i as f32`, counted in f32: exact below 2²⁴ (image sizes are u16).
        let mut column = i0 as f32;
        for ((d, t), s) in dirs.iter_mut().zip(ts.iter_mut()).zip(ss.iter_mut()) {
            // `primary_ray(i, j, sx, sy, n)`, the same bits.
            *d = row.ray(column + ox).dir;
            // No limit yet, finite for `hit_outside` (any root is finite).
            *t = f32::MAX;
            *s = NONE;
            column += 1.0;
        }
        for &sphere in &cull.span {
            let (Some(b), Some(k)) = (
                self.tables.boxes.get(sphere as usize),
                self.tables.eye.get(sphere as usize),
            ) else {
                continue;
            };
            // The box's columns within the span (the span list holds only boxes that meet it).
            let lo = (b.i0 as u32).max(i0) - i0;
            let hi = (b.i1 as u32 + 1).min(i1).saturating_sub(i0);
            let (Some(dirs), Some(ts), Some(ss)) = (
                dirs.get(lo as usize..hi as usize),
                ts.get_mut(lo as usize..hi as usize),
                ss.get_mut(lo as usize..hi as usize),
            ) else {
                continue;
            };
            // The eye outside the sphere, as for most: decided once per box, not per ray.
            let outside = OUTSIDE_TEST && k.outside();
            for ((d, t), s) in dirs.iter().zip(ts.iter_mut()).zip(ss.iter_mut()) {
                let hit = if outside {
                    k.hit_outside(*d, T_EPS, *t)
                } else {
                    k.hit(*d, T_EPS, *t)
                };
                if let Some(hit) = hit {
                    *t = hit;
                    *s = sphere;
                }
            }
        }
    }

    /// `trace_span` `LANES` columns at a time: the view directions
    /// ([`Camera::directions4`]) and the sphere loop ([`Prepared::hit_lanes`]), the same
    /// operations and tests in the same order, so the same directions and hits. The directions
    /// go to the span's arrays by coordinate (`Cull::hit_dc`), padded to whole lanes: their
    /// lanes past the span hold whatever they held, which only lanes that are not the span's
    /// read.
    #[cfg(lanes)]
    #[inline(always)]
    pub(super) fn trace_lanes<const PAD: usize>(
        &self,
        [dx, dy, dz]: [&mut [f32; PAD]; 3],
        ts: &mut [f32],
        ss: &mut [u16],
        points: Option<(&mut [Vec3], &mut [Vec3])>,
        span: &[u16],
        (i0, i1, ox, y, row): (u32, u32, f32, f32, u32),
    ) {
        use crate::geometry::LANES;
        use crate::math::finite;
        use crate::simd::F;
        let (mut t, mut sp) = ([f32::INFINITY; PAD], [NONE; PAD]);
        let len = ts.len().min(SPAN);
        let lane = F::from(core::array::from_fn(|l| l as f32));
        for m in (0..len).step_by(LANES) {
            // `primary_ray(i, j, sx, sy, n)`: pixel column i at `i + ox`. Columns (below
            // `MAX_SIZE` + `LANES`) are exact in f32, so the lanes' `(i0 + m) + l` is each
            // column converted, in one conversion instead of four.
            let x = F::splat((i0 + m as u32) as f32) + lane;
            let x = (x + F::splat(ox)).to_array();
            let [x, y, z] = self.camera.directions4(x, y);
            let lanes = m..m + LANES;
            if let (Some(a), Some(b), Some(c)) = (
                dx.get_mut(lanes.clone()),
                dy.get_mut(lanes.clone()),
                dz.get_mut(lanes),
            ) {
                a.copy_from_slice(&x);
                b.copy_from_slice(&y);
                c.copy_from_slice(&z);
            }
        }
        for &sphere in span {
            let (Some(b), Some(k)) = (
                self.tables.boxes.get(sphere as usize),
                self.tables.eye.get(sphere as usize),
            ) else {
                continue;
            };
            // A tile's span lists the spheres of all its rows; the box holds every hit.
            if !b.has_row(row) {
                continue;
            }
            let lo = ((b.i0 as u32).max(i0) - i0) as usize;
            let hi = ((b.i1 as u32 + 1).min(i1).saturating_sub(i0) as usize).min(SPAN);
            if !finite(k.c) {
                // Overflowing constants: the scalar path, whose scaled roots handle them.
                for m in lo..hi {
                    let d = Vec3::new(dx[m], dy[m], dz[m]);
                    if let Some(hit) = k.hit(d, T_EPS, t[m]) {
                        (t[m], sp[m]) = (hit, sphere);
                    }
                }
                continue;
            }
            let hb = k.hearn_baker();
            let mut m = lo;
            while m < hi {
                let lanes = |a: &[f32; PAD]| -> [f32; LANES] {
                    core::array::from_fn(|l| a.get(m + l).copied().unwrap_or(0.0))
                };
                let (x, y, z, tm) = (lanes(dx), lanes(dy), lanes(dz), lanes(&t));
                let h = k.hit_lanes(hb, x, y, z, T_EPS, tm);
                // Lanes past the box's last column are not its to change.
                let valid = if hi - m >= LANES {
                    (1 << LANES) - 1
                } else {
                    (1u32 << (hi - m)) - 1
                };
                let (hit, redo) = (h.hit & valid, h.redo & valid);
                for l in 0..LANES {
                    if hit & (1 << l) != 0 {
                        if let (Some(tt), Some(ss)) = (t.get_mut(m + l), sp.get_mut(m + l)) {
                            (*tt, *ss) = (h.t[l], sphere);
                        }
                    }
                }
                if redo != 0 {
                    for l in 0..LANES {
                        if redo & (1 << l) != 0 {
                            let q = m + l;
                            let d = Vec3::new(dx[q], dy[q], dz[q]);
                            if let Some(hit) = k.hit(d, T_EPS, t[q]) {
                                (t[q], sp[q]) = (hit, sphere);
                            }
                        }
                    }
                }
                m += LANES;
            }
        }
        for (k, (tt, s)) in ts.iter_mut().zip(ss.iter_mut()).enumerate().take(SPAN) {
            (*tt, *s) = (t[k], sp[k]);
        }
        if let Some((ps, os)) = points {
            self.hit_points_lanes(ps, os, (dx, dy, dz), &t, &sp);
        }
    }

    /// `hit_point_within` of every hit of a span (its point and offset, as `make_hit` and the
    /// span's bounds compute them) into `ps` and `os`: four at a time where four neighbouring
    /// columns hit one sphere on `f + t·d`'s side of `near2` (the same operations lane by lane,
    /// so the same bits; the offset, `f + t·d`, is not stored there), else one by one.
    #[cfg(lanes)]
    #[inline(always)]
    pub(super) fn hit_points_lanes<const PAD: usize>(
        &self,
        ps: &mut [Vec3],
        os: &mut [Vec3],
        (dx, dy, dz): (&[f32; PAD], &[f32; PAD], &[f32; PAD]),
        t: &[f32; PAD],
        sp: &[u16; PAD],
    ) {
        use crate::geometry::{hit_point_far4, LANES};
        use wide::f32x4 as F;
        let eye = self.camera.eye();
        let spheres = self.scene.spheres();
        let one = |m: usize, ps: &mut [Vec3], os: &mut [Vec3]| {
            let s = sp[m] as usize;
            if let (Some(k), Some(sphere), Some(p), Some(o)) = (
                self.tables.eye.get(s),
                spheres.get(s),
                ps.get_mut(m),
                os.get_mut(m),
            ) {
                let ray = Ray::new(eye, Vec3::new(dx[m], dy[m], dz[m]));
                (*p, *o) = hit_point_near(&ray, t[m], k.f, sphere, self.offset_near(s));
            }
        };
        let len = ps.len().min(os.len());
        let mut m = 0;
        while m < len {
            let s = sp[m];
            let whole = m + LANES <= len && sp[m..m + LANES].iter().all(|&x| x == s);
            let near = whole && self.offset_near(s as usize);
            // Four hits on one sphere beyond `near2`: `hit_point_far` lane by lane.
            if whole && !near {
                if let (Some(k), Some(sphere)) =
                    (self.tables.eye.get(s as usize), spheres.get(s as usize))
                {
                    let lanes = |a: &[f32; PAD]| {
                        F::from(core::array::from_fn::<f32, LANES, _>(|l| a[m + l]))
                    };
                    let d = crate::simd::V {
                        x: lanes(dx),
                        y: lanes(dy),
                        z: lanes(dz),
                    };
                    if let Some((p, o)) = hit_point_far4(d, lanes(t), k.f, sphere) {
                        for l in 0..LANES {
                            if let (Some(pp), Some(oo)) = (ps.get_mut(m + l), os.get_mut(m + l)) {
                                (*pp, *oo) = (p.lane(l), o.lane(l));
                            }
                        }
                        m += LANES;
                        continue;
                    }
                }
            }
            if !near {
                let end = if whole { m + LANES } else { m + 1 };
                for (q, &sq) in sp.iter().enumerate().take(end.min(len)).skip(m) {
                    if sq != NONE {
                        one(q, ps, os);
                    }
                }
                m = end;
                continue;
            }
            let lanes =
                |a: &[f32; PAD]| F::from(core::array::from_fn::<f32, LANES, _>(|l| a[m + l]));
            let (x, y, z, tt) = (lanes(dx), lanes(dy), lanes(dz), lanes(t));
            // `ray.at(t)` = eye + d·t and `f + d·t`, coordinate by coordinate.
            let (px, py, pz) = (
                F::splat(eye.x) + x * tt,
                F::splat(eye.y) + y * tt,
                F::splat(eye.z) + z * tt,
            );
            // The offsets, `f + t·d`, are left out: shading redoes them where it needs them
            // (`kept_hit`, `shade4`), which costs less than storing them by point.
            let (px, py, pz) = (px.to_array(), py.to_array(), pz.to_array());
            for l in 0..LANES {
                if let Some(p) = ps.get_mut(m + l) {
                    *p = Vec3::new(px[l], py[l], pz[l]);
                }
            }
            m += LANES;
        }
    }
}
