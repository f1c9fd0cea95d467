//! The host render path (`cfg(lanes)`: x86-64, AArch64 with NEON): a span's primary rays traced
//! and its pixels shaded four columns at a time in vector lanes, and with one sample a pixel and
//! shadow rays, tiles of `KEPT` rows that share their shadow lists. Each lane does the scalar
//! path's operations in its order, so the pixels are those of `scalar.rs`, the Cortex-M path.
//! The shading of four pixels at a time is in `shade.rs`.

use super::*;

mod mirror;
mod shade;

impl<'a, const S: usize, const L: usize> Frame<'a, S, L> {
    /// `scalar.rs`'s `trace_span`, the same hits, `LANES` columns at a time ([`Frame::trace_lanes`]),
    /// and with shadow rays the hit points for the span's bounds too.
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
        if span.len() > DEEP {
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
    /// `PILE` (spans that meet more than [`DEEP`] boxes, a deep pile of spheres): a group of lanes skips a sphere whose
    /// every root lies beyond the lanes' closest hits so far, which the test would reject
    /// (a hit needs its root at or before them). In a pile of spheres most lie behind the
    /// first few hits. The pile comes nearest first (`Frame::sort_pile`), so the row stops at
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
        // `Frame::sort_pile` ordered the pile nearest first.
        let sorted = PILE && span.len() <= PILE_SORT;
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
            let near = if PILE { pile_key(k) / d_max } else { 0.0 };
            if PILE && sorted {
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
                    if sq != SphereId::NONE {
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

    /// The pixel `(i, j)` of the span just started: hosts shade the whole span at its start
    /// ([`Frame::fill_span`]).
    #[inline(always)]
    pub(super) fn span_output(&self, _j: u32, i: u32, cull: &Cull<S, L>) -> Rgb888 {
        let k = (i - cull.span_start) as usize;
        cull.hits.path.px.get(k).copied().unwrap_or(cull.miss)
    }

    /// What a span does once gathered: hosts shade all its pixels ([`Frame::fill_span`]).
    #[inline(always)]
    pub(super) fn span_gathered(&self, j: u32, cull: &mut Cull<S, L>) {
        self.fill_span(j, cull);
    }

    /// Every pixel of the span just gathered into `cull.hits.path.px`: groups of four in lanes
    /// (`shade_span4`), the others one by one, so that the pixel loop only reads them.
    #[inline(never)]
    pub(super) fn fill_span(&self, j: u32, cull: &mut Cull<S, L>) {
        cull.hits.path.done = 0;
        if cull.hits.kept == Kept::Pixels {
            self.shade_span4(cull);
        }
        let len = cull.span_len();
        let span = if len >= 32 { u32::MAX } else { (1 << len) - 1 };
        for k in crate::simd::ones(!cull.hits.path.done & span) {
            let c = self.span_pixel(j, cull.span_start + k as u32, cull);
            if let Some(p) = cull.hits.path.px.get_mut(k) {
                *p = c;
            }
        }
    }

    /// Narrows the span that `Frame::gather` is starting, and its spheres, where the boxes of
    /// more than [`CROWD`] spheres meet it: to its first 8 columns if at most [`DEEP`] boxes meet
    /// those, else to 16 (a deep pile of spheres, where narrower spans repeat each sphere's
    /// set-up for little gain). The next span starts where this one ends: spans only group
    /// pixels, whose hits and colours are the same whatever the width.
    #[inline(always)]
    pub(super) fn narrow_span(&self, cull: &mut Cull<S, L>) {
        if cull.spheres.span.len() > CROWD {
            self.narrow_crowded(cull);
        }
        if cull.spheres.span.len() > DEEP {
            self.sort_pile(cull);
        }
    }

    /// Orders a deep pile's spheres (a span that meets more than [`DEEP`] boxes) by
    /// [`pile_key`], nearest first, so that [`Frame::trace_lanes`] meets each pixel's front
    /// sphere early and stops where every sphere left lies beyond every hit so far. Piles of
    /// more than [`PILE_SORT`] spheres keep their order (and their rows test each sphere).
    #[inline(never)]
    fn sort_pile(&self, cull: &mut Cull<S, L>) {
        let span = &mut cull.spheres.span;
        if span.len() > PILE_SORT {
            return;
        }
        let mut keyed: heapless::Vec<(f32, SphereId), PILE_SORT> = heapless::Vec::new();
        for &s in span.iter() {
            let key = self.tables.eye.get(s.index()).map_or(0.0, pile_key);
            let _ = keyed.push((key, s));
        }
        keyed.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
        for (s, &(_, id)) in span.iter_mut().zip(keyed.iter()) {
            *s = id;
        }
    }

    /// [`Frame::narrow_span`] of a span that meets more than [`CROWD`] boxes.
    #[inline(never)]
    fn narrow_crowded(&self, cull: &mut Cull<S, L>) {
        let i0 = cull.span_start;
        // How many of the span's boxes meet its first 16 and first 8 columns.
        let (mut half, mut quarter) = (0, 0);
        for s in &cull.spheres.span {
            if let Some(b) = self.tables.boxes.get(s.index()) {
                half += usize::from((b.i0 as u32) < i0 + 16);
                quarter += usize::from((b.i0 as u32) < i0 + 8);
            }
        }
        let end = i0
            + if half > CROWD && quarter <= DEEP {
                8
            } else {
                16
            };
        if end < cull.span_end {
            cull.span_end = end;
            let boxes = &self.tables.boxes;
            cull.spheres
                .span
                .retain(|s| boxes.get(s.index()).is_some_and(|b| (b.i0 as u32) < end));
        }
    }

    /// [`Frame::start_row`] for the `n` rows from `j` that a span gathers at once (a tile,
    /// `Cull::rows`): their spheres are those whose box crosses any of them.
    pub(super) fn start_rows(&self, j: u32, n: u32, cull: &mut Cull<S, L>) {
        cull.spheres.row.clear();
        // The rows the box and the tile share, none for an empty box (`j0 > j1`).
        let last = j + n.max(1) - 1;
        for (s, b) in self.tables.boxes.iter().enumerate() {
            if (b.j0 as u32).max(j) <= (b.j1 as u32).min(last) {
                let _ = cull.spheres.row.push(SphereId::new(s));
            }
        }
        cull.hits.path.rows = n;
        self.start_miss(cull);
    }

    /// [`Frame::render_rows`]'s rows `first_row..first_row + rows` into `buf` (whole rows of the
    /// image's width): tile by tile ([`Frame::tile_rows`]).
    #[inline(always)]
    pub(super) fn rows_into<C: From<Rgb888>>(&self, first_row: u32, rows: u32, buf: &mut [C]) {
        let w = self.width() as usize;
        let _ = self.tile_rows(first_row, rows, |t: TileRow<'_>| {
            for (o, &p) in t.place(buf, first_row, w).iter_mut().zip(t.px) {
                *o = p.into();
            }
            Ok::<(), core::convert::Infallible>(())
        });
    }

    /// Rows `first ..first + n` as hosts trace them: span by span, each span shaded whole by
    /// `fill_span`, and with one sample a pixel and shadow rays `KEPT` (8) rows at a time (a
    /// tile), whose hits the sample slots hold: one set of shadow lists for the tile's groups
    /// instead of one per row. A tile's bounds are barely larger than a row's (a span is 32
    /// pixels wide), so its lists are barely longer. `out` gets each row of each span of each
    /// tile in turn; its first error ends it.
    pub(crate) fn tile_rows<E>(
        &self,
        first: u32,
        n: u32,
        mut out: impl FnMut(TileRow<'_>) -> Result<(), E>,
    ) -> Result<(), E> {
        let tile = if self.samples == 1 && self.shadow_rays {
            KEPT as u32
        } else {
            1
        };
        let end = (first + n).min(self.height());
        let mut cull = Cull::new();
        let mut j = first;
        while j < end {
            let rows = tile.min(end - j);
            self.start_rows(j, rows, &mut cull);
            let mut i = 0;
            while i < self.width() {
                cull.span_start = i;
                cull.span_end = (i + SPAN as u32).min(self.width());
                // Which may narrow the span (`Frame::narrow_span`).
                self.gather(j, &mut cull);
                for r in 0..rows {
                    cull.hits.path.base = r as usize * SPAN;
                    self.fill_span(j + r, &mut cull);
                    let px = cull.hits.path.px.get(..cull.span_len()).unwrap_or(&[]);
                    out(TileRow { i, j: j + r, px })?;
                }
                i = cull.span_end;
            }
            j += rows;
        }
        Ok(())
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
pub(super) fn nearest_root(k: &crate::Prepared, d_max: f32) -> f32 {
    let near = k.c / ((libm::sqrtf(k.f.dot(k.f)) + k.r) * d_max) * (1.0 - 1.0 / 1024.0);
    if near > 0.0 {
        near
    } else {
        0.0
    }
}

/// [`nearest_root`] of a direction of length 1, the order of a sorted pile
/// ([`Frame::sort_pile`]): zero where the sphere's constants overflow, which the trace tests
/// apart and must not pass by.
#[inline(always)]
fn pile_key(k: &crate::Prepared) -> f32 {
    if crate::math::finite(k.c) {
        nearest_root(k, 1.0)
    } else {
        0.0
    }
}

/// Whether a root `t` on `sphere`, at most the lane's closest `best` (on `on`), takes its
/// place: the closest of scene order, where equal roots go to the greater index, whatever order
/// the spheres come in.
#[inline(always)]
fn wins(t: f32, sphere: SphereId, best: f32, on: SphereId) -> bool {
    t < best || on == SphereId::NONE || sphere.index() > on.index()
}

/// The most spheres a deep pile is sorted with (`Frame::sort_pile`): 8 KiB of keys on the stack.
const PILE_SORT: usize = 1024;

/// The most spheres' boxes a host's span should meet: a span that meets more is narrowed
/// (`Frame::narrow_span`). Over many small spheres a tile of `SPAN` columns hits more spheres
/// than it has hit groups (`GROUPS`), and the group of the rest then bounds points across the
/// whole tile: its shadow candidates are all the spheres in the tile's shadow. A narrower span
/// keeps each group's bound, and so its lists, to a few pixels.
const CROWD: usize = 8;

/// The spheres' boxes from which a span's spheres are a deep pile (see `Frame::narrow_span`
/// and `Frame::trace_lanes`).
const DEEP: usize = 4 * CROWD;

/// One row of one span of a tile (see [`Frame::tile_rows`]): the pixels `(i.., j)`.
pub(crate) struct TileRow<'p> {
    pub(crate) i: u32,
    pub(crate) j: u32,
    pub(crate) px: &'p [Rgb888],
}

impl TileRow<'_> {
    /// Where these pixels go in `buf`, whole rows of `w` pixels from row `first_row`: the rest
    /// of `buf` from pixel `(i, j)` (empty past its end).
    #[inline(always)]
    pub(crate) fn place<'b, C>(&self, buf: &'b mut [C], first_row: u32, w: usize) -> &'b mut [C] {
        let at = (self.j - first_row) as usize * w + self.i as usize;
        buf.get_mut(at..).unwrap_or(&mut [])
    }
}

/// The host path's part of the per-row state ([`SpanHits::path`]).
#[derive(Debug)]
pub(super) struct PathState {
    /// The directions by coordinate (x, y, z), padded to whole lanes past the last slot: traced
    /// and shaded four columns at a time, a lane group is one load per coordinate (`Vec3`s
    /// would be transposed both ways).
    pub(super) hit_dc: [[f32; DPAD]; 3],
    /// The span's pixels that `Frame::shade_span4` shaded four at a time or found to be misses
    /// (bit `k` for pixel `k`), and all the span's pixels once `Frame::fill_span` has shaded
    /// the rest.
    pub(super) done: u32,
    pub(super) px: [Rgb888; SPAN],
    /// The rows a span gathers at once (`Frame::tile_rows`: up to `KEPT`), row `r`'s hits in
    /// slots `r·SPAN + k`, and the first slot of the row being shaded.
    pub(super) rows: u32,
    pub(super) base: usize,
}

impl PathState {
    pub(super) fn new() -> Self {
        PathState {
            hit_dc: [[0.0; DPAD]; 3],
            done: 0,
            px: [Rgb888::new(0, 0, 0); SPAN],
            rows: 1,
            base: 0,
        }
    }
}

impl<const S: usize, const L: usize> Cull<S, L> {
    /// The rows the span gathers at once.
    #[inline(always)]
    pub(super) fn rows(&self) -> u32 {
        self.hits.path.rows
    }

    /// The slot of pixel `k` of the row being shaded.
    #[inline(always)]
    pub(super) fn slot(&self, k: usize) -> usize {
        self.hits.path.base + k
    }

    /// Pixels in the current span.
    #[inline(always)]
    pub(super) fn span_len(&self) -> usize {
        ((self.span_end - self.span_start) as usize).min(SPAN)
    }

    /// The view direction kept in slot `k`.
    #[inline(always)]
    pub(super) fn dir(&self, k: usize) -> Option<Vec3> {
        let [x, y, z] = &self.hits.path.hit_dc;
        Some(Vec3::new(*x.get(k)?, *y.get(k)?, *z.get(k)?))
    }

    /// Keeps `d` as the view direction of slot `k`.
    #[inline(always)]
    pub(super) fn set_dir(&mut self, k: usize, d: Vec3) {
        for (a, v) in self.hits.path.hit_dc.iter_mut().zip([d.x, d.y, d.z]) {
            if let Some(a) = a.get_mut(k) {
                *a = v;
            }
        }
    }
}

/// Where hosts collect a light's candidates before weighing them four at a time.
pub(super) type Found<const S: usize> = List<S>;

impl<const S: usize> Blockers<'_, S> {
    /// Sphere `s` may be a candidate.
    #[inline(always)]
    pub(super) fn consider(&mut self, s: SphereId) {
        if self.found.push(s).is_err() {
            self.full = true;
        }
    }

    /// Keeps the spheres that can block in the pool; whether a list or the pool ran out of room.
    #[inline(always)]
    pub(super) fn finish(&mut self) -> bool {
        let mut full = self.full;
        for c in self.found.chunks(4) {
            let ids: [SphereId; 4] =
                core::array::from_fn(|l| c.get(l).copied().unwrap_or(SphereId::NONE));
            let sph = ids.map(|i| self.spheres.get(i.index()).copied());
            let m = sph.map(|s| s.map_or(Vec3::ZERO, |s| s.center));
            let r = sph.map(|s| s.map_or(0.0, |s| s.radius));
            let pass = self.light.may_block4(m, r, self.q, self.rho);
            for (l, &i) in ids.iter().enumerate() {
                if pass & (1 << l) != 0 && sph[l].is_some() && self.pool.push(i).is_err() {
                    full = true;
                }
            }
        }
        full
    }
}

impl<const S: usize> Sweep<S> {
    /// The start of [`Sweep::scan`] from entry `i`, four entries at a time: the same
    /// comparisons lane by lane, and as the keys are sorted, the entries within the band are a
    /// prefix of the four. Where the scalar scan goes on, or `None` when the band has ended.
    #[inline(always)]
    pub(super) fn scan_lanes(
        &self,
        mut i: usize,
        hi: f32,
        key: f32,
        slack: f32,
        key2: f32,
        consider: &mut impl FnMut(SphereId),
    ) -> Option<usize> {
        use crate::simd::CmpLe;
        use crate::simd::{bits, ones, F};
        fn from(v: &[f32], i: usize) -> &[f32] {
            v.get(i..).unwrap_or(&[])
        }
        let (ks, hs, k2s) = (from(&self.key, i), from(&self.half, i), from(&self.key2, i));
        let ss = self.sphere.get(i..).unwrap_or(&[]);
        let quads = ks.chunks_exact(4).zip(hs.chunks_exact(4));
        for ((k, h), (k2, s)) in quads.zip(k2s.chunks_exact(4).zip(ss.chunks_exact(4))) {
            let four = |c: &[f32]| <[f32; 4]>::try_from(c).ok().map(F::from);
            let (Some(k), Some(h), Some(k2)) = (four(k), four(h), four(k2)) else {
                break;
            };
            let near = h + F::splat(slack);
            let within = k.cmp_le(F::splat(hi));
            let keep = within
                & (k - F::splat(key)).abs().cmp_le(near)
                & (k2 - F::splat(key2)).abs().cmp_le(near);
            for l in ones(bits(keep)) {
                if let Some(&s) = s.get(l) {
                    consider(s);
                }
            }
            if bits(within) != 0b1111 {
                return None;
            }
            i += 4;
        }
        Some(i)
    }
}
