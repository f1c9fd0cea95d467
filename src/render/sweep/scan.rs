//! A sweep's scans: the spheres a light's sweep names for shadow rays from a ball, handed to a
//! [`Consider`] one at a time or four at once.

use super::*;

/// What a scan hands its spheres to: one at a time, or four entries at once with a mask of
/// those that pass (bit `l` for `ids[l]`), which a collector can take without a branch per
/// entry. Any `FnMut(SphereId)` is one, taking the four one by one.
pub(in crate::render) trait Consider {
    /// Sphere `s` passes.
    fn one(&mut self, s: SphereId);
    /// The spheres `ids[l]` whose bit `l` is set in `keep` pass, in lane order (hosts' scans).
    #[cfg_attr(not(lanes), allow(dead_code))]
    #[inline(always)]
    fn four(&mut self, ids: &[SphereId], keep: u32) {
        for (l, &s) in ids.iter().enumerate().take(4) {
            if keep & (1 << l) != 0 {
                self.one(s);
            }
        }
    }
}

impl<F: FnMut(SphereId)> Consider for F {
    #[inline(always)]
    fn one(&mut self, s: SphereId) {
        self(s)
    }
}

/// Appends to `list` the spheres `ids[l]` (at most four) whose bit `l` is set in `keep`, in
/// order; `false` when one of them did not fit. All are written and the length advanced past
/// those kept: no branch on each entry's outcome, which a scan over spheres side by side
/// mispredicts about as often as it is taken.
#[cfg_attr(not(lanes), allow(dead_code))]
#[inline(always)]
pub(in crate::render) fn push_masked<const S: usize>(
    list: &mut List<S>,
    ids: &[SphereId],
    keep: u32,
) -> bool {
    let ids = ids.get(..4).unwrap_or(ids);
    let mut n = list.len();
    if list.extend_from_slice(ids).is_err() {
        // Out of room for all of them: the kept ones one at a time.
        let mut fits = true;
        for (l, &s) in ids.iter().enumerate() {
            if keep & (1 << l) != 0 {
                fits &= list.push(s).is_ok();
            }
        }
        return fits;
    }
    for (l, &s) in ids.iter().enumerate() {
        if let Some(slot) = list.get_mut(n) {
            *slot = s;
        }
        n += ((keep >> l) & 1) as usize;
    }
    list.truncate(n);
    true
}

/// What a scan asks of a sweep's entries, for shadow rays from one ball ([`Sweep::band`]).
#[derive(Debug, Clone, Copy)]
pub(in crate::render) struct Band {
    /// The ball's key, and how far from it an entry's key may lie.
    pub(in crate::render) key: f32,
    pub(in crate::render) band: f32,
    /// What the ball adds to every half-width.
    pub(in crate::render) slack: f32,
    /// The ball's key along `Sweep::axis2`.
    pub(in crate::render) key2: f32,
    /// How far along the light's rays the ball reaches ([`LightKind::far_depth`]): an entry that
    /// begins beyond it lies behind the ball and blocks none of its shadow rays.
    pub(in crate::render) far: f32,
}

impl Band {
    /// How far from the key `k` (`key` or `key2`) a scan reads: `band` widened by 2⁻¹⁰ and a
    /// few ulp of `k`, far beyond the rounding of `k ± band`, so that every entry the filter
    /// passes (`|k_j − k| ≤ half_j + slack ≤ band`, each side rounded its own way) lies within.
    #[inline(always)]
    fn reach(&self, k: f32) -> f32 {
        self.band * (1.0 + 1.0 / 1024.0) + libm::fabsf(k) * (4.0 * f32::EPSILON)
    }
}

impl<const S: usize> Sweep<S> {
    /// The first entry of slab `slab` (entries `lo..hi`) whose `key2` is `k2` or more: from the
    /// start of `k2`'s bucket in the slab, where every entry before has a smaller bucket and
    /// so a smaller `key2`, a step at a time over the bucket's few smaller ones; a binary search
    /// (a chain of dependent loads, each a likely cache miss in a large sweep) where the slab
    /// has no index.
    #[inline(always)]
    fn first_in_slab(&self, slab: usize, (lo, hi): (usize, usize), k2: f32) -> usize {
        #[cfg(lanes)]
        {
            let (slabs, per) = (
                usize::from(self.buckets),
                usize::from(self.by_key2.per_slab),
            );
            let at = slabs + 1 + slab * (per + 1) + self.bucket2(k2);
            if let (Some(&i), true) = (self.start.get(at), per > 0) {
                let mut i = i as usize;
                while i < hi && self.key2.get(i).is_some_and(|&x| x < k2) {
                    i += 1;
                }
                return i;
            }
        }
        let _ = slab;
        lo + self
            .key2
            .get(lo..hi)
            .map_or(0, |k2s| k2s.partition_point(|&x| x < k2))
    }

    /// The index of the first key ≥ `x` (`key.partition_point(|&k| k < x)`), searched in
    /// `x`'s bucket only.
    #[cfg(test)]
    pub(in crate::render) fn first(&self, x: f32) -> usize {
        self.first_in(self.bucket(x), x)
    }

    /// The index of the first key ≥ `x` in its bucket `b`.
    #[inline(always)]
    pub(in crate::render) fn first_in(&self, b: usize, x: f32) -> usize {
        let (lo, hi) = (self.start.get(b), self.start.get(b + 1));
        let (lo, hi) = (
            lo.map_or(0, |&i| i as usize),
            hi.map_or(self.key.len(), |&i| i as usize),
        );
        lo + self
            .key
            .get(lo..hi)
            .map_or(0, |keys| keys.partition_point(|&k| k < x))
    }

    /// An index at or before the first key ≥ `x`, and at most 8 entries before it: its
    /// bucket's start where the bucket is that small (a search there costs more, in
    /// mispredicted branches, than scanning its keys in lanes).
    #[inline(always)]
    pub(in crate::render) fn near_first(&self, x: f32) -> usize {
        let b = self.bucket(x);
        match (self.start.get(b), self.start.get(b + 1)) {
            (Some(&lo), Some(&hi)) if hi - lo <= 8 => lo as usize,
            _ => self.first_in(b, x),
        }
    }

    /// Calls `consider` with every sphere that a shadow ray from within the band can meet: the
    /// wide ones, then those of [`Sweep::scan`].
    #[inline(always)]
    pub(in crate::render) fn each<const DEPTH: bool>(&self, b: Band, consider: &mut impl Consider) {
        for &s in &self.wide {
            consider.one(s);
        }
        self.scan::<DEPTH>(b, consider);
    }

    /// Calls `consider` with the sorted spheres, in their order, whose `|key_j − key| ≤
    /// half_j + slack`, `|key2_j − key2| ≤ half_j + slack` and, with `DEPTH`, `depth_j` not
    /// beyond `far`, among those with `key_j` within `band` of `key` (see [`Sweep::band`]),
    /// and a few before
    /// them that pass the same test only by rounding (a candidate more, which the shadow test
    /// decides). `DEPTH` where the list serves many shadow rays (a span's group): the depth
    /// costs every scan a test per entry, which a single ray's list (a secondary hit's) does
    /// not repay where the spheres lie side by side.
    #[inline(always)]
    pub(in crate::render) fn scan<const DEPTH: bool>(&self, b: Band, consider: &mut impl Consider) {
        if self.slabs {
            return self.scan_slabs::<DEPTH>(b, consider);
        }
        // The band's ends widened beyond the rounding of `key ± band` (`Band::reach`): an entry
        // on the filter's edge passes or fails by the rounding of `|k − key|`, which is not
        // that of the ends.
        let w = b.reach(b.key);
        let hi = b.key + w;
        // Within a few entries of the first key ≥ key − w: the keys before that are more than
        // `band` from `key`, and the filter below decides those after it.
        let i = self.near_first(b.key - w);
        // Hosts first take four entries at a time (`Sweep::scan_lanes`); `None`: done.
        if let Some(i) = self.scan_lanes::<DEPTH>(i, hi, b, consider) {
            self.run::<DEPTH>(i..self.key.len(), |e| e[0] > hi, b, consider);
        }
    }

    /// The scalar part of a scan: the entries of `at` in order, until one lies `beyond` the
    /// run (as the entries are sorted, so do the rest), each that passes handed to `consider`.
    #[inline(always)]
    fn run<const DEPTH: bool>(
        &self,
        at: core::ops::Range<usize>,
        beyond: impl Fn(&[f32; 4]) -> bool,
        b: Band,
        consider: &mut impl Consider,
    ) {
        for i in at {
            let Some((e, s)) = self.entry::<DEPTH>(i) else {
                return;
            };
            if beyond(&e) {
                return;
            }
            if self.passes::<DEPTH>(b, e) {
                consider.one(s);
            }
        }
    }

    /// Whether an entry (key, half-width, second key, depth: [`Sweep::entry`]) passes the
    /// filter of [`Sweep::scan`].
    #[inline(always)]
    fn passes<const DEPTH: bool>(&self, b: Band, [k, h, k2, d]: [f32; 4]) -> bool {
        // `&`, not `&&`: one branch on the outcome rather than three.
        let near = h + b.slack;
        // Not beyond: a NaN depth (coordinates that overflow) keeps the entry.
        let ahead = !DEPTH || !(d > b.far);
        (libm::fabsf(k - b.key) <= near) & (libm::fabsf(k2 - b.key2) <= near) & ahead
    }

    /// Entry `i` by field, `[key, half, key2, depth]` (the depth where `DEPTH` asks for it,
    /// else a stand-in that is never read), and its sphere; `None` past the last entry.
    #[inline(always)]
    fn entry<const DEPTH: bool>(&self, i: usize) -> Option<([f32; 4], SphereId)> {
        let d = if DEPTH { *self.depth.get(i)? } else { 0.0 };
        let fields = [*self.key.get(i)?, *self.half.get(i)?, *self.key2.get(i)?, d];
        Some((fields, *self.sphere.get(i)?))
    }

    /// [`Sweep::scan`] over slabs: the slabs of the keys within `band` of `key`, and in each
    /// the run of entries whose `key2` is within `band` of `key2` (a passing entry's `key2` is
    /// within its half-width and `slack`, at most `band`). Both windows are widened
    /// ([`Band::reach`]) and the filter then decides each entry as `scan` does: the same
    /// spheres, in another order.
    #[inline(never)]
    fn scan_slabs<const DEPTH: bool>(&self, b: Band, consider: &mut impl Consider) {
        let (w, w2) = (b.reach(b.key), b.reach(b.key2));
        let (lo2, hi2) = (b.key2 - w2, b.key2 + w2);
        for slab in self.bucket(b.key - w)..=self.bucket(b.key + w) {
            let (Some(&lo), Some(&hi)) = (self.start.get(slab), self.start.get(slab + 1)) else {
                return;
            };
            let (lo, hi) = (lo as usize, hi as usize);
            let i = self.first_in_slab(slab, (lo, hi), lo2);
            // Hosts first take four entries at a time (`Sweep::slab_lanes`); `None`: the run
            // has ended.
            if let Some(i) = self.slab_lanes::<DEPTH>(i, hi, hi2, b, consider) {
                self.run::<DEPTH>(i..hi, |e| e[2] > hi2, b, consider);
            }
        }
    }

    /// For shadow rays from the ball `(q, rho)`: the [`Band`] where the spheres to consider
    /// have `|key_j − key| ≤ half-width_j + slack` (so `key_j` within `band`) and, along
    /// `axis2`, `|key2_j − key2| ≤ half-width_j + slack`, with no depth bound (`far`
    /// infinite: a scan with `DEPTH` is given the ball's reach, [`LightKind::far_depth`]); or
    /// `None` when the sweep does not apply (no axis, or the light inside the ball).
    /// Inlined: a secondary hit's shadow ray asks it once per ray (`Frame::swept_blockers`).
    #[inline(always)]
    pub(in crate::render) fn band(
        &self,
        light: &Light,
        q: Vec3,
        rho: f32,
    ) -> Option<(&Self, Band)> {
        if self.axis == Vec3::ZERO {
            return None;
        }
        let (key, slack, key2) = light.band(q, rho, self.axis, self.axis2)?;
        if !(key.is_finite() && slack.is_finite() && key2.is_finite()) {
            return None;
        }
        let band = self.hw_max + slack;
        let far = f32::INFINITY;
        Some((
            self,
            Band {
                key,
                band,
                slack,
                key2,
                far,
            },
        ))
    }
}
