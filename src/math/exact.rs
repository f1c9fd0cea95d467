//! Error-free transformations in plain f32: TwoSum, Dekker's split, exact squares and products.
//! Each is one definition generic over [`Ieee`], so the scalar path and the
//! vector lanes compute the same bits.

use core::ops::{Add, BitAnd, Div, Mul, Sub};

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

/// [`Ieee`] with division, absolute values and comparisons, for formulas with branches: a
/// comparison gives a [`IeeeCmp::Mask`] (a `bool` for one f32, a lane mask for four) and a
/// branch becomes [`IeeeCmp::select`] between both arms, so one definition gives the scalar
/// answers in every lane. [`IeeeCmp::select_lazy`] keeps the scalar form's early exit: one f32
/// computes the arm only when it is taken, the lanes compute it and blend.
pub(crate) trait IeeeCmp: Ieee + Div<Output = Self> {
    /// The outcome of a comparison.
    type Mask: Copy + BitAnd<Output = Self::Mask>;
    /// `|x|`: the sign cleared (`libm::fabsf` for one f32).
    fn abs(self) -> Self;
    /// `self < o` (false where either is NaN).
    fn lt(self, o: Self) -> Self::Mask;
    /// `self > o` (false where either is NaN).
    fn gt(self, o: Self) -> Self::Mask;
    /// `!(self > o)`: true where either is NaN.
    fn not_gt(self, o: Self) -> Self::Mask;
    /// `if m { a } else { b }`.
    fn select(m: Self::Mask, a: Self, b: Self) -> Self;
    /// `if m { a() } else { b }`, `a` evaluated only where needed (one f32: only when `m`).
    fn select_lazy(m: Self::Mask, a: impl FnOnce() -> Self, b: Self) -> Self;
}

impl IeeeCmp for f32 {
    type Mask = bool;
    #[inline(always)]
    fn abs(self) -> f32 {
        libm::fabsf(self)
    }
    #[inline(always)]
    fn lt(self, o: f32) -> bool {
        self < o
    }
    #[inline(always)]
    fn gt(self, o: f32) -> bool {
        self > o
    }
    #[inline(always)]
    fn not_gt(self, o: f32) -> bool {
        !(self > o)
    }
    #[inline(always)]
    fn select(m: bool, a: f32, b: f32) -> f32 {
        if m {
            a
        } else {
            b
        }
    }
    #[inline(always)]
    fn select_lazy(m: bool, a: impl FnOnce() -> f32, b: f32) -> f32 {
        if m {
            a()
        } else {
            b
        }
    }
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
pub(super) fn split<T: Ieee>(a: T) -> (T, T) {
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
