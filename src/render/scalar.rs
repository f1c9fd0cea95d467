//! The Cortex-M render path (no vector lanes): a span's primary rays traced one ray at a time
//! (sphere by sphere over each box's columns; on the M0, without kept directions, pixel by
//! pixel in `Frame::gather`), its pixels shaded one at a time as the row asks for them, in a
//! row's worth of state that fits a microcontroller's stack. `lanes/` is the host path, which
//! computes the same pixels.

use super::*;

impl<'a, const S: usize, const L: usize> Frame<'a, S, L> {
    /// The span's spheres: the row's whose box meets its columns, in the row's order.
    #[inline(always)]
    pub(super) fn span_spheres(&self, cull: &mut Cull<S, L>) {
        let (i0, i1) = (cull.span_start, cull.span_end);
        cull.spheres.span.clear();
        for &s in &cull.spheres.row {
            if let Some(b) = self.tables.boxes.get(s.index()) {
                if meets_columns(b, i0, i1) {
                    let _ = cull.spheres.span.push(s);
                }
            }
        }
    }

    /// Nothing to index: a span reads the row's whole list, which holds a microcontroller
    /// scene's few spheres.
    #[inline(always)]
    pub(super) fn index_row(&self, _cull: &mut Cull<S, L>) {}

    /// Spans keep their width here: one row's span holds few hit groups' worth of pixels.
    #[inline(always)]
    pub(super) fn narrow_span(&self, _cull: &mut Cull<S, L>) {}

    /// The closest primary hits of the span's pixels `i0..i1` for one sample (`ox`, row
    /// coordinate `y`) into the slots `base..`: view directions in `path`, `(t, sphere)` in
    /// `hit_t`/`hit_s` (`SphereId::NONE`: a miss). Sphere by sphere in scene order, each over
    /// the columns of its box: every pixel sees its candidates in the order and with the `tmax` of
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
        // One row at a time on Cortex-M: the row's spheres are the span's.
        let _ = row;
        self.trace_scalar(i0, i1, ox, y, base, cull);
    }

    /// `trace_span` one column at a time.
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
            cull.hits.path.hit_d.get_mut(base..base + len),
            cull.hits.t.get_mut(base..base + len),
            cull.hits.s.get_mut(base..base + len),
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
            *s = SphereId::NONE;
            column += 1.0;
        }
        for &sphere in &cull.spheres.span {
            let (Some(b), Some(k)) = (
                self.tables.boxes.get(sphere.index()),
                self.tables.eye.get(sphere.index()),
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

    /// The pixel `(i, j)` of the span just started, shaded now.
    #[inline(always)]
    pub(super) fn span_output(&self, j: u32, i: u32, cull: &Cull<S, L>) -> Rgb888 {
        self.span_pixel(j, i, cull)
    }

    /// What a span does once gathered: nothing more here (its pixels are shaded one by one).
    #[inline(always)]
    pub(super) fn span_gathered(&self, _j: u32, _cull: &mut Cull<S, L>) {}

    /// [`Frame::render_rows`]'s rows `first_row..first_row + rows` into `buf` (whole rows of the
    /// image's width): row by row, as [`Pixels`] does.
    #[inline(always)]
    pub(super) fn rows_into<C: From<Rgb888>>(&self, first_row: u32, _rows: u32, buf: &mut [C]) {
        let w = self.width() as usize;
        let mut cull = Cull::new();
        for (r, row) in buf.chunks_exact_mut(w).enumerate() {
            let j = first_row + r as u32;
            for (i, px) in row.iter_mut().enumerate() {
                *px = self.next_pixel(j, i as u32, &mut cull).into();
            }
        }
    }
}

/// The Cortex-M path's part of the per-row state ([`Cull::path`]): the view direction of each
/// slot, where there is room ([`DIRS`]).
#[derive(Debug)]
pub(super) struct PathState {
    pub(super) hit_d: [Vec3; DIRS],
}

impl PathState {
    #[inline(always)]
    pub(super) fn new() -> Self {
        PathState {
            hit_d: [Vec3::ZERO; DIRS],
        }
    }
}

impl<const S: usize, const L: usize> Cull<S, L> {
    /// The rows the span gathers at once: one.
    #[inline(always)]
    pub(super) fn rows(&self) -> u32 {
        1
    }

    /// The slot of pixel `k` of the row being shaded.
    #[inline(always)]
    pub(super) fn slot(&self, k: usize) -> usize {
        k
    }

    /// The view direction kept in slot `k` (none where `DIRS` keeps none).
    #[inline(always)]
    pub(super) fn dir(&self, k: usize) -> Option<Vec3> {
        self.hits.path.hit_d.get(k).copied()
    }

    /// Keeps `d` as the view direction of slot `k`, where there is room.
    #[inline(always)]
    pub(super) fn set_dir(&mut self, k: usize, d: Vec3) {
        if let Some(a) = self.hits.path.hit_d.get_mut(k) {
            *a = d;
        }
    }
}

/// Cortex-M weighs each candidate at once: nothing is collected.
pub(super) type Found<const S: usize> = ();

impl<const S: usize> Consider for Blockers<'_, S> {
    /// Sphere `s` may be a candidate: kept if it can block.
    #[inline(always)]
    fn one(&mut self, s: SphereId) {
        if s == self.own {
            return;
        }
        if let Some(sphere) = self.spheres.get(s.index()) {
            if self
                .light
                .may_block(sphere.center, sphere.radius, self.q, self.rho)
                && self.pool.push(s).is_err()
            {
                self.full = true;
            }
        }
    }
}

impl<const S: usize> Blockers<'_, S> {
    /// Whether the pool ran out of room.
    #[inline(always)]
    pub(super) fn finish(&mut self) -> bool {
        self.full
    }
}

impl<const S: usize> Sweep<S> {
    /// The start of [`Sweep::scan`] from entry `i`: nothing before the scalar scan here.
    #[inline(always)]
    pub(super) fn scan_lanes<const DEPTH: bool>(
        &self,
        i: usize,
        _hi: f32,
        _band: Band,
        _consider: &mut impl Consider,
    ) -> Option<usize> {
        Some(i)
    }

    /// The start of a slab's run: nothing before the scalar run here (no slabs are built).
    #[inline(always)]
    pub(super) fn slab_lanes<const DEPTH: bool>(
        &self,
        i: usize,
        _hi: usize,
        _hi2: f32,
        _band: Band,
        _consider: &mut impl Consider,
    ) -> Option<usize> {
        Some(i)
    }
}
