//! Screen-space bounds of spheres: which pixels a primary ray can hit a sphere from, computed
//! once per frame so that a pixel tests only the spheres whose bounds contain it.
//!
//! A ray from the eye meets a ball only if its projection onto the plane of the camera's
//! forward axis and one screen axis meets the ball's projection there, a disc. The forward
//! directions `(p, 1)` in that plane that meet a disc (centre `(a, z)` from the eye, radius
//! `ρ < g = |(a, z)|`) lie between its two tangents, the centre's direction turned by
//! `±asin(ρ/g)`: `(a h ± z ρ, z h ∓ a ρ)` with `h = √(g² − ρ²)`. That gives the sphere's range
//! of `px` from the (right, forward) plane and of `py` from the (up, forward) plane; a tangent
//! that points backwards leaves its side open. It is the exact bounding box of a sphere in
//! front of the eye; for one that reaches behind it (a ground) the open sides are clamped to
//! the screen. All in f32: a handful of operations per sphere and frame, and no software f64
//! on a microcontroller.
//!
//! **Conservative by construction.** The f32 test [`Prepared::hit`](crate::Prepared::hit) is not
//! exact: it reports hits for rays that pass within `ρ` of the centre, `ρ` slightly above `r`
//! by the worst rounding of the branch that `Prepared::roots` takes for this sphere (`ETA`, with
//! a margin of about 70 ulp). `h²` is taken as `|F|² − ρ² − o²` (`o` the third camera
//! coordinate) from the compensated `c`, not as `g² − ρ²`, which cancels for a ground seen from
//! nearby. The tangents' half-angle is then widened by a `δ` that covers, about 8 times over,
//! the rounding of the centre's camera coordinates and of the ray directions (a few ulp of
//! `|F|/g`), of the tangents (a few ulp of angle) and of `h` (see `tangents`); where `δ` passes
//! 2⁻⁸ radians or the widened angle reaches a right angle, that axis is left open. The box is
//! then padded by a pixel each side. A sphere the f32 test can report as hit through a pixel is
//! therefore always in that pixel's box, and the accelerated renderer computes exactly the pixels
//! of the brute-force one (`tests/accelerated.rs` checks the boxes ray by ray, and whole images,
//! on random scenes). Where the bound degenerates (the eye inside or within rounding of a
//! sphere, coordinates near f32 overflow), the box is the whole screen: correct, only slower.

use crate::camera::Camera;
use crate::geometry::Prepared;
use crate::math::{sqrt, Vec3};

/// Relative rounding budget of the f32 intersection test, as a fraction of `|o − m|` (about 70
/// ulp of f32; the test's own error is below 20 ulp).
pub(crate) const ETA: f32 = 4.0e-6;

/// An inclusive rectangle of pixels `[i0, i1] × [j0, j1]`; empty when `i0 > i1`.
///
/// ```
/// use microray::raster::PixelBox;
/// assert!(PixelBox::EMPTY.is_empty());
/// assert!(PixelBox { i0: 0, i1: 3, j0: 2, j1: 2 }.contains(3, 2));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PixelBox {
    /// First column.
    pub i0: u16,
    /// Last column.
    pub i1: u16,
    /// First row.
    pub j0: u16,
    /// Last row.
    pub j1: u16,
}

impl PixelBox {
    /// No pixel.
    pub const EMPTY: PixelBox = PixelBox {
        i0: 1,
        i1: 0,
        j0: 1,
        j1: 0,
    };

    /// Whether the box holds no pixel.
    ///
    /// ```
    /// # use microray::raster::PixelBox;
    /// assert!(!PixelBox { i0: 0, i1: 0, j0: 0, j1: 0 }.is_empty());
    /// ```
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.i0 > self.i1 || self.j0 > self.j1
    }

    /// Whether pixel `(i, j)` is inside.
    ///
    /// ```
    /// # use microray::raster::PixelBox;
    /// assert!(!PixelBox::EMPTY.contains(0, 0));
    /// ```
    #[inline]
    pub fn contains(&self, i: u32, j: u32) -> bool {
        self.i0 as u32 <= i && i <= self.i1 as u32 && self.j0 as u32 <= j && j <= self.j1 as u32
    }

    /// Whether row `j` crosses the box.
    ///
    /// ```
    /// # use microray::raster::PixelBox;
    /// assert!(PixelBox { i0: 0, i1: 3, j0: 2, j1: 4 }.has_row(4));
    /// ```
    #[inline]
    pub fn has_row(&self, j: u32) -> bool {
        self.j0 as u32 <= j && j <= self.j1 as u32
    }
}

/// A camera's basis and its affine map between image coordinates `(x, y)` and image-plane
/// coordinates `px = x·sx − ox`, `py = oy − y·sy`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Screen {
    u: Vec3,
    v: Vec3,
    w: Vec3,
    map: [f32; 4],
    width: u32,
    height: u32,
    /// The largest `|(px, py, 1)|` on the screen, padded by two pixels.
    dmax: f32,
}

impl Screen {
    pub(crate) fn new(camera: &Camera) -> Self {
        let (u, v, w) = camera.basis();
        let (width, height) = (camera.width(), camera.height());
        let map = camera.plane_map();
        let [sx, ox, sy, oy] = map;
        let xm = libm::fabsf(ox) + 2.0 * sx;
        let ym = libm::fabsf(oy) + 2.0 * sy;
        Screen {
            u,
            v,
            w,
            map,
            width,
            height,
            dmax: sqrt(xm * xm + ym * ym + 1.0),
        }
    }

    fn full(&self) -> PixelBox {
        PixelBox {
            i0: 0,
            i1: (self.width - 1) as u16,
            j0: 0,
            j1: (self.height - 1) as u16,
        }
    }

    /// The pixels through which a primary ray can hit the sphere of `k` (eye constants).
    pub(crate) fn sphere_box(&self, k: &Prepared) -> PixelBox {
        let (f, r) = (k.f, k.r);
        let fn2 = f.dot(f);
        let fnorm = sqrt(fn2);
        // Far from f32 overflow only; otherwise `roots` may take its scaled path (`roots_scaled`):
        // no bound.
        if !(fnorm < 1.0e15 && r < 1.0e15) {
            return self.full();
        }
        // `kk`: a lower bound of (F·d)²/|d|² for the directions d that the test reports as hits
        // (F = m − e), from the branch that `Prepared::roots` takes, as it decides it; `rho`:
        // the radius of the ball whose cone holds them, √(|F|² − kk).
        let (kk, rho) = if libm::fabsf(k.c) <= r * r {
            // b² − a c: b errs by at most η|f||d|, c is the stored f32 value, a by a few ulp.
            let c = k.c;
            let s = sqrt(c * (1.0 - 1e-6)) - ETA * fnorm;
            if !(c > 0.0 && s > 0.0) {
                return self.full();
            }
            let kk = s * s * (1.0 - 1e-6);
            // No cancellation: |F|² ≤ 2r² here, kk ≤ r².
            (kk, sqrt(fn2 - kk))
        } else {
            // Hearn–Baker: the distance of the centre from the line errs by at most η|f|.
            let rr = r + ETA * fnorm;
            ((fnorm - rr) * (fnorm + rr), rr)
        };
        // The forward condition F·d > 0: the f32 sign of b can err by μ = η|f||d| (the test
        // takes b < 0 from outside), so a ball that keeps F·d ≥ 2μ is safely in front.
        let mu = 2.0 * ETA * fnorm * self.dmax;
        if !(kk > 4.0 * mu * mu) {
            return self.full();
        }
        // F in camera coordinates.
        let (fx, fy, fz) = (-f.dot(self.u), -f.dot(self.v), -f.dot(self.w));
        let [sx, ox, sy, oy] = self.map;
        let Some((pxa, pxb)) = tangents([fx, fz, fy], kk, rho, fnorm) else {
            return PixelBox::EMPTY;
        };
        let Some((pya, pyb)) = tangents([fy, fz, fx], kk, rho, fnorm) else {
            return PixelBox::EMPTY;
        };
        let x = pixels((pxa + ox) / sx, (pxb + ox) / sx, self.width);
        // py grows upwards, rows downwards.
        let y = pixels((oy - pyb) / sy, (oy - pya) / sy, self.height);
        match (x, y) {
            (Some((i0, i1)), Some((j0, j1))) => PixelBox { i0, i1, j0, j1 },
            (None, _) | (_, None) => PixelBox::EMPTY,
        }
    }
}

/// The range `[lo, hi]` of `p` over the forward directions `(p, 1)` in the plane of one screen
/// axis that meet the ball's projection there, the disc of radius `rho` about `(a, z)`: an end
/// is infinite where its tangent points backwards, and `None` when both do (the disc is behind
/// the eye). `o` is the centre's third camera coordinate, `kk = |F|² − rho²`.
///
/// The tangents are the centre's direction turned by `±atan(rho/h)`, `h = √(g² − rho²)` the
/// tangent's length (`g = |(a, z)|`). `h² = kk − o²`, not `g² − rho²`: `kk` comes accurate from
/// the compensated `c`, while `g` and `rho` agree in most bits for a ground seen from nearby.
/// The half-angle is widened by `δ`, which covers the rounding of the centre's direction (a few
/// ulp of `|F|/g`), of the ray directions and of the tangents (a few ulp of angle), and of `h`
/// (its first-order effect), each about 8 times over; where that is more than 2⁻⁸ radians, or
/// the widened angle reaches a right angle, the whole axis is returned.
fn tangents([a, z, o]: [f32; 3], kk: f32, rho: f32, fnorm: f32) -> Option<(f32, f32)> {
    const ALL: (f32, f32) = (f32::NEG_INFINITY, f32::INFINITY);
    let (g2, h2) = (a * a + z * z, kk - o * o);
    if !(g2 > 0.0 && h2 > 0.0) {
        return Some(ALL);
    }
    let h = sqrt(h2);
    let delta = (1.0 + fnorm / sqrt(g2)) * (1.0 / 262_144.0)
        + rho * (kk + o * o + libm::fabsf(o) * fnorm) * (1.0 / 1_048_576.0) / (g2 * h);
    if !(delta < 1.0 / 256.0) {
        return Some(ALL);
    }
    // (h, rho) turned by δ: tan of the half-angle plus δ.
    let (rho, h) = (rho + h * delta, h - rho * delta);
    if !(h > 0.0) {
        return Some(ALL);
    }
    // The tangent directions, turned up (+) and down (−) from the centre's.
    let (au, zu) = (a * h + z * rho, z * h - a * rho);
    let (al, zl) = (a * h - z * rho, z * h + a * rho);
    let (lo, hi) = match (zl > 0.0, zu > 0.0) {
        (true, true) => (al / zl, au / zu),
        (true, false) => (al / zl, f32::INFINITY),
        (false, true) => (f32::NEG_INFINITY, au / zu),
        // Both backwards: the disc, less than a half-turn wide from the eye, is behind it.
        (false, false) => return None,
    };
    // Tangents a few ulp of angle apart (a tiny disc) may come out swapped.
    Some(if lo <= hi { (lo, hi) } else { (hi, lo) })
}

/// The pixels `[floor(lo) − 1, floor(hi) + 1]` of an axis of `n`, or `None` when none is on
/// it; the whole axis if a bound is NaN. The saturating casts truncate towards zero, which is
/// above floor only below zero, where the clamp decides the same. Out of line: one copy for
/// both axes (set-up code, where flash counts more than a call).
#[inline(never)]
fn pixels(lo: f32, hi: f32, n: u32) -> Option<(u16, u16)> {
    let last = n as i32 - 1;
    if !(lo <= hi) {
        return Some((0, last as u16));
    }
    let (a, b) = ((lo as i32).saturating_sub(1), (hi as i32).saturating_add(1));
    if a > last || b < 0 {
        return None;
    }
    Some((a.max(0) as u16, b.min(last) as u16))
}
