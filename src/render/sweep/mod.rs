//! Shadow sweeps: per light, its spheres sorted by a key across the light's direction, so that
//! a span's shadow candidates are found by a bucketed search instead of a scan.

use super::*;

mod scan;
#[cfg(lanes)]
pub(super) use scan::push_masked;
pub(super) use scan::{Band, Consider};

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
/// ([`Sweep::slabs`]). Below it they would save a frame of spread or clustered spheres 0.2–1.0 %
/// of its instructions (their sort included) and cost a frame of mirrors 0.4–0.8 %, whose
/// secondary hits each search a sweep for a small ball (`bench/scale_scenes.py`'s scenes of 300
/// to 511 spheres).
pub(super) const SLABS_FROM: usize = 512;

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

/// The room of a sweep's radix sort (hosts; [`Sweep::sort`]): at least as many entries as it
/// sorts, whatever they hold.
#[cfg(lanes)]
pub(super) type SortRoom<const S: usize> = heapless::Vec<Entry, S>;
/// Microcontrollers sort by comparisons, without room.
#[cfg(not(lanes))]
pub(super) type SortRoom<const S: usize> = ();

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
        if room.len() < n {
            // The sort needs the room's length, not its contents: grown only when short (to
            // at most S, its capacity, so this cannot fail), never copied from `all`.
            let _ = room.resize(n, Entry::new(0.0, 0.0, 0, 0.0, 0.0));
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
}
