//! Sphere ids: a sphere's index in its scene in two bytes, the size of the render path's
//! candidate lists and per-pixel slots.

/// The index of a sphere in its scene, or one of two markers the culling state needs: a slot
/// with no hit, a group of every other sphere. Two bytes rather than a `usize` (lists of
/// thousands per light), and no sphere index reaches the markers (`Frame::FITS`: capacity
/// below 65 533).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[repr(transparent)]
pub(crate) struct SphereId(u16);

impl SphereId {
    /// No sphere: a slot without a hit, a hit group not in use.
    pub(crate) const NONE: Self = SphereId(u16::MAX);
    /// Every sphere that has no hit group of its own (the last group of a span).
    pub(crate) const REST: Self = SphereId(u16::MAX - 1);

    /// The id of sphere `i`, an index into the scene's spheres (below `REST`).
    #[inline(always)]
    pub(crate) const fn new(i: usize) -> Self {
        SphereId(i as u16)
    }

    /// The scene index, for ids that name a sphere (a marker indexes nothing: `get` on the
    /// scene's spheres finds none).
    #[inline(always)]
    pub(crate) const fn index(self) -> usize {
        self.0 as usize
    }

    /// Whether the id names a sphere rather than a marker.
    #[inline(always)]
    pub(crate) const fn is_sphere(self) -> bool {
        self.0 < Self::REST.0
    }
}
