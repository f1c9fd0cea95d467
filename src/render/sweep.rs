//! Shadow sweeps: per light, its spheres sorted by a key across the light's direction, so that
//! a span's shadow candidates are found by a bucketed search instead of a scan.

use super::*;

/// What a scan hands its spheres to: one at a time, or four entries at once with a mask of
/// those that pass (bit `l` for `ids[l]`), which a collector can take without a branch per
/// entry. Any `FnMut(SphereId)` is one, taking the four one by one.
pub(super) trait Consider {
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
pub(super) fn push_masked<const S: usize>(list: &mut List<S>, ids: &[SphereId], keep: u32) -> bool {
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

/// One light's spheres sorted by a key, so that a span finds its possible shadow blockers by a
/// search in a bucket instead of testing every sphere, and filtered by a second key (`axis2`):
/// for a point light, the component along an axis across the light of the unit direction from
/// the light to the sphere, with the half-angle of the sphere's (padded) cone as half-width;
/// for a directional light, the position along an axis across the light, with the padded
/// radius as half-width. A sphere can block a shadow ray from a span only if its key interval
/// meets the span's (two unit directions at an angle θ differ by at most θ in any component; a
/// distance is at least the difference of its projections), so the band is a superset of
/// [`LightKind::may_block`]'s answers, which then decides.
/// Spheres much wider than the rest (a ground, a wall) would widen every band: they are kept
/// apart and always tested.
#[derive(Debug)]
pub(super) struct Sweep<const S: usize> {
    /// The wide spheres.
    pub(super) wide: List<S>,
    /// The rest sorted by key, by field: hosts weigh four entries at a time (`Frame::gather`).
    pub(super) key: heapless::Vec<f32, S>,
    /// Each one's half-width of its padded cone (angle) or radius (length) along the key.
    pub(super) half: heapless::Vec<f32, S>,
    /// Each one's coordinate along `axis2`.
    pub(super) key2: heapless::Vec<f32, S>,
    pub(super) sphere: List<S>,
    /// The largest half-width of the sorted ones.
    pub(super) hw_max: f32,
    /// Where a scan starts: `start[b]` counts the sorted entries whose [`Sweep::bucket`] is
    /// below `b` (one more than the buckets, the last the number of entries), so that a
    /// search for a key needs only its bucket's few entries, not a binary search over all of
    /// them (a chain of dependent loads). With slabs, each slab's index by `key2` follows
    /// ([`Sweep::first_in_slab`]).
    pub(super) start: heapless::Vec<u16, S>,
    /// The buckets of `key` (the slabs, with `slabs`), whose starts open `start`.
    pub(super) buckets: u16,
    /// The smallest key, and buckets per unit of key (zero: one bucket).
    pub(super) k_lo: f32,
    pub(super) per_key: f32,
    /// With slabs, each slab's index by `key2`.
    pub(super) by_key2: SlabIndex,
    /// The buckets are slabs (hosts, [`SLABS_FROM`] entries or more): a few long ones, each
    /// sorted by `key2` instead of `key`, so that a search takes the entries near the span in
    /// both keys, not all those in a slab across the scene.
    pub(super) slabs: bool,
    /// The key axis (unit, across the light: a point light's mean direction to the spheres).
    pub(super) axis: Vec3,
    /// A second axis (unit, across the light and `axis`), whose coordinates are each entry's
    /// `key2`: a sphere must be near the span in both keys, a tube along the light instead of
    /// a slab.
    pub(super) axis2: Vec3,
    /// How far along the light's rays each one begins ([`LightKind::near_depth`]).
    pub(super) depth: heapless::Vec<f32, S>,
}

/// The entries from which a host's sweep keeps slabs sorted by the second key
/// ([`Sweep::slabs`]): below it a scan of the band's few entries costs less than a search per
/// slab.
pub(super) const SLABS_FROM: usize = 4096;

/// Each slab's bucket index by `key2` ([`Sweep::first_in_slab`]): `per_slab` buckets a slab
/// (zero: none, a binary search), over the sweep's range of `key2` from `lo`, `per` buckets a
/// unit. Hosts only, whose large sweeps have slabs; elsewhere an empty type.
#[cfg(lanes)]
#[derive(Debug, Clone, Copy)]
pub(super) struct SlabIndex {
    pub(super) per_slab: u16,
    lo: f32,
    per: f32,
}

/// No slabs without lanes: nothing to index.
#[cfg(not(lanes))]
#[derive(Debug, Clone, Copy)]
pub(super) struct SlabIndex;

impl SlabIndex {
    #[cfg(lanes)]
    const NONE: Self = SlabIndex {
        per_slab: 0,
        lo: 0.0,
        per: 0.0,
    };
    #[cfg(not(lanes))]
    const NONE: Self = SlabIndex;
}

/// The bucket of `key` among `buckets` from `lo`, `per` to a unit: a subtraction, a product by a
/// constant ≥ 0 and a saturating conversion, each monotonic in IEEE arithmetic.
#[inline(always)]
fn bucket_of(key: f32, lo: f32, per: f32, buckets: usize) -> usize {
    let x = (key - lo) * per;
    // `!(x >= 0)` also takes a NaN (x = 0·∞) to the first bucket.
    if !(x >= 0.0) {
        0
    } else {
        (x as usize).min(buckets.saturating_sub(1))
    }
}

/// The start of each bucket `0..=buckets` of `keys`, along which `bucket` does not decrease:
/// the index (counted from `base`) of the first key whose bucket is that one or a later, given
/// to `out` bucket by bucket, which returns `false` to stop (and then so does this).
fn bucket_starts(
    keys: &[f32],
    base: usize,
    buckets: usize,
    bucket: impl Fn(f32) -> usize,
    mut out: impl FnMut(usize) -> bool,
) -> bool {
    let mut i = 0;
    for b in 0..=buckets {
        while keys.get(i).is_some_and(|&k| bucket(k) < b) {
            i += 1;
        }
        if !out(base + i) {
            return false;
        }
    }
    true
}

/// One sphere in a [`Sweep`], while it is built.
#[derive(Debug, Clone, Copy)]
pub(super) struct Entry {
    /// Its position along the sweep's axis (of its unit direction, for a point light).
    pub(super) key: f32,
    /// The half-width of its padded cone (angle) or radius (length) along the key.
    pub(super) half: f32,
    pub(super) sphere: SphereId,
    /// Its coordinate along `Sweep::axis2`.
    pub(super) key2: f32,
    /// How far along the light's rays it begins.
    pub(super) depth: f32,
}

impl Entry {
    pub(super) fn new(key: f32, half: f32, sphere: usize, key2: f32, depth: f32) -> Self {
        Entry {
            key,
            half,
            sphere: SphereId::new(sphere),
            key2,
            depth,
        }
    }
}

/// The room of a sweep's radix sort (hosts; [`Sweep::sort`]): as many entries as it sorts.
#[cfg(lanes)]
pub(super) type SortRoom<const S: usize> = heapless::Vec<Entry, S>;
/// Microcontrollers sort by comparisons, without room.
#[cfg(not(lanes))]
pub(super) type SortRoom<const S: usize> = ();

/// What a scan asks of a sweep's entries, for shadow rays from one ball ([`Sweep::band`]).
#[derive(Debug, Clone, Copy)]
pub(super) struct Band {
    /// The ball's key, and how far from it an entry's key may lie.
    pub(super) key: f32,
    pub(super) band: f32,
    /// What the ball adds to every half-width.
    pub(super) slack: f32,
    /// The ball's key along `Sweep::axis2`.
    pub(super) key2: f32,
    /// How far along the light's rays the ball reaches ([`LightKind::far_depth`]): an entry that
    /// begins beyond it lies behind the ball and blocks none of its shadow rays.
    pub(super) far: f32,
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
    pub(super) const fn empty() -> Self {
        Sweep {
            wide: heapless::Vec::new(),
            key: heapless::Vec::new(),
            half: heapless::Vec::new(),
            key2: heapless::Vec::new(),
            depth: heapless::Vec::new(),
            sphere: heapless::Vec::new(),
            hw_max: 0.0,
            start: heapless::Vec::new(),
            buckets: 0,
            k_lo: 0.0,
            per_key: 0.0,
            by_key2: SlabIndex::NONE,
            slabs: false,
            axis: Vec3::ZERO,
            axis2: Vec3::ZERO,
        }
    }

    /// The bucket of a key: a non-decreasing function of it (a subtraction, a product by a
    /// constant ≥ 0 and a saturating conversion, each monotonic in IEEE arithmetic), so that
    /// the entries before `start[bucket(x)]` have keys below `x` and those from
    /// `start[bucket(x) + 1]` keys above it.
    #[inline(always)]
    pub(super) fn bucket(&self, key: f32) -> usize {
        bucket_of(key, self.k_lo, self.per_key, self.buckets.into())
    }

    /// The bucket of `key2` within a slab, as [`Sweep::bucket`] is of `key`: non-decreasing.
    #[cfg(lanes)]
    #[inline(always)]
    fn bucket2(&self, key2: f32) -> usize {
        let x = &self.by_key2;
        bucket_of(key2, x.lo, x.per, x.per_slab.into())
    }

    /// Empties the sweep in place, as [`Sweep::empty`] is (lengths and scalars only).
    pub(super) fn clear(&mut self) {
        self.wide.clear();
        self.key.clear();
        self.half.clear();
        self.key2.clear();
        self.depth.clear();
        self.sphere.clear();
        self.hw_max = 0.0;
        self.start.clear();
        self.buckets = 0;
        self.k_lo = 0.0;
        self.per_key = 0.0;
        self.by_key2 = SlabIndex::NONE;
        self.slabs = false;
        self.axis = Vec3::ZERO;
        self.axis2 = Vec3::ZERO;
    }

    /// Sorts `spheres` for `light` into this sweep, which must be empty, sorting them in
    /// `all` (whatever it held is overwritten): no list of capacity size on the stack.
    pub(super) fn fill(
        &mut self,
        light: &Light,
        spheres: &[crate::Sphere],
        u: Vec3,
        v: Vec3,
        all: &mut heapless::Vec<Entry, S>,
        room: &mut SortRoom<S>,
    ) {
        // Keys across the light's direction (`LightKind::sweep_along`, else the view's),
        // where they spread the spheres the most.
        let along = light
            .sweep_along(spheres)
            .or_else(|| u.cross(v).normalized());
        let axis = along.and_then(|c| {
            // The camera's right (or up) vector without its component along `c`.
            let across = |a: Vec3| a - c * a.dot(c);
            let a = across(u);
            let a = if a.dot(a) > 0.01 { a } else { across(v) };
            a.normalized()
        });
        let (Some(along), Some(axis)) = (along, axis) else {
            return;
        };
        self.axis = axis;
        // The third coordinate, which the keys leave out, is then along the light, where a
        // scene's spheres seldom lie on both sides of a point light.
        self.axis2 = along.cross(axis).normalized().unwrap_or(Vec3::ZERO);
        let axis2 = self.axis2;
        all.clear();
        for (s, sphere) in spheres.iter().enumerate() {
            let (m, r) = (sphere.center, sphere.radius);
            let (key, half, key2) = light.sweep_entry(m, r, axis, axis2);
            let e = Entry::new(key, half, s, key2, light.near_depth(m, r));
            let _ = all.push(e);
        }
        // "Wide": more than 8 times the median half-width.
        // The median half-width, selected in `key`, which is empty until the sorted entries
        // fill it (a selection, not a sort: the same element, in linear time).
        let hws = &mut self.key;
        for e in all.iter() {
            let _ = hws.push(e.half);
        }
        let mid = hws.len() / 2;
        if mid < hws.len() {
            hws.select_nth_unstable_by(mid, |a, b| a.total_cmp(b));
        }
        let median = hws.get(mid).copied().unwrap_or(0.0);
        hws.clear();
        let is_wide =
            |e: &Entry| !(e.half <= 8.0 * median && e.key.is_finite() && e.key2.is_finite());
        for e in all.iter().filter(|e| is_wide(e)) {
            let _ = self.wide.push(e.sphere);
        }
        all.retain(|e| !is_wide(e));
        self.arrange(all, room);
    }

    /// Fills the sorted fields from `all` (the spheres that are not wide), which it sorts, and
    /// indexes them.
    pub(super) fn arrange(&mut self, all: &mut heapless::Vec<Entry, S>, room: &mut SortRoom<S>) {
        self.sort(all, false, |e| e.key, room);
        self.hw_max = all.iter().fold(self.hw_max, |m, e| m.max(e.half));
        let n = all.len();
        if cfg!(lanes) && n >= SLABS_FROM {
            // About √n / 2 slabs of 2√n entries: a search meets a slab or two, and in each
            // the entries of its window of `key2`. The index reads only the keys: the other
            // fields are filled once, after the slabs' sort.
            self.key.clear();
            for e in all.iter() {
                let _ = self.key.push(e.key);
            }
            self.index((libm::sqrtf(n as f32) * 0.5) as usize);
            self.slabs = true;
            // Each slab's entries by `key2`: the slabs stay where they are, a slab being a
            // run of keys (`bucket` is monotonic).
            self.sort(all, true, |e| e.key2, room);
            self.fill_fields(all);
            #[cfg(lanes)]
            self.index_slabs();
        } else {
            self.fill_fields(all);
            self.index((n / 4).max(1));
        }
    }

    /// The sorted fields, from `all`: at most S entries, so none of the pushes can fail.
    fn fill_fields(&mut self, all: &[Entry]) {
        self.key.clear();
        self.half.clear();
        self.key2.clear();
        self.depth.clear();
        self.sphere.clear();
        for e in all {
            let _ = self.key.push(e.key);
            let _ = self.half.push(e.half);
            let _ = self.key2.push(e.key2);
            let _ = self.depth.push(e.depth);
            let _ = self.sphere.push(e.sphere);
        }
    }

    /// Sorts `all` by `key`, or with `slabs` each slab's run of it (as `start` marks them): on
    /// hosts by a radix sort ([`radix_sort`]) through `room`, elsewhere by comparisons (no
    /// count table of 1 KiB on a microcontroller's stack, nor room in its RAM). Equal keys come
    /// in any order: a scan decides each entry by its keys, not by where it lies among equal
    /// ones.
    fn sort(
        &self,
        all: &mut [Entry],
        slabs: bool,
        key: impl Fn(&Entry) -> f32 + Copy,
        room: &mut SortRoom<S>,
    ) {
        let n = all.len();
        let runs = if slabs { usize::from(self.buckets) } else { 1 };
        let run = |b: usize| match slabs {
            false => Some((0, n)),
            true => Some((
                usize::from(*self.start.get(b)?),
                usize::from(*self.start.get(b + 1)?),
            )),
        };
        #[cfg(lanes)]
        {
            // As long as `all`: of the same capacity, so the copy cannot fail.
            room.clear();
            let _ = room.extend_from_slice(all);
        }
        #[cfg(not(lanes))]
        let _ = room;
        for b in 0..runs {
            let Some(items) = run(b).and_then(|(lo, hi)| all.get_mut(lo..hi)) else {
                continue;
            };
            #[cfg(lanes)]
            radix_sort(items, &mut room[..], key);
            #[cfg(not(lanes))]
            items.sort_unstable_by(|x, y| key(x).total_cmp(&key(y)));
        }
    }

    /// Indexes each slab by `key2` (`per_slab`), its starts after the slabs' in `start`: about
    /// four entries a bucket, over the range of every slab's `key2` (the slabs lie across it
    /// alike). Without room in `start` (never, from `SLABS_FROM` entries: the slabs' indexes
    /// take about a quarter as many starts), none: a slab is then searched.
    #[cfg(lanes)]
    fn index_slabs(&mut self) {
        let (n, slabs) = (self.key.len(), usize::from(self.buckets));
        let per_slab = (n / slabs.max(1) / 4).max(1);
        let (lo, hi) = self
            .key2
            .iter()
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(l, h), &k| {
                (if k < l { k } else { l }, if k > h { k } else { h })
            });
        let per = per_slab as f32 / (hi - lo);
        self.by_key2 = SlabIndex {
            // At most `n / 4`, and n ≤ S is below 2¹⁶ (`Frame::FITS`).
            per_slab: per_slab as u16,
            lo,
            per: if per.is_finite() { per } else { 0.0 },
        };
        for s in 0..slabs {
            let (Some(&first), Some(&end)) = (self.start.get(s), self.start.get(s + 1)) else {
                break;
            };
            let (first, x) = (first as usize, self.by_key2);
            let keys = self.key2.get(first..end as usize).unwrap_or(&[]);
            let start = &mut self.start;
            let bucket = |k| bucket_of(k, x.lo, x.per, per_slab);
            if !bucket_starts(keys, first, per_slab, bucket, |i| {
                start.push(i as u16).is_ok()
            }) {
                self.start.truncate(slabs + 1);
                self.by_key2 = SlabIndex::NONE;
                return;
            }
        }
    }

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
    pub(super) fn first(&self, x: f32) -> usize {
        self.first_in(self.bucket(x), x)
    }

    /// The index of the first key ≥ `x` in its bucket `b`.
    #[inline(always)]
    pub(super) fn first_in(&self, b: usize, x: f32) -> usize {
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
    pub(super) fn near_first(&self, x: f32) -> usize {
        let b = self.bucket(x);
        match (self.start.get(b), self.start.get(b + 1)) {
            (Some(&lo), Some(&hi)) if hi - lo <= 8 => lo as usize,
            _ => self.first_in(b, x),
        }
    }

    /// Builds `start` for the sorted keys: `buckets` (at least one), evenly spaced in key.
    pub(super) fn index(&mut self, buckets: usize) {
        self.start.clear();
        let buckets = buckets.max(1);
        if let (Some(&lo), Some(&hi)) = (self.key.first(), self.key.last()) {
            let per_key = buckets as f32 / (hi - lo);
            self.k_lo = lo;
            self.per_key = if per_key.is_finite() { per_key } else { 0.0 };
        }
        // At most S / 4 + 1 ≤ S values (or √S / 2 + 1), or two for no entry: only a sweep of
        // capacity 1 (never built, `SWEEPS`) could lack room, and `first` then searches all
        // keys.
        for _ in 0..=buckets {
            let _ = self.start.push(0);
        }
        // `start` holds at most S values, and S is below 2¹⁶ (`Frame::FITS`).
        self.buckets = self.start.len().saturating_sub(1) as u16;
        let (lo, per, n) = (self.k_lo, self.per_key, usize::from(self.buckets));
        let mut starts = self.start.iter_mut();
        let bucket = |k| bucket_of(k, lo, per, n);
        bucket_starts(&self.key, 0, buckets, bucket, |i| {
            if let Some(first) = starts.next() {
                *first = i as u16;
            }
            true
        });
    }

    /// Calls `consider` with every sphere that a shadow ray from within the band can meet: the
    /// wide ones, then those of [`Sweep::scan`].
    #[inline(always)]
    pub(super) fn each<const DEPTH: bool>(&self, b: Band, consider: &mut impl Consider) {
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
    pub(super) fn scan<const DEPTH: bool>(&self, b: Band, consider: &mut impl Consider) {
        if self.slabs {
            return self.scan_slabs::<DEPTH>(b, consider);
        }
        // The band's ends widened beyond the rounding of `key ± band` (`Band::reach`): an entry
        // on the filter's edge passes or fails by the rounding of `|k − key|`, which is not
        // that of the ends.
        let w = b.reach(b.key);
        let (hi, n) = (b.key + w, self.key.len());
        // Within a few entries of the first key ≥ key − w: the keys before that are more than
        // `band` from `key`, and the filter below decides those after it.
        let i = self.near_first(b.key - w);
        // Hosts first take four entries at a time (`Sweep::scan_lanes`); `None`: done.
        let Some(mut i) = self.scan_lanes::<DEPTH>(i, hi, b, consider) else {
            return;
        };
        while i < n {
            let (Some(&k), Some(&h), Some(&k2), Some(&d), Some(&s)) = (
                self.key.get(i),
                self.half.get(i),
                self.key2.get(i),
                self.depth_at::<DEPTH>(i),
                self.sphere.get(i),
            ) else {
                return;
            };
            if k > hi {
                return;
            }
            if self.passes::<DEPTH>(b, k, h, k2, d) {
                consider.one(s);
            }
            i += 1;
        }
    }

    /// Whether the entry of key `k`, half-width `h`, second key `k2` and depth `d` passes the
    /// filter of [`Sweep::scan`].
    #[inline(always)]
    fn passes<const DEPTH: bool>(&self, b: Band, k: f32, h: f32, k2: f32, d: f32) -> bool {
        // `&`, not `&&`: one branch on the outcome rather than three.
        let near = h + b.slack;
        // Not beyond: a NaN depth (coordinates that overflow) keeps the entry.
        let ahead = !DEPTH || !(d > b.far);
        (libm::fabsf(k - b.key) <= near) & (libm::fabsf(k2 - b.key2) <= near) & ahead
    }

    /// Entry `i`'s depth where `DEPTH` asks for it, else a stand-in that is never read.
    #[inline(always)]
    fn depth_at<const DEPTH: bool>(&self, i: usize) -> Option<&f32> {
        if DEPTH {
            self.depth.get(i)
        } else {
            Some(&0.0)
        }
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
            let Some(mut i) = self.slab_lanes::<DEPTH>(i, hi, hi2, b, consider) else {
                continue;
            };
            while i < hi {
                let (Some(&k), Some(&h), Some(&k2), Some(&d), Some(&s)) = (
                    self.key.get(i),
                    self.half.get(i),
                    self.key2.get(i),
                    self.depth_at::<DEPTH>(i),
                    self.sphere.get(i),
                ) else {
                    return;
                };
                if k2 > hi2 {
                    break;
                }
                if self.passes::<DEPTH>(b, k, h, k2, d) {
                    consider.one(s);
                }
                i += 1;
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
    pub(super) fn band(&self, light: &Light, q: Vec3, rho: f32) -> Option<(&Self, Band)> {
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
