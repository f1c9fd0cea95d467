//! The per-row culling state: a span's hits, kept view directions and offsets, and the shadow
//! candidate lists of its groups.

use super::*;

/// The shadow candidates of one light for one hit group: every sphere ([`Candidates::ALL`]), or
/// the spheres `pool[start..end]` (`Cull::pool`). A pair with `ALL` as `start > end` rather than
/// an enum, so that the common question, whether there is no candidate, is one comparison: as
/// an enum, about 1 % more M4F instructions a pixel (`examples/firmware/run.sh m4f`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Candidates {
    start: u16,
    end: u16,
}

impl Candidates {
    /// Every sphere: the group has no bound, or its list did not fit in the pool.
    pub(super) const ALL: Candidates = Candidates {
        start: u16::MAX,
        end: 0,
    };

    /// The spheres `pool[start..end]`.
    #[inline(always)]
    pub(super) fn listed(start: u16, end: u16) -> Self {
        Candidates { start, end }
    }

    /// No candidate at all (not "every sphere").
    #[inline(always)]
    pub(super) fn is_empty(self) -> bool {
        self.start == self.end
    }

    /// The candidates in `pool`, or `None` for every sphere.
    #[inline]
    pub(super) fn of(self, pool: &[SphereId]) -> Option<&[SphereId]> {
        let Candidates { start, end } = self;
        // The common case, no candidate, without the slice's bounds checks.
        if start == end {
            return Some(&[]);
        }
        // `ALL` has start > end: no slice.
        pool.get(start as usize..end as usize)
    }
}

/// Which primary hits a span kept for shading (`SpanHits::kept`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Kept {
    /// None: shading traces each pixel's rays again.
    Nothing,
    /// One hit a pixel, in slot `k` of pixel `k` (or of the tile's row, `Cull::slot`): one
    /// sample a pixel, as `t` and sphere (`SphereId::NONE`: no hit), with the view direction where
    /// [`DIRS`] keeps it; 6 or 18 bytes a pixel, for microcontroller stacks.
    Pixels,
    /// Every sample of a supersampled span, sample `m` of pixel `k` in slot `m·SPAN + k` (see
    /// [`KEPT`]; hosts only).
    Samples,
}

/// The per-row state of the pixel loop: the current span's primary hits, the spheres primary
/// rays test, and the shadow candidate lists of the span's hit groups. `repr(C)` on Cortex-M:
/// see [`SpanHits`].
#[derive(Debug)]
#[cfg_attr(not(lanes), repr(C))]
pub(super) struct Cull<const S: usize, const L: usize> {
    /// The span's primary hits, slot by slot (first: see [`SpanHits`]).
    pub(super) hits: SpanHits,
    pub(super) spheres: Spheres<S>,
    pub(super) shadow: ShadowLists<S, L>,
    /// The span: columns `span_start..span_end` of the row.
    pub(super) span_start: u32,
    pub(super) span_end: u32,
    /// The pixel of every primary ray that hits nothing.
    pub(super) miss: Rgb888,
}

/// The primary hits a span keeps for its bounds and shading, slot by slot (see [`Kept`]).
///
/// On Cortex-M `repr(C)`, the per-slot arrays first (and [`Cull`] starts with them), so that a
/// new row's zeros (`Cull::new`) are written straight into the `Pixels` that `Frame::pixels` returns,
/// not built in a temporary and copied. Hosts keep the compiler's layout: `repr(C)` gains them
/// nothing.
#[derive(Debug)]
#[cfg_attr(not(lanes), repr(C))]
pub(super) struct SpanHits {
    /// Each slot's `t`.
    pub(super) t: [f32; SPAN * KEPT],
    /// What the render path keeps besides (`lanes/`, `scalar.rs`): the view directions, and on
    /// hosts the span's shaded pixels and the tile's rows.
    pub(super) path: PathState,
    /// Each slot's sphere (`SphereId::NONE`: no hit).
    pub(super) s: [SphereId; SPAN * KEPT],
    /// Where the span has shadow lists, the hit group of each slot's hit (`NO_GROUP`: none),
    /// whose lists shading takes without searching the groups for the hit's sphere.
    pub(super) g: [u8; SPAN * KEPT],
    /// Which primary hits the slots hold for shading.
    pub(super) kept: Kept,
    /// Where the span has shadow lists, each kept hit's point and offset from its sphere's
    /// centre, which the span's bounds take and shading reuses (see [`OFFS`]); the offset only
    /// for spheres beyond near2 (`Frame::offset_near`), whose offsets cost more than `f + t·d`.
    pub(super) p: [Vec3; OFFS],
    pub(super) o: [Vec3; OFFS],
}

/// The spheres primary rays test: those whose box crosses the row, and of those the ones whose
/// box meets the span, in scene order.
#[derive(Debug)]
pub(super) struct Spheres<const S: usize> {
    pub(super) row: List<S>,
    pub(super) span: List<S>,
    /// The row's list is sorted nearest first (hosts, `Frame::sort_piles`), and so is every
    /// span's drawn from it.
    pub(super) sorted: bool,
}

/// The shadow candidates of the span's hit groups: for each group and light the spheres that can
/// block its shadow rays from the group's bound, all in one pool of `S` indices (a light that
/// does not fit tests every sphere).
#[derive(Debug)]
pub(super) struct ShadowLists<const S: usize, const L: usize> {
    pub(super) pool: List<S>,
    /// The sphere of each hit group (`SphereId::NONE`: unused, `SphereId::REST`: every other
    /// sphere).
    pub(super) groups: [SphereId; GROUPS],
    /// Per group and light, its candidates.
    pub(super) ranges: [[Candidates; L]; GROUPS],
    /// The lists are valid for this span.
    pub(super) culled: bool,
}

impl<const S: usize, const L: usize> Cull<S, L> {
    pub(super) fn new() -> Self {
        Cull {
            // Zeros, which the compiler writes in place (one `memset`), wherever `gather` writes
            // the field before it is read: the groups, their ranges and the slots.
            hits: SpanHits {
                t: [0.0; SPAN * KEPT],
                path: PathState::new(),
                s: [SphereId::new(0); SPAN * KEPT],
                g: [0; SPAN * KEPT],
                kept: Kept::Nothing,
                p: [Vec3::ZERO; OFFS],
                o: [Vec3::ZERO; OFFS],
            },
            spheres: Spheres {
                row: heapless::Vec::new(),
                span: heapless::Vec::new(),
                sorted: false,
            },
            shadow: ShadowLists {
                pool: heapless::Vec::new(),
                groups: [SphereId::new(0); GROUPS],
                ranges: [[Candidates::listed(0, 0); L]; GROUPS],
                culled: false,
            },
            span_start: 0,
            span_end: 0,
            miss: Rgb888::new(0, 0, 0),
        }
    }

    /// The stored primary hit of the span's pixel `k`, as `(t, sphere)`.
    #[inline]
    pub(super) fn hit(&self, k: usize) -> Option<(f32, SphereId)> {
        match (self.hits.t.get(k), self.hits.s.get(k)) {
            (Some(&t), Some(&s)) if s != SphereId::NONE => Some((t, s)),
            _ => None,
        }
    }

    /// Records that the hits in `slots` joined group `g` (see `hit_g`).
    #[inline(always)]
    pub(super) fn set_group(&mut self, slots: core::ops::Range<usize>, g: u8) {
        if let Some(gs) = self.hits.g.get_mut(slots) {
            gs.fill(g);
        }
    }

    /// The shadow lists of the primary hit in `slot` (see `hit_g`), when the span has them.
    #[inline(always)]
    pub(super) fn lists_at(&self, slot: usize) -> Option<Lists<'_, L>> {
        if !self.shadow.culled {
            return None;
        }
        Some(Lists {
            ranges: self.shadow.ranges.get(*self.hits.g.get(slot)? as usize)?,
            pool: &self.shadow.pool,
        })
    }

    /// The shadow lists of a primary hit on `sphere`: its group's pool range per light; none
    /// where the span built no lists (`gather`, which every span's pixels come after, clears
    /// the groups first and names them only with shadow rays).
    #[inline]
    pub(super) fn lists(&self, sphere: usize) -> Option<Lists<'_, L>> {
        let mut g = None;
        for (k, &s) in self.shadow.groups.iter().enumerate() {
            if s.index() == sphere && s.is_sphere() {
                g = Some(k);
                break;
            }
            if s == SphereId::REST {
                g = Some(k);
            }
        }
        Some(Lists {
            ranges: self.shadow.ranges.get(g?)?,
            pool: &self.shadow.pool,
        })
    }
}

/// The shadow lists of one primary hit (see [`Cull::lists`]).
#[derive(Debug, Clone, Copy)]
pub(super) struct Lists<'c, const L: usize> {
    pub(super) ranges: &'c [Candidates; L],
    pub(super) pool: &'c [SphereId],
}

impl<'c, const L: usize> Lists<'c, L> {
    /// Whether light `i` has no candidate blocker (its list is empty, not "every sphere").
    #[inline(always)]
    pub(super) fn is_empty(self, i: usize) -> bool {
        self.ranges.get(i).is_some_and(|c| c.is_empty())
    }

    /// The candidate blockers of light `i`, or `None` when it must test every sphere.
    #[inline]
    pub(super) fn light(self, i: usize) -> Option<&'c [SphereId]> {
        self.ranges.get(i)?.of(self.pool)
    }
}
