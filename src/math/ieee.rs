//! The IEEE operations that generic formulas are written in, on one f32 ([`Vec3`] for vectors)
//! and, where `cfg(lanes)` gives vector registers, on four lanes (implemented in `simd.rs`).
//! A formula written once over these traits does the same operations in the same order in
//! both, so a lane computes the scalar bits; the scalar instance keeps its early exits, as a
//! `bool` mask makes every selection a branch.

use super::{spec_pow, sqrt, Vec3};
use core::ops::{Add, BitAnd, BitOr, Div, Mul, Not, Sub};

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

/// [`Ieee`] with division, square roots, absolute values and comparisons, for formulas with
/// branches: a comparison gives a [`IeeeCmp::Mask`] (a `bool` for one f32, a lane mask for
/// four) and a branch becomes [`IeeeCmp::select`] between both arms, so one definition gives
/// the scalar answers in every lane. [`IeeeCmp::select_lazy`] keeps the scalar form's early
/// exit: one f32 computes the arm only when it is taken, the lanes compute it and blend.
/// Decisions that skip work for every lane at once go through [`IeeeCmp::bits`].
pub(crate) trait IeeeCmp: Ieee + Div<Output = Self> {
    /// The outcome of a comparison.
    type Mask: Copy
        + BitAnd<Output = Self::Mask>
        + BitOr<Output = Self::Mask>
        + Not<Output = Self::Mask>;
    /// `|x|`: the sign cleared (`libm::fabsf` for one f32).
    fn abs(self) -> Self;
    /// The correctly rounded square root ([`sqrt`] for one f32).
    fn sqrt(self) -> Self;
    /// `self < o` (false where either is NaN).
    fn lt(self, o: Self) -> Self::Mask;
    /// `self ≤ o` (false where either is NaN).
    fn le(self, o: Self) -> Self::Mask;
    /// `self > o` (false where either is NaN).
    fn gt(self, o: Self) -> Self::Mask;
    /// `self ≥ o` (false where either is NaN).
    fn ge(self, o: Self) -> Self::Mask;
    /// `self == o` (false where either is NaN; `0 == −0`).
    #[cfg_attr(not(any(test, lanes)), allow(dead_code))]
    fn eq(self, o: Self) -> Self::Mask;
    /// `!(self > o)`: true where either is NaN.
    fn not_gt(self, o: Self) -> Self::Mask;
    /// `f32::MIN_POSITIVE ≤ self ≤ f32::MAX`: a positive normal number.
    fn positive_normal(self) -> Self::Mask;
    /// `if m { a } else { b }`.
    fn select(m: Self::Mask, a: Self, b: Self) -> Self;
    /// The greater of the two. Where either is NaN it may give either operand or a NaN (x86's
    /// `maxps` gives `o`, NEON's `vmaxq` a NaN): a formula that uses it must hold with any.
    fn greater(self, o: Self) -> Self;
    /// The lesser of the two, with [`IeeeCmp::greater`]'s latitude at a NaN.
    fn lesser(self, o: Self) -> Self;
    /// `if m { a() } else { b }`, `a` evaluated only where needed (one f32: only when `m`).
    fn select_lazy(m: Self::Mask, a: impl FnOnce() -> Self, b: Self) -> Self;
    /// `if m { a() } else { b() }` where only the lanes `care` (bits `0..4`) are read: one f32
    /// computes the arm it takes; the lanes compute one arm where every lane of `care` takes
    /// it, both where they differ.
    #[cfg_attr(not(any(test, lanes)), allow(dead_code))]
    fn choose(m: Self::Mask, care: u32, a: impl FnOnce() -> Self, b: impl FnOnce() -> Self)
        -> Self;
    /// The lanes of a mask as bits `0..4` (one f32: bit 0).
    fn bits(m: Self::Mask) -> u32;
    /// The mask whose lanes are the bits `0..4` of `bits`.
    fn mask(bits: u32) -> Self::Mask;
    /// [`spec_pow`] of each lane to one exponent `s`, or `None` where the lanes cannot compute
    /// it (one f32 always can).
    fn spec_pow(self, s: f32) -> Option<Self>;
}

impl IeeeCmp for f32 {
    type Mask = bool;
    #[inline(always)]
    fn abs(self) -> f32 {
        libm::fabsf(self)
    }
    #[inline(always)]
    fn sqrt(self) -> f32 {
        sqrt(self)
    }
    #[inline(always)]
    fn lt(self, o: f32) -> bool {
        self < o
    }
    #[inline(always)]
    fn le(self, o: f32) -> bool {
        self <= o
    }
    #[inline(always)]
    fn gt(self, o: f32) -> bool {
        self > o
    }
    #[inline(always)]
    fn ge(self, o: f32) -> bool {
        self >= o
    }
    #[inline(always)]
    fn eq(self, o: f32) -> bool {
        self == o
    }
    #[inline(always)]
    fn not_gt(self, o: f32) -> bool {
        !(self > o)
    }
    /// A bit test: on a Cortex-M4F cheaper than the two float comparisons where the value goes
    /// to a core register anyway, as `vsqrt`'s argument does.
    #[inline(always)]
    fn positive_normal(self) -> bool {
        super::positive_normal(self)
    }
    #[inline(always)]
    fn greater(self, o: f32) -> f32 {
        if self > o {
            self
        } else {
            o
        }
    }
    #[inline(always)]
    fn lesser(self, o: f32) -> f32 {
        if self < o {
            self
        } else {
            o
        }
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
    #[inline(always)]
    fn choose(m: bool, _: u32, a: impl FnOnce() -> f32, b: impl FnOnce() -> f32) -> f32 {
        if m {
            a()
        } else {
            b()
        }
    }
    #[inline(always)]
    fn bits(m: bool) -> u32 {
        m as u32
    }
    #[inline(always)]
    fn mask(bits: u32) -> bool {
        bits & 1 != 0
    }
    #[inline(always)]
    fn spec_pow(self, s: f32) -> Option<f32> {
        Some(spec_pow(self, s))
    }
}

/// Three [`IeeeCmp`] values as a vector: [`Vec3`] for one f32, three vectors of lanes for
/// four. The operations are `Vec3`'s, coordinate by coordinate in its order (`dot` is
/// `(x·x' + y·y') + z·z'`).
pub(crate) trait Ieee3: Copy {
    /// One coordinate.
    type S: IeeeCmp;
    /// `v` in every lane.
    fn splat(v: Vec3) -> Self;
    fn dot(self, o: Self) -> Self::S;
    fn add(self, o: Self) -> Self;
    fn sub(self, o: Self) -> Self;
    /// The signs flipped, as `Vec3`'s `-`.
    fn neg(self) -> Self;
    fn mul(self, s: Self::S) -> Self;
    fn div(self, s: Self::S) -> Self;
    fn mul_elem(self, o: Self) -> Self;
    /// The cross product, as [`Vec3::cross`].
    fn cross(self, o: Self) -> Self;
    /// `if m { a } else { b }`, lane by lane.
    fn select(m: <Self::S as IeeeCmp>::Mask, a: Self, b: Self) -> Self;
    /// [`Vec3::normalize_fast`]: each coordinate divided by the length.
    #[inline(always)]
    fn normalize_fast(self) -> Self {
        self.div(self.dot(self).sqrt())
    }
    /// [`Vec3::normalized`] of `self` or zero, where the lanes can compute it (one f32 can):
    /// the guarded form of a vector whose square leaves the normal range.
    fn normalized_or_zero(self) -> Option<Self>;
}

impl Ieee3 for Vec3 {
    type S = f32;
    #[inline(always)]
    fn splat(v: Vec3) -> Vec3 {
        v
    }
    #[inline(always)]
    fn dot(self, o: Vec3) -> f32 {
        Vec3::dot(self, o)
    }
    #[inline(always)]
    fn add(self, o: Vec3) -> Vec3 {
        self + o
    }
    #[inline(always)]
    fn sub(self, o: Vec3) -> Vec3 {
        self - o
    }
    #[inline(always)]
    fn neg(self) -> Vec3 {
        -self
    }
    #[inline(always)]
    fn mul(self, s: f32) -> Vec3 {
        self * s
    }
    #[inline(always)]
    fn div(self, s: f32) -> Vec3 {
        self / s
    }
    #[inline(always)]
    fn mul_elem(self, o: Vec3) -> Vec3 {
        Vec3::mul_elem(self, o)
    }
    #[inline(always)]
    fn cross(self, o: Vec3) -> Vec3 {
        Vec3::cross(self, o)
    }
    #[inline(always)]
    fn select(m: bool, a: Vec3, b: Vec3) -> Vec3 {
        if m {
            a
        } else {
            b
        }
    }
    #[inline(always)]
    fn normalized_or_zero(self) -> Option<Vec3> {
        Some(self.normalized().unwrap_or(Vec3::ZERO))
    }
}

/// Rounding a channel's `255c + 0.5` down to its byte, saturating: NaN and values below 0 give
/// 0, 255 and above 255 (a `u8` for one f32, four in integer lanes).
pub(crate) trait Byte: Ieee {
    /// The byte, or four.
    type Out;
    fn byte(self) -> Self::Out;
}

impl Byte for f32 {
    type Out = u8;
    /// The cast saturates (NaN to 0), which a Cortex-M4F's `vcvt` does by itself, and truncates,
    /// which is floor for v ≥ 0; the clamp is one `usat` there.
    #[inline(always)]
    fn byte(self) -> u8 {
        (self as i32).clamp(0, 255) as u8
    }
}
