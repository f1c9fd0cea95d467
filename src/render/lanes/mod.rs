//! The host render path (`cfg(lanes)`: x86-64, AArch64 with NEON): a span's primary rays traced
//! and its pixels shaded four columns at a time in vector lanes, and with one sample a pixel and
//! shadow rays, tiles of `KEPT` rows that share their shadow lists. Each lane does the scalar
//! path's operations in its order, so the pixels are those of `scalar.rs`, the Cortex-M path.
//! The tracing of a span's primary rays is in `trace.rs`, the shading of four pixels at a time
//! in `shade.rs`.

use super::*;

mod mirror;
mod shade;
mod trace;

#[cfg(test)]
pub(super) use trace::nearest_root;
pub(super) use trace::pile_key;

impl<'a, const S: usize, const L: usize> Frame<'a, S, L> {
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
            // At the tile's first row (`j`): in a crowded tile, every row's mixed groups.
            if cull.hits.path.base == 0 {
                self.start_mixed(j, cull);
            }
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
        if cull.spheres.span.len() > DEEP && !cull.spheres.sorted {
            self.sort_piles(cull);
        }
    }

    /// Orders the tile's spheres by [`pile_key`], nearest first, at its first deep pile (a
    /// span that meets more than [`DEEP`] boxes): the rows' list, and the span's drawn from it.
    /// Every later span of the tile draws its spheres from the sorted list, in its order, so
    /// its pile is sorted with no sort of its own, and [`Frame::trace_lanes`] meets each
    /// pixel's front sphere early and stops where every sphere left lies beyond every hit so
    /// far. Out of scene order, every span of the tile then takes the pile's tie rule
    /// (`primary::wins`, with `Spheres::sorted` set), which decides equal roots by index: the
    /// order of equal keys is free.
    ///
    /// The list is sorted by a radix sort of the keys' bits ([`radix_sort`]): four byte-wide
    /// passes over a tile's thousands of spheres, instead of a sort by comparisons that
    /// fetches two keys for each of about log₂ n passes.
    #[inline(never)]
    fn sort_piles(&self, cull: &mut Cull<S, L>) {
        let pile = self.tables.pile;
        let Spheres { row, span, .. } = &mut cull.spheres;
        // The span's list is the sort's room (of the same capacity: the resize cannot fail):
        // it is drawn again below.
        span.clear();
        let _ = span.resize(row.len(), SphereId::NONE);
        radix_sort(row, &mut span[..], |s| {
            pile.get(s.index()).copied().unwrap_or(0.0)
        });
        cull.spheres.sorted = true;
        self.index_row(cull);
        // The span's spheres drawn again from the sorted row: the same ones (those whose box
        // meets its columns, which `narrow_crowded` may have narrowed), in its order.
        self.span_spheres(cull);
    }

    /// The span's spheres: the row's whose box meets its columns, in the row's order, from the
    /// blocks of the row's list that meet them (`Frame::index_row`).
    #[inline(always)]
    pub(super) fn span_spheres(&self, cull: &mut Cull<S, L>) {
        let (i0, i1) = (cull.span_start, cull.span_end);
        let Spheres { row, span, .. } = &mut cull.spheres;
        let path = &cull.hits.path;
        span.clear();
        for (block, cols) in row.chunks(path.block.max(1)).zip(&path.blocks) {
            if !meets_columns(cols, i0, i1) {
                continue;
            }
            // Every sphere of the block written, and the length advanced past those whose box
            // meets the span: no branch on the outcome, which over a pile of small spheres
            // mispredicts about as often as it is taken. The block fits: `span` has room for
            // the whole row.
            let mut n = span.len();
            let _ = span.extend_from_slice(block);
            for &s in block {
                let meets = self
                    .tables
                    .boxes
                    .get(s.index())
                    .is_some_and(|b| ((b.i0 as u32) < i1) & (b.i1 as u32 >= i0));
                if let Some(slot) = span.get_mut(n) {
                    *slot = s;
                }
                n += usize::from(meets);
            }
            span.truncate(n);
        }
    }

    /// Splits the row's list into at most [`BLOCKS`] blocks of consecutive entries and keeps
    /// each block's columns (the least `i0`, the greatest `i1` of its boxes), so that a span
    /// skips the blocks that miss it: over many small spheres in scene order a block lies in a
    /// few columns, and a span then reads a few blocks of the row's hundreds of spheres.
    pub(super) fn index_row(&self, cull: &mut Cull<S, L>) {
        let row = &cull.spheres.row;
        let path = &mut cull.hits.path;
        path.block = row.len().div_ceil(BLOCKS).max(1);
        for (block, out) in row.chunks(path.block).zip(path.blocks.iter_mut()) {
            let boxes = block
                .iter()
                .filter_map(|s| self.tables.boxes.get(s.index()));
            let (i0, i1) = boxes.fold((u16::MAX, 0), |(lo, hi), b| (lo.min(b.i0), hi.max(b.i1)));
            // Only the columns are read (`meets_columns`).
            *out = PixelBox {
                i0,
                i1,
                j0: 0,
                j1: 0,
            };
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
        cull.spheres.sorted = false;
        let last = j + n.max(1) - 1;
        let (boxes, blocks) = (self.tables.boxes, self.tables.box_rows);
        let size = box_block(boxes.len());
        for (k, (block, rows)) in boxes.chunks(size).zip(blocks).enumerate() {
            if !meets_rows(rows, j, last) {
                continue;
            }
            for (s, b) in (k * size..).zip(block) {
                if meets_rows(b, j, last) {
                    let _ = cull.spheres.row.push(SphereId::new(s));
                }
            }
        }
        self.index_row(cull);
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
    /// The colours of the tile's pixels in groups of four not all on one sphere, shaded
    /// sphere by sphere across the tile's rows (`Frame::shade_mixed`), by slot, and per row
    /// which of its pixels they hold.
    pub(super) mixed_px: [Rgb888; SPAN * KEPT],
    pub(super) mixed_done: [u32; KEPT],
    /// Whether the tile's first row shaded every row's mixed groups (a crowded tile), or each
    /// row shades its own.
    pub(super) tiled: bool,
    /// The rows a span gathers at once (`Frame::tile_rows`: up to `KEPT`), row `r`'s hits in
    /// slots `r·SPAN + k`, and the first slot of the row being shaded.
    pub(super) rows: u32,
    pub(super) base: usize,
    /// The row's list in blocks of `block` entries, and each block's columns as a box whose
    /// rows are not read (`Frame::index_row`).
    pub(super) block: usize,
    pub(super) blocks: [PixelBox; BLOCKS],
}

/// Splits the frame's `boxes`, in scene order, into at most [`BOX_BLOCKS`] blocks of
/// [`box_block`] boxes and keeps in `rows` each block's rows (the least `j0`, the greatest
/// `j1`), so that `Frame::start_rows` skips the blocks that miss its tile: over many small
/// spheres in scene order a block lies in a few rows. Once a frame (`FrameStorage::fill`).
pub(super) fn index_boxes(boxes: &[PixelBox], rows: &mut heapless::Vec<PixelBox, BOX_BLOCKS>) {
    rows.clear();
    for block in boxes.chunks(box_block(boxes.len())) {
        let (j0, j1) = block
            .iter()
            .fold((u16::MAX, 0), |(lo, hi), b| (lo.min(b.j0), hi.max(b.j1)));
        // Only the rows are read (`meets_rows`). At most `BOX_BLOCKS` blocks: room for each.
        let _ = rows.push(PixelBox {
            i0: 0,
            i1: 0,
            j0,
            j1,
        });
    }
}

/// Boxes a block of [`index_boxes`]: as few as make at most [`BOX_BLOCKS`] blocks.
#[inline(always)]
fn box_block(n: usize) -> usize {
    n.div_ceil(BOX_BLOCKS).max(1)
}

/// Whether the box `b` meets the rows `j..=last` (a tile's), none for an empty box (`j0 > j1`).
#[inline(always)]
fn meets_rows(b: &PixelBox, j: u32, last: u32) -> bool {
    (b.j0 as u32).max(j) <= (b.j1 as u32).min(last)
}

/// The most blocks the frame's boxes are split into ([`index_boxes`]).
pub(super) const BOX_BLOCKS: usize = 256;

/// The most blocks a row's list is split into (`Frame::index_row`).
const BLOCKS: usize = 64;

impl PathState {
    pub(super) fn new() -> Self {
        PathState {
            hit_dc: [[0.0; DPAD]; 3],
            done: 0,
            px: [Rgb888::new(0, 0, 0); SPAN],
            mixed_px: [Rgb888::new(0, 0, 0); SPAN * KEPT],
            mixed_done: [0; KEPT],
            tiled: false,
            rows: 1,
            base: 0,
            block: 1,
            blocks: [PixelBox::EMPTY; BLOCKS],
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

impl<const S: usize> Consider for Blockers<'_, S> {
    /// Sphere `s` may be a candidate.
    #[inline(always)]
    fn one(&mut self, s: SphereId) {
        if self.found.push(s).is_err() {
            self.full = true;
        }
    }

    /// Without a branch on each entry's outcome ([`push_masked`]).
    #[inline(always)]
    fn four(&mut self, ids: &[SphereId], keep: u32) {
        if !push_masked(&mut self.found, ids, keep) {
            self.full = true;
        }
    }
}

impl<const S: usize> Blockers<'_, S> {
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
                // Not the group's own sphere (`Blockers::own`).
                let keep = pass & (1 << l) != 0 && sph[l].is_some() && i != self.own;
                if keep && self.pool.push(i).is_err() {
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
    pub(super) fn scan_lanes<const DEPTH: bool>(
        &self,
        mut i: usize,
        hi: f32,
        b: Band,
        consider: &mut impl Consider,
    ) -> Option<usize> {
        use crate::simd::{bits, CmpLe, F};
        fn from(v: &[f32], i: usize) -> &[f32] {
            v.get(i..).unwrap_or(&[])
        }
        // By chunks rather than `Sweep::four`'s loads at `i`: fewer bounds checks in this loop,
        // which every span's scan of a sweep under `SLABS_FROM` entries runs.
        let (ks, hs, k2s) = (from(&self.key, i), from(&self.half, i), from(&self.key2, i));
        let ds = from(if DEPTH { &self.depth } else { &self.key }, i);
        let ss = self.sphere.get(i..).unwrap_or(&[]);
        let quads = ks.chunks_exact(4).zip(hs.chunks_exact(4));
        let rest = k2s.chunks_exact(4).zip(ds.chunks_exact(4));
        for ((k, h), ((k2, d), s)) in quads.zip(rest.zip(ss.chunks_exact(4))) {
            let four = |c: &[f32]| <[f32; 4]>::try_from(c).ok().map(F::from);
            let (Some(k), Some(h), Some(k2), Some(d)) = (four(k), four(h), four(k2), four(d))
            else {
                break;
            };
            let within = bits(k.cmp_le(F::splat(hi)));
            consider.four(s, Self::passes4::<DEPTH>(b, [k, h, k2, d]) & within);
            if within != 0b1111 {
                return None;
            }
            i += 4;
        }
        Some(i)
    }

    /// The start of a slab's run in [`Sweep::scan_slabs`] from entry `i`, four entries at a
    /// time: the same comparisons lane by lane, the lanes from the slab's end `hi` on masked
    /// (the next slab's entries would be named twice), and as the slab is sorted by `key2`,
    /// the entries not beyond `hi2` are a prefix of the four. Where the scalar run goes on, or
    /// `None` when the run has ended.
    #[inline(always)]
    pub(super) fn slab_lanes<const DEPTH: bool>(
        &self,
        mut i: usize,
        hi: usize,
        hi2: f32,
        b: Band,
        consider: &mut impl Consider,
    ) -> Option<usize> {
        use crate::simd::{bits, CmpGt, F};
        while i < hi {
            let Some((e, s)) = self.four::<DEPTH>(i) else {
                break;
            };
            // The lanes still in the slab, and of those the ones not beyond `hi2` (`!(k2 >
            // hi2)`, as the scalar run stops).
            let slab = (1u32 << (hi - i).min(4)) - 1;
            let within = bits(!e[2].cmp_gt(F::splat(hi2))) & slab;
            consider.four(s, Self::passes4::<DEPTH>(b, e) & within);
            if within != 0b1111 {
                return None;
            }
            i += 4;
        }
        Some(i)
    }

    /// Entries `i..i + 4` by field, `[key, half, key2, depth]` (without `DEPTH` the keys stand
    /// in for the depths, never read), and their spheres; `None` where fewer than four remain.
    #[inline(always)]
    fn four<const DEPTH: bool>(&self, i: usize) -> Option<([crate::simd::F; 4], &[SphereId])> {
        let at = |v: &[f32]| {
            v.get(i..i + 4)
                .and_then(|c| <[f32; 4]>::try_from(c).ok())
                .map(crate::simd::F::from)
        };
        let depth = if DEPTH { &self.depth } else { &self.key };
        let fields = [at(&self.key)?, at(&self.half)?, at(&self.key2)?, at(depth)?];
        Some((fields, self.sphere.get(i..i + 4)?))
    }

    /// [`Sweep::passes`] of four entries (see [`Sweep::four`]), lane by lane: the bits of
    /// those that pass.
    #[inline(always)]
    fn passes4<const DEPTH: bool>(b: Band, [k, h, k2, d]: [crate::simd::F; 4]) -> u32 {
        use crate::simd::{bits, CmpGt, CmpLe, F};
        let near = h + F::splat(b.slack);
        let keep =
            (k - F::splat(b.key)).abs().cmp_le(near) & (k2 - F::splat(b.key2)).abs().cmp_le(near);
        // Not beyond: a NaN depth keeps the entry.
        bits(if DEPTH {
            keep & !d.cmp_gt(F::splat(b.far))
        } else {
            keep
        })
    }
}
