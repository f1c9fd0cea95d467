//! The host path's shading: a span's stored hits four pixels at a time, in lanes, all on one
//! sphere (four neighbours, or elsewhere four of a sphere's pixels in the span), each lane the
//! scalar shading's operations in the scalar order.

use super::*;

impl<'a, const S: usize, const L: usize> Frame<'a, S, L> {
    /// Shades the span's stored primary hits on spheres that send no secondary ray, four at a
    /// time in lanes ([`shade_model`](crate::shading)): four neighbours on one sphere in one
    /// pass, the other groups of four sphere by sphere ([`Frame::mixed_row`]: at the tile's
    /// first row where the tile is crowded, else now). Into
    /// `cull.hits.path.px`, marking them in `cull.hits.path.done`: the pixels `next_pixel`
    /// would compute one by one, bit for bit (the hit records built lane by lane as `make_hit`
    /// builds them, the shadow tests the scalar ones, asked for the same lanes and lights).
    /// Misses are marked done too (`px` starts as the background); mirrors and glass then take
    /// a pass of their own ([`Frame::shade_span4_secondary`]), and every other pixel is left
    /// to the scalar path.
    #[inline(never)]
    pub(super) fn shade_span4(&self, cull: &mut Cull<S, L>) {
        let len = cull.span_len();
        let (mut done, mut px) = (0u32, [cull.miss; SPAN]);
        // The pixels of groups not all on one sphere, for `shade_mixed`.
        let mut mixed = 0u32;
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
                let (Ok(ts), slots) = (ts.try_into(), [q, q + 1, q + 2, q + 3]) else {
                    break;
                };
                let stored = (slots, ts, [x, y, z]);
                let colour = self.shade4::<true, false>(cull, stored, ss[0].index(), hits);
                keep4(
                    self,
                    &mut px,
                    &mut done,
                    [k0, k0 + 1, k0 + 2, k0 + 3],
                    hits,
                    colour,
                );
            } else {
                mixed |= hits << k0;
            }
        }
        if mixed != 0 {
            self.mixed_row(mixed, &mut px, &mut done, cull);
        }
        cull.hits.path.px = px;
        cull.hits.path.done = done;
        if self.scene.has_secondary() {
            self.shade_span4_secondary(cull);
        }
    }

    /// The colours of the row's pixels `mixed` (bits of the span), in groups of four not all on
    /// one sphere, into `px`, marking them `done`: shaded at the tile's first row where it is
    /// crowded ([`Frame::start_mixed`]), else now, sphere by sphere along the row. Out of line,
    /// so that the common group's code keeps its values in registers.
    #[inline(never)]
    fn mixed_row(&self, mixed: u32, px: &mut [Rgb888; SPAN], done: &mut u32, cull: &Cull<S, L>) {
        let base = cull.slot(0);
        if cull.hits.path.tiled {
            let path = &cull.hits.path;
            let shaded = mixed & path.mixed_done.get(base / SPAN).copied().unwrap_or(0);
            let from = path.mixed_px.get(base..).unwrap_or(&[]);
            for k in crate::simd::ones(shaded) {
                if let (Some(p), Some(&c)) = (px.get_mut(k), from.get(k)) {
                    *p = c;
                }
            }
            *done |= shaded;
            return;
        }
        // Sphere by sphere along the row: four of a sphere's pixels a pass, neighbours first.
        let mut todo = mixed;
        let ss = cull.hits.s.get(base..base + cull.span_len()).unwrap_or(&[]);
        while let Some(&s) = ss.get(todo.trailing_zeros() as usize) {
            let (pixels, n) = same_sphere(ss, todo, s);
            for &k in pixels.iter().take(n) {
                todo &= !(1 << k);
            }
            let active = (1 << n) - 1;
            let Some(stored) = stored4(cull, pixels.map(|k| base + k)) else {
                continue;
            };
            let colour = self.shade4::<false, false>(cull, stored, s.index(), active);
            keep4(self, px, done, pixels, active, colour);
        }
    }

    /// At a tile's first row (`j`): no mixed group shaded yet, and in a crowded tile (a span
    /// that meets more than [`TILED`] spheres' boxes) every row's shaded now, sphere by sphere
    /// across the rows ([`Frame::shade_mixed`]). Elsewhere each row shades its own: there a
    /// sphere shows long runs of pixels, and classing every row's groups twice costs more than
    /// the passes it saves.
    #[inline(always)]
    pub(super) fn start_mixed(&self, j: u32, cull: &mut Cull<S, L>) {
        let path = &mut cull.hits.path;
        path.mixed_done = [0; KEPT];
        path.tiled = cull.spheres.span.len() > TILED;
        if !path.tiled {
            return;
        }
        let (len, rows) = (cull.span_len(), (cull.rows() as usize).min(KEPT));
        let mut todo = [0u32; KEPT];
        for (r, t) in todo.iter_mut().enumerate().take(rows) {
            *t = mixed_groups(cull.hits.s.get(r * SPAN..r * SPAN + len).unwrap_or(&[]));
        }
        self.shade_mixed(j, todo, cull);
    }

    /// The tile's pixels `todo` (per row, bits of the span; the tile's first row is `j`), in
    /// groups of four neighbours not all on one sphere, those that [`Frame::shade_span4`]
    /// leaves, sphere by sphere: four of a sphere's pixels at a time, in one lane pass,
    /// neighbours or not and from any of the tile's rows, into `cull.hits.path.mixed_px`,
    /// marked in `mixed_done`. Where spheres are small, most groups of four neighbours meet two
    /// or three, and a sphere shows a few pixels in each of a few rows: a pass per sphere in
    /// each group, or in each row, shaded few lanes (spread16384: 2.3 lanes a pass by rows, 3.3
    /// across them).
    #[inline(never)]
    pub(super) fn shade_mixed(&self, j: u32, mut todo: [u32; KEPT], cull: &mut Cull<S, L>) {
        let (rows, i0) = ((cull.rows() as usize).min(KEPT), cull.span_start);
        // Every pixel of one sphere, by slot, four to a pass: a sphere's pixels lie in its
        // box, so only the box's columns of its rows are searched, once per sphere.
        let mut mine = [0u16; SPAN * KEPT];
        let mut r0 = 0;
        while r0 < rows {
            let Some(&first) = todo.get(r0) else { break };
            if first == 0 {
                r0 += 1;
                continue;
            }
            let slot0 = r0 * SPAN + first.trailing_zeros() as usize;
            let Some(&s) = cull.hits.s.get(slot0) else {
                break;
            };
            let (cols, last) = match self.tables.boxes.get(s.index()) {
                Some(b) => {
                    let lo = (b.i0 as u32).saturating_sub(i0).min(31);
                    let hi = (b.i1 as u32).saturating_sub(i0).min(31);
                    let cols = (u32::MAX >> (31 - hi)) & (u32::MAX << lo);
                    let last = (b.j1 as u32).saturating_sub(j) as usize;
                    (cols, last.min(rows - 1))
                }
                None => (u32::MAX, rows - 1),
            };
            // The first pixel at least, whatever the box says.
            let mut n = 0;
            for r in r0..=last.max(r0) {
                let Some(t) = todo.get_mut(r) else { break };
                let mask = if r == r0 {
                    cols | (first & first.wrapping_neg())
                } else {
                    cols
                };
                for k in crate::simd::ones(*t & mask) {
                    let q = r * SPAN + k;
                    if cull.hits.s.get(q) == Some(&s) {
                        *t &= !(1 << k);
                        if let Some(m) = mine.get_mut(n) {
                            *m = q as u16;
                            n += 1;
                        }
                    }
                }
            }
            for four in mine.get(..n).unwrap_or(&[]).chunks(4) {
                // Lanes past the sphere's last pixel repeat its first.
                let first = four.first().copied().unwrap_or(0);
                let slots: [usize; 4] =
                    core::array::from_fn(|l| usize::from(four.get(l).copied().unwrap_or(first)));
                let active = (1 << four.len()) - 1;
                let Some(stored) = stored4(cull, slots) else {
                    continue;
                };
                let Some(colour) = self.shade4::<false, false>(cull, stored, s.index(), active)
                else {
                    continue;
                };
                let path = &mut cull.hits.path;
                for (&c, &q) in self.encode4(&colour).iter().zip(four) {
                    let q = usize::from(q);
                    if let (Some(p), Some(d)) =
                        (path.mixed_px.get_mut(q), path.mixed_done.get_mut(q / SPAN))
                    {
                        *p = c;
                        *d |= 1 << (q % SPAN);
                    }
                }
            }
        }
    }

    /// The colours of the lanes `active` of the span's four stored hits in `slots`, all on
    /// sphere `si`, shaded in lanes as `shade_span4` describes; the other lanes' values are
    /// meaningless. `None` where the scalar path must shade them (a mirror or glass without
    /// `SECONDARY`). `ALL`: all four lanes (the common group); a parameter so that it and
    /// `shade_mixed` each get a copy of their own, whose shadow-test closure is inlined
    /// (shared, it goes out of line).
    /// `SECONDARY`: shade a mirror's or glass's lanes too, their secondary rays walked one by
    /// one (`follow4`); else leave them (`None`). A parameter so that the copies in the pixel
    /// loop stay without the walk: [`Frame::shade_span4_secondary`] has its own.
    #[inline(always)]
    pub(super) fn shade4<const ALL: bool, const SECONDARY: bool>(
        &self,
        cull: &Cull<S, L>,
        (slots, ts, [x, y, z]): Stored4,
        si: usize,
        active: u32,
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
        let t = F::from(ts);
        // `hit_point_within`'s offset: `f + t·d` within near2 radii, else the one the span's
        // bounds kept, or without them (no shadow rays) `hit_point_far`'s, in lanes here.
        let offset = if self.offset_near(si) {
            V::splat(k.f).add(dir.mul(t))
        } else {
            // The common group's slots follow each other: one load.
            let o = if ALL {
                let [q, ..] = slots;
                cull.hits.o.get(q..q + 4).and_then(|o| o.try_into().ok())
            } else {
                gather4(&cull.hits.o, slots)
            };
            match o {
                Some(o) if cull.shadow.culled => V::from_lanes(o),
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
            let Some(ss) = cull.hits.s.get(q..q + 4) else {
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
                let Some(stored) = stored4(cull, [q, q + 1, q + 2, q + 3]) else {
                    continue;
                };
                let colour = self.shade4::<false, true>(cull, stored, si, active);
                keep4(
                    self,
                    &mut px,
                    &mut done,
                    [0, 1, 2, 3].map(|l| k0 + l),
                    active,
                    colour,
                );
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
        // The mirror rays in lanes where the walk tests every sphere.
        let culled = self.culled();
        let left = if culled.is_some() {
            active & 0b1111
        } else {
            self.mirror4(h, dir, colour, active & 0b1111, &mut out)
        };
        for l in crate::simd::ones(left) {
            if let Some(o) = out.get_mut(l) {
                let (ray, hit, c) = (Ray::new(eye, dir.lane(l)), h.hit(l), colour.lane(l));
                // The scalar path's walks, out of line: a copy of the walk of its own here
                // would cost the scalar path's (`Frame::follow_every`).
                *o = match culled {
                    Some(bvh) => self.follow_culled(bvh, &ray, &hit, c),
                    None => self.follow_every(&ray, &hit, c),
                };
            }
        }
        crate::simd::V::from_lanes(out)
    }
}

/// Stores the encoded `colour` of the lanes `active` into `px` at the lanes' pixels `pixels`,
/// marking them done; nothing when the lanes could not shade them (`None`: the scalar path
/// will).
#[inline(always)]
pub(super) fn keep4<const S: usize, const L: usize>(
    frame: &Frame<'_, S, L>,
    px: &mut [Rgb888; SPAN],
    done: &mut u32,
    pixels: [usize; 4],
    active: u32,
    colour: Option<crate::simd::V>,
) {
    let Some(colour) = colour else { return };
    for ((l, &c), &k) in frame.encode4(&colour).iter().enumerate().zip(&pixels) {
        if active & (1 << l) != 0 {
            if let Some(p) = px.get_mut(k) {
                *p = c;
                *done |= 1 << k;
            }
        }
    }
}

/// The spheres' boxes above which a span's tile shades its mixed groups at its first row
/// (`Frame::start_mixed`).
const TILED: usize = 4;

/// The pixels of a row's hits `ss` (by pixel) in groups of four neighbours (`0..4`, `4..8`, …,
/// whole groups only) not all on one sphere, but for misses: those that [`Frame::shade_span4`]
/// does not shade four at a time, as bits of the row.
#[inline(always)]
fn mixed_groups(ss: &[SphereId]) -> u32 {
    let mut mixed = 0;
    for (g, four) in ss.chunks_exact(4).enumerate() {
        let &[a, b, c, d] = four else { continue };
        if a == b && a == c && a == d && a != SphereId::NONE {
            continue;
        }
        let hit = |x: SphereId, l: u32| u32::from(x != SphereId::NONE) << l;
        mixed |= (hit(a, 0) | hit(b, 1) | hit(c, 2) | hit(d, 3)) << (4 * g);
    }
    mixed
}

/// The first four pixels of `todo` (bits of the span) whose hit is on `s` (`ss` by pixel), in
/// order, and how many there are (at least one where `todo`'s first is on `s`); the lanes
/// past them repeat the first.
#[inline(always)]
fn same_sphere(ss: &[SphereId], todo: u32, s: SphereId) -> ([usize; 4], usize) {
    let first = todo.trailing_zeros() as usize;
    // Most often: the next four neighbours.
    let four = (todo >> first) & 0b1111 == 0b1111;
    if four
        && ss
            .get(first..first + 4)
            .is_some_and(|f| f.iter().all(|&x| x == s))
    {
        return ([first, first + 1, first + 2, first + 3], 4);
    }
    let (mut pixels, mut n) = ([first; 4], 0);
    for k in crate::simd::ones(todo) {
        if ss.get(k) == Some(&s) {
            if let Some(p) = pixels.get_mut(n) {
                *p = k;
            }
            n += 1;
            if n == 4 {
                break;
            }
        }
    }
    (pixels, n)
}

/// The values of `a` in four slots.
#[inline(always)]
fn gather4<T: Copy>(a: &[T], [s0, s1, s2, s3]: [usize; 4]) -> Option<[T; 4]> {
    Some([*a.get(s0)?, *a.get(s1)?, *a.get(s2)?, *a.get(s3)?])
}

/// Four slots of a span's stored hits, their `t` and their view directions by coordinate.
type Stored4 = ([usize; 4], [f32; 4], [[f32; 4]; 3]);

/// The stored hits in four slots.
#[inline(always)]
fn stored4<const S: usize, const L: usize>(
    cull: &Cull<S, L>,
    slots: [usize; 4],
) -> Option<Stored4> {
    let [dx, dy, dz] = &cull.hits.path.hit_dc;
    let dir = [
        gather4(dx, slots)?,
        gather4(dy, slots)?,
        gather4(dz, slots)?,
    ];
    Some((slots, gather4(&cull.hits.t, slots)?, dir))
}
