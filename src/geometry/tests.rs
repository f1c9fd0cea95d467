//! Unit tests: the lanes and the scalar copies against the generic definitions, bit for bit.

#[cfg(test)]
use crate::math::{TestRng, Vec3};

#[cfg(test)]
/// Magnitudes over many decades, for the test's spheres and rays.
pub(super) trait Decades {
    /// ±(1 … 10) · 10^e for e in lo..hi.
    fn mag(&mut self, lo: i32, hi: i32) -> f32;
    fn decades(&mut self, lo: i32, hi: i32) -> Vec3;
}
#[cfg(test)]
impl Decades for TestRng {
    fn mag(&mut self, lo: i32, hi: i32) -> f32 {
        let e = lo + (self.next() % (hi - lo) as u64) as i32;
        let v = (1.0 + 9.0 * self.unit()) * libm::powf(10.0, e as f32);
        if self.next() & 1 == 0 {
            v
        } else {
            -v
        }
    }
    fn decades(&mut self, lo: i32, hi: i32) -> Vec3 {
        Vec3::new(self.mag(lo, hi), self.mag(lo, hi), self.mag(lo, hi))
    }
}

#[cfg(all(test, lanes))]
mod lane_tests {
    use super::super::*;

    use crate::math::TestRng;

    use super::Decades;

    /// `c_near_across` (coordinates in lanes) is `c_near_of` on scalars, bit for bit, with and
    /// without an offset: origins on, near and far from spheres of every size, coordinates
    /// where the squares overflow, zeros, infinities and NaNs.
    #[test]
    fn c_across_lanes_is_the_scalar_c() {
        let mut g = TestRng(0x1319_8a2e_0370_7344);
        let special = [0.0, -0.0, f32::INFINITY, f32::NAN, 3e19, f32::MIN_POSITIVE];
        let bits = |x: f32| if x.is_nan() { u32::MAX } else { x.to_bits() };
        let mut cancelled = 0;
        for case in 0..200_000u32 {
            let r = g.mag(-4, 7).abs();
            let m = g.decades(-4, 7);
            let offset = Vec3::new(r, 0.0, 0.0) * (1.0 + 1e-3 * (g.unit() - 0.5));
            let (mut b, mut o) = match case % 3 {
                0 => (m + g.decades(-3, 1) * r, offset),
                1 => (g.decades(-4, 7), g.decades(-4, 3)),
                _ => (m - offset, offset),
            };
            let mut m = [m.x, m.y, m.z];
            let mut r = r;
            if case % 64 == 7 {
                let v = special[(case / 64) as usize % special.len()];
                match (case / 7) % 4 {
                    0 => b.y = v,
                    1 => o.z = v,
                    2 => m[0] = v,
                    _ => r = v,
                }
            }
            let (b, o) = ([b.x, b.y, b.z], [o.x, o.y, o.z]);
            let scalar = c_near_of::<f32, true>(b, o, m, r);
            assert_eq!(
                bits(c_near_across::<true>(b, o, m, r)),
                bits(scalar),
                "case {case}"
            );
            let plain = c_near_of::<f32, false>(b, [0.0; 3], m, r);
            let across = c_near_across::<false>(b, [0.0; 3], m, r);
            assert_eq!(bits(across), bits(plain), "case {case}, no offset");
            let (f, rr) = (Vec3::from(b) - Vec3::from(m) + Vec3::from(o), r * r);
            cancelled += (libm::fabsf(f.dot(f) - rr) < 1e-3 * (f.dot(f) + rr)) as u32;
        }
        assert!(
            cancelled > 2_000,
            "{cancelled} cases where the f32 c cancels"
        );
    }

    /// `hit_bits4` answers as the scalar `hit` does for every asked lane and leaves the others
    /// out: spheres of every size, origins on, near and far from them, overflowing constants,
    /// zero, huge and tangent directions, and `tmax` at a root.
    #[test]
    fn hit_bits_are_the_scalar_hits() {
        let mut g = TestRng(0x243f_6a88_85a3_08d3);
        let (mut yes, mut asked) = (0, 0);
        for case in 0..100_000u32 {
            let r = g.mag(-4, 5).abs();
            let m = g.decades(-4, 5);
            let origin = match case % 4 {
                0 => m + Vec3::new(0.0, r, 0.0) * (1.0 + 0.01 * (g.unit() - 0.5)),
                1 => m + g.decades(-5, 2),
                2 if case % 32 == 2 => Vec3::new(3e19, -2e19, 1e19),
                _ => g.decades(-4, 6),
            };
            let k = Prepared::exact(origin, &Sphere::new(m, r));
            let aim = m - origin;
            let d: [Vec3; LANES] = core::array::from_fn(|l| match (case + l as u32) % 5 {
                0 => Vec3::ZERO,
                1 => aim,
                2 => g.decades(15, 20),
                _ => aim + g.decades(-6, 1) * aim.length(),
            });
            let tmin = [f32::MIN_POSITIVE, 0.0][case as usize % 2];
            let tmax = match case % 3 {
                0 => 1.0 - f32::EPSILON / 2.0,
                1 => k.hit(d[0], tmin, f32::INFINITY).unwrap_or(f32::INFINITY),
                _ => f32::INFINITY,
            };
            let v = crate::simd::V::from_lanes(d);
            let ask = (case / 3) % 16;
            let bits = k.hit_bits4(&v, tmin, tmax, ask);
            for (l, &dl) in d.iter().enumerate() {
                let scalar = ask & (1 << l) != 0 && k.hit(dl, tmin, tmax).is_some();
                assert_eq!(
                    bits & (1 << l) != 0,
                    scalar,
                    "case {case} lane {l}: {k:?} {dl:?}"
                );
                yes += scalar as u32;
                asked += (ask >> l) & 1;
            }
        }
        assert!(yes > asked / 10, "{yes} hits of {asked} asked lanes");
    }

    /// Every lane of `hit_lanes` is the scalar `hit`, bit for bit, or marked to redo, on rays
    /// of every scale: far and tiny spheres, origins on, near and inside the surface
    /// (both discriminants), tangents, zero and huge directions, overflowing constants, and
    /// `tmax` at the root itself.
    #[test]
    fn lanes_are_the_scalar_hit() {
        let mut g = TestRng(0x9e37_79b9_7f4a_7c15);
        let (mut hits, mut redos, mut near, mut lanes) = (0, 0, 0, 0);
        let mut ordinary_redos = 0;
        for case in 0..200_000u32 {
            let r = g.mag(-4, 5).abs();
            let m = g.decades(-4, 5);
            let origin = match case % 4 {
                // on or just off the surface, where `|c| ≤ r²`
                0 => m + Vec3::new(r, 0.0, 0.0) * (1.0 + 0.01 * (g.unit() - 0.5)),
                1 => m + g.decades(-5, 2),
                // centres near 10¹⁹ (squares overflow) now and then
                2 if case % 64 == 2 => Vec3::new(3e19, -2e19, 1e19),
                _ => g.decades(-4, 6),
            };
            let k = Prepared::exact(origin, &Sphere::new(m, r));
            // (An origin that rounded onto the centre has no direction to aim along.)
            if !finite(k.c) || k.f == Vec3::ZERO {
                continue;
            }
            let hb = libm::fabsf(k.c) > k.r * k.r;
            near += !hb as u32;
            let aim = m - origin;
            let d: [Vec3; LANES] = core::array::from_fn(|l| match (case + l as u32) % 7 {
                0 => Vec3::ZERO,
                1 => aim,
                // towards the rim: tangent or nearly
                // along a tangent, give or take up to 10⁻⁴ of r: where the two roots, the two
                // discriminants and the margins of the clear-miss test part ways
                2 | 4 => {
                    let (dd, u) = (aim.length(), aim.cross(Vec3::new(0.3, 1.0, 0.1)));
                    let side = libm::sqrtf(libm::fabsf(dd * dd - r * r)) / dd;
                    let off = 1.0 + libm::powf(10.0, -4.0 - 3.0 * g.unit()) * (g.unit() - 0.5);
                    aim * side + u.normalized().unwrap_or(Vec3::ZERO) * (r * off)
                }
                3 => g.decades(15, 20),
                _ => aim + g.decades(-6, 1) * aim.length(),
            });
            // (`hit_lanes` takes any tmin; the renderer's is `f32::MIN_POSITIVE`.)
            let tmin = [0.0, f32::MIN_POSITIVE, -1e3][case as usize % 3];
            let tmax: [f32; LANES] = core::array::from_fn(|l| match (case / 7 + l as u32) % 4 {
                0 => f32::INFINITY,
                // exactly the root: `t ≤ tmax` must hold as in the scalar test
                1 => k.hit(d[l], tmin, f32::INFINITY).unwrap_or(1.0),
                2 => g.mag(-3, 4).abs(),
                _ => f32::NAN,
            });
            let h = k.hit_lanes_of(&d, tmin, tmax);
            for l in 0..LANES {
                lanes += 1;
                if h.redo & (1 << l) != 0 {
                    redos += 1;
                    // Zero and huge directions aside, redoing is the exception.
                    ordinary_redos += !matches!((case + l as u32) % 7, 0 | 3) as u32;
                    continue;
                }
                let lane = (h.hit & (1 << l) != 0).then(|| h.t[l].to_bits());
                let scalar = k.hit(d[l], tmin, tmax[l]).map(f32::to_bits);
                assert_eq!(
                    lane, scalar,
                    "case {case} lane {l}: {k:?} d {:?} tmax {}",
                    d[l], tmax[l]
                );
                hits += scalar.is_some() as u32;
            }
        }
        // The sets reach every path: hits, redos (overflow, q = 0) and both discriminants.
        assert!(
            hits > lanes / 10 && redos > 0 && near > 1000,
            "{hits} {redos} {near} {lanes}"
        );
        assert!(
            ordinary_redos < lanes / 1000,
            "{ordinary_redos} of {lanes} lanes redone"
        );
    }

    /// `hit_outside` is `hit`, bit for bit, for constants of an origin outside the sphere
    /// (`c > 0`) and `tmin ≥ 0`: near the surface and far, both discriminants, tangents, huge
    /// and zero directions (overflow and the scaled roots), `tmax` at the root itself.
    #[test]
    fn hit_outside_is_hit() {
        let mut g = TestRng(0x5851_f42d_4c95_7f2d);
        let (mut tested, mut hits, mut near, mut far_roots) = (0u32, 0u32, 0u32, 0u32);
        for case in 0..200_000u32 {
            let r = g.mag(-4, 5).abs();
            let m = g.decades(-4, 5);
            let origin = match case % 3 {
                0 => m + Vec3::new(r, 0.0, 0.0) * (1.0 + 0.01 * g.unit()),
                1 => m + g.decades(-5, 2),
                _ => g.decades(-4, 6),
            };
            let k = Prepared::exact(origin, &Sphere::new(m, r));
            if !k.outside() {
                continue;
            }
            near += (k.c <= k.r * k.r) as u32;
            let aim = m - origin;
            let d = match case % 5 {
                0 => Vec3::ZERO,
                1 => aim,
                2 => {
                    let (dd, u) = (aim.length(), aim.cross(Vec3::new(0.3, 1.0, 0.1)));
                    let side = libm::sqrtf(libm::fabsf(dd * dd - r * r)) / dd;
                    let off = 1.0 + libm::powf(10.0, -4.0 - 3.0 * g.unit()) * (g.unit() - 0.5);
                    aim * side + u.normalized().unwrap_or(Vec3::ZERO) * (r * off)
                }
                3 if case % 50 == 3 => g.decades(15, 20),
                _ => aim + g.decades(-6, 1) * aim.length(),
            };
            let tmin = [0.0, f32::MIN_POSITIVE, 1e-3][(case / 3) as usize % 3];
            let root = k.hit(d, tmin, f32::INFINITY);
            let tmax = match case / 5 % 4 {
                0 => f32::INFINITY,
                1 => root.unwrap_or(1.0),
                // below the near root: only the far one (or none) can answer
                2 => root.map_or(1.0, |t| t * 0.999),
                _ => g.mag(-3, 4).abs(),
            };
            let scalar = k.hit(d, tmin, tmax);
            assert_eq!(
                // Its `tmax` finite: `f32::MAX` for ∞.
                k.hit_outside(d, tmin, tmax.min(f32::MAX)).map(f32::to_bits),
                scalar.map(f32::to_bits),
                "case {case}: {k:?} d {d:?} tmin {tmin} tmax {tmax}"
            );
            tested += 1;
            hits += scalar.is_some() as u32;
            far_roots += (scalar.is_some() && k.hit(d, 0.0, f32::INFINITY) != scalar) as u32;
        }
        // Hits, far roots and both discriminants are reached.
        assert!(
            tested > 100_000 && hits > tested / 10 && far_roots > 0 && near > 1000,
            "{tested} {hits} {far_roots} {near}"
        );
    }

    /// A Hearn–Baker discriminant that underflows to −0 (a tiny direction grazing a sphere):
    /// `hit_outside` hands it to the general test, whose float range check lets −0 through,
    /// and answers as that test does, bit for bit.
    #[test]
    fn hit_outside_takes_a_negative_zero_discriminant_as_hit_does() {
        const T_MIN: f32 = f32::MIN_POSITIVE; // the renderer's primary rays'
        type Test = fn(f32, f32, f32, f32, f32, f32, f32, f32, f32, f32, f32, f32) -> Option<f32>;
        let (f, r) = (Vec3::new(10.0, 0.0, 0.0), 1.0f32);
        let c = f.dot(f) - r * r;
        let mut negative_zeros = 0;
        for k in -200..200 {
            // a = |d|² ≈ 10⁻⁴⁰ (subnormal): a·(r² − |l|²) underflows near the tangent.
            let y = 1.005_037_8e-21 * (1.0 + k as f32 * f32::EPSILON);
            let d = Vec3::new(-1e-20, y, 0.0);
            let (a, b) = (d.dot(d), f.dot(d));
            let l = f - d * (b / a);
            let disc = a * (r * r - l.dot(l));
            negative_zeros += (disc == 0.0 && disc.is_sign_negative()) as u32;
            for tmax in [f32::MAX, 1e21, 1e20] {
                let run = |test: Test| {
                    let t = test(f.x, f.y, f.z, c, r, d.x, d.y, d.z, a, b, T_MIN, tmax);
                    t.map(f32::to_bits)
                };
                assert_eq!(
                    run(hit_outside_xyz),
                    run(hit_ab_xyz),
                    "k {k} d {d:?} disc {disc:e} tmax {tmax}"
                );
            }
        }
        assert!(negative_zeros > 0, "no case reached a discriminant of -0");
    }

    /// Every lane that `leaving_blocks4` decides is the scalar `leaving_blocks`, and every lane
    /// that `leaving_hit4` decides the scalar `leaving_hit` (its `t` and `f`, bit for bit, each
    /// lane to a limit of its own), for shadow (or mirror) rays
    /// from just above spheres of radius 10⁻² … 10⁶ (the hit given as an anchor and an offset,
    /// as shading gives it), many of them grazing the sphere to within 10⁻¹² … 10⁻³ of its
    /// radius, where the clear-miss margin must cover the error of an f32 `c` that cancels; and
    /// it decides most lanes, misses and blocks (a function that decides nothing would pass
    /// the first check alone).
    #[test]
    fn leaving_lanes_decide_as_the_scalar_tests() {
        use crate::simd::V;
        let mut g = TestRng(0x2545_f491_4f6c_dd1d);
        let (mut claimed, mut misses, mut grazing) = (0u32, 0u32, 0u32);
        let (mut open_claimed, mut open_misses) = (0u32, 0u32);
        let (mut blocks_decided, mut blocks_all) = (0u32, 0u32);
        let (mut mirror_rejected, mut mirror_misses, mut mirror_hits) = (0u32, 0u32, 0u32);
        let unit = |g: &mut TestRng| loop {
            let v = [g.unit() - 0.5, g.unit() - 0.5, g.unit() - 0.5].map(f64::from);
            let n = libm::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
            if n > 0.1 {
                break v.map(|x| x / n);
            }
        };
        let v32 = |v: [f64; 3]| Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32);
        for case in 0..50_000u32 {
            let r = libm::pow(10.0, -2.0 + 8.0 * f64::from(g.unit()));
            let shift = if case % 2 == 0 { 0.0 } else { 1e4 };
            let m = [shift + f64::from(g.unit()), shift - r, -shift];
            let s = Sphere::new(v32(m), r as f32);
            let c = s.center;
            let (r, m) = (f64::from(s.radius), [c.x, c.y, c.z].map(f64::from));
            let lane = |g: &mut TestRng| {
                let u = unit(g);
                // From just above (the hit's own sphere) to 100 radii away (another's).
                let h = r * libm::pow(10.0, -7.0 + 9.0 * f64::from(g.unit()));
                let p = [0, 1, 2].map(|i| m[i] + u[i] * (r + h));
                // A direction whose closest approach to the centre is r (1 ± δ), or any.
                let mut close = f64::INFINITY;
                let d = if !g.next().is_multiple_of(4) {
                    let w = unit(g);
                    let wu = w[0] * u[0] + w[1] * u[1] + w[2] * u[2];
                    let q = [0, 1, 2].map(|i| w[i] - u[i] * wu);
                    let ql = libm::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
                    let delta = libm::pow(10.0, -12.0 + 9.0 * f64::from(g.unit()));
                    close = if g.next().is_multiple_of(2) {
                        delta
                    } else {
                        -delta
                    };
                    let rd = r * (1.0 + close);
                    let dist = r + h;
                    let t = rd * dist / libm::sqrt(dist * dist - rd * rd);
                    [0, 1, 2].map(|i| m[i] + q[i] / ql * t - p[i])
                } else {
                    unit(g)
                };
                // The hit's own ball (anchor) of radius up to 2 holds p.
                let (w, k) = (unit(g), 2.0 * f64::from(g.unit()));
                let anchor = v32([0, 1, 2].map(|i| p[i] + w[i] * k));
                let a = [anchor.x, anchor.y, anchor.z].map(f64::from);
                let rel = v32([0, 1, 2].map(|i| p[i] - a[i]));
                (anchor, rel, v32(d), close, h > r)
            };
            let ls: [(Vec3, Vec3, Vec3, f64, bool); 4] = core::array::from_fn(|_| lane(&mut g));
            let tmax = if case % 3 == 0 { 1.0 } else { f32::INFINITY };
            let (hit, undecided) = leaving_blocks4(
                V::from_lanes(ls.map(|l| l.0)),
                V::from_lanes(ls.map(|l| l.1)),
                &s,
                V::from_lanes(ls.map(|l| l.2)),
                tmax,
                0b1111,
            );
            // The same rays as mirror rays, each lane to a limit of its own: `leaving_hit4`
            // decides a lane as the scalar test does, to the bits of `t` and `f`.
            let limits: [f32; 4] = core::array::from_fn(|l| match (case as usize + l) % 3 {
                0 => 1.0,
                1 => f32::INFINITY,
                _ => 30.0,
            });
            let mirror = leaving_hit4(
                (
                    V::from_lanes(ls.map(|l| l.0)),
                    V::from_lanes(ls.map(|l| l.1)),
                ),
                &s,
                V::from_lanes(ls.map(|l| l.2)),
                (crate::shading::T_EPS, crate::simd::F::from(limits)),
                0b1111,
            );
            for (l, &(anchor, rel, d, close, _)) in ls.iter().enumerate() {
                let found =
                    Prepared::leaving_hit(anchor, rel, &s, d, crate::shading::T_EPS, limits[l]);
                let bits = |(t, f): (f32, Vec3)| (t.to_bits(), [f.x, f.y, f.z].map(f32::to_bits));
                let lanes = (mirror.hit & (1 << l) != 0).then(|| (mirror.t[l], mirror.f.lane(l)));
                let decided = mirror.undecided & (1 << l) == 0;
                assert!(
                    !decided || found.map(bits) == lanes.map(bits),
                    "case {case} lane {l}: {s:?} anchor {anchor:?} rel {rel:?} d {d:?}: \
                     {lanes:?} in lanes, {found:?} alone"
                );
                mirror_hits += (decided && found.is_some()) as u32;
                if close.is_infinite() && found.is_none() {
                    mirror_misses += 1;
                    mirror_rejected += decided as u32;
                }
            }
            for (l, &(anchor, rel, d, close, far)) in ls.iter().enumerate() {
                let blocks = Prepared::leaving_blocks(anchor, rel, &s, d, tmax);
                let decided = undecided & (1 << l) == 0;
                let lane = hit & (1 << l) != 0;
                assert!(
                    !decided || lane == blocks,
                    "case {case} lane {l}: {s:?} anchor {anchor:?} rel {rel:?} d {d:?} tmax {tmax}"
                );
                if far {
                    blocks_all += blocks as u32;
                    blocks_decided += (blocks && decided) as u32;
                }
                let claim = decided && !lane;
                misses += !blocks as u32;
                claimed += claim as u32;
                // Passing within 10⁻⁴ radii of the sphere, and claimed: near the margin's edge.
                grazing += (claim && close > 0.0 && close < 1e-4) as u32;
                if close.is_infinite() {
                    open_misses += !blocks as u32;
                    open_claimed += claim as u32;
                }
            }
        }
        // Rays in any direction from above a surface: the first steps decide most misses
        // (not those from within ~10⁻⁶ radii, where c is within its error of zero). Grazing
        // ones are often left to the scalar test.
        assert!(
            open_claimed > open_misses - open_misses / 5 && grazing > 1000,
            "{open_claimed} of {open_misses} open misses claimed ({claimed} of {misses} in \
             all), {grazing} grazing"
        );
        // Most misses in any direction are decided in lanes, and hits from afar are found.
        assert!(
            mirror_rejected > mirror_misses - mirror_misses / 5 && mirror_hits > 1000,
            "{mirror_rejected} of {mirror_misses} open misses of mirror rays decided in lanes, \
             {mirror_hits} hits"
        );
        // Blocks from origins more than a radius away (another sphere's shadow rays): the
        // lanes decide them, but for those that graze within the margins.
        assert!(
            blocks_decided > blocks_all - blocks_all / 10,
            "{blocks_decided} of {blocks_all} blocks from afar decided in lanes"
        );
    }

    /// `leaving_open_among` (one ray, four spheres) rejects a sphere exactly where the scalar
    /// test's first steps do (its clear miss or `behind`, with `r²` rounded per lane as the
    /// scalar `r * r`), so only misses of `leaving_hit`; and it rejects most misses. Rays leave
    /// points near spheres of radius 10⁻² … 10⁴ (as an anchor and an offset) towards spheres
    /// of other radii ahead, behind and grazing.
    #[test]
    fn leaving_open_among_is_the_scalar_first_steps() {
        let mut g = TestRng(0x6a09_e667_f3bc_c909);
        let (mut rejected, mut misses, mut hits) = (0u32, 0u32, 0u32);
        for case in 0..20_000u32 {
            let scale = libm::powf(10.0, -2.0 + 6.0 * g.unit());
            let anchor = g.vec(4.0 * scale);
            let rel = g.vec(scale);
            let d = loop {
                let d = g.vec(2.0);
                if d.length() > 0.1 {
                    break d;
                }
            };
            let spheres: [Sphere; 4] = core::array::from_fn(|k| {
                // Half of them centred near the ray, ahead or behind, some grazed.
                let t = (g.unit() - 0.3) * 8.0 * scale;
                let near = (anchor + rel) + d * t;
                let off = if k % 2 == 0 { 0.2 } else { 3.0 };
                let r = scale * libm::powf(10.0, -1.0 + 1.5 * g.unit());
                Sphere::new(near + g.vec(off * scale), r)
            });
            let open = leaving_open_among(anchor, rel, spheres.each_ref(), d, 0b1111);
            for (k, s) in spheres.iter().enumerate() {
                let f = (anchor - s.center) + rel;
                let start = leaving_start(f, s.radius, d);
                let scalar_open = !(start.clear || start.behind());
                let lane_open = open & (1 << k) != 0;
                assert_eq!(lane_open, scalar_open, "case {case} sphere {k}: {s:?}");
                let found = Prepared::leaving_hit(anchor, rel, s, d, f32::MIN_POSITIVE, f32::MAX);
                assert!(
                    lane_open || found.is_none(),
                    "case {case} sphere {k} rejected"
                );
                hits += found.is_some() as u32;
                misses += found.is_none() as u32;
                rejected += !lane_open as u32;
            }
        }
        assert!(
            rejected > misses - misses / 10 && hits > 10_000,
            "{rejected} of {misses} misses rejected, {hits} hits"
        );
    }

    /// Where `fused` computes the compensated `c` (an origin within √3 radii of the centre,
    /// where f32 `c` cancels), the lanes must leave the answer to it: shadow rays that reach
    /// the sphere near their `tmax`, from origins √2 … 2 radii from the centre, where `c`'s
    /// rounding moves the near root by ~10 ulp. With the lanes keeping f32 `c` a little
    /// further in (`CANCEL` 0.5 → 0.2, c > r²/2 instead of c > 2r²), 514 of the 42 247 lanes
    /// within √3 radii answer differently: this fails then, while the random rays above pass.
    #[test]
    fn leaving_blocks4_leaves_cancelling_c_to_the_scalar_test() {
        use crate::simd::V;
        let mut g = TestRng(0x9e37_79b9_7f4a_7c15);
        let (mut scalar_zone, mut lanes) = (0u32, 0u32);
        for case in 0..20_000u32 {
            let r = libm::powf(10.0, -1.0 + 3.0 * g.unit());
            let m = Vec3::new(g.unit() * 10.0, g.unit() * 10.0 - r, g.unit() * 10.0);
            let s = Sphere::new(m, r);
            let unit = |g: &mut TestRng| loop {
                let v = Vec3::new(g.unit() - 0.5, g.unit() - 0.5, g.unit() - 0.5);
                if let Some(u) = v.normalized() {
                    break u;
                }
            };
            // Each lane from √2 … 2 radii out towards a point of the near cap, so that its
            // near root is 1 up to the rounding of `d`; `tmax` within ±16 ulp of 1.
            let lane = |g: &mut TestRng| {
                let u = unit(g);
                let p = m + u * (r * (1.414 + 0.6 * g.unit()));
                let aim = (u + unit(g) * 0.3).normalized().unwrap_or(u);
                let target = m + aim * r;
                (p, target - p)
            };
            let ls: [(Vec3, Vec3); 4] = core::array::from_fn(|_| lane(&mut g));
            let tmax = 1.0 + (case % 33) as f32 * f32::EPSILON - 16.0 * f32::EPSILON;
            let (hit, undecided) = leaving_blocks4(
                V::from_lanes(ls.map(|l| l.0)),
                V::splat(Vec3::ZERO),
                &s,
                V::from_lanes(ls.map(|l| l.1)),
                tmax,
                0b1111,
            );
            for (l, &(p, d)) in ls.iter().enumerate() {
                let blocks = Prepared::leaving_blocks(p, Vec3::ZERO, &s, d, tmax);
                let decided = undecided & (1 << l) == 0;
                assert!(
                    !decided || (hit & (1 << l) != 0) == blocks,
                    "case {case} lane {l}: {s:?} from {p:?} along {d:?}, tmax {tmax}"
                );
                let f = p - m;
                let cancels = (f.dot(f) - r * r) <= 2.0 * r * r;
                scalar_zone += (cancels && !decided) as u32;
                lanes += cancels as u32;
            }
        }
        // The origins within √3 radii are the scalar test's (those beyond it the lanes').
        assert!(
            scalar_zone > lanes - lanes / 50,
            "{scalar_zone} of {lanes} left to the scalar test"
        );
        assert!(lanes > 20_000, "{lanes} lanes within √3 radii");
    }

    /// `c_origin_of` is `c_near_of` with `m` and the offset zero: the same bits, or both zero
    /// (of either sign), or both NaN, for coordinates and radii from subnormal to overflowing
    /// squares, zeros of both signs among them.
    #[test]
    fn c_origin_is_c_near() {
        let mut g = TestRng(0x2545_f491_4f6c_dd1d);
        let (mut same, mut zeros) = (0u32, 0u32);
        for case in 0..200_000u32 {
            let pick = |g: &mut TestRng| match g.next() % 8 {
                0 => 0.0,
                1 => -0.0,
                2 => g.mag(-45, -37),
                3 => g.mag(17, 38),
                _ => g.mag(-8, 8),
            };
            let b = [pick(&mut g), pick(&mut g), pick(&mut g)];
            let r = if case % 4 == 0 {
                pick(&mut g).abs()
            } else {
                g.mag(-4, 4).abs()
            };
            let (got, want) = (
                c_origin_of(b, r),
                c_near_of::<f32, true>(b, [0.0; 3], [0.0; 3], r),
            );
            if got.to_bits() == want.to_bits() {
                same += 1;
            } else if got == 0.0 && want == 0.0 {
                zeros += 1;
            } else {
                assert!(
                    got.is_nan() && want.is_nan(),
                    "case {case}: {b:?}, r {r}: {got} and {want}"
                );
            }
        }
        assert!(
            same > 190_000,
            "{same} the same bits, {zeros} zeros of other signs"
        );
    }

    /// `hit_point_far4` and `hit_point_far_lanes` are `hit_point_far` lane by lane, bit for
    /// bit: rays from origins 30 … 10⁵ radii from spheres of radius 10⁻⁴ … 10², centres up to
    /// 10⁴ away from the origin of coordinates, hitting near the rim and the middle, both
    /// roots, and `t` perturbed as a rounded root is. Every other case gives each lane its own
    /// sphere and origin (`hit_point_far_lanes` only), the others one for all four (primary
    /// rays, both). A lane is left out (`None`, a clear bit) exactly where its scalar answer is
    /// not finite.
    #[test]
    fn hit_point_far_lanes_are_the_scalar_offset() {
        use crate::simd::{F, V};
        let mut g = TestRng(0x5851_f42d_4c95_7f2d);
        let (mut some, mut cases) = (0u32, 0u32);
        let bits = |v: Vec3| [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()];
        for case in 0..50_000u32 {
            let setting = |g: &mut TestRng| {
                let r = g.mag(-4, 3).abs();
                let m = g.decades(-2, 5);
                let dist = r * libm::powf(10.0, 1.5 + 3.5 * g.unit());
                let u = g.vec(2.0).normalized().unwrap_or(Vec3::new(0.0, 0.0, 1.0));
                let origin = m + u * dist;
                (
                    Sphere::new(m, r),
                    origin,
                    Prepared::exact(origin, &Sphere::new(m, r)),
                )
            };
            let shared = case % 2 == 0;
            let one = setting(&mut g);
            let lanes: [(Sphere, Vec3, Prepared); 4] = core::array::from_fn(|l| {
                if shared || l == 0 {
                    one
                } else {
                    setting(&mut g)
                }
            });
            let ds: [Vec3; 4] = core::array::from_fn(|l| {
                let (s, origin, _) = lanes[l];
                // Aim at a point of the disc the sphere shows, out to its rim.
                let aim = s.center + g.vec(2.0 * s.radius) * (0.5 + 0.5 * g.unit()) - origin;
                aim * g.mag(-2, 2).abs()
            });
            let ts: [f32; 4] = core::array::from_fn(|l| {
                let t = match lanes[l].2.roots(ds[l]) {
                    Some((near, far)) => {
                        if case % 5 == 0 {
                            far
                        } else {
                            near
                        }
                    }
                    None => 1.0,
                };
                // a rounded root: a few ulp either way
                f32::from_bits((t.to_bits() as i64 + (g.next() % 9) as i64 - 4) as u32)
            });
            let scalar: [Option<(Vec3, Vec3)>; 4] = core::array::from_fn(|l| {
                let (d, (s, _, k)) = (ds[l], lanes[l]);
                hit_point_far(d.x, d.y, d.z, ts[l], k.f.x, k.f.y, k.f.z, &s)
            });
            cases += 1;
            let (p, o, finite) = hit_point_far_lanes(
                V::from_lanes(ds),
                F::from(ts),
                V::from_lanes(lanes.map(|(_, _, k)| k.f)),
                V::from_lanes(lanes.map(|(s, _, _)| s.center)),
                F::from(lanes.map(|(s, _, _)| s.radius)),
            );
            for l in 0..4 {
                let (lane, d, t) = (lanes[l], ds[l], ts[l]);
                match scalar[l] {
                    Some((sp, so)) => {
                        assert!(
                            finite & (1 << l) != 0,
                            "case {case} lane {l}: {lane:?} {d:?} {t}"
                        );
                        assert_eq!(
                            (bits(p.lane(l)), bits(o.lane(l))),
                            (bits(sp), bits(so)),
                            "case {case} lane {l}: {lane:?} along {d:?} t {t}"
                        );
                    }
                    None => assert!(finite & (1 << l) == 0, "case {case} lane {l}: {lane:?}"),
                }
            }
            if shared {
                let (s, _, k) = one;
                match hit_point_far4(V::from_lanes(ds), F::from(ts), k.f, &s) {
                    Some((p4, o4)) => {
                        some += 1;
                        assert_eq!(finite, 0b1111, "case {case}");
                        for l in 0..4 {
                            assert_eq!(
                                (bits(p4.lane(l)), bits(o4.lane(l))),
                                (bits(p.lane(l)), bits(o.lane(l)))
                            );
                        }
                    }
                    None => assert!(scalar.iter().any(Option::is_none), "case {case}"),
                }
            }
        }
        assert!(some > cases / 2 - cases / 100, "{some} of {cases}");
    }
}

#[cfg(test)]
mod scalar_tests {
    use super::super::*;
    use super::Decades;
    use crate::math::TestRng;

    /// [`hit_core`]'s scalar instance, finished as `hit_ab_xyz` finishes its rare cases.
    fn generic_hit(k: &Prepared, d: Vec3, tmin: f32, tmax: f32) -> Option<f32> {
        let (f, c, r) = (k.f, k.c, k.r);
        let (a, b) = (d.dot(d), f.dot(d));
        let hb = !(libm::fabsf(c) <= r * r);
        let h = hit_core(f, c, r * r, hb, finite(c), d, a, b, tmin, tmax);
        if h.scaled != 0 {
            return select(roots_scaled(f.x, f.y, f.z, d.x, d.y, d.z, r)?, tmin, tmax);
        }
        if h.tangent != 0 {
            return select((0.0, 0.0), tmin, tmax);
        }
        (h.hit != 0).then_some(h.t)
    }

    /// `hit_ab_xyz`, the scalar test written out with its branches, is [`hit_core`] on one f32,
    /// bit for bit: spheres of every size, origins on, near, inside and far from them (both
    /// discriminants), tangents, zero and huge directions, overflowing and infinite constants,
    /// and `tmin`, `tmax` of every kind (negative, at the root, NaN).
    #[test]
    fn hit_ab_xyz_is_hit_core() {
        let mut g = TestRng(0x452_821e_638d_0137);
        let bits = |t: Option<f32>| t.map(|t| if t.is_nan() { u32::MAX } else { t.to_bits() });
        let (mut hits, mut scaled, mut tangents, mut near) = (0, 0, 0, 0);
        for case in 0..300_000u32 {
            let r = g.mag(-4, 5).abs();
            let m = g.decades(-4, 5);
            let origin = match case % 5 {
                0 => m + Vec3::new(r, 0.0, 0.0) * (1.0 + 0.01 * (g.unit() - 0.5)),
                1 => m + g.decades(-5, 2),
                2 if case % 64 == 2 => Vec3::new(3e19, -2e19, 1e19),
                _ => g.decades(-4, 6),
            };
            let mut k = Prepared::exact(origin, &Sphere::new(m, r));
            match case % 97 {
                // on the surface exactly, with tangent directions below: q = 0
                3 => {
                    k = Prepared {
                        f: Vec3::new(r, 0.0, 0.0),
                        c: 0.0,
                        r,
                    }
                }
                5 => k.c = f32::INFINITY,
                7 => k.c = f32::NAN,
                _ => {}
            }
            let aim = -k.f;
            let d = match case % 7 {
                0 => Vec3::ZERO,
                1 => aim,
                2 => Vec3::new(0.0, 1.0, 0.0) * g.mag(-3, 3),
                3 => g.decades(15, 20),
                4 => {
                    let (dd, u) = (aim.length(), aim.cross(Vec3::new(0.3, 1.0, 0.1)));
                    let side = libm::sqrtf(libm::fabsf(dd * dd - r * r)) / dd;
                    let off = 1.0 + libm::powf(10.0, -4.0 - 3.0 * g.unit()) * (g.unit() - 0.5);
                    aim * side + u.normalized().unwrap_or(Vec3::ZERO) * (r * off)
                }
                _ => aim + g.decades(-6, 1) * aim.length(),
            };
            let tmin = [0.0, f32::MIN_POSITIVE, -1e3][case as usize % 3];
            let tmax = match (case / 7) % 4 {
                0 => f32::INFINITY,
                1 => k.hit(d, tmin, f32::INFINITY).unwrap_or(1.0),
                2 => g.mag(-3, 4).abs(),
                _ => f32::NAN,
            };
            let scalar = k.hit(d, tmin, tmax);
            assert_eq!(
                bits(generic_hit(&k, d, tmin, tmax)),
                bits(scalar),
                "case {case}: {k:?} {d:?} [{tmin}, {tmax}]"
            );
            let (a, b) = (d.dot(d), k.f.dot(d));
            let hb = !(libm::fabsf(k.c) <= k.r * k.r);
            let h = hit_core(k.f, k.c, k.r * k.r, hb, finite(k.c), d, a, b, tmin, tmax);
            hits += scalar.is_some() as u32;
            scaled += h.scaled;
            tangents += h.tangent;
            near += !hb as u32;
        }
        assert!(hits > 50_000, "{hits} hits");
        assert!(scaled > 500, "{scaled} overflows");
        assert!(tangents > 100, "{tangents} tangents");
        assert!(near > 20_000, "{near} origins with |c| ≤ r²");
    }
}
