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
    /// What the render path keeps besides (`lanes.rs`, `scalar.rs`): the view directions, and on
    /// hosts the span's shaded pixels and the tile's rows.
    pub(super) path: PathState,
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
    /// (`NONE`: no hit), and `path`'s directions (see [`DIRS`]) the direction of each hit's view ray: 6 or
    /// 18 bytes a pixel, for microcontroller stacks.
    pub(super) stored: bool,
    /// The same for every sample of a supersampled span, sample `m` of pixel `k` in slot
    /// `m·SPAN + k` (see [`KEPT`]). Apart from `stored` so that a pixel of one sample tests one
    /// flag, not also the sample count.
    pub(super) kept: bool,
    /// Where `culled`, each kept hit's point and offset from its sphere's centre, which the
    /// span's bounds take and shading reuses (see [`OFFS`]); the offset only for spheres
    /// beyond near2 (`Frame::offset_near`), whose offsets cost more than `f + t·d`.
    pub(super) hit_p: [Vec3; OFFS],
    pub(super) hit_o: [Vec3; OFFS],
    /// The pixel of every primary ray that hits nothing.
    pub(super) miss: Rgb888,
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
            path: PathState::new(),
            hit_p: [Vec3::ZERO; OFFS],
            hit_o: [Vec3::ZERO; OFFS],
            miss: Rgb888::new(0, 0, 0),
        }
    }

    /// The stored primary hit of the span's pixel `k`, as `(t, sphere)`.
    #[inline]
    pub(super) fn hit(&self, k: usize) -> Option<(f32, u16)> {
        match (self.hit_t.get(k), self.hit_s.get(k)) {
            (Some(&t), Some(&s)) if s != NONE => Some((t, s)),
            _ => None,
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
