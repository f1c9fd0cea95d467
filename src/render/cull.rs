//! The per-row culling state: a span's hits, kept view directions and offsets, and the shadow
//! candidate lists of its groups.

use super::*;

/// The group of every other sphere.
pub(super) const REST: u16 = u16::MAX - 1;

/// A light's pool range when it must test every sphere (empty as `a..b`: `a > b`).
pub(super) const ALL: (u16, u16) = (u16::MAX, 0);

/// The candidate lists of the span being traced: the row's spheres, the span's, and for each
/// light the spheres that can block its shadow rays from the span's primary hits (all kept in
/// one pool of `S` indices; a light that does not fit tests every sphere).
///
/// On Cortex-M `repr(C)`, the per-slot arrays first, so that a new row's zeros (`Cull::new`)
/// are written straight into the `Row` that `Frame::row` returns, not built in a temporary and
/// copied. Hosts keep the compiler's layout: `repr(C)` gains them nothing.
#[derive(Debug)]
#[cfg_attr(not(lanes), repr(C))]
pub(super) struct Cull<const S: usize, const L: usize> {
    pub(super) hit_t: [f32; SPAN * KEPT],
    #[cfg(not(lanes))]
    pub(super) hit_d: [Vec3; DIRS],
    pub(super) hit_s: [u16; SPAN * KEPT],
    /// Where `culled`, the hit group of each slot's hit (`NO_GROUP`: none), whose shadow lists
    /// shading takes without searching the groups for the hit's sphere.
    pub(super) hit_g: [u8; SPAN * KEPT],
    pub(super) row: List<S>,
    pub(super) span: List<S>,
    pub(super) pool: List<S>,
    /// The sphere of each hit group (`NONE`: unused, `REST`: every other sphere).
    pub(super) groups: [u16; GROUPS],
    /// Per group and light, its slice `a..b` of `pool`; [`ALL`] (`a > b`): test every sphere.
    pub(super) ranges: [[(u16, u16); L]; GROUPS],
    pub(super) span_start: u32,
    pub(super) span_end: u32,
    /// Shadow lists are valid for this span.
    pub(super) culled: bool,
    /// `hit_t`, `hit_s` hold the span's primary hits (one sample per pixel) as `t` and sphere
    /// (`NONE`: no hit), and `hit_d` (see [`DIRS`]) the direction of each hit's view ray: 6 or
    /// 18 bytes a pixel, for microcontroller stacks.
    pub(super) stored: bool,
    /// The same for every sample of a supersampled span, sample `m` of pixel `k` in slot
    /// `m·SPAN + k` (see [`KEPT`]). Apart from `stored` so that a pixel of one sample tests one
    /// flag, not also the sample count.
    pub(super) kept: bool,
    /// On hosts, the directions by coordinate (x, y, z), padded to whole lanes past the last
    /// slot: traced and shaded four columns at a time, a lane group is one load per
    /// coordinate (`Vec3`s would be transposed both ways).
    #[cfg(lanes)]
    pub(super) hit_dc: [[f32; DPAD]; 3],
    /// Where `culled`, each kept hit's point and offset from its sphere's centre, which the
    /// span's bounds take and shading reuses (see [`OFFS`]); the offset only for spheres
    /// beyond near2 (`Frame::offset_near`), whose offsets cost more than `f + t·d`.
    pub(super) hit_p: [Vec3; OFFS],
    pub(super) hit_o: [Vec3; OFFS],
    /// On hosts with f32 vectors (`cfg(lanes)`), the span's pixels that `Frame::shade_span4`
    /// shaded four at a time or found to be misses (bit `k` for pixel `k`), and all the span's
    /// pixels once `Frame::fill_span` has shaded the rest.
    #[cfg(lanes)]
    pub(super) done: u32,
    #[cfg(lanes)]
    pub(super) px: [Rgb888; SPAN],
    /// The pixel of every primary ray that hits nothing.
    pub(super) miss: Rgb888,
    /// On hosts, the rows a span gathers at once (`Frame::render_rows` with one sample a
    /// pixel and shadow rays: up to `KEPT`), row `r`'s hits in slots `r·SPAN + k`, and the
    /// first slot of the row being shaded.
    #[cfg(lanes)]
    pub(super) rows: u32,
    #[cfg(lanes)]
    pub(super) base: usize,
}

impl<const S: usize, const L: usize> Cull<S, L> {
    pub(super) fn new() -> Self {
        Cull {
            row: heapless::Vec::new(),
            span: heapless::Vec::new(),
            pool: heapless::Vec::new(),
            // Zeros, which the compiler writes in place (one `memset`), wherever `gather` writes
            // the field before it is read: the groups, their ranges and the slots.
            groups: [0; GROUPS],
            ranges: [[(0, 0); L]; GROUPS],
            span_start: 0,
            span_end: 0,
            culled: false,
            stored: false,
            kept: false,
            hit_t: [0.0; SPAN * KEPT],
            hit_s: [0; SPAN * KEPT],
            hit_g: [0; SPAN * KEPT],
            #[cfg(not(lanes))]
            hit_d: [Vec3::ZERO; DIRS],
            #[cfg(lanes)]
            hit_dc: [[0.0; DPAD]; 3],
            hit_p: [Vec3::ZERO; OFFS],
            hit_o: [Vec3::ZERO; OFFS],
            #[cfg(lanes)]
            done: 0,
            #[cfg(lanes)]
            px: [Rgb888::new(0, 0, 0); SPAN],
            miss: Rgb888::new(0, 0, 0),
            #[cfg(lanes)]
            rows: 1,
            #[cfg(lanes)]
            base: 0,
        }
    }

    /// The rows the span gathers at once (1 on Cortex-M).
    #[inline(always)]
    pub(super) fn rows(&self) -> u32 {
        #[cfg(lanes)]
        return self.rows;
        #[cfg(not(lanes))]
        1
    }

    /// The slot of pixel `k` of the row being shaded.
    #[inline(always)]
    pub(super) fn slot(&self, k: usize) -> usize {
        #[cfg(lanes)]
        return self.base + k;
        #[cfg(not(lanes))]
        k
    }

    /// The stored primary hit of the span's pixel `k`, as `(t, sphere)`.
    #[inline]
    pub(super) fn hit(&self, k: usize) -> Option<(f32, u16)> {
        match (self.hit_t.get(k), self.hit_s.get(k)) {
            (Some(&t), Some(&s)) if s != NONE => Some((t, s)),
            _ => None,
        }
    }

    /// Pixels in the current span (the lane paths').
    #[cfg(lanes)]
    #[inline(always)]
    pub(super) fn span_len(&self) -> usize {
        ((self.span_end - self.span_start) as usize).min(SPAN)
    }

    /// The view direction kept in slot `k` (none where `DIRS` keeps none).
    #[inline(always)]
    pub(super) fn dir(&self, k: usize) -> Option<Vec3> {
        #[cfg(lanes)]
        {
            let [x, y, z] = &self.hit_dc;
            Some(Vec3::new(*x.get(k)?, *y.get(k)?, *z.get(k)?))
        }
        #[cfg(not(lanes))]
        self.hit_d.get(k).copied()
    }

    /// Keeps `d` as the view direction of slot `k`, where there is room.
    #[inline(always)]
    pub(super) fn set_dir(&mut self, k: usize, d: Vec3) {
        #[cfg(lanes)]
        for (a, v) in self.hit_dc.iter_mut().zip([d.x, d.y, d.z]) {
            if let Some(a) = a.get_mut(k) {
                *a = v;
            }
        }
        #[cfg(not(lanes))]
        if let Some(a) = self.hit_d.get_mut(k) {
            *a = d;
        }
    }

    /// Records that the hits in `slots` joined group `g` (see `hit_g`).
    #[inline(always)]
    pub(super) fn set_group(&mut self, slots: core::ops::Range<usize>, g: u8) {
        if let Some(gs) = self.hit_g.get_mut(slots) {
            gs.fill(g);
        }
    }

    /// The shadow lists of the primary hit in `slot` (see `hit_g`), when the span has them.
    #[inline(always)]
    pub(super) fn lists_at(&self, slot: usize) -> Option<Lists<'_, L>> {
        if !self.culled {
            return None;
        }
        Some(Lists {
            ranges: self.ranges.get(*self.hit_g.get(slot)? as usize)?,
            pool: &self.pool,
        })
    }

    /// The shadow lists of a primary hit on `sphere`: its group's pool range per light; none
    /// where the span built no lists (`gather`, which every span's pixels come after, clears
    /// the groups first and names them only with shadow rays).
    #[inline]
    pub(super) fn lists(&self, sphere: usize) -> Option<Lists<'_, L>> {
        let mut g = None;
        for (k, &s) in self.groups.iter().enumerate() {
            if s as usize == sphere && s < REST {
                g = Some(k);
                break;
            }
            if s == REST {
                g = Some(k);
            }
        }
        Some(Lists {
            ranges: self.ranges.get(g?)?,
            pool: &self.pool,
        })
    }
}

/// The shadow lists of one primary hit (see [`Cull::lists`]).
#[derive(Debug, Clone, Copy)]
pub(super) struct Lists<'c, const L: usize> {
    pub(super) ranges: &'c [(u16, u16); L],
    pub(super) pool: &'c [u16],
}

impl<'c, const L: usize> Lists<'c, L> {
    /// Whether light `i` has no candidate blocker (its list is empty, not "every sphere").
    #[inline(always)]
    pub(super) fn is_empty(self, i: usize) -> bool {
        self.ranges.get(i).is_some_and(|&(a, b)| a == b)
    }

    /// The candidate blockers of light `i`, or `None` when it must test every sphere.
    #[inline]
    pub(super) fn light(self, i: usize) -> Option<&'c [u16]> {
        let (a, b) = self.ranges.get(i).copied()?;
        // The common case, no candidate, without the slice's bounds checks.
        if a == b {
            return Some(&[]);
        }
        // `ALL` has a > b: no slice.
        self.pool.get(a as usize..b as usize)
    }
}
