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
