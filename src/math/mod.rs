//! Vectors, colours and the few float functions the tracer needs.
//!
//! Every float function goes through [`libm`] (or a hardware instruction that returns the same,
//! correctly rounded bits), never through std's inherent methods: the host and a microcontroller
//! must compute identical pixels. Rust never fuses `a * b + c` into an FMA on its own, so plain
//! arithmetic is reproducible as written.

use core::ops::{Add, AddAssign, Div, Mul, Neg, Sub};

mod exact;
mod func;
mod ieee;

pub use exact::*;
pub use func::*;
pub(crate) use ieee::{Byte, Ieee, Ieee3, IeeeCmp};

/// A vector in 3-D space, also used for linear RGB colours.
///
/// ```
/// use microray::Vec3;
/// let a = Vec3::new(1.0, 2.0, 3.0);
/// assert_eq!(a.dot(Vec3::new(1.0, 0.0, 0.0)), 1.0);
/// assert_eq!(a - a, Vec3::ZERO);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Vec3 {
    /// x component (red, for colours).
    pub x: f32,
    /// y component (green, for colours).
    pub y: f32,
    /// z component (blue, for colours).
    pub z: f32,
}

/// A linear RGB colour; channels are not clamped until a pixel is encoded.
///
/// ```
/// use microray::Color;
/// let grey: Color = Color::splat(0.5);
/// assert_eq!(grey.mul_elem(Color::new(1.0, 0.0, 2.0)), Color::new(0.5, 0.0, 1.0));
/// ```
pub type Color = Vec3;

impl Vec3 {
    /// The zero vector (black).
    pub const ZERO: Vec3 = Vec3::new(0.0, 0.0, 0.0);
    /// All ones (white).
    pub const ONE: Vec3 = Vec3::new(1.0, 1.0, 1.0);

    /// A vector from its components.
    ///
    /// ```
    /// # use microray::Vec3;
    /// assert_eq!(Vec3::new(1.0, 2.0, 3.0).y, 2.0);
    /// ```
    #[inline]
    pub const fn new(x: f32, y: f32, z: f32) -> Self {
        Vec3 { x, y, z }
    }

    /// A vector with all three components equal to `v`.
    ///
    /// ```
    /// # use microray::Vec3;
    /// assert_eq!(Vec3::splat(2.0), Vec3::new(2.0, 2.0, 2.0));
    /// ```
    #[inline]
    pub const fn splat(v: f32) -> Self {
        Vec3 { x: v, y: v, z: v }
    }

    /// Whether all three components are zero (of either sign): `self == Vec3::ZERO`, NaN
    /// included (never zero), as integer tests on the bits, which on a Cortex-M4F are cheaper
    /// than three float comparisons. The shading asks it of every hit's material.
    ///
    /// ```
    /// # use microray::Vec3;
    /// assert!(Vec3::new(0.0, -0.0, 0.0).is_zero());
    /// assert!(!Vec3::new(0.0, 1e-45, 0.0).is_zero() && !Vec3::splat(f32::NAN).is_zero());
    /// ```
    #[inline]
    pub fn is_zero(self) -> bool {
        (self.x.to_bits() | self.y.to_bits() | self.z.to_bits()) << 1 == 0
    }

    /// The dot product.
    ///
    /// ```
    /// # use microray::Vec3;
    /// assert_eq!(Vec3::new(1.0, 2.0, 3.0).dot(Vec3::new(4.0, 5.0, 6.0)), 32.0);
    /// ```
    #[inline]
    pub fn dot(self, o: Vec3) -> f32 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    /// The cross product (right-handed).
    ///
    /// ```
    /// # use microray::Vec3;
    /// let z = Vec3::new(1.0, 0.0, 0.0).cross(Vec3::new(0.0, 1.0, 0.0));
    /// assert_eq!(z, Vec3::new(0.0, 0.0, 1.0));
    /// ```
    #[inline]
    pub fn cross(self, o: Vec3) -> Vec3 {
        Vec3::new(
            self.y * o.z - self.z * o.y,
            self.z * o.x - self.x * o.z,
            self.x * o.y - self.y * o.x,
        )
    }

    /// Component-wise product (how colours filter each other).
    ///
    /// ```
    /// # use microray::Vec3;
    /// assert_eq!(Vec3::new(1.0, 2.0, 3.0).mul_elem(Vec3::splat(2.0)), Vec3::new(2.0, 4.0, 6.0));
    /// ```
    #[inline]
    pub fn mul_elem(self, o: Vec3) -> Vec3 {
        Vec3::new(self.x * o.x, self.y * o.y, self.z * o.z)
    }

    /// The Euclidean length.
    ///
    /// ```
    /// # use microray::Vec3;
    /// assert_eq!(Vec3::new(3.0, 4.0, 0.0).length(), 5.0);
    /// ```
    #[inline]
    pub fn length(self) -> f32 {
        sqrt(self.dot(self))
    }

    /// The absolute value of each component.
    ///
    /// ```
    /// # use microray::Vec3;
    /// assert_eq!(Vec3::new(1.0, -7.0, -0.0).abs(), Vec3::new(1.0, 7.0, 0.0));
    /// ```
    #[inline]
    pub fn abs(self) -> Vec3 {
        Vec3::new(
            libm::fabsf(self.x),
            libm::fabsf(self.y),
            libm::fabsf(self.z),
        )
    }

    /// The largest absolute component.
    ///
    /// ```
    /// # use microray::Vec3;
    /// assert_eq!(Vec3::new(1.0, -7.0, 3.0).max_abs(), 7.0);
    /// ```
    #[inline]
    pub fn max_abs(self) -> f32 {
        let (x, y, z) = (
            libm::fabsf(self.x),
            libm::fabsf(self.y),
            libm::fabsf(self.z),
        );
        let m = if x > y { x } else { y };
        if m > z {
            m
        } else {
            z
        }
    }

    /// Whether all components are finite.
    ///
    /// ```
    /// # use microray::Vec3;
    /// assert!(Vec3::ONE.is_finite());
    /// assert!(!Vec3::new(f32::NAN, 0.0, 0.0).is_finite());
    /// ```
    #[inline]
    pub fn is_finite(self) -> bool {
        self.x.is_finite() && self.y.is_finite() && self.z.is_finite()
    }

    /// The unit vector in the same direction, for any finite non-zero input.
    ///
    /// Dividing by the largest component first keeps the squares from overflowing (a length of
    /// 10³⁰) or underflowing (a length of 10⁻³⁰), where `v / |v|` would give inf or NaN.
    ///
    /// ```
    /// # use microray::Vec3;
    /// let n = Vec3::new(0.0, 1e30, 0.0).normalized().unwrap();
    /// assert_eq!(n, Vec3::new(0.0, 1.0, 0.0));
    /// assert!(Vec3::new(1e-30, 0.0, 0.0).normalized().is_some());
    /// assert!(Vec3::ZERO.normalized().is_none());
    /// ```
    pub fn normalized(self) -> Option<Vec3> {
        let m = self.max_abs();
        if !(m > 0.0) || !m.is_finite() {
            return None;
        }
        let s = self / m;
        Some(s / s.length())
    }

    /// `self / |self|` without the overflow guard of [`Vec3::normalized`]: for vectors whose
    /// length is known to be moderate (ray directions built by the tracer itself).
    ///
    /// ```
    /// # use microray::Vec3;
    /// assert_eq!(Vec3::new(0.0, 0.0, 2.0).normalize_fast(), Vec3::new(0.0, 0.0, 1.0));
    /// ```
    #[inline]
    pub fn normalize_fast(self) -> Vec3 {
        self / self.length()
    }
}

impl Add for Vec3 {
    type Output = Vec3;
    #[inline]
    fn add(self, o: Vec3) -> Vec3 {
        Vec3::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}

impl AddAssign for Vec3 {
    #[inline]
    fn add_assign(&mut self, o: Vec3) {
        *self = *self + o;
    }
}

impl Sub for Vec3 {
    type Output = Vec3;
    #[inline]
    fn sub(self, o: Vec3) -> Vec3 {
        Vec3::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}

impl Neg for Vec3 {
    type Output = Vec3;
    #[inline]
    fn neg(self) -> Vec3 {
        Vec3::new(-self.x, -self.y, -self.z)
    }
}

impl Mul<f32> for Vec3 {
    type Output = Vec3;
    #[inline]
    fn mul(self, s: f32) -> Vec3 {
        Vec3::new(self.x * s, self.y * s, self.z * s)
    }
}

impl Div<f32> for Vec3 {
    type Output = Vec3;
    #[inline]
    fn div(self, s: f32) -> Vec3 {
        Vec3::new(self.x / s, self.y / s, self.z / s)
    }
}

impl From<[f32; 3]> for Vec3 {
    #[inline]
    fn from(a: [f32; 3]) -> Self {
        Vec3::new(a[0], a[1], a[2])
    }
}

/// Whether `x` is neither infinite nor NaN, by a float comparison: `f32::is_finite` tests the
/// bits, which on a Cortex-M4F moves the value to an integer register and back.
///
/// ```
/// use microray::math::finite;
/// assert!(finite(f32::MAX) && !finite(f32::INFINITY) && !finite(f32::NAN));
/// ```
#[inline]
pub fn finite(x: f32) -> bool {
    libm::fabsf(x) <= f32::MAX
}

/// Whether `f32::MIN_POSITIVE ≤ x ≤ f32::MAX` (a positive normal number), by one unsigned
/// comparison of the bits: ±0, subnormals, negatives, ∞ and NaN are outside, as they are for
/// the two float comparisons. Cheaper than those only where `x` goes to a core register anyway,
/// as `sqrt`'s argument does on a Cortex-M4F (see [`finite`]).
#[inline(always)]
pub(crate) fn positive_normal(x: f32) -> bool {
    let from = f32::MIN_POSITIVE.to_bits();
    x.to_bits().wrapping_sub(from) <= f32::MAX.to_bits() - from
}

/// Whether `+0 ≤ x ≤ f32::MAX` with `+0`'s sign, by one unsigned comparison of the bits: −0,
/// negatives, ∞ and NaN are outside (the float comparisons would let −0 in). For the same
/// places as [`positive_normal`].
#[cfg(any(test, not(lanes)))]
#[inline(always)]
pub(crate) fn plus_finite(x: f32) -> bool {
    x.to_bits() <= f32::MAX.to_bits()
}

/// The unit tests' random numbers: xorshift64*, as tests/common/rng.rs (which unit tests cannot
/// reach), so every random unit test is reproducible by its seed.
#[cfg(test)]
pub(crate) struct TestRng(pub u64);

#[cfg(test)]
impl TestRng {
    /// The next 64 random bits.
    pub(crate) fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    /// Uniform in [0, 1), from 24 bits.
    pub(crate) fn unit(&mut self) -> f32 {
        (self.next() >> 40) as f32 / (1u64 << 24) as f32
    }

    /// Each coordinate uniform in [−s/2, s/2).
    pub(crate) fn vec(&mut self, s: f32) -> Vec3 {
        Vec3::new(self.unit() - 0.5, self.unit() - 0.5, self.unit() - 0.5) * s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The bit tests are the float comparisons they stand for, on the edges of their ranges and
    /// on random bit patterns (every sign, exponent and NaN payload).
    #[test]
    fn bit_range_tests_are_the_float_comparisons() {
        let edges = [
            0.0,
            -0.0,
            f32::MIN_POSITIVE,
            f32::MIN_POSITIVE.next_down(),
            f32::MIN_POSITIVE.next_up(),
            f32::from_bits(1),
            f32::MAX,
            -f32::MAX,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            -f32::NAN,
            f32::from_bits(0x7f80_0001),
            1.0,
            -1.0,
            -f32::MIN_POSITIVE,
        ];
        let mut g = TestRng(0x9e37_79b9_7f4a_7c15);
        let random = (0..1_000_000).map(|_| f32::from_bits(g.next() as u32));
        let (mut inside, mut outside) = (0, 0);
        for x in edges.into_iter().chain(random) {
            let normal = (f32::MIN_POSITIVE..=f32::MAX).contains(&x);
            assert_eq!(positive_normal(x), normal, "{x:e} ({:#x})", x.to_bits());
            let plus = (0.0..=f32::MAX).contains(&x) && x.is_sign_positive();
            assert_eq!(plus_finite(x), plus, "{x:e} ({:#x})", x.to_bits());
            inside += normal as u32;
            outside += !normal as u32;
        }
        assert!(inside > 100_000 && outside > 100_000, "{inside} {outside}");
    }
}
