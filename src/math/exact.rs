//! Error-free transformations in plain f32: TwoSum, Dekker's split, exact squares and products.
//! Each is one definition generic over [`Ieee`], so the scalar path and the
//! vector lanes compute the same bits.

use super::Ieee;

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
