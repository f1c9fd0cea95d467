//! xorshift64*: a small deterministic generator, so every random test is reproducible by seed.

use microray::Vec3;

/// The generator; the state must not be 0.
pub struct Rng(pub u64);

impl Rng {
    /// The next 64 random bits.
    pub fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    /// Uniform in [0, 1), from 53 bits.
    pub fn u(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.u()
    }

    /// Uniform in [lo, hi) in f32, from 24 bits.
    pub fn range_f32(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * ((self.next() >> 40) as f32 / (1u64 << 24) as f32)
    }

    /// Uniform in [lo, hi), rounded to a multiple of 1/64.
    pub fn grid(&mut self, lo: f64, hi: f64) -> f64 {
        (self.range(lo, hi) * 64.0).round() / 64.0
    }

    /// A uniformly random unit vector.
    pub fn dir(&mut self) -> [f64; 3] {
        loop {
            let v = [
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
            ];
            let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            if n > 0.1 && n <= 1.0 {
                return [v[0] / n, v[1] / n, v[2] / n];
            }
        }
    }

    /// A unit ray from 0–0.01 above height 1 (over a ground sphere whose top is at 0) towards a
    /// ground point up to 30 away horizontally (grazing at 1/30): the ground ray set of the
    /// accuracy tests and of the speed-against-error report, which must measure the same rays.
    pub fn ground_ray(&mut self) -> (Vec3, Vec3) {
        let o = [
            self.range(-10.0, 10.0),
            1.0 + self.range(0.0, 0.01),
            self.range(-10.0, 10.0),
        ];
        let dist = 30f64.powf(self.u());
        let phi = self.range(0.0, std::f64::consts::TAU);
        let d = [dist * phi.cos(), -o[1], dist * phi.sin()];
        let nd = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let v32 = |v: [f64; 3]| Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32);
        (v32(o), v32([d[0] / nd, d[1] / nd, d[2] / nd]))
    }
}
