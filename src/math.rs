//! Vectors, colours and the few float functions the tracer needs.
//!
//! Every float function goes through [`libm`] (or a hardware instruction that returns the same,
//! correctly rounded bits), never through std's inherent methods: the host and a microcontroller
//! must compute identical pixels. Rust never fuses `a * b + c` into an FMA on its own, so plain
//! arithmetic is reproducible as written.

use core::ops::{Add, AddAssign, Div, Mul, Neg, Sub};

/// A vector in 3-D space, also used for linear RGB colours.
///
/// ```
/// use microray::Vec3;
/// let a = Vec3::new(1.0, 2.0, 3.0);
/// assert_eq!(a.dot(Vec3::new(1.0, 0.0, 0.0)), 1.0);
/// assert_eq!(a - a, Vec3::ZERO);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default)]
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
    /// included (never zero), as integer tests on the bits, which cost a third of three float
    /// comparisons on a Cortex-M4F. The shading asks it of every hit's material.
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

/// `a + b` rounded, and the rounding error exactly: `a + b = s + e` (Knuth's TwoSum, which
/// needs no ordering of `a` and `b`). Exact for finite inputs whose sum does not overflow.
///
/// ```
/// use microray::math::two_sum;
/// assert_eq!(two_sum(1.0, 1e-8), (1.0, 1e-8)); // the small addend survives in `e`
/// ```
#[inline(always)]
pub fn two_sum(a: f32, b: f32) -> (f32, f32) {
    two_sum_of(a, b)
}

/// The IEEE operations of the error-free transformations, on one f32 and (`cfg(lanes)`) on the
/// four lanes of a vector: both run the one generic definition, the same operations in the same
/// order, so a lane computes the scalar bits.
pub(crate) trait Ieee:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self>
{
    fn splat(x: f32) -> Self;
    /// `-x`: the sign flipped.
    fn flip(self) -> Self;
}

impl Ieee for f32 {
    #[inline(always)]
    fn splat(x: f32) -> f32 {
        x
    }
    #[inline(always)]
    fn flip(self) -> f32 {
        -self
    }
}

#[cfg(lanes)]
impl Ieee for lanes::F {
    #[inline(always)]
    fn splat(x: f32) -> lanes::F {
        lanes::F::splat(x)
    }
    #[inline(always)]
    fn flip(self) -> lanes::F {
        lanes::neg(self)
    }
}

/// [`two_sum`] on any [`Ieee`] type.
#[inline(always)]
pub(crate) fn two_sum_of<T: Ieee>(a: T, b: T) -> (T, T) {
    let s = a + b;
    let bv = s - a;
    (s, (a - (s - bv)) + (b - bv))
}

/// Veltkamp's split: `a = hi + lo` with halves of at most 12 significant bits, whose products
/// are exact in f32.
#[inline(always)]
fn split<T: Ieee>(a: T) -> (T, T) {
    let t = a * T::splat(4097.0); // 2¹² + 1
    let hi = t - (t - a);
    (hi, a - hi)
}

/// `a²` rounded, and the rounding error exactly: `a² = p + e` (Dekker's product, with
/// Veltkamp's split of `a` into two 12-bit halves whose products are exact). Plain f32
/// operations rather than a fused multiply-add, which not every target has in hardware, so
/// every target gets the same bits. Exact unless `a²` overflows (`|a| ≥ 2⁶⁴`: `p` is ∞ and `e`
/// not finite) or the error is below the normal range (`|a| < 2⁻⁵⁰`).
///
/// ```
/// use microray::math::two_square;
/// let (p, e) = two_square(4097.0); // 4097² = 16 785 409 needs 25 bits
/// assert_eq!((p, e), (16_785_408.0, 1.0));
/// ```
#[inline(always)]
pub fn two_square(a: f32) -> (f32, f32) {
    two_square_of(a)
}

/// [`two_square`] on any [`Ieee`] type.
#[inline(always)]
pub(crate) fn two_square_of<T: Ieee>(a: T) -> (T, T) {
    let p = a * a;
    let (hi, lo) = split(a);
    (p, ((hi * hi - p) + T::splat(2.0) * hi * lo) + lo * lo)
}

/// `a·b` rounded, and the rounding error exactly: `a·b = p + e` ([`two_square`]'s method for
/// two factors). Exact unless the product overflows or its error is below the normal range.
///
/// ```
/// use microray::math::two_product;
/// let (p, e) = two_product(4097.0, 4095.0); // 16 777 215 = 2²⁴ − 1 fits; 4097·4097 does not
/// assert_eq!((p, e), (16_777_215.0, 0.0));
/// assert_eq!(two_product(4097.0, 4097.0), (16_785_408.0, 1.0));
/// ```
#[inline(always)]
pub fn two_product(a: f32, b: f32) -> (f32, f32) {
    two_product_of(a, b)
}

/// [`two_product`] on any [`Ieee`] type.
#[inline(always)]
pub(crate) fn two_product_of<T: Ieee>(a: T, b: T) -> (T, T) {
    let p = a * b;
    let ((ah, al), (bh, bl)) = (split(a), split(b));
    (p, ((ah * bh - p) + ah * bl + al * bh) + al * bl)
}

/// The correctly rounded square root.
///
/// On Cortex-M4F/M7 (`thumbv7em-none-eabihf`) this is the `vsqrt.f32` instruction; elsewhere
/// `libm::sqrtf`. Both are correctly rounded (IEEE 754), so they return the same bits.
///
/// ```
/// assert_eq!(microray::math::sqrt(2.0), 1.4142135);
/// ```
#[inline]
pub fn sqrt(x: f32) -> f32 {
    #[cfg(all(target_arch = "arm", target_abi = "eabihf"))]
    {
        hw::vsqrt(x)
    }
    #[cfg(not(all(target_arch = "arm", target_abi = "eabihf")))]
    {
        libm::sqrtf(x)
    }
}

#[cfg(all(target_arch = "arm", target_abi = "eabihf"))]
#[allow(unsafe_code)]
mod hw {
    /// `vsqrt.f32`: libm's `sqrtf` is a ~200-instruction software routine on thumbv7em.
    ///
    /// Rust exposes no `vfp2` target feature on thumbv7em-none-eabihf (its FPU is
    /// single-precision only), so S registers cannot be asm operands: the value travels through
    /// core registers, and `s0` is declared clobbered (a clobber needs no operand type), which
    /// lets the compiler keep nothing there instead of saving and restoring it in the block.
    #[inline(always)]
    pub fn vsqrt(x: f32) -> f32 {
        let bits: u32;
        // SAFETY: the eabihf ABI guarantees an enabled FPU whenever this code runs. The block
        // touches no memory and no stack, and writes only `r` and the declared clobber `s0`.
        unsafe {
            core::arch::asm!(
                "vmov s0, {x}",
                "vsqrt.f32 s0, s0",
                "vmov {r}, s0",
                x = in(reg) x.to_bits(),
                r = lateout(reg) bits,
                out("s0") _,
                options(pure, nomem, nostack, preserves_flags),
            );
        }
        f32::from_bits(bits)
    }
}

/// `base` raised to `exp`, through `libm::powf`.
///
/// ```
/// assert_eq!(microray::math::powf(2.0, 10.0), 1024.0);
/// ```
#[inline]
pub fn powf(base: f32, exp: f32) -> f32 {
    libm::powf(base, exp)
}

/// `x^s` for the Blinn–Phong highlight (`0 ≤ x ≤ 1`, `s > 0`): repeated squaring when `s` is a
/// whole number up to 2¹⁶, `libm::powf` otherwise.
///
/// `powf` is a ~250-instruction routine and the highlight is evaluated per light and hit; the
/// shininess of real scenes is a whole number, where at most 2·16 multiplications do. Each
/// multiplication rounds once, so the result is within ~2 log₂(s) ulp of `x^s`: at s = 5000
/// under 0.011 of an 8-bit level (see docs/numerics.md), far below what the image resolves.
///
/// ```
/// use microray::math::spec_pow;
/// assert_eq!(spec_pow(0.5, 3.0), 0.125);
/// assert_eq!(spec_pow(0.0, 32.0), 0.0);
/// assert!((spec_pow(0.9, 2.5) - 0.9f32.powf(2.5)).abs() < 1e-6); // not whole: powf
/// assert!((spec_pow(0.999, 5000.0) - 0.999f32.powf(5000.0)).abs() < 1e-5);
/// ```
#[inline]
pub fn spec_pow(x: f32, s: f32) -> f32 {
    let n = s as u32;
    if n as f32 != s || n > 1 << 16 {
        return libm::powf(x, s);
    }
    if n == 0 {
        return 1.0;
    }
    pow_by_squaring(x, n)
}

/// `x^n` for `n ≥ 1` by right-to-left binary powering: [`spec_pow`]'s loop, shared with its
/// vector lanes so that both multiply in the same order. The lowest set bit's power starts the
/// product (the same bits as 1 · x^(2^k)), so whole powers of two cost their squarings only.
#[inline(always)]
fn pow_by_squaring<T: Copy + core::ops::MulAssign>(x: T, n: u32) -> T {
    let (mut base, mut e) = (x, n);
    while e & 1 == 0 {
        base *= base;
        e >>= 1;
    }
    let mut acc = base;
    e >>= 1;
    while e != 0 {
        base *= base;
        if e & 1 == 1 {
            acc *= base;
        }
        e >>= 1;
    }
    acc
}

/// Four `Vec3`s in vector registers, one lane each (`cfg(lanes)`: hosts with f32 vectors), for
/// shading four pixels at once. Every operation is the lane-wise IEEE operation of its `Vec3`
/// counterpart in the same order, so each lane computes the scalar bits.
#[cfg(lanes)]
pub(crate) mod lanes {
    use super::Vec3;
    pub(crate) use wide::f32x4 as F;

    /// `-x` as `Vec3` negates: the sign flipped (wide's `-` is `0 − x`, which differs at zero).
    #[inline(always)]
    pub(crate) fn neg(x: F) -> F {
        x ^ F::splat(-0.0)
    }

    /// The lanes of a mask (all bits set or clear per lane) as bits `0..4`.
    #[inline(always)]
    pub(crate) fn bits(mask: F) -> u32 {
        mask.move_mask() as u32
    }

    /// The indices of the set bits of `bits`, lowest first: the lanes (or span pixels) a mask
    /// names, for the loops that visit them one by one.
    #[inline(always)]
    pub(crate) fn ones(mut bits: u32) -> impl Iterator<Item = usize> {
        core::iter::from_fn(move || {
            (bits != 0).then(|| {
                let l = bits.trailing_zeros() as usize;
                bits &= bits - 1;
                l
            })
        })
    }

    /// A mask from bits `0..4`.
    #[inline(always)]
    pub(crate) fn mask(bits: u32) -> F {
        let b = |l: u32| {
            if bits & (1 << l) != 0 {
                f32::from_bits(!0)
            } else {
                0.0
            }
        };
        F::from([b(0), b(1), b(2), b(3)])
    }

    /// Four vectors, lane by lane.
    #[derive(Debug, Clone, Copy)]
    pub(crate) struct V {
        pub x: F,
        pub y: F,
        pub z: F,
    }

    impl V {
        #[inline(always)]
        pub(crate) fn splat(v: Vec3) -> V {
            V {
                x: F::splat(v.x),
                y: F::splat(v.y),
                z: F::splat(v.z),
            }
        }
        #[inline(always)]
        pub(crate) fn from_lanes(v: [Vec3; 4]) -> V {
            V {
                x: F::from(v.map(|v| v.x)),
                y: F::from(v.map(|v| v.y)),
                z: F::from(v.map(|v| v.z)),
            }
        }
        #[inline(always)]
        pub(crate) fn lane(&self, l: usize) -> Vec3 {
            let (x, y, z) = (
                self.x.as_array_ref(),
                self.y.as_array_ref(),
                self.z.as_array_ref(),
            );
            Vec3::new(x[l & 3], y[l & 3], z[l & 3])
        }
        /// `Vec3::dot`'s association: `(x·x' + y·y') + z·z'`.
        #[inline(always)]
        pub(crate) fn dot(self, o: V) -> F {
            self.x * o.x + self.y * o.y + self.z * o.z
        }
        #[inline(always)]
        pub(crate) fn add(self, o: V) -> V {
            V {
                x: self.x + o.x,
                y: self.y + o.y,
                z: self.z + o.z,
            }
        }
        #[inline(always)]
        pub(crate) fn sub(self, o: V) -> V {
            V {
                x: self.x - o.x,
                y: self.y - o.y,
                z: self.z - o.z,
            }
        }
        #[inline(always)]
        pub(crate) fn neg(self) -> V {
            V {
                x: neg(self.x),
                y: neg(self.y),
                z: neg(self.z),
            }
        }
        #[inline(always)]
        pub(crate) fn mul(self, s: F) -> V {
            V {
                x: self.x * s,
                y: self.y * s,
                z: self.z * s,
            }
        }
        #[inline(always)]
        pub(crate) fn div(self, s: F) -> V {
            V {
                x: self.x / s,
                y: self.y / s,
                z: self.z / s,
            }
        }
        #[inline(always)]
        pub(crate) fn mul_elem(self, o: V) -> V {
            V {
                x: self.x * o.x,
                y: self.y * o.y,
                z: self.z * o.z,
            }
        }
        /// `Vec3::cross`'s formula.
        #[inline(always)]
        pub(crate) fn cross(self, o: V) -> V {
            V {
                x: self.y * o.z - self.z * o.y,
                y: self.z * o.x - self.x * o.z,
                z: self.x * o.y - self.y * o.x,
            }
        }
        /// All three coordinates finite, as bits `0..4`.
        #[inline(always)]
        pub(crate) fn finite(self) -> u32 {
            use wide::CmpLe;
            let max = F::splat(f32::MAX);
            let ok = self.x.abs().cmp_le(max) & self.y.abs().cmp_le(max) & self.z.abs().cmp_le(max);
            bits(ok)
        }
        /// `Vec3::normalize_fast`: each coordinate divided by the length.
        #[inline(always)]
        pub(crate) fn normalize_fast(self) -> V {
            self.div(self.dot(self).sqrt())
        }
        /// `a` in the lanes of `mask`, else `b`.
        #[inline(always)]
        pub(crate) fn select(mask: F, a: V, b: V) -> V {
            V {
                x: mask.blend(a.x, b.x),
                y: mask.blend(a.y, b.y),
                z: mask.blend(a.z, b.z),
            }
        }
    }

    /// [`spec_pow`](super::spec_pow) of each lane of `x` to one exponent `s`: the same
    /// multiplications in the same order; `None` where `spec_pow` calls `powf` (an `s` that is
    /// not a whole number up to 2¹⁶).
    #[inline(always)]
    pub(crate) fn spec_pow(x: F, s: f32) -> Option<F> {
        let n = s as u32;
        if n as f32 != s || n > 1 << 16 {
            return None;
        }
        if n == 0 {
            return Some(F::ONE);
        }
        Some(super::pow_by_squaring(x, n))
    }
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
