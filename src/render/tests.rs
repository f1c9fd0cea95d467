//! Unit tests of the render module's internals.

#[cfg(all(test, lanes))]
mod lane_tests {
    use super::super::*;

    /// `byte_of` in lanes is `encode_channel(_, Linear)` on every kind of value: the byte range and
    /// its edges, just below and above 0 and 1, values that round to 256, huge, infinite, NaN,
    /// negative zero and subnormals.
    #[test]
    fn lane_bytes_are_encode_channel() {
        let mut xs = [
            0.0,
            -0.0,
            1.0,
            -1.0,
            f32::NAN,
            -f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::MAX,
            f32::MIN,
            1e-45,
            -1e-45,
            0.5 / 255.0,
            255.5 / 255.0,
            1.0 + f32::EPSILON,
            1.0 - f32::EPSILON,
            -0.5 / 255.0,
            3e9,
        ]
        .to_vec();
        for k in 0..=65_536u32 {
            let x = k as f32 / 65_536.0 * 1.1 - 0.05;
            xs.extend([
                x,
                f32::from_bits(x.to_bits() + 1),
                f32::from_bits(x.to_bits() ^ 1),
            ]);
        }
        for c in xs.chunks(4) {
            let mut a = [0.0f32; 4];
            a[..c.len()].copy_from_slice(c);
            let lanes = byte_of(crate::simd::F::from(a)).to_array();
            for (l, &x) in a.iter().enumerate() {
                let byte = i32::from(encode_channel(x, Encoding::Linear));
                assert_eq!(lanes[l], byte, "{x:e}");
            }
        }
    }

    /// `SRGB_STEPS` holds, for each byte from 1 to 255, the least f32 whose byte by the curve
    /// (`srgb_curve_byte`, through `powf`) is that byte or more, and `srgb_byte` gives the
    /// curve's byte: at each step and the f32 just below it, over 4096 f32 either side of each
    /// step (where `powf`'s rounding could make the curve's bytes step back), every 509th f32
    /// of [0, 1], and outside it (negatives, above 1, infinities, NaNs, zeros, subnormals).
    #[test]
    fn srgb_steps_are_the_curves_bytes() {
        let below = |x: f32| f32::from_bits(x.to_bits() - 1);
        let check = |x: f32| {
            assert_eq!(
                srgb_byte(x),
                srgb_curve_byte(x),
                "{x:e} ({:#x})",
                x.to_bits()
            );
        };
        for (k, &step) in SRGB_STEPS.iter().enumerate() {
            assert_eq!(
                usize::from(srgb_curve_byte(step)),
                k + 1,
                "step {k}: {step:e}"
            );
            assert_eq!(
                usize::from(srgb_curve_byte(below(step))),
                k,
                "below step {k}"
            );
            let b = step.to_bits();
            for bits in b - 4096..=b + 4096 {
                check(f32::from_bits(bits));
            }
        }
        for bits in (0..=1.0f32.to_bits()).step_by(509) {
            check(f32::from_bits(bits));
        }
        for x in [
            -0.0,
            -1e-45,
            -0.5,
            -f32::MAX,
            f32::NEG_INFINITY,
            1.0,
            1.0 + f32::EPSILON,
            2.0,
            f32::MAX,
            f32::INFINITY,
            f32::NAN,
            -f32::NAN,
            1e-45,
        ] {
            check(x);
        }
    }
}

#[cfg(all(test, lanes))]
mod pile_tests {
    use super::super::lanes::nearest_root;
    use super::super::radix_sort;
    use crate::math::TestRng;
    use crate::Sphere;

    /// `radix_sort` (a deep pile's sort, and a sweep's) orders as a stable sort by
    /// `f32::total_cmp` does: negative and positive zeros, infinities, NaNs of both signs,
    /// subnormals, keys that differ in one bit of any byte, many repeats, and none; keys whose
    /// high bytes are all the same (passes skipped); with more room than items (its values
    /// past them unread), and with too little (by comparisons).
    #[test]
    fn radix_sort_is_a_stable_total_order() {
        let mut rng = TestRng(0x0051_ACE5);
        let special = [
            0.0,
            -0.0,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            -f32::NAN,
            f32::MIN_POSITIVE,
            1e-45,
            -1e-45,
            f32::MAX,
            f32::MIN,
            1.0,
            -1.0,
        ];
        // Keys of every kind; keys that share their high byte (three passes, the sort ending
        // in the room), all but their low byte (one pass), or every byte (none).
        let families = [
            |rng: &mut TestRng, i: usize, special: &[f32]| match rng.next() % 4 {
                0 => special[i % special.len()],
                // A key one bit from another in any of its bytes.
                1 => f32::from_bits(10.0f32.to_bits() ^ (1 << (rng.next() % 32))),
                2 => (rng.next() % 5) as f32,
                _ => (rng.unit() - 0.5) * 100.0,
            },
            |rng: &mut TestRng, _: usize, _: &[f32]| 1.0 + rng.unit() * 0.999,
            |rng: &mut TestRng, _: usize, _: &[f32]| {
                f32::from_bits(0x4120_0000 | (rng.next() % 256) as u32)
            },
            |_: &mut TestRng, _: usize, _: &[f32]| 7.0,
        ];
        for (n, family) in [0, 1, 2, 13, 63, 64, 200, 3_000]
            .into_iter()
            .flat_map(|n| families.iter().map(move |f| (n, f)))
        {
            let keys: heapless::Vec<f32, 3_000> =
                (0..n).map(|i| family(&mut rng, i, &special)).collect();
            // A stable sort: equal keys by index.
            let mut want: heapless::Vec<u16, 3_000> = (0..n as u16).collect();
            let key = |s: u16| keys[usize::from(s)];
            want.sort_unstable_by(|&a, &b| key(a).total_cmp(&key(b)).then(a.cmp(&b)));
            let mut got: heapless::Vec<u16, 3_000> = (0..n as u16).collect();
            let mut room = [u16::MAX; 3_001];
            radix_sort(&mut got, &mut room[..], |&s| key(s));
            assert_eq!(got, want, "n {n}");
            // Too little room: the same keys in order, equal ones in any.
            let mut got: heapless::Vec<u16, 3_000> = (0..n as u16).collect();
            radix_sort(&mut got, &mut room[..n.saturating_sub(1)], |&s| key(s));
            let bits = |v: &[u16]| {
                v.iter()
                    .map(|&s| key(s).to_bits())
                    .collect::<heapless::Vec<u32, 3_000>>()
            };
            assert_eq!(bits(&got), bits(&want), "n {n}, little room");
        }
    }

    /// `nearest_root` bounds every root `Prepared::hit` finds, for directions of any length
    /// up to `d_max`: head-on rays (whose root is the bound before its margin, so that rounding
    /// alone would cross an unpadded one), random and grazing ones, eyes near the surface and
    /// far from it, at scales from 10⁻⁴ to 10⁴; and it is zero from inside.
    #[test]
    fn nearest_root_bounds_every_root() {
        let mut rng = TestRng(0x9_1E5);
        let mut tight = 0;
        for n in 0..200_000 {
            let scale = [1e-4, 1.0, 1e4][n % 3];
            let r = (0.01 + rng.unit()) * scale;
            let m = rng.vec(4.0 * scale);
            // From just outside the surface (10⁻⁶ of the radius) to 10³ radii away.
            let away = r * (1.0 + [1e-6, 1e-3, 0.5, 10.0, 1e3][n % 5] * (0.5 + rng.unit()));
            let Some(u) = rng.vec(2.0).normalized() else {
                continue;
            };
            let eye = m + u * away;
            let sphere = Sphere::new(m, r);
            let k = crate::Prepared::exact(eye, &sphere);
            let to = m - eye;
            let d = match n % 3 {
                0 => to,
                1 => to + rng.vec(2.0) * r,
                _ => to + rng.vec(0.1) * away,
            } * (0.1 + 3.0 * rng.unit());
            let len = libm::sqrtf(d.dot(d));
            let Some(t) = k.hit(d, 0.0, f32::INFINITY) else {
                continue;
            };
            for d_max in [len, len * 1.5] {
                let near = nearest_root(&k, d_max);
                assert!(near <= t, "{n}: bound {near:e} above root {t:e}");
            }
            if n % 3 == 0 && nearest_root(&k, len) > t * (1.0 - 1.0 / 512.0) {
                tight += 1;
            }
            let inside = crate::Prepared::exact(m + u * (r * 0.5), &sphere);
            assert_eq!(nearest_root(&inside, len), 0.0);
        }
        // The head-on rays' bounds sit within the margin of their roots: the test is near
        // the edge it guards.
        assert!(tight > 10_000, "{tight}");
    }
}

#[cfg(test)]
mod nearest_tests {
    use super::super::candidates::{nearest_first, KEYED, NEAREST};
    use super::super::*;
    use crate::Sphere;

    /// `nearest_first` keeps a list's spheres (a permutation) and puts first the `NEAREST` that
    /// lie nearest the shadow ray from the point to the light (the least `perp² − r²`, `perp`
    /// the centre's distance from the ray's line), for both kinds of light, for lists with keys
    /// kept on the stack and longer ones, with ties and indices that name no sphere (key 0).
    #[test]
    fn nearest_candidates_come_first() {
        let mut g = crate::math::TestRng(0x0dd_ba11);
        let spheres: [Sphere; 64] = core::array::from_fn(|k| {
            // Every other sphere repeats the previous one's centre: ties.
            let c = g.vec(10.0);
            Sphere::new(if k % 2 == 1 { Vec3::ZERO } else { c }, 0.25 + g.unit())
        });
        let q = g.vec(4.0);
        for (case, len) in [NEAREST + 1, 40, KEYED, KEYED + 300]
            .into_iter()
            .enumerate()
        {
            let (light, u) = if case % 2 == 0 {
                let position = g.vec(20.0);
                let light = Light::Point {
                    position,
                    intensity: crate::Color::ONE,
                };
                (light, (position - q).normalized().unwrap_or(Vec3::ZERO))
            } else {
                let direction = g.vec(1.0);
                let light = Light::Directional {
                    direction,
                    intensity: crate::Color::ONE,
                };
                (light, (-direction).normalized().unwrap_or(Vec3::ZERO))
            };
            // The key: the squared distance from the line, less the square of r.
            let d2 = |s: SphereId| {
                spheres.get(s.index()).map_or(0.0, |b| {
                    let v = b.center - q;
                    let along = v.dot(u);
                    v.dot(v) - along * along - b.radius * b.radius
                })
            };
            // Up to 70 ids: the last six name no sphere.
            let mut list: heapless::Vec<SphereId, 1400> = (0..len)
                .map(|_| SphereId::new((g.next() % 70) as usize))
                .collect();
            let mut before: heapless::Vec<usize, 1400> = list.iter().map(|s| s.index()).collect();
            nearest_first(&mut list, &spheres, q, &light);
            let mut after: heapless::Vec<usize, 1400> = list.iter().map(|s| s.index()).collect();
            let (front, rest) = list.split_at(NEAREST);
            let far = front.iter().map(|&s| d2(s)).fold(f32::MIN, f32::max);
            let near = rest.iter().map(|&s| d2(s)).fold(f32::MAX, f32::min);
            assert!(far <= near, "len {len}: {far} in front, {near} behind");
            before.sort_unstable();
            after.sort_unstable();
            assert_eq!(before, after, "len {len}: not a permutation");
        }
    }
}

#[cfg(test)]
mod sweep_tests {
    use super::super::*;

    /// `Sweep::first` is the binary search over all keys, and `near_first` at most 8 entries
    /// before it, for keys spread evenly, clustered, repeated, uneven, a single one, none, and
    /// for queries inside, below, above and between them, at their exact values and one ulp
    /// off; and a bucket holds a few keys when they are spread.
    #[test]
    fn bucketed_search_is_the_binary_search() {
        let mut g = crate::math::TestRng(0x5eed_5eed_5eed);
        let (mut in_bucket, mut queries) = (0usize, 0usize);
        for case in 0..400 {
            let n = [0, 1, 2, 5, 64, 256][case % 6];
            let mut keys: heapless::Vec<f32, 256> = (0..n)
                .map(|_| match case % 4 {
                    0 => g.unit() * 3.0 - 1.5,             // spread
                    1 => 0.5 + g.unit() * 1e-6,            // clustered in a few ulp
                    2 => (g.unit() * 8.0) as u32 as f32,   // repeated values
                    _ => libm::powf(10.0, g.unit() * 8.0), // uneven
                })
                .collect();
            keys.sort_unstable_by(|a, b| a.total_cmp(b));
            let mut w: Sweep<256> = Sweep::empty();
            for &k in &keys {
                let _ = w.key.push(k);
            }
            w.index((n / 4).max(1));
            assert_eq!(w.start.len(), (n / 4).max(1) + 1);
            // Each key and its neighbours a step of the bits either side; below +0 that is the
            // negative subnormal, where `bits - 1` would wrap (to a NaN, probed on its own).
            let toward_zero = |k: f32| match k.to_bits() {
                0 => -f32::from_bits(1),
                b => f32::from_bits(b - 1),
            };
            let probes = keys
                .iter()
                .flat_map(|&k| [k, f32::from_bits(k.to_bits() + 1), toward_zero(k)]);
            let others = [-1e30, -2.0, 0.0, 0.5, 2.0, 1e9, 1e30, f32::MIN, f32::MAX];
            for x in probes.chain(others).chain([f32::NAN]) {
                let exact = keys.partition_point(|&k| k < x);
                assert_eq!(w.first(x), exact, "case {case}: key {x}");
                let near = w.near_first(x);
                assert!(
                    near <= exact && exact - near <= 8,
                    "case {case}: key {x} at {near}"
                );
                if case % 4 == 0 {
                    let b = w.bucket(x);
                    in_bucket += (w.start[b + 1] - w.start[b]) as usize;
                    queries += 1;
                }
            }
        }
        // Spread keys, about four a bucket: a search of two or three steps, not eight.
        assert!(
            in_bucket < 8 * queries,
            "{in_bucket} keys in {queries} queries' buckets"
        );
    }
}

// Feature `std`: the sweep of 8192 entries is boxed.
#[cfg(all(test, lanes, feature = "std"))]
mod slab_tests {
    use super::super::*;
    use std::boxed::Box;

    /// A sweep names the spheres of its filter over every entry, with and without the depth
    /// filter: a host's sweep of [`SLABS_FROM`] entries or more scanning slabs sorted by the
    /// second key, and a smaller one scanning four entries at a time, for keys spread and
    /// clustered, half-widths from zero to wide, depths anywhere and some NaN (kept: not
    /// beyond), slacks from none to half the keys' range (a slab's run then reaches its end),
    /// and queries anywhere, on the filter's edge in either key, and outside every key; the
    /// spheres taken one by one, and four at a time through `push_masked`, each once.
    #[test]
    fn sweeps_name_the_filtered_spheres() {
        use crate::math::TestRng;
        let mut g = TestRng(0x51AB);
        let (mut named, mut deep) = (0usize, 0usize);
        for case in 0..9 {
            let n = [SLABS_FROM, SLABS_FROM + 1, SLABS_FROM + 3000, 300, 37][case % 5];
            let scale = [1.0, 1e-3][case % 2];
            let mut all: heapless::Vec<Entry, 8192> = heapless::Vec::new();
            for s in 0..n {
                let (k, k2) = if s % 5 == 0 {
                    // A cluster in both keys.
                    (0.3 + g.unit() * 1e-4, -0.2 + g.unit() * 1e-4)
                } else {
                    (g.unit() * 2.0 - 1.0, g.unit() * 2.0 - 1.0)
                };
                let half = [0.0, 1e-4, 1e-3, 0.01][s % 4] * g.unit();
                let depth = if s % 7 == 0 {
                    f32::NAN
                } else {
                    g.unit() * 2.0 - 1.0
                };
                let e = Entry::new(k * scale, half * scale, s, k2 * scale, depth * scale);
                let _ = all.push(e);
            }
            let entries = all.clone();
            let mut w: Box<Sweep<8192>> = Box::new(Sweep::empty());
            w.hw_max = entries.iter().map(|e| e.half).fold(0.0, f32::max);
            w.arrange(&mut all, &mut Box::new(heapless::Vec::new()));
            assert_eq!(w.slabs, n >= SLABS_FROM, "case {case}");
            // Slabs come with their index by `key2`, not a binary search each.
            assert_eq!(w.by_key2.per_slab > 0, w.slabs, "case {case}");
            for q in 0..3000 {
                // Slacks of none, a little, and so wide that a run reaches its slab's end.
                let slack = [0.0, 1e-5, 1e-3, 0.0, 0.5][q % 5] * scale;
                let e = entries[(g.next() % n as u64) as usize];
                let near = e.half + slack;
                let (key, key2) = match q % 4 {
                    // On the filter's edge of an entry, in one key or both.
                    0 => (e.key + near, e.key2),
                    1 => (e.key, e.key2 - near),
                    2 => (e.key - near, e.key2 + near),
                    _ => (
                        (g.unit() * 2.4 - 1.2) * scale,
                        (g.unit() * 2.4 - 1.2) * scale,
                    ),
                };
                // On an entry's depth, or anywhere.
                let far = if q % 2 == 0 {
                    e.depth
                } else {
                    (g.unit() * 2.4 - 1.2) * scale
                };
                let band = Band {
                    key,
                    band: w.hw_max + slack,
                    slack,
                    key2,
                    far,
                };
                let keys = |s: usize| {
                    let e = entries[s];
                    let near = e.half + slack;
                    (libm::fabsf(e.key - key) <= near) & (libm::fabsf(e.key2 - key2) <= near)
                };
                for (depth, masked) in [(false, false), (true, false), (false, true), (true, true)]
                {
                    // Taken one by one, or four at a time as `Frame::gather` takes them.
                    let mut got = Collect(heapless::Vec::new(), masked);
                    if depth {
                        w.scan::<true>(band, &mut got);
                    } else {
                        w.scan::<false>(band, &mut got);
                    }
                    let mut got: heapless::Vec<usize, 8192> =
                        got.0.iter().map(|s| s.index()).collect();
                    got.sort_unstable();
                    let want: heapless::Vec<usize, 8192> = (0..n)
                        .filter(|&s| keys(s) && (!depth || !(entries[s].depth > far)))
                        .collect();
                    assert_eq!(
                        got, want,
                        "case {case}, query {q}: ({key}, {key2}, {far}), masked {masked}"
                    );
                    match (masked, depth) {
                        (true, _) => {}
                        (false, true) => deep += got.len(),
                        (false, false) => named += got.len(),
                    }
                }
            }
        }
        // The depth filter names some spheres and drops others.
        assert!(
            named > 10_000 && deep > 5_000 && deep < named * 3 / 4,
            "{named} {deep}"
        );
    }

    /// A scan's spheres collected one by one, or (`.1`) four at a time by `push_masked`.
    struct Collect(heapless::Vec<SphereId, 8192>, bool);

    impl Consider for Collect {
        fn one(&mut self, s: SphereId) {
            assert!(self.0.push(s).is_ok());
        }
        fn four(&mut self, ids: &[SphereId], keep: u32) {
            if self.1 {
                assert!(push_masked(&mut self.0, ids, keep));
            } else {
                for (l, &s) in ids.iter().enumerate() {
                    if keep & (1 << l) != 0 {
                        self.one(s);
                    }
                }
            }
        }
    }

    /// `push_masked` appends the kept ids in order for every mask and every count of room
    /// left, and says when one did not fit.
    #[test]
    fn push_masked_appends_the_kept_ids() {
        let ids = [10, 11, 12, 13].map(SphereId::new);
        for keep in 0..16u32 {
            let want: heapless::Vec<SphereId, 4> = (0..4)
                .filter(|l| keep & (1 << l) != 0)
                .map(|l| ids[l])
                .collect();
            for before in 0..=6 {
                let mut list: heapless::Vec<SphereId, 6> = (0..before).map(SphereId::new).collect();
                let fits = push_masked(&mut list, &ids, keep);
                let room = 6 - before;
                assert_eq!(fits, want.len() <= room, "mask {keep:04b}, {before} before");
                let kept = want.len().min(room);
                assert_eq!(
                    list.len(),
                    before + kept,
                    "mask {keep:04b}, {before} before"
                );
                assert!((0..before).all(|s| list[s] == SphereId::new(s)));
                assert_eq!(
                    list[before..],
                    want[..kept],
                    "mask {keep:04b}, {before} before"
                );
            }
        }
    }
}

#[cfg(test)]
mod bvh_tests {
    use super::super::*;
    use crate::math::TestRng;
    use crate::shading::find_from;
    use crate::{Material, Sphere};

    type Small = Scene<96, 1>;

    /// A scene of 49 to 88 spheres (above `MIN_SPHERES`) for the hierarchy: radii 0.05–1.5 in a box of 10, tiny ones
    /// (0.001–0.05) up to 40 away, at times a ground of radius 10³–10⁶ and an enclosing sphere,
    /// and some spheres twice (their hits tie, and the brute-force order breaks the tie), all
    /// moved by `shift` and scaled by `scale`.
    fn scene(rng: &mut TestRng, shift: Vec3, scale: f32) -> Small {
        let mut scene: Small = Scene::new();
        let n = MIN_SPHERES as u64 + 1 + rng.next() % 40;
        let mut spheres: heapless::Vec<Sphere, 96> = heapless::Vec::new();
        for _ in 0..n {
            let s = match rng.next() % 12 {
                0 | 1 => Sphere::new(rng.vec(80.0), 0.001 + 0.049 * rng.unit()),
                2 => {
                    let r = [1e3, 1e5, 1e6][(rng.next() % 3) as usize];
                    Sphere::new(Vec3::new(0.0, -r - 5.0 * rng.unit(), 0.0), r)
                }
                3 => Sphere::new(rng.vec(1.0), 20.0 + 40.0 * rng.unit()),
                4 if !spheres.is_empty() => spheres[(rng.next() % spheres.len() as u64) as usize],
                _ => Sphere::new(rng.vec(10.0), 0.05 + 1.45 * rng.unit()),
            };
            let _ = spheres.push(s);
        }
        for s in &spheres {
            let moved = Sphere::new(s.center * scale + shift, s.radius * scale);
            scene.add_sphere(moved, Material::default()).unwrap();
        }
        scene
    }

    /// A unit vector in f64 towards a point within a relative `k` of a tangent point of
    /// `sphere` seen from `o` (a ray grazing it), or `None` from inside it.
    fn grazing(rng: &mut TestRng, o: Vec3, sphere: &Sphere, k: f64) -> Option<Vec3> {
        let f64s = |v: Vec3| [v.x as f64, v.y as f64, v.z as f64];
        let (o, m, r) = (f64s(o), f64s(sphere.center), sphere.radius as f64);
        let f = [o[0] - m[0], o[1] - m[1], o[2] - m[2]];
        let dd = f[0] * f[0] + f[1] * f[1] + f[2] * f[2];
        if dd <= r * r {
            return None;
        }
        let w = f64s(rng.vec(2.0));
        let wf = (w[0] * f[0] + w[1] * f[1] + w[2] * f[2]) / dd;
        let w = [w[0] - wf * f[0], w[1] - wf * f[1], w[2] - wf * f[2]];
        let wn = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
        let (a, b) = (r * r / dd, r * (dd - r * r).sqrt() / dd.sqrt() / wn);
        let k = 1.0 + k * (2.0 * rng.unit() as f64 - 1.0);
        let q: [f64; 3] = core::array::from_fn(|n| m[n] + (a * f[n] + b * w[n]) * k - o[n]);
        Vec3::new(q[0] as f32, q[1] as f32, q[2] as f32).normalized()
    }

    /// Secondary rays from hits all over random scenes (at the origin, moved by 10⁴, scaled by
    /// 10⁻⁴ and 10⁴), in random directions, along the axes and grazing other spheres within
    /// 10⁻³ to 10⁻⁷:
    /// the hierarchy's closest hit is `find_from`'s, bit for bit and tie for tie, and its
    /// shadow candidates give `in_shadow_among` over every sphere's answer, for point lights
    /// (with and without their per-frame constants) and directional ones.
    #[test]
    fn hierarchy_finds_the_brute_force_hits_and_blockers() {
        let mut rng = TestRng(0x5EED_0B17);
        let (mut hits, mut blocked, mut ties) = (0, 0, 0);
        for case in 0..400 {
            let (shift, scale) = match case % 4 {
                0 => (Vec3::ZERO, 1.0),
                1 => (Vec3::new(1e4, 1e4, -1e4), 1.0),
                2 => (Vec3::ZERO, 1e-4),
                _ => (Vec3::ZERO, 1e4),
            };
            let scene = scene(&mut rng, shift, scale);
            let mut bvh: Bvh<96> = Bvh::EMPTY;
            bvh.fill(scene.spheres());
            assert!(bvh.built(), "case {case}");
            let spheres = scene.spheres();
            for _ in 0..60 {
                // A hit: from a random point towards a random sphere.
                let target = spheres[(rng.next() % spheres.len() as u64) as usize];
                let eye = shift + rng.vec(30.0 * scale);
                let aim = target.center + rng.vec(target.radius);
                let Some(dir) = (aim - eye).normalized() else {
                    continue;
                };
                let Some(h) = scene.find_intersection(&Ray::new(eye, dir), T_EPS, f32::INFINITY)
                else {
                    continue;
                };
                let p = h.anchor + h.rel;
                let other = spheres[(rng.next() % spheres.len() as u64) as usize];
                let k = [1e-3, 1e-5, 1e-7][(rng.next() % 3) as usize];
                let d = match rng.next() % 4 {
                    0 => rng.vec(2.0).normalized(),
                    // Along an axis, the other components +0 or −0: parallel to two slabs
                    // of every box, whose `1/d` are ±∞.
                    1 => {
                        let mut c = [0.0f32; 3];
                        for x in &mut c {
                            *x = if rng.next() & 1 == 0 { 0.0 } else { -0.0 };
                        }
                        c[(rng.next() % 3) as usize] = if rng.next() & 1 == 0 { 1.0 } else { -1.0 };
                        Some(Vec3::from(c))
                    }
                    _ => grazing(&mut rng, p, &other, k),
                };
                let Some(d) = d else { continue };
                let ray = Ray::new(p, d);
                let brute = find_from(&scene, &ray, &h);
                let fast = bvh.find_from(&scene, &ray, &h);
                assert_eq!(brute, fast, "case {case}: {ray:?} from {h:?}");
                assert_eq!(brute.map(|x| x.t.to_bits()), fast.map(|x| x.t.to_bits()));
                hits += brute.is_some() as usize;
                if let Some(b) = brute {
                    ties += spheres
                        .iter()
                        .enumerate()
                        .filter(|&(j, s)| j != b.sphere && *s == spheres[b.sphere])
                        .count();
                }
                // Shadow rays towards a light beyond that direction, or along it.
                let lights = [
                    Light::Point {
                        position: p + d * (scale * (0.5 + 20.0 * rng.unit())),
                        intensity: Color::ONE,
                    },
                    Light::Directional {
                        direction: -d,
                        intensity: Color::ONE,
                    },
                ];
                for light in &lights {
                    let v = light.to_light(h.anchor, h.rel);
                    let cs: heapless::Vec<f32, 96> = match light.origin() {
                        Some(o) => spheres.iter().map(|s| Prepared::exact(o, s).c).collect(),
                        None => heapless::Vec::new(),
                    };
                    for consts in [false, true] {
                        let c = |j: usize| cs.get(j).copied().filter(|_| consts);
                        let all = in_shadow_among(&scene, &h, light, v, c, 0..spheres.len());
                        let cands = bvh.shadow_candidates(&h, light, v);
                        let culled = in_shadow_among(&scene, &h, light, v, c, cands);
                        assert_eq!(all, culled, "case {case}: {light:?} from {h:?}");
                        blocked += all as usize;
                    }
                }
            }
        }
        // The sets hold what they are meant to: hits, ties and blocked lights by the thousand.
        assert!(
            hits > 5_000 && blocked > 5_000 && ties > 200,
            "{hits} {blocked} {ties}"
        );
    }

    /// The hierarchy culls: a ray across a grid of small spheres asks a few of them, not all.
    #[test]
    fn hierarchy_names_few_spheres() {
        let mut scene: Scene<1100, 1> = Scene::new();
        for k in 0..1024 {
            let c = Vec3::new((k % 32) as f32, (k / 32) as f32, 0.0);
            scene
                .add_sphere(Sphere::new(c, 0.3), Material::default())
                .unwrap();
        }
        let mut bvh: Bvh<1100> = Bvh::EMPTY;
        bvh.fill(scene.spheres());
        let h = scene
            .find_intersection(
                &Ray::new(Vec3::new(10.0, 10.0, 5.0), Vec3::new(0.0, 0.0, -1.0)),
                T_EPS,
                f32::INFINITY,
            )
            .unwrap();
        let sun = Light::Directional {
            direction: Vec3::new(-0.3, -0.2, -1.0),
            intensity: Color::ONE,
        };
        let v = sun.to_light(h.anchor, h.rel);
        let named = bvh.shadow_candidates(&h, &sun, v).count();
        assert!((1..=16).contains(&named), "{named} of 1024");
    }
}

#[cfg(test)]
mod depth_tests {
    use crate::math::{Color, Vec3};
    use crate::shading::LightKind;
    use crate::Light;

    /// A sphere that meets a shadow ray from a point of the ball `(q, rho)` (its segment to a
    /// point light, its ray towards a directional one) begins no farther along the light's rays
    /// than the ball reaches: `near_depth ≤ far_depth`, the sweep's depth filter never drops a
    /// blocker. Spheres touching the rays just inside their radius, at every scale and far
    /// from the origin; and spheres behind the ball are dropped (a filter that drops nothing
    /// would pass the first check alone).
    #[test]
    fn depth_filter_keeps_every_blocker() {
        let mut g = crate::math::TestRng(0x1f83_d9ab_fb41_bd6b);
        let (mut kept, mut behind, mut dropped) = (0u32, 0u32, 0u32);
        for case in 0..40_000 {
            let scale = [1e-3f32, 1.0, 1e3][case % 3];
            let shift = if case % 5 == 0 {
                Vec3::splat(1e4 * scale)
            } else {
                Vec3::ZERO
            };
            let (q, rho) = (shift + g.vec(8.0 * scale), g.unit() * scale);
            let d = g.vec(1.0).normalized().unwrap_or(Vec3::new(0.0, -1.0, 0.0));
            let light = if case % 2 == 0 {
                Light::Point {
                    position: shift + g.vec(16.0 * scale),
                    intensity: Color::ONE,
                }
            } else {
                Light::Directional {
                    direction: d,
                    intensity: Color::ONE,
                }
            };
            // A point y of the ball, and a point x on its shadow ray.
            let y = q + g.vec(1.0).normalized().unwrap_or(Vec3::ZERO) * (rho * g.unit());
            let x = match light {
                Light::Point { position, .. } => y + (position - y) * g.unit(),
                Light::Directional { direction, .. } => y - direction * (8.0 * scale * g.unit()),
            };
            // A sphere through x, its centre up to 0.999 radii from it in any direction.
            let r = scale * (0.01 + g.unit());
            let side = g.vec(1.0).normalized().unwrap_or(Vec3::new(1.0, 0.0, 0.0));
            let m = x + side * (0.999 * r * g.unit());
            let (near, far) = (light.near_depth(m, r), light.far_depth(q, rho));
            assert!(
                near <= far,
                "{light:?} ball {q:?} {rho} sphere {m:?} {r}: {near} > {far}"
            );
            kept += 1;
            // The same sphere moved behind the ball, past its radius, the ball's and 1 %, and
            // 10⁻³ of the coordinates' size (the pads grow with it).
            let away = match light {
                Light::Point { position, .. } => (q - position).normalized().unwrap_or(Vec3::ZERO),
                Light::Directional { direction, .. } => direction,
            };
            let size = q.x.abs() + q.y.abs() + q.z.abs() + scale;
            let back = q + away * ((r + rho) * 1.01 + 1e-3 * size * (1.0 + g.unit()));
            if light.origin().is_none_or(|p| (q - p).length() > 2.0 * rho) {
                behind += 1;
                dropped += (light.near_depth(back, r) > far) as u32;
            }
        }
        assert!(
            kept == 40_000 && dropped == behind && behind > 30_000,
            "{dropped} of {behind}"
        );
    }
}
