//! The culling of secondary rays. Mirror and refracted rays, and the shadow rays of their hits,
//! leave from anywhere in any direction, so neither the screen boxes nor the lights' sweeps
//! bound them: a hierarchy of bounding balls over the scene's spheres, built once a frame in
//! the caller's storage, names the spheres such a ray can meet. Each of those is asked with the
//! brute-force test, and ties are broken as the brute-force loop breaks them, so the hits are
//! its hits, bit for bit. A node has up to four children, whose balls a walk tests at once,
//! in vector lanes on hosts: half the levels of a binary tree, and a quarter of the tests.
//!
//! Built where the capacity is above 8 (`Frame::SWEEPS`: a microcontroller's scene links none of
//! it) and the scene has more than [`MIN_SPHERES`] spheres, for scenes with secondary rays.
//! Below that a ray tests every sphere, and hosts find and shade the first mirror rays of four
//! pixels together (`lanes/mirror.rs`): at 48 spheres the hierarchy took 1.21 times as long,
//! all mirrors, and 1.15 times all glass; at 64, 0.97 and 0.92 times (`bench/ab.sh`).

use super::*;
use crate::math::{sqrt, Ieee, Ieee3, IeeeCmp};
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
/// bounding ball is in [`Bvh::balls`].
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
    /// The nodes' bounding balls by coordinate, `[x, y, z, r]`: a node's children are
    /// consecutive, so a walk tests up to four of them in one set of vector lanes.
    balls: [heapless::Vec<f32, S>; 4],
    /// The spheres of the leaves, leaf by leaf.
    order: List<S>,
    /// Spheres above 8 times the median radius (a ground, a wall), kept out of the tree, whose
    /// balls they would swell, and always tested.
    wide: List<S>,
    /// Whether the frame has a hierarchy: else every sphere is tested.
    built: bool,
}

/// A ray or segment asked about: from `anchor + rel` along `d` (`a = d·d`), over
/// `0 ≤ t ≤ tmax`; `reach` bounds the length of `tmax·d` where that is finite and the ray's
/// test rounds with it (a point light's shadow ray, cast from the light).
#[derive(Debug, Clone, Copy)]
struct Probe {
    anchor: Vec3,
    rel: Vec3,
    d: Vec3,
    a: f32,
    root_a: f32,
    rel_max: f32,
    reach: f32,
}

impl Probe {
    fn new(anchor: Vec3, rel: Vec3, d: Vec3, reach: f32) -> Self {
        let a = d.dot(d);
        Probe {
            anchor,
            rel,
            d,
            a,
            root_a: sqrt(a),
            rel_max: rel.max_abs(),
            reach,
        }
    }

    /// Whether the ray can meet a sphere inside the ball `(c, r)`, as the sphere's own test decides:
    /// `None` where it certainly cannot (it misses the ball, or the ball is behind), else the
    /// ball's [`Probe::beyond`] key.
    #[inline(always)]
    fn meets(&self, c: Vec3, r: f32) -> Option<f32> {
        let (meets, key) = self.meets_balls(c, r);
        meets.then_some(key)
    }

    /// [`Probe::meets`] of the balls centred at `c` of radii `r`: one ball, or four in lanes.
    /// Every comparison is written so that a NaN or an overflow culls nothing.
    #[inline(always)]
    fn meets_balls<P: Ieee3>(&self, c: P, r: P::S) -> (<P::S as IeeeCmp>::Mask, P::S) {
        let v = <P::S as Ieee>::splat;
        let e = P::splat(self.anchor).sub(c);
        let f = e.add(P::splat(self.rel));
        // The ball padded by PAD of every length the tests round with: the distances from the
        // origin (`e`, `rel`, as the spheres' tests form `(anchor − m) + rel`), the ball's
        // radius and the ray's reach. A sphere's test reports a hit only where the exact ray
        // passes within a few ε of those of it; 1.75 ≥ √3 turns max-norms into lengths.
        let pad = v(1.75) * (e.max_abs() + v(self.rel_max)) + r + v(self.reach);
        let rho = r + v(PAD) * pad;
        let (ff, b, rr) = (f.dot(f), f.dot(P::splat(self.d)), rho * rho);
        let a = v(self.a);
        // Squares that may have lost bits to underflow, or a NaN: the ball culls nothing.
        let sure = ff.gt(v(TINY)) & rr.gt(v(TINY)) & a.gt(v(TINY));
        // The line misses the ball: |f|² − b²/a > ρ². Written times `a`; the difference
        // cancels when the line passes near the centre from afar, by a few ε |f|² a, which
        // the `PAD ff` term covers.
        let misses = (a * ff - b * b).gt(a * (rr + v(PAD) * ff));
        // Outside the ball and heading away (the centre behind): |f + t d|² grows with t.
        let behind = b.ge(v(0.0)) & ff.gt(rr * v(1.0 + PAD));
        // Every point of the ball is at t ≥ (−b − ρ√a)/a; the key is that bound times `a`,
        // lowered by the rounding of its difference.
        let reach = rho * v(self.root_a);
        let key = (b.flip() - reach) - v(PAD) * (b.abs() + reach);
        let meets = !sure | !(misses | behind);
        (
            meets,
            <P::S as IeeeCmp>::select(sure, key, v(f32::NEG_INFINITY)),
        )
    }

    /// Whether a ball of key `key` lies wholly beyond `t = tmax`, past the rounding of the
    /// key and of the hits' own `t` (`tmax` is one of them).
    #[inline(always)]
    fn beyond(&self, key: f32, tmax: f32) -> bool {
        key > tmax * self.a * (1.0 + PAD)
    }
}

impl<const S: usize> Bvh<S> {
    pub(super) const EMPTY: Self = Bvh {
        nodes: heapless::Vec::new(),
        balls: [const { heapless::Vec::new() }; 4],
        order: heapless::Vec::new(),
        wide: heapless::Vec::new(),
        built: false,
    };

    /// Builds the hierarchy over `spheres` (at most `S`) in place, or none for a few spheres.
    pub(super) fn fill(&mut self, spheres: &[Sphere]) {
        self.nodes.clear();
        for b in &mut self.balls {
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
            let (c, r, axis) = bound(spheres, ids);
            for (b, v) in self.balls.iter_mut().zip([c.x, c.y, c.z, r]) {
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

    /// Appends a node to fill in, with its ball.
    fn add_node(&mut self) {
        let _ = self.nodes.push(Node {
            first: 0,
            count: 0,
            children: 0,
        });
        for b in &mut self.balls {
            let _ = b.push(0.0);
        }
    }

    /// Whether `probe` can meet the balls of nodes `first..first + n` (`n ≤ 4`), as bits
    /// `0..n`, and their keys ([`Probe::meets`]): four lanes at once where there are lanes,
    /// else one ball after another.
    #[inline(always)]
    fn meets4(&self, probe: &Probe, first: usize, n: usize) -> (u32, [f32; 4]) {
        let all = (1u32 << n) - 1;
        // The four balls from `first`; past the last node, lanes repeat it (masked off).
        let lanes = |b: &heapless::Vec<f32, S>| -> [f32; 4] {
            match b.get(first..first + 4) {
                Some(&[a, b, c, d]) => [a, b, c, d],
                _ => {
                    core::array::from_fn(|l| b.get(first + l).or(b.last()).copied().unwrap_or(0.0))
                }
            }
        };
        let [x, y, z, r] = [0, 1, 2, 3].map(|i| self.balls.get(i).map_or([0.0; 4], lanes));
        #[cfg(lanes)]
        {
            use crate::simd::{bits, F, V};
            let c = V {
                x: F::from(x),
                y: F::from(y),
                z: F::from(z),
            };
            let (meets, key) = probe.meets_balls(c, F::from(r));
            (bits(meets) & all, key.to_array())
        }
        #[cfg(not(lanes))]
        {
            let (mut meets, mut keys) = (0, [0.0; 4]);
            for (l, key) in keys.iter_mut().enumerate().take(n) {
                let (m, k) = probe.meets_balls(Vec3::new(x[l], y[l], z[l]), r[l]);
                meets |= (m as u32) << l;
                *key = k;
            }
            (meets & all, keys)
        }
    }

    /// Whether the frame has a hierarchy (else every sphere is tested).
    #[inline(always)]
    pub(super) fn built(&self) -> bool {
        self.built
    }

    /// The spheres a shadow ray from `hit` towards `light` (`v` its `to_light`) can meet: the
    /// wide ones, then the tree's leaves whose balls the ray or segment passes.
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
        let from = hit.sphere;
        let spheres = scene.spheres();
        let mut best = leaving_own(spheres, ray, hit);
        // The brute-force loop asks `from` first, then the others in scene order, each with
        // the closest `t` so far as its `tmax` (a closed bound): of equal `t`s the last in that
        // order wins. A sphere's `t` does not depend on `tmax`, which only accepts it.
        let probe = Probe::new(hit.anchor, hit.rel, ray.dir, 0.0);
        let mut walk = Walk::new(self, probe, f32::INFINITY);
        let mut wide = self.wide.iter();
        loop {
            let j = match wide.next() {
                Some(s) => s.index(),
                None => match walk.next() {
                    Some(j) => j,
                    None => break,
                },
            };
            let Some(s) = spheres.get(j) else {
                continue;
            };
            if j == from {
                continue;
            }
            let tmax = best.map_or(f32::INFINITY, |b| b.0);
            let Some((t, f)) = Prepared::leaving_hit(hit.anchor, hit.rel, s, ray.dir, T_EPS, tmax)
            else {
                continue;
            };
            let wins = match best {
                Some((tb, jb, ..)) => t < tb || jb == from || j > jb,
                None => true,
            };
            if wins {
                best = Some((t, j, f, s));
                walk.tmax = t;
            }
        }
        best.map(|b| closest_hit(scene, ray, hit, b))
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

/// The centre and radius of a ball holding the spheres `ids` (the centre of their box, the
/// radius rounded up), and the axis along which their centres spread the most.
fn bound(spheres: &[Sphere], ids: &[SphereId]) -> (Vec3, f32, usize) {
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
    // Halves first: no overflow for coordinates near f32::MAX.
    let c = Vec3::new(
        lo[0] * 0.5 + hi[0] * 0.5,
        lo[1] * 0.5 + hi[1] * 0.5,
        lo[2] * 0.5 + hi[2] * 0.5,
    );
    let mut r = 0.0f32;
    for s in ids.iter().filter_map(|s| spheres.get(s.index())) {
        r = r.max((s.center - c).length() + s.radius);
    }
    // The length and the sum round by a few ε: 2⁻²⁰ above keeps every sphere inside.
    let r = r * (1.0 + 1.0 / 1_048_576.0);
    let spread = [chi[0] - clo[0], chi[1] - clo[1], chi[2] - clo[2]];
    let axis = if spread[0] >= spread[1] && spread[0] >= spread[2] {
        0
    } else if spread[1] >= spread[2] {
        1
    } else {
        2
    };
    (c, r, axis)
}

/// A walk of the tree for one ray: the spheres of every leaf whose ball the ray can meet
/// within `tmax`, which the caller may lower as it goes (a closest-hit search). Each ball is
/// tested when its parent is opened, and its key kept beside it on the stack, so that a ball
/// pushed before a nearer hit lowered `tmax` is dropped without testing it again.
struct Walk<'b, const S: usize> {
    bvh: &'b Bvh<S>,
    probe: Probe,
    tmax: f32,
    stack: [(u16, f32); DEPTH],
    top: usize,
    leaf: core::slice::Iter<'b, SphereId>,
}

impl<'b, const S: usize> Walk<'b, S> {
    #[inline(always)]
    fn new(bvh: &'b Bvh<S>, probe: Probe, tmax: f32) -> Self {
        let mut w = Walk {
            bvh,
            probe,
            tmax,
            stack: [(0, 0.0); DEPTH],
            top: 0,
            leaf: [].iter(),
        };
        let ball = bvh.balls.each_ref().map(|b| b.first().copied());
        let root = match ball {
            [Some(x), Some(y), Some(z), Some(r)] => probe.meets(Vec3::new(x, y, z), r),
            _ => None,
        };
        if let Some(key) = root {
            w.stack[0] = (0, key);
            w.top = 1;
        }
        w
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
            if self.top == 0 {
                return None;
            }
            self.top -= 1;
            let (k, key) = *self.stack.get(self.top)?;
            if self.probe.beyond(key, self.tmax) {
                continue;
            }
            let node = *self.bvh.nodes.get(k as usize)?;
            let (first, count) = (node.first as usize, node.count as usize);
            if count > 0 {
                self.leaf = self.bvh.order.get(first..first + count)?.iter();
                continue;
            }
            if self.top + 4 > DEPTH {
                // Cannot happen: the build splits a node only while its own stack, which the
                // walk's mirrors, has room. Were it to, every sphere is named (again): a
                // sphere asked twice changes no answer.
                self.top = 0;
                self.leaf = self.bvh.order.iter();
                continue;
            }
            // The balls the ray can meet, the nearest on top: a closest-hit search finds near
            // hits first and drops what lies behind them.
            let (meets, keys) = self.bvh.meets4(&self.probe, first, node.children as usize);
            let base = self.top;
            for (l, &key) in keys.iter().enumerate() {
                if meets & (1 << l) == 0 {
                    continue;
                }
                let k = (first + l) as u16;
                // Insertion by key, farthest at the bottom.
                let mut i = self.top;
                while i > base {
                    match self.stack.get(i - 1) {
                        Some(&(_, below)) if below < key => i -= 1,
                        _ => break,
                    }
                }
                let mut j = self.top;
                while j > i {
                    if let Some(&e) = self.stack.get(j - 1) {
                        if let Some(slot) = self.stack.get_mut(j) {
                            *slot = e;
                        }
                    }
                    j -= 1;
                }
                if let Some(slot) = self.stack.get_mut(i) {
                    *slot = (k, key);
                    self.top += 1;
                }
            }
        }
    }
}
