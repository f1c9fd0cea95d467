//! Unit tests of the render module's internals.

#[cfg(all(test, lanes))]
mod lane_tests {
    use super::super::*;

    /// `may_block4` answers as `may_block` does, lane by lane, for both kinds of light, on
    /// spheres and balls of every size and distance, near the edge of the test especially.
    #[test]
    fn lane_blockers_are_may_block() {
        let mut g = crate::math::TestRng(0x9e37_79b9_7f4a_7c15);
        let (mut yes, mut no) = (0, 0);
        for case in 0..50_000 {
            let scale = [1e-3f32, 1.0, 1e3][case % 3];
            let (q, rho) = (g.vec(8.0 * scale), g.unit() * scale);
            let light = if case % 2 == 0 {
                Light::Point {
                    position: g.vec(8.0 * scale),
                    intensity: Color::ONE,
                }
            } else {
                let d = g.vec(1.0).normalized().unwrap_or(Vec3::new(0.0, -1.0, 0.0));
                Light::Directional {
                    direction: d,
                    intensity: Color::ONE,
                }
            };
            let r: [f32; 4] = core::array::from_fn(|_| g.unit() * scale);
            // Half the spheres anywhere, half about as far from the shadow rays' axis as the
            // test's edge, where it decides by a hair.
            let far_end = match light {
                Light::Point { position, .. } => position,
                Light::Directional { direction, .. } => q - direction * (8.0 * scale),
            };
            let m: [Vec3; 4] = core::array::from_fn(|l| {
                if l % 2 == 0 {
                    return g.vec(8.0 * scale);
                }
                let u = g.unit();
                let axis = q + (far_end - q) * u;
                let side = g.vec(1.0).normalized().unwrap_or(Vec3::new(1.0, 0.0, 0.0));
                if l == 1 {
                    return axis + side * ((r[l] + rho * u) * (0.9 + 0.2 * g.unit()));
                }
                // Within half the test's pad either side of its edge: the cone's radius there
                // (ρ at the ball, 0 at a point light; ρ all along a directional light's sweep)
                // plus r and the pad's estimate, 2·10⁻⁴ r + 2 ETA |w|₁.
                let (w, reach) = match light {
                    Light::Point { position, .. } => (axis - position, rho * (1.0 - u)),
                    Light::Directional { .. } => (axis - q, rho),
                };
                let l1 = w.x.abs() + w.y.abs() + w.z.abs();
                let pad = 2e-4 * r[l] + 2.0 * ETA * (l1 + r[l] + reach);
                axis + side * (r[l] + reach + pad * (0.5 + g.unit()))
            });
            let lanes = may_block4(&light, m, r, q, rho);
            for l in 0..4 {
                let scalar = may_block(&light, m[l], r[l], q, rho);
                assert_eq!(
                    lanes & (1 << l) != 0,
                    scalar,
                    "{light:?} {:?} {} {q:?} {rho}",
                    m[l],
                    r[l]
                );
                if scalar {
                    yes += 1
                } else {
                    no += 1
                }
            }
        }
        assert!(yes > 10_000 && no > 10_000, "{yes} {no}");
    }

    /// `linear_bytes` is `encode_channel(_, Linear)` on every kind of value: the byte range and
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
            let lanes = linear_bytes(crate::simd::F::from(a)).to_array();
            for (l, &x) in a.iter().enumerate() {
                let byte = i32::from(encode_channel(x, Encoding::Linear));
                assert_eq!(lanes[l], byte, "{x:e}");
            }
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
            w.index();
            assert_eq!(w.start.len(), (n / 4).max(1) + 1);
            let probes = keys.iter().flat_map(|&k| {
                [
                    k,
                    f32::from_bits(k.to_bits() + 1),
                    f32::from_bits(k.to_bits() - 1),
                ]
            });
            let others = [-1e30, -2.0, 0.0, 0.5, 2.0, 1e9, 1e30, f32::MIN, f32::MAX];
            for x in probes.chain(others) {
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
