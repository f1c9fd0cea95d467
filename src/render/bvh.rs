//! The culling of secondary rays. Mirror and refracted rays, and the shadow rays of their hits,
//! leave from anywhere in any direction, so neither the screen boxes nor the lights' sweeps
//! bound them: a hierarchy of bounding boxes over the scene's spheres, built once a frame in
//! the caller's storage, names the spheres such a ray can meet. Each of those is asked with the
//! brute-force test, and ties are broken as the brute-force loop breaks them, so the hits are
//! its hits, bit for bit. A node has up to four children, whose boxes a walk tests at once,
//! in vector lanes on hosts: half the levels of a binary tree, and a quarter of the tests.
//! A closest-hit search asks a leaf's spheres at once too, one ray against four spheres in
//! lanes: only those that the scalar test would not reject at its first steps take it.
//! Boxes, not balls: a layer of spheres is thin along one axis, which a ball about it is not
//! (mirrors1024: 10 % fewer boxes opened than balls, 11 % faster).
//!
//! Built where the capacity is above 8 (`Frame::SWEEPS`: a microcontroller's scene links none of
//! it) and the scene has more than [`MIN_SPHERES`] spheres, for scenes with secondary rays.
//! Below that a ray tests every sphere, and hosts find and shade the mirror rays of four
//! pixels together (`lanes/mirror.rs`): all glass, at 48 spheres the hierarchy took 1.02 times
//! as long and at 56 0.89 times; all mirrors, at 56 1.03 times and at 64 0.93 times
//! (`bench/ab.sh`). Glass, whose rays the lanes do not take, sets the one threshold.

use super::*;
use crate::math::IeeeCmp;
use crate::Sphere;

/// Up to this many spheres a ray tests them all: the walk costs more than it saves.
pub(super) const MIN_SPHERES: usize = 48;
/// Spheres a leaf holds at most.
const LEAF: usize = 4;
/// The traversal's stack (and the build's): median splits make the tree at most
/// ⌈log₂ S⌉ / 2 + 1 ≤ 9 deep, each level leaves at most three balls on it and the last four:
/// 3 · 9 + 4 ≤ 32. A smaller stack is a smaller `Walk` to set up for every ray.
const DEPTH: usize = 32;
/// The relative pad of every bound: 2⁻¹⁶, far above the few ε by which the tests of the
/// spheres themselves and these bounds round.
const PAD: f32 = 1.0 / 65_536.0;
/// Below this a square may have lost bits to underflow: such a bound culls nothing.
const TINY: f32 = 1e-30;

/// A node of the tree: a leaf, the spheres `order[first..first + count]`, or (`count == 0`) an
/// inner node whose `children` (two to four) are the nodes `first..first + children`. Its
/// bounding box is in [`Bvh::boxes`].
#[derive(Debug, Clone, Copy)]
pub(super) struct Node {
    first: u16,
    count: u16,
    children: u8,
}

/// The hierarchy over a scene's spheres (see the module's documentation).
#[derive(Debug)]
pub(super) struct Bvh<const S: usize> {
    nodes: heapless::Vec<Node, S>,
    /// The nodes' bounding boxes, padded ([`Probe`]), by coordinate: low x, y, z, then high
    /// x, y, z. A node's children are consecutive, so a walk tests up to four of them in one
    /// set of vector lanes.
    boxes: [heapless::Vec<f32, S>; 6],
    /// The spheres of the leaves, leaf by leaf.
    order: List<S>,
    /// Spheres above 8 times the median radius (a ground, a wall), kept out of the tree, whose
    /// boxes they would swell, and always tested.
    wide: List<S>,
    /// Whether the frame has a hierarchy: else every sphere is tested.
    built: bool,
}

/// A ray or segment asked about: from `o = anchor + rel` along `d`, over `0 ≤ t ≤ tmax`, as
/// the slabs of a box see it. Every box is padded by [`PAD`] of every length the spheres' own
/// tests round with: a sphere's test reports a hit only where the exact ray passes within a few
/// ε of those of it (the distance from the origin, `rel`, the radius, and `reach`, which bounds
/// the length of `tmax·d` where that is finite and the ray's test rounds with it: a point
/// light's shadow ray, cast from the light). The distance is bounded by the coordinates'
/// magnitudes, half of it in the stored boxes ([`Bvh::fill`]) and half here: far from the
/// origin the boxes are looser, never too tight.
#[derive(Debug, Clone, Copy)]
struct Probe {
    /// Per axis, the origin's coordinate moved by the pad, so that `(plane − o)` reaches the
    /// padded near and far planes: `near − (o + pad)` is `(near − pad) − o` within the ε of
    /// the coordinates, which the pad is far above.
    near_o: [f32; 3],
    far_o: [f32; 3],
    /// `1/d` per axis: ±∞ where `d` has a zero there (a ray parallel to the slab).
    inv: [f32; 3],
    /// Per axis, whether the ray runs down it (`1/d < 0`, −0 included): its near plane is then
    /// the box's high side, else the low side.
    down: [bool; 3],
    /// Whether the slabs decide: `d` is long enough to square without underflow, every
    /// component is zero or large enough that `1/d` is finite, and `o` and the pad are finite.
    /// Else every box meets the ray.
    sure: bool,
}

impl Probe {
    #[inline(always)]
    fn new(anchor: Vec3, rel: Vec3, d: Vec3, reach: f32) -> Self {
        let o = anchor + rel;
        let pad = PAD * (2.0 * o.max_abs() + 4.0 * rel.max_abs() + reach) + f32::MIN_POSITIVE;
        let (o, d) = ([o.x, o.y, o.z], [d.x, d.y, d.z]);
        let inv = d.map(|x| 1.0 / x);
        let up = inv.map(|i| i >= 0.0);
        let down = up.map(|u| !u);
        let near_o = core::array::from_fn(|k| if up[k] { o[k] + pad } else { o[k] - pad });
        let far_o = core::array::from_fn(|k| if up[k] { o[k] - pad } else { o[k] + pad });
        // A component below 10⁻³⁰ (but not zero) has a reciprocal above 10³⁰, which
        // overflows below 2⁻¹²⁸, and whose products with the planes' distances could overflow
        // where their ratios are finite: such a ray culls nothing.
        let small = |x: f32| x != 0.0 && libm::fabsf(x) < 1e-30;
        let a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        let finite = crate::math::finite;
        let sure =
            a > TINY && !d.iter().any(|&x| small(x)) && o.iter().all(|&x| finite(x)) && finite(pad);
        Probe {
            near_o,
            far_o,
            inv,
            down,
            sure,
        }
    }

    /// The slabs' constants as lanes of `P`, splat once for a walk rather than at every node.
    #[inline(always)]
    fn slabs<P: IeeeCmp>(&self) -> Slabs<P> {
        let v = |[a, b, c]: [f32; 3]| [P::splat(a), P::splat(b), P::splat(c)];
        Slabs {
            near_o: v(self.near_o),
            far_o: v(self.far_o),
            inv: v(self.inv),
        }
    }
}

/// A [`Probe`]'s origins and reciprocals, each splat across the lanes of `P`.
#[derive(Debug, Clone, Copy)]
struct Slabs<P> {
    near_o: [P; 3],
    far_o: [P; 3],
    inv: [P; 3],
}

impl<P: IeeeCmp> Slabs<P> {
    /// Whether the ray can meet a sphere inside the boxes whose near planes are `near` and far
    /// planes `far` (one box, or four in lanes) before `limit`, as the sphere's own test decides,
    /// and each box's key: a `t` at or before any point of it on the ray.
    ///
    /// Each slab gives its `t` interval as `(plane − o)·(1/d)`, whose rounding (a few ε of
    /// `|plane − o|/|d|`) the pad's margin (at least `pad/|d|` on both sides of any `t` where
    /// the exact ray is inside the unpadded box) is far above. A comparison that culls is false
    /// where an operand is NaN (a zero `d` component whose ray lies on a padded plane), and
    /// [`IeeeCmp::greater`] and [`IeeeCmp::lesser`] drop or keep such a slab: either culls less.
    #[inline(always)]
    fn meets_boxes(&self, near: [P; 3], far: [P; 3], limit: f32) -> (P::Mask, P) {
        let t = |p: P, o: P, inv: P| (p - o) * inv;
        let [n0, n1, n2] = near;
        let [f0, f1, f2] = far;
        let [i0, i1, i2] = self.inv;
        let (no, fo) = (self.near_o, self.far_o);
        let enter = t(n0, no[0], i0)
            .greater(t(n1, no[1], i1))
            .greater(t(n2, no[2], i2));
        let leave = t(f0, fo[0], i0)
            .lesser(t(f1, fo[1], i1))
            .lesser(t(f2, fo[2], i2));
        let culled = enter.gt(leave) | leave.lt(P::splat(0.0)) | enter.gt(P::splat(limit));
        (!culled, enter)
    }
}

/// The bound `beyond` which a box's key lies wholly past `t = tmax`, past the rounding of the
/// key and of the hits' own `t` (`tmax` is one of them).
#[inline(always)]
fn limit(tmax: f32) -> f32 {
    tmax * (1.0 + PAD)
}

impl<const S: usize> Bvh<S> {
    pub(super) const EMPTY: Self = Bvh {
        nodes: heapless::Vec::new(),
        boxes: [const { heapless::Vec::new() }; 6],
        order: heapless::Vec::new(),
        wide: heapless::Vec::new(),
        built: false,
    };

    /// Builds the hierarchy over `spheres` (at most `S`) in place, or none for a few spheres.
    pub(super) fn fill(&mut self, spheres: &[Sphere]) {
        self.nodes.clear();
        for b in &mut self.boxes {
            b.clear();
        }
        self.order.clear();
        self.wide.clear();
        self.built = false;
        if spheres.len() <= MIN_SPHERES {
            return;
        }
        // The median radius: `order` sorted by radius up to its middle, as scratch.
        for s in 0..spheres.len() {
            let _ = self.order.push(SphereId::new(s));
        }
        let radius = |s: &SphereId| spheres.get(s.index()).map_or(0.0, |x| x.radius);
        let mid = self.order.len() / 2;
        if mid < self.order.len() {
            self.order
                .select_nth_unstable_by(mid, |a, b| radius(a).total_cmp(&radius(b)));
        }
        let median = self.order.get(mid).map_or(0.0, radius);
        self.order.clear();
        for (s, sphere) in spheres.iter().enumerate() {
            let list = if sphere.radius <= 8.0 * median {
                &mut self.order
            } else {
                &mut self.wide
            };
            let _ = list.push(SphereId::new(s));
        }
        // Nodes by median splits along the widest axis of their centres, depth first: a node
        // of n > LEAF spheres is halved, and each half of more than LEAF halved again, into two
        // to four children of at least two spheres each (⌊n/2⌋ and ⌈n/2⌉ ≥ 2). Leaves hold at
        // least two spheres and every inner node has two children or more, so the tree has at
        // most n − 1 nodes: `S` is room enough.
        let mut todo: heapless::Vec<(usize, usize, usize), DEPTH> = heapless::Vec::new();
        if !self.order.is_empty() {
            self.add_node();
            let _ = todo.push((0, 0, self.order.len()));
        }
        while let Some((k, lo, hi)) = todo.pop() {
            let Some(ids) = self.order.get_mut(lo..hi) else {
                continue;
            };
            let (low, high, axis) = bound(spheres, ids);
            // The half of the pad that the box's coordinates bound ([`Probe`]): the distance
            // from any origin to a sphere in it, less the origin's magnitude, and the radius.
            let pad = PAD * 4.0 * low.max_abs().max(high.max_abs()) + f32::MIN_POSITIVE;
            let (l, h) = (low - Vec3::splat(pad), high + Vec3::splat(pad));
            for (b, v) in self.boxes.iter_mut().zip([l.x, l.y, l.z, h.x, h.y, h.z]) {
                if let Some(slot) = b.get_mut(k) {
                    *slot = v;
                }
            }
            let mut node = Node {
                first: lo as u16,
                count: (hi - lo) as u16,
                children: 0,
            };
            let child = self.nodes.len();
            if hi - lo > LEAF && child + 4 <= S && todo.len() + 4 <= DEPTH {
                let mid = lo + split(spheres, ids, axis);
                let mut groups: heapless::Vec<(usize, usize), 4> = heapless::Vec::new();
                for (a, b) in [(lo, mid), (mid, hi)] {
                    match self.order.get_mut(a..b) {
                        Some(half) if b - a > LEAF => {
                            let (_, _, axis) = bound(spheres, half);
                            let m = a + split(spheres, half, axis);
                            let _ = groups.push((a, m));
                            let _ = groups.push((m, b));
                        }
                        _ => {
                            let _ = groups.push((a, b));
                        }
                    }
                }
                node.first = child as u16;
                node.count = 0;
                node.children = groups.len() as u8;
                for (g, &(a, b)) in groups.iter().enumerate() {
                    self.add_node();
                    let _ = todo.push((child + g, a, b));
                }
            }
            if let Some(slot) = self.nodes.get_mut(k) {
                *slot = node;
            }
        }
        self.built = true;
    }

    /// Appends a node to fill in, with its box.
    fn add_node(&mut self) {
        let _ = self.nodes.push(Node {
            first: 0,
            count: 0,
            children: 0,
        });
        for b in &mut self.boxes {
            let _ = b.push(0.0);
        }
    }

    /// The planes a walk along `probe` reads, chosen once for its ray ([`Planes`]).
    #[inline(always)]
    fn planes(&self, probe: &Probe) -> Planes<'_> {
        // Axis `k`'s low side is `boxes[k]`, its high side `boxes[k + 3]`.
        let side = |k: usize, high: bool| {
            self.boxes
                .get(k + 3 * high as usize)
                .map_or(&[][..], |b| b.as_slice())
        };
        let [d0, d1, d2] = probe.down;
        Planes {
            near: [side(0, d0), side(1, d1), side(2, d2)],
            far: [side(0, !d0), side(1, !d1), side(2, !d2)],
        }
    }

    /// Whether the frame has a hierarchy (else every sphere is tested).
    #[inline(always)]
    pub(super) fn built(&self) -> bool {
        self.built
    }

    /// The spheres a shadow ray from `hit` towards `light` (`v` its `to_light`) can meet: the
    /// wide ones, then the tree's leaves whose boxes the ray or segment passes.
    #[inline(always)]
    pub(super) fn shadow_candidates<'b>(
        &'b self,
        hit: &Hit,
        light: &Light,
        v: Vec3,
    ) -> impl Iterator<Item = usize> + 'b {
        // A point light's segment ends at the light (t = 1), and its test may be cast from
        // there, rounding with the segment's length; a directional light's ray has no end.
        let (tmax, reach) = match light.origin() {
            Some(_) => (1.0, 1.75 * v.max_abs()),
            None => (f32::INFINITY, 0.0),
        };
        let probe = Probe::new(hit.anchor, hit.rel, v, reach);
        let walk = Walk::new(self, probe, tmax);
        self.wide.iter().map(|s| s.index()).chain(walk)
    }

    /// [`find_from`](crate::shading::find_from) over the spheres the tree names: the same hit,
    /// bit for bit.
    pub(super) fn find_from<const L: usize>(
        &self,
        scene: &Scene<S, L>,
        ray: &Ray,
        hit: &Hit,
    ) -> Option<Hit> {
        use crate::shading::{closest_hit, leaving_own};
        let spheres = scene.spheres();
        let mut best = leaving_own(spheres, ray, hit);
        // The brute-force loop asks `from` first, then the others in scene order, each with
        // the closest `t` so far as its `tmax` (a closed bound): of equal `t`s the last in that
        // order wins. A sphere's `t` does not depend on `tmax`, which only accepts it.
        let probe = Probe::new(hit.anchor, hit.rel, ray.dir, 0.0);
        let mut walk = Walk::new(self, probe, f32::INFINITY);
        let d = ray.dir;
        for s in &self.wide {
            ask(spheres, s.index(), hit, d, &mut best, &mut walk);
        }
        while let Some(leaf) = walk.next_leaf() {
            for four in leaf.chunks(4) {
                let mut open = open_among(spheres, four, hit, d);
                while open != 0 {
                    let l = open.trailing_zeros() as usize;
                    open &= open - 1;
                    if let Some(s) = four.get(l) {
                        ask(spheres, s.index(), hit, d, &mut best, &mut walk);
                    }
                }
            }
        }
        best.map(|b| closest_hit(scene, ray, hit, b))
    }
}

/// [`Bvh::find_from`]'s question to sphere `j`: its hit along `d` from `hit` (none for `hit`'s
/// own sphere, which `leaving_own` answered), which replaces `best` where the brute-force loop's
/// order would let it win, and then limits the walk. A function, not a closure called from two
/// places, so that it is inlined in both.
#[inline(always)]
fn ask<'s, const S: usize>(
    spheres: &'s [Sphere],
    j: usize,
    hit: &Hit,
    d: Vec3,
    best: &mut Option<crate::shading::Closest<'s>>,
    walk: &mut Walk<'_, S>,
) {
    let from = hit.sphere;
    let Some(s) = spheres.get(j) else {
        return;
    };
    if j == from {
        return;
    }
    let tmax = best.map_or(f32::INFINITY, |b| b.0);
    let Some((t, f)) = Prepared::leaving_hit(hit.anchor, hit.rel, s, d, T_EPS, tmax) else {
        return;
    };
    let wins = match *best {
        Some((tb, jb, ..)) => t < tb || jb == from || j > jb,
        None => true,
    };
    if wins {
        *best = Some((t, j, f, s));
        walk.tmax = t;
    }
}

/// Splits `ids` at its middle, the spheres whose centres lie lower along `axis` first: the
/// length of the first half.
fn split(spheres: &[Sphere], ids: &mut [SphereId], axis: usize) -> usize {
    let mid = ids.len() / 2;
    let key = |s: &SphereId| {
        let m = spheres.get(s.index()).map_or(Vec3::ZERO, |x| x.center);
        [m.x, m.y, m.z].get(axis).copied().unwrap_or(0.0)
    };
    if mid < ids.len() {
        ids.select_nth_unstable_by(mid, |a, b| key(a).total_cmp(&key(b)));
    }
    mid
}

/// The box holding the spheres `ids` (each coordinate rounded once: the pad covers it), and
/// the axis along which their centres spread the most.
fn bound(spheres: &[Sphere], ids: &[SphereId]) -> (Vec3, Vec3, usize) {
    let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
    let (mut clo, mut chi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
    for s in ids.iter().filter_map(|s| spheres.get(s.index())) {
        let m = [s.center.x, s.center.y, s.center.z];
        for k in 0..3 {
            lo[k] = lo[k].min(m[k] - s.radius);
            hi[k] = hi[k].max(m[k] + s.radius);
            clo[k] = clo[k].min(m[k]);
            chi[k] = chi[k].max(m[k]);
        }
    }
    let spread = [chi[0] - clo[0], chi[1] - clo[1], chi[2] - clo[2]];
    let axis = if spread[0] >= spread[1] && spread[0] >= spread[2] {
        0
    } else if spread[1] >= spread[2] {
        1
    } else {
        2
    };
    (Vec3::from(lo), Vec3::from(hi), axis)
}

/// Per axis, the boxes' near planes for one ray (their high side where it runs down the axis,
/// else the low side) and their far planes: a node's children are consecutive, so one slice
/// gives the four planes of its children to load at once.
#[derive(Debug, Clone, Copy)]
struct Planes<'b> {
    near: [&'b [f32]; 3],
    far: [&'b [f32]; 3],
}

/// The lanes a walk tests boxes in: four f32 where there are lanes, else one.
#[cfg(lanes)]
type Lane = crate::simd::F;
#[cfg(not(lanes))]
type Lane = f32;

/// A walk of the tree for one ray: the spheres of every leaf whose box the ray can meet
/// within `tmax`, which the caller may lower as it goes (a closest-hit search). Each box is
/// tested when its parent is opened, and its key kept beside it on the stack, so that a box
/// pushed before a nearer hit lowered `tmax` is dropped without testing it again.
struct Walk<'b, const S: usize> {
    bvh: &'b Bvh<S>,
    planes: Planes<'b>,
    slabs: Slabs<Lane>,
    /// Whether the slabs decide ([`Probe::sure`]): else every box meets the ray.
    sure: bool,
    tmax: f32,
    /// Nodes to open and their keys; `u32`, not `u16`, so that an entry has no padding and
    /// the walk's zero fill is a few wide stores.
    stack: [(u32, f32); DEPTH],
    top: usize,
    leaf: core::slice::Iter<'b, SphereId>,
}

impl<'b, const S: usize> Walk<'b, S> {
    /// A walk from the root, whose own box is not tested: its children's are, when it is
    /// opened. (Built as one value, which the caller's `let` holds without a copy.)
    #[inline(always)]
    fn new(bvh: &'b Bvh<S>, probe: Probe, tmax: f32) -> Self {
        // Zeros but for the root's key: a fill the compiler writes sixteen bytes at a time.
        let mut stack = [(0, 0.0); DEPTH];
        stack[0] = (0, f32::NEG_INFINITY);
        Walk {
            bvh,
            planes: bvh.planes(&probe),
            slabs: probe.slabs(),
            sure: probe.sure,
            tmax,
            stack,
            top: usize::from(!bvh.nodes.is_empty()),
            leaf: [].iter(),
        }
    }
}

impl<'b, const S: usize> Walk<'b, S> {
    /// Whether the ray can meet the boxes of nodes `first..first + n` (`n ≤ 4`) before
    /// `limit`, as bits `0..n`, and their keys ([`Slabs::meets_boxes`]): four lanes at once
    /// where there are lanes, else one box after another.
    #[inline(always)]
    fn meets4(&self, first: usize, n: usize, limit: f32) -> (u32, [f32; 4]) {
        let all = (1u32 << n) - 1;
        if !self.sure {
            return (all, [f32::NEG_INFINITY; 4]);
        }
        // The four planes from `first`; past the last node, lanes repeat it (masked off).
        let lanes = |b: &[f32]| -> [f32; 4] {
            match b.get(first..first + 4) {
                Some(&[a, b, c, d]) => [a, b, c, d],
                _ => {
                    core::array::from_fn(|l| b.get(first + l).or(b.last()).copied().unwrap_or(0.0))
                }
            }
        };
        let ([n0, n1, n2], [f0, f1, f2]) = (self.planes.near, self.planes.far);
        let near = [lanes(n0), lanes(n1), lanes(n2)];
        let far = [lanes(f0), lanes(f1), lanes(f2)];
        #[cfg(lanes)]
        {
            use crate::simd::{bits, F};
            let f = |[a, b, c]: [[f32; 4]; 3]| [F::from(a), F::from(b), F::from(c)];
            let (meets, key) = self.slabs.meets_boxes(f(near), f(far), limit);
            (bits(meets) & all, key.to_array())
        }
        #[cfg(not(lanes))]
        {
            let (mut meets, mut keys) = (0, [0.0; 4]);
            for (l, key) in keys.iter_mut().enumerate().take(n) {
                let at = |p: [[f32; 4]; 3]| p.map(|c| c[l]);
                let (m, k) = self.slabs.meets_boxes(at(near), at(far), limit);
                meets |= (m as u32) << l;
                *key = k;
            }
            (meets & all, keys)
        }
    }

    /// The spheres of the next leaf whose box the ray can meet within `tmax`, nearest boxes
    /// first; `None` once none is left.
    #[inline(always)]
    fn next_leaf(&mut self) -> Option<&'b [SphereId]> {
        // The node to open next: the nearest child of the last one opened, held here rather
        // than pushed and popped again, or else the top of the stack.
        let mut next: Option<usize> = None;
        loop {
            let k = match next.take() {
                Some(k) => k,
                None => {
                    if self.top == 0 {
                        return None;
                    }
                    self.top -= 1;
                    let (k, key) = *self.stack.get(self.top)?;
                    if key > limit(self.tmax) {
                        continue;
                    }
                    k as usize
                }
            };
            let node = *self.bvh.nodes.get(k)?;
            let (first, count) = (node.first as usize, node.count as usize);
            if count > 0 {
                return self.bvh.order.get(first..first + count);
            }
            if self.top + 4 > DEPTH {
                // Cannot happen: the build splits a node only while its own stack, which the
                // walk's mirrors, has room. Were it to, every sphere is named (again): a
                // sphere asked twice changes no answer.
                self.top = 0;
                return Some(&self.bvh.order);
            }
            let limit = limit(self.tmax);
            let (meets, keys) = self.meets4(first, node.children as usize, limit);
            if meets == 0 {
                continue;
            }
            // The nearest box next, the others onto the stack in their order: a closest-hit
            // search opens the nearest first and drops the boxes behind its hits.
            let mut nearest = meets.trailing_zeros() as usize;
            for (l, &key) in keys.iter().enumerate() {
                if meets & (1 << l) != 0 && key < keys[nearest & 3] {
                    nearest = l;
                }
            }
            let mut rest = meets & !(1 << nearest);
            while rest != 0 {
                let l = rest.trailing_zeros() as usize;
                rest &= rest - 1;
                if let Some(slot) = self.stack.get_mut(self.top) {
                    *slot = ((first + l) as u32, keys[l & 3]);
                    self.top += 1;
                }
            }
            next = Some(first + nearest);
        }
    }
}

impl<const S: usize> Iterator for Walk<'_, S> {
    type Item = usize;

    #[inline]
    fn next(&mut self) -> Option<usize> {
        loop {
            if let Some(s) = self.leaf.next() {
                return Some(s.index());
            }
            self.leaf = self.next_leaf()?.iter();
        }
    }
}

/// The spheres of `ids` (up to four, as bits `0..4`) that the ray from `hit` along `d` may meet:
/// those [`Prepared::leaving_hit`] does not reject at once, decided in lanes for the four at
/// once where there are lanes, else all of them (each then takes the scalar test).
#[inline(always)]
fn open_among(spheres: &[Sphere], ids: &[SphereId], hit: &Hit, d: Vec3) -> u32 {
    let all = (1u32 << ids.len().min(4)) - 1;
    #[cfg(lanes)]
    {
        // Lanes past the leaf's spheres repeat its first (masked off).
        let sphere = |l: usize| {
            ids.get(l)
                .or(ids.first())
                .and_then(|s| spheres.get(s.index()))
        };
        if let (Some(a), Some(b), Some(c), Some(e)) = (sphere(0), sphere(1), sphere(2), sphere(3)) {
            return crate::geometry::leaving_open_among(hit.anchor, hit.rel, [a, b, c, e], d, all);
        }
    }
    #[cfg(not(lanes))]
    let _ = (spheres, hit, d);
    all
}
