//! A span's primary rays in lanes (`cfg(lanes)`): `scalar.rs`'s `trace_span`, four columns at
//! a time, the same hits bit for bit, and the hit points of the span's bounds. A deep pile of
//! spheres comes nearest first (`Frame::sort_piles`), and the loops here give an equal root to
//! the greater index, so that any order finds the brute-force hits.

use super::*;

impl<'a, const S: usize, const L: usize> Frame<'a, S, L> {
    /// `scalar.rs`'s `trace_span`, the same hits, `LANES` columns at a time ([`Frame::trace_lanes`]),
    /// and with shadow rays the hit points for the span's bounds too.
    #[inline]
    pub(in crate::render) fn trace_span(
        &self,
        i0: u32,
        i1: u32,
        ox: f32,
        (row, y): (u32, f32),
        base: usize,
        cull: &mut Cull<S, L>,
    ) {
        const PAD: usize = SPAN + crate::geometry::LANES - 1;
        let len = (i1 - i0) as usize;
        let [dx, dy, dz] = &mut cull.hits.path.hit_dc;
        fn lanes<const N: usize>(a: &mut [f32; DPAD], base: usize) -> Option<&mut [f32; N]> {
            a.get_mut(base..base + N)?.try_into().ok()
        }
        let (Some(ts), Some(ss), Some(ps), Some(os)) = (
            cull.hits.t.get_mut(base..base + len),
            cull.hits.s.get_mut(base..base + len),
            cull.hits.p.get_mut(base..base + len),
            cull.hits.o.get_mut(base..base + len),
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
        let span = &cull.spheres.span;
        let at = (i0, i1, ox, y, row);
        // A sorted tile's spans are out of scene order: the pile's tie rule for all of them.
        if span.len() > DEEP || cull.spheres.sorted {
            self.trace_lanes::<PAD, true>([dx, dy, dz], ts, ss, points, span, at);
        } else {
            self.trace_lanes::<PAD, false>([dx, dy, dz], ts, ss, points, span, at);
        }
    }

    /// `trace_span` `LANES` columns at a time: the view directions
    /// ([`Camera::directions4`]) and the sphere loop ([`Prepared::hit_lanes`]), the same
    /// operations and tests in the same order, so the same directions and hits. The directions
    /// go to the span's arrays by coordinate (`Cull::hit_dc`), padded to whole lanes: their
    /// lanes past the span hold whatever they held, which only lanes that are not the span's
    /// read.
    ///
    /// `PILE` (spans that meet more than [`DEEP`] boxes, a deep pile of spheres, and every span
    /// of a tile sorted for one, `Cull::spheres.sorted`): a group of lanes skips a sphere whose
    /// every root lies beyond the lanes' closest hits so far, which the test would reject
    /// (a hit needs its root at or before them). In a pile of spheres most lie behind the
    /// first few hits. The pile comes nearest first (`Frame::sort_piles`), so the row stops at
    /// the first sphere that every lane skips: the ones after it lie further still. Out of
    /// scene order, a root equal to a lane's closest is kept only from a sphere of a greater
    /// index: the closest hit of scene order, whose later spheres win ties.
    #[inline(always)]
    pub(super) fn trace_lanes<const PAD: usize, const PILE: bool>(
        &self,
        [dx, dy, dz]: [&mut [f32; PAD]; 3],
        ts: &mut [f32],
        ss: &mut [SphereId],
        points: Option<(&mut [Vec3], &mut [Vec3])>,
        span: &[SphereId],
        (i0, i1, ox, y, row): (u32, u32, f32, f32, u32),
    ) {
        use crate::geometry::LANES;
        use crate::math::finite;
        use crate::simd::F;
        let (mut t, mut sp) = ([f32::INFINITY; PAD], [SphereId::NONE; PAD]);
        let len = ts.len().min(SPAN);
        let lane = F::from(core::array::from_fn(|l| l as f32));
        // The longest direction's squared length (`PILE`).
        let mut dd = F::splat(0.0);
        for m in (0..len).step_by(LANES) {
            // `primary_ray(i, j, sx, sy, n)`: pixel column i at `i + ox`. Columns (below
            // `MAX_SIZE` + `LANES`) are exact in f32, so the lanes' `(i0 + m) + l` is each
            // column converted, in one conversion instead of four.
            let x = F::splat((i0 + m as u32) as f32) + lane;
            let x = (x + F::splat(ox)).to_array();
            let [x, y, z] = self.camera.directions4(x, y);
            if PILE {
                let (a, b, c) = (F::from(x), F::from(y), F::from(z));
                dd = dd.max(a * a + b * b + c * c);
            }
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
        let d_max = if PILE {
            libm::sqrtf(
                dd.to_array()
                    .iter()
                    .fold(0.0, |a: f32, &b| if b > a { b } else { a }),
            )
        } else {
            0.0
        };
        for &sphere in span {
            let (Some(b), Some(k)) = (
                self.tables.boxes.get(sphere.index()),
                self.tables.eye.get(sphere.index()),
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
                        if !PILE || wins(hit, sphere, t[m], sp[m]) {
                            (t[m], sp[m]) = (hit, sphere);
                        }
                    }
                }
                continue;
            }
            let hb = k.hearn_baker();
            // `pile_key` over `d_max`: at or below every root (see `nearest_root`), and in
            // the pile's order, as the division by one positive number keeps it.
            let near = if PILE {
                self.tables.pile.get(sphere.index()).copied().unwrap_or(0.0) / d_max
            } else {
                0.0
            };
            // `Frame::sort_piles` ordered the pile nearest first.
            if PILE {
                let last = t.get(..len).unwrap_or(&[]);
                if last.iter().all(|&tl| near > tl) {
                    break;
                }
            }
            let mut m = lo;
            while m < hi {
                let lanes = |a: &[f32; PAD]| -> [f32; LANES] {
                    core::array::from_fn(|l| a.get(m + l).copied().unwrap_or(0.0))
                };
                let (x, y, z, tm) = (lanes(dx), lanes(dy), lanes(dz), lanes(&t));
                if PILE && near > tm.iter().fold(0.0, |a: f32, &b| if b > a { b } else { a }) {
                    m += LANES;
                    continue;
                }
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
                            if !PILE || wins(h.t[l], sphere, *tt, *ss) {
                                (*tt, *ss) = (h.t[l], sphere);
                            }
                        }
                    }
                }
                if redo != 0 {
                    for l in 0..LANES {
                        if redo & (1 << l) != 0 {
                            let q = m + l;
                            let d = Vec3::new(dx[q], dy[q], dz[q]);
                            if let Some(hit) = k.hit(d, T_EPS, t[q]) {
                                if !PILE || wins(hit, sphere, t[q], sp[q]) {
                                    (t[q], sp[q]) = (hit, sphere);
                                }
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
    #[inline(always)]
    pub(super) fn hit_points_lanes<const PAD: usize>(
        &self,
        ps: &mut [Vec3],
        os: &mut [Vec3],
        (dx, dy, dz): (&[f32; PAD], &[f32; PAD], &[f32; PAD]),
        t: &[f32; PAD],
        sp: &[SphereId; PAD],
    ) {
        use crate::geometry::{hit_point_far4, LANES};
        use crate::simd::F;
        let eye = self.camera.eye();
        let spheres = self.scene.spheres();
        let one = |m: usize, ps: &mut [Vec3], os: &mut [Vec3]| {
            let s = sp[m].index();
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
        let (mut queue, mut queued) = ([0usize; LANES], 0);
        let len = ps.len().min(os.len());
        let mut m = 0;
        while m < len {
            let s = sp[m];
            let whole = m + LANES <= len && sp[m..m + LANES].iter().all(|&x| x == s);
            let near = whole && self.offset_near(s.index());
            // Four hits on one sphere beyond `near2`: `hit_point_far` lane by lane.
            if whole && !near {
                if let (Some(k), Some(sphere)) =
                    (self.tables.eye.get(s.index()), spheres.get(s.index()))
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
                    if sq == SphereId::NONE {
                        continue;
                    }
                    if self.offset_near(sq.index()) {
                        one(q, ps, os);
                        continue;
                    }
                    if let Some(slot) = queue.get_mut(queued) {
                        *slot = q;
                        queued += 1;
                    }
                    if queued == LANES {
                        self.far_points_lanes(queue, LANES, (ps, os), (dx, dy, dz), t, sp);
                        queued = 0;
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
        if queued > 0 {
            self.far_points_lanes(queue, queued, (ps, os), (dx, dy, dz), t, sp);
        }
    }

    /// The points and offsets of far hits of several spheres, the slots `q[..n]`, four a pass
    /// ([`hit_point_far_lanes`](crate::geometry::hit_point_far_lanes)), each lane its own
    /// sphere: the slots of a span's small far spheres seldom come four to a sphere. Lanes past
    /// `n` repeat the first, computed and not stored; a lane left out takes the scalar call.
    /// Out of line: the span's hot loop stays as small as it was.
    #[inline(never)]
    fn far_points_lanes<const PAD: usize>(
        &self,
        q: [usize; crate::geometry::LANES],
        n: usize,
        (ps, os): (&mut [Vec3], &mut [Vec3]),
        (dx, dy, dz): (&[f32; PAD], &[f32; PAD], &[f32; PAD]),
        t: &[f32; PAD],
        sp: &[SphereId; PAD],
    ) {
        use crate::geometry::{hit_point_far_lanes, LANES};
        use crate::simd::{F, V};
        let spheres = self.scene.spheres();
        let at = |l: usize| q[if l < n { l } else { 0 }];
        let lane = |l: usize| {
            let m = at(l);
            let s = sp.get(m).map_or(usize::MAX, |s| s.index());
            let k = self.tables.eye.get(s).zip(spheres.get(s));
            (m, k)
        };
        let lanes: [_; LANES] = core::array::from_fn(lane);
        let of = |l: usize| {
            let (m, k) = lanes[l];
            let d = Vec3::new(dx[m], dy[m], dz[m]);
            match k {
                Some((k, sphere)) => (d, t[m], k.f, sphere.center, sphere.radius),
                None => (d, t[m], Vec3::ZERO, Vec3::ZERO, 1.0),
            }
        };
        let ls: [_; LANES] = core::array::from_fn(of);
        let (p, o, finite) = hit_point_far_lanes(
            V::from_lanes(ls.map(|l| l.0)),
            F::from(ls.map(|l| l.1)),
            V::from_lanes(ls.map(|l| l.2)),
            V::from_lanes(ls.map(|l| l.3)),
            F::from(ls.map(|l| l.4)),
        );
        for (l, &(m, k)) in lanes.iter().enumerate().take(n) {
            let (Some((k, sphere)), Some(pp), Some(oo)) = (k, ps.get_mut(m), os.get_mut(m)) else {
                continue;
            };
            (*pp, *oo) = if finite & (1 << l) != 0 {
                (p.lane(l), o.lane(l))
            } else {
                // `hit_point_far`'s fallback.
                let ray = Ray::new(self.camera.eye(), Vec3::new(dx[m], dy[m], dz[m]));
                hit_point_near(&ray, t[m], k.f, sphere, false)
            };
        }
    }
}

/// A lower bound on every root of a primary ray with a direction no longer than `d_max` on
/// the sphere of the eye's constants `k`: the distance to the sphere over `d_max`, `|f| − r`
/// written as `c / (|f| + r)` (`c = |f|² − r²` is accurate where the difference cancels, an
/// eye near the surface), and shrunk by 2⁻¹⁰, far beyond the roots' rounding (a few ulp; a
/// grazing root's larger error is about a root near `√(|f|² − r²)`, well past the bound).
/// Zero, which bounds nothing, for an eye inside or on the sphere, and where the constants
/// overflow (NaN).
#[inline(always)]
pub(in crate::render) fn nearest_root(k: &crate::Prepared, d_max: f32) -> f32 {
    let near = k.c / ((libm::sqrtf(k.f.dot(k.f)) + k.r) * d_max) * (1.0 - 1.0 / 1024.0);
    if near > 0.0 {
        near
    } else {
        0.0
    }
}

/// [`nearest_root`] of a direction of length 1, the order of a sorted pile
/// ([`Frame::sort_piles`]; `FrameStorage` keeps it per sphere): zero where the sphere's
/// constants overflow, which the trace tests apart and must not pass by.
#[inline(always)]
pub(in crate::render) fn pile_key(k: &crate::Prepared) -> f32 {
    if crate::math::finite(k.c) {
        nearest_root(k, 1.0)
    } else {
        0.0
    }
}
