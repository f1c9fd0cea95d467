//! The one place that chooses the lane backend: on hosts with f32 vector registers
//! (`cfg(lanes)`, set by build.rs: x86-64, AArch64 with NEON, wasm32 with simd128) four lanes of `wide::f32x4`;
//! elsewhere none, and the code above runs its scalar path. Every lane operation is the IEEE
//! operation of its scalar counterpart in the same order (no fused multiply-add), so a lane
//! computes the scalar bits. The math traits (`Ieee`, `IeeeCmp`, `Ieee3`, `Byte`, in
//! `math/ieee.rs`) are implemented here for the lanes, so that each formula is written once,
//! generic over one f32 and four lanes (ARCHITECTURE.md lists them). The lanes pay for
//! themselves: the target scene takes 287.9 x86 instructions a pixel with them, 672.7 built as
//! the Cortex-M path (`bench/instructions.sh`, and with `MICRORAY_HOST_AS=m4f`).

#[cfg(lanes)]
use crate::math::{Byte, Ieee, Ieee3, IeeeCmp, Vec3};

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

#[cfg(lanes)]
impl IeeeCmp for lanes::F {
    type Mask = lanes::F;
    #[inline(always)]
    fn abs(self) -> lanes::F {
        lanes::F::abs(self)
    }
    #[inline(always)]
    fn sqrt(self) -> lanes::F {
        lanes::F::sqrt(self)
    }
    #[inline(always)]
    fn lt(self, o: lanes::F) -> lanes::F {
        lanes::CmpLt::cmp_lt(self, o)
    }
    #[inline(always)]
    fn le(self, o: lanes::F) -> lanes::F {
        lanes::CmpLe::cmp_le(self, o)
    }
    #[inline(always)]
    fn gt(self, o: lanes::F) -> lanes::F {
        lanes::CmpGt::cmp_gt(self, o)
    }
    #[inline(always)]
    fn ge(self, o: lanes::F) -> lanes::F {
        lanes::CmpGe::cmp_ge(self, o)
    }
    #[inline(always)]
    fn eq(self, o: lanes::F) -> lanes::F {
        lanes::CmpEq::cmp_eq(self, o)
    }
    #[inline(always)]
    fn not_gt(self, o: lanes::F) -> lanes::F {
        lanes::CmpGt::cmp_gt(self, o) ^ lanes::F::splat(f32::from_bits(!0))
    }
    #[inline(always)]
    fn positive_normal(self) -> lanes::F {
        use lanes::CmpLe;
        lanes::F::splat(f32::MIN_POSITIVE).cmp_le(self) & self.cmp_le(lanes::F::splat(f32::MAX))
    }
    #[inline(always)]
    fn greater(self, o: lanes::F) -> lanes::F {
        self.fast_max(o)
    }
    #[inline(always)]
    fn lesser(self, o: lanes::F) -> lanes::F {
        self.fast_min(o)
    }
    #[inline(always)]
    fn select(m: lanes::F, a: lanes::F, b: lanes::F) -> lanes::F {
        m.blend(a, b)
    }
    #[inline(always)]
    fn select_lazy(m: lanes::F, a: impl FnOnce() -> lanes::F, b: lanes::F) -> lanes::F {
        m.blend(a(), b)
    }
    #[inline(always)]
    fn choose(
        m: lanes::F,
        care: u32,
        a: impl FnOnce() -> lanes::F,
        b: impl FnOnce() -> lanes::F,
    ) -> lanes::F {
        let taken = lanes::bits(m) & care;
        if taken == 0 {
            b()
        } else if taken == care {
            a()
        } else {
            m.blend(a(), b())
        }
    }
    #[inline(always)]
    fn bits(m: lanes::F) -> u32 {
        lanes::bits(m)
    }
    #[inline(always)]
    fn mask(bits: u32) -> lanes::F {
        lanes::mask(bits)
    }
    #[inline(always)]
    fn spec_pow(self, s: f32) -> Option<lanes::F> {
        lanes::spec_pow(self, s)
    }
}

#[cfg(lanes)]
impl Byte for lanes::F {
    type Out = lanes::I;
    /// The saturating cast's cases as selections (NaN and below 0 give 0, 256 and above 255),
    /// then a plain truncation of what is left, in `[0, 256)`.
    #[inline(always)]
    fn byte(self) -> lanes::I {
        use lanes::{CmpGe, CmpLt, F};
        let (zero, top, end) = (F::ZERO, F::splat(255.0), F::splat(256.0));
        let outside = self.cmp_ge(end).blend(top, zero);
        let v = (self.cmp_ge(zero) & self.cmp_lt(end)).blend(self, outside);
        v.fast_trunc_int()
    }
}

#[cfg(lanes)]
impl Ieee3 for lanes::V {
    type S = lanes::F;
    #[inline(always)]
    fn splat(v: Vec3) -> lanes::V {
        lanes::V::splat(v)
    }
    #[inline(always)]
    fn dot(self, o: lanes::V) -> lanes::F {
        lanes::V::dot(self, o)
    }
    #[inline(always)]
    fn add(self, o: lanes::V) -> lanes::V {
        lanes::V::add(self, o)
    }
    #[inline(always)]
    fn sub(self, o: lanes::V) -> lanes::V {
        lanes::V::sub(self, o)
    }
    #[inline(always)]
    fn neg(self) -> lanes::V {
        lanes::V::neg(self)
    }
    #[inline(always)]
    fn mul(self, s: lanes::F) -> lanes::V {
        lanes::V::mul(self, s)
    }
    #[inline(always)]
    fn div(self, s: lanes::F) -> lanes::V {
        lanes::V::div(self, s)
    }
    #[inline(always)]
    fn mul_elem(self, o: lanes::V) -> lanes::V {
        lanes::V::mul_elem(self, o)
    }
    #[inline(always)]
    fn cross(self, o: lanes::V) -> lanes::V {
        lanes::V::cross(self, o)
    }
    #[inline(always)]
    fn select(m: lanes::F, a: lanes::V, b: lanes::V) -> lanes::V {
        lanes::V::select(m, a, b)
    }
    /// The lanes leave the guarded form to the scalar path.
    #[inline(always)]
    fn normalized_or_zero(self) -> Option<lanes::V> {
        None
    }
}

#[cfg(lanes)]
pub(crate) use lanes::*;

/// Four `Vec3`s in vector registers, one lane each (`cfg(lanes)`: hosts with f32 vectors), for
/// shading four pixels at once. Every operation is the lane-wise IEEE operation of its `Vec3`
/// counterpart in the same order, so each lane computes the scalar bits.
#[cfg(lanes)]
pub(crate) mod lanes {
    use crate::math::Vec3;
    pub(crate) use wide::f32x4 as F;
    /// Four i32 lanes, for the bytes of four encoded pixels.
    pub(crate) use wide::i32x4 as I;
    pub(crate) use wide::{CmpEq, CmpGe, CmpGt, CmpLe, CmpLt};

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

    /// [`spec_pow`](crate::math::spec_pow) of each lane of `x` to one exponent `s`: the same
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
        Some(crate::math::pow_by_squaring(x, n))
    }
}
