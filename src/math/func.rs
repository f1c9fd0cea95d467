//! The float functions: square root (libm, or `vsqrt.f32` on a Cortex-M4F: both correctly
//! rounded), `powf` and the specular power.

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
    target_sqrt(x)
}

/// [`sqrt`] on a Cortex-M4F/M7: the instruction.
#[cfg(all(target_arch = "arm", target_abi = "eabihf"))]
#[inline(always)]
fn target_sqrt(x: f32) -> f32 {
    hw::vsqrt(x)
}

/// [`sqrt`] elsewhere: libm's correctly rounded routine.
#[cfg(not(all(target_arch = "arm", target_abi = "eabihf")))]
#[inline(always)]
fn target_sqrt(x: f32) -> f32 {
    libm::sqrtf(x)
}

#[cfg(all(target_arch = "arm", target_abi = "eabihf"))]
#[allow(unsafe_code)]
pub(super) mod hw {
    /// `vsqrt.f32`: libm's `sqrtf` is a long software routine on thumbv7em.
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
/// `powf` is a long routine and the highlight is evaluated per light and hit; the shininess of
/// real scenes is a whole number, where at most 2·16 multiplications do. Each multiplication
/// rounds once, so the result is within ~2 log₂(s) ulp of `x^s`: at s = 5000 under 0.011 of an
/// 8-bit level (see docs/numerics.md), far below what the image resolves.
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
pub(crate) fn pow_by_squaring<T: Copy + core::ops::MulAssign>(x: T, n: u32) -> T {
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
