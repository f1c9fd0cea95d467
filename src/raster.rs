//! Screen-space bounds of spheres: which pixels a primary ray can hit a sphere from, computed
//! once per frame so that a pixel tests only the spheres whose bounds contain it.
//!
//! A ray from the eye along `d` meets a sphere (centre `m`, radius `r`, `F = m − e`) only if
//! `(F·d)² ≥ |d|² (|F|² − r²)` and `F·d > 0`: `d` lies in the forward cone of directions towards
//! the sphere. With `d = w + px·u + py·v` this is a conic in the image plane `(px, py)`; the
//! bounding box of its part inside the screen is found from a handful of candidate points (the
//! screen corners inside it, where its boundary crosses the screen edges, and its horizontal and
//! vertical tangents), all in f64, once per sphere and frame.
//!
//! **Conservative by construction.** The f32 test [`Prepared::hit`](crate::Prepared::hit) is not
//! the exact cone: it rounds. Rather than the exact cone we bound a slightly wider one, whose
//! `|F|² − r²` is lowered by the worst rounding of the branch that `Prepared::roots` takes for
//! this sphere (with a margin of about 70 ulp), and pad the box by a pixel each side. A sphere
//! the f32 test can report as hit through a pixel is therefore always in that pixel's box, and
//! the accelerated renderer computes exactly the pixels of the brute-force one (the
//! `accelerated_equals_brute_force` test checks it on random scenes). Where the cone degenerates
//! (the eye inside or within rounding of a sphere, coordinates near f32 overflow), the box is the
//! whole screen: correct, only slower.

use crate::camera::Camera;
use crate::geometry::Prepared;

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

/// The affine map between image coordinates `(x, y)` and image-plane coordinates `(px, py)` of
/// a camera, and its basis, in f64.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Screen {
    u: [f64; 3],
    v: [f64; 3],
    w: [f64; 3],
    /// `px = ax + bx·x`, `py = ay + by·y`.
    ax: f64,
    bx: f64,
    ay: f64,
    by: f64,
    width: u32,
    height: u32,
}

fn v64(v: crate::Vec3) -> [f64; 3] {
    [v.x as f64, v.y as f64, v.z as f64]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

impl Screen {
    pub(crate) fn new(camera: &Camera) -> Self {
        let (u, v, w) = camera.basis();
        let (u, v, w) = (v64(u), v64(v), v64(w));
        let (width, height) = (camera.width(), camera.height());
        // The camera's own f32 mapping, read back through `direction`: exact up to rounding,
        // which the one-pixel padding of every box absorbs.
        let plane = |x: f32, y: f32| {
            let d = v64(camera.direction(x, y));
            let d = [d[0] - w[0], d[1] - w[1], d[2] - w[2]];
            (dot(d, u), dot(d, v))
        };
        let (px0, py0) = plane(0.0, 0.0);
        let (px1, py1) = plane(width as f32, height as f32);
        Screen {
            u,
            v,
            w,
            ax: px0,
            bx: (px1 - px0) / width as f64,
            ay: py0,
            by: (py1 - py0) / height as f64,
            width,
            height,
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
        let f = v64(k.f);
        let fn2 = dot(f, f);
        let fnorm = libm::sqrt(fn2);
        let r = k.r as f64;
        // Far from f32 overflow only; otherwise `roots` may take its f64 path: no bound.
        if !(fnorm < 1.0e15 && r < 1.0e15) {
            return self.full();
        }
        let eta = ETA as f64;
        // The branch that `Prepared::roots` takes for this origin and sphere, as it decides it.
        let kk = if libm::fabsf(k.c) <= k.r * k.r {
            // b² − a c: b errs by at most η|f||d|, c is the stored f32 value.
            let c = k.c as f64;
            if !(c > 0.0) {
                return self.full();
            }
            let s = libm::sqrt(c * (1.0 - 1e-6)) - eta * fnorm;
            if s > 0.0 {
                s * s
            } else {
                0.0
            }
        } else {
            // Hearn–Baker: the distance of the centre from the line errs by at most η|f|.
            let rr = r + eta * fnorm;
            fn2 - rr * rr
        };
        // |d|² of the f32 basis differs from px² + py² + 1 by a few ulp.
        let kk = kk * (1.0 - 1e-6);
        // The forward condition F·d ≥ −μ (the f32 sign of b can err by η|f||d|).
        let (x0, x1) = (
            self.ax - 2.0 * self.bx,
            self.ax + (self.width as f64 + 2.0) * self.bx,
        );
        let (y0, y1) = (
            self.ay - 2.0 * self.by,
            self.ay + (self.height as f64 + 2.0) * self.by,
        );
        let (xlo, xhi) = (x0.min(x1), x0.max(x1));
        let (ylo, yhi) = (y0.min(y1), y0.max(y1));
        let xm = libm::fabs(xlo).max(libm::fabs(xhi));
        let ym = libm::fabs(ylo).max(libm::fabs(yhi));
        let dmax = libm::sqrt(xm * xm + ym * ym + 1.0);
        let mu = 2.0 * eta * fnorm * dmax;
        if !(kk > 4.0 * mu * mu) {
            return self.full();
        }
        // F = m − e in camera coordinates.
        let fc = [-dot(f, self.u), -dot(f, self.v), -dot(f, self.w)];
        match conic_bounds(fc, kk, [xlo, xhi, ylo, yhi]) {
            None => PixelBox::EMPTY,
            Some([pxa, pxb, pya, pyb]) => {
                let xa = (pxa - self.ax) / self.bx;
                let xb = (pxb - self.ax) / self.bx;
                let ya = (pya - self.ay) / self.by;
                let yb = (pyb - self.ay) / self.by;
                let clamp = |lo: f64, hi: f64, n: u32| {
                    let a = libm::floor(lo.min(hi)) - 1.0;
                    let b = libm::floor(lo.max(hi)) + 1.0;
                    let last = (n - 1) as f64;
                    if !(a <= last && b >= 0.0) {
                        return None;
                    }
                    Some((a.max(0.0) as u16, b.min(last) as u16))
                };
                match (clamp(xa, xb, self.width), clamp(ya, yb, self.height)) {
                    (Some((i0, i1)), Some((j0, j1))) => PixelBox { i0, i1, j0, j1 },
                    _ => PixelBox::EMPTY,
                }
            }
        }
    }
}

/// Real roots of `a x² + b x + c` (a double root once), robust to cancellation.
fn quadratic(a: f64, b: f64, c: f64) -> [Option<f64>; 2] {
    if a == 0.0 {
        return if b != 0.0 {
            [Some(-c / b), None]
        } else {
            [None, None]
        };
    }
    let mut disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        // A tangent that rounding pushed below zero still counts.
        if disc > -1e-12 * (b * b + libm::fabs(4.0 * a * c)) {
            disc = 0.0;
        } else {
            return [None, None];
        }
    }
    let s = libm::sqrt(disc);
    let q = -0.5 * if b >= 0.0 { b + s } else { b - s };
    if q == 0.0 {
        return [Some(0.0), None];
    }
    [Some(q / a), Some(c / q)]
}

/// The bounding box `[px_lo, px_hi, py_lo, py_hi]` of `{(px, py) in rect : Q ≥ 0, L > 0}` with
/// `L = F·(px, py, 1)` and `Q = L² − k (px² + py² + 1)`, or `None` when it is empty. Requires
/// `k > 0`; the forward half (`L > 0`) is then one nappe of the cone.
fn conic_bounds(fc: [f64; 3], k: f64, rect: [f64; 4]) -> Option<[f64; 4]> {
    let [fx, fy, fz] = fc;
    let [xlo, xhi, ylo, yhi] = rect;
    let lin = |px: f64, py: f64| fx * px + fy * py + fz;
    let q = |px: f64, py: f64| {
        let l = lin(px, py);
        l * l - k * (px * px + py * py + 1.0)
    };
    let tol_x = 1e-9 * (xhi - xlo);
    let tol_y = 1e-9 * (yhi - ylo);
    let mut bb: Option<[f64; 4]> = None;
    let mut add = |px: f64, py: f64| {
        if !(px >= xlo - tol_x && px <= xhi + tol_x && py >= ylo - tol_y && py <= yhi + tol_y) {
            return;
        }
        if !(lin(px, py) > 0.0) {
            return;
        }
        let (px, py) = (px.max(xlo).min(xhi), py.max(ylo).min(yhi));
        bb = Some(match bb {
            None => [px, px, py, py],
            Some([a, b, c, d]) => [a.min(px), b.max(px), c.min(py), d.max(py)],
        });
    };
    // The cone's axis, always inside its forward nappe: keeps tiny, far spheres in.
    if fz > 0.0 {
        add(fx / fz, fy / fz);
    }
    // Screen corners inside.
    for &(px, py) in &[(xlo, ylo), (xlo, yhi), (xhi, ylo), (xhi, yhi)] {
        if q(px, py) >= 0.0 {
            add(px, py);
        }
    }
    // The conic's crossings of the horizontal edges (py fixed: quadratic in px) ...
    for &py in &[ylo, yhi] {
        let g = fy * py + fz;
        for px in quadratic(fx * fx - k, 2.0 * fx * g, g * g - k * (py * py + 1.0))
            .into_iter()
            .flatten()
        {
            add(px, py);
        }
    }
    // ... and of the vertical ones.
    for &px in &[xlo, xhi] {
        let h = fx * px + fz;
        for py in quadratic(fy * fy - k, 2.0 * fy * h, h * h - k * (px * px + 1.0))
            .into_iter()
            .flatten()
        {
            add(px, py);
        }
    }
    // Horizontal tangents (extreme py): the px-discriminant vanishes.
    let a2 = fx * fx + fy * fy - k;
    let (ax, ay) = (fx * fx - k, fy * fy - k);
    if ax != 0.0 {
        for py in quadratic(a2, 2.0 * fy * fz, fx * fx + fz * fz - k)
            .into_iter()
            .flatten()
        {
            add(-fx * (fy * py + fz) / ax, py);
        }
    }
    // Vertical tangents (extreme px).
    if ay != 0.0 {
        for px in quadratic(a2, 2.0 * fx * fz, fy * fy + fz * fz - k)
            .into_iter()
            .flatten()
        {
            add(px, -fy * (fx * px + fz) / ay);
        }
    }
    bb
}
