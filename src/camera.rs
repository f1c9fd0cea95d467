//! The pinhole camera: which ray leaves the eye for each pixel sample.

use crate::error::Error;
use crate::geometry::Ray;
use crate::math::Vec3;

/// Largest accepted image width or height.
pub const MAX_SIZE: u32 = 16384;

/// A pinhole camera with its image size.
///
/// `w = normalize(look_at − eye)`, `u = normalize(w × up)`, `v = u × w`; pixel (i, j), row 0 at
/// the top, covers `[i, i+1) × [j, j+1)` in image coordinates.
///
/// ```
/// use microray::{Camera, Vec3};
/// let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 60.0, 4, 3)?;
/// let centre = cam.ray(2.0, 1.5); // the middle of the image looks straight at look_at
/// assert_eq!(centre.dir, Vec3::new(0.0, 0.0, -1.0));
/// # Ok::<(), microray::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Camera {
    eye: Vec3,
    u: Vec3,
    v: Vec3,
    w: Vec3,
    width: u32,
    height: u32,
    // px = x·sx − ox, py = oy − y·sy
    sx: f32,
    ox: f32,
    sy: f32,
    oy: f32,
}

impl Camera {
    /// A value to overwrite, for a struct that holds a camera and is built as a constant
    /// (`scene_file`: a file built in place on the heap); renders nothing meaningful.
    #[cfg(feature = "scene-file")]
    pub(crate) const PLACEHOLDER: Camera = Camera {
        eye: Vec3::ZERO,
        u: Vec3::ZERO,
        v: Vec3::ZERO,
        w: Vec3::ZERO,
        width: 1,
        height: 1,
        sx: 0.0,
        ox: 0.0,
        sy: 0.0,
        oy: 0.0,
    };

    /// A camera at `eye` looking at `look_at`, with `vfov` the full vertical field of view in
    /// degrees, for a `width`×`height` image.
    ///
    /// ```
    /// # use microray::{Camera, Error, Vec3};
    /// let up = Vec3::new(0.0, 1.0, 0.0);
    /// let bad = Camera::new(Vec3::ZERO, Vec3::new(0.0, 5.0, 0.0), up, 60.0, 4, 3);
    /// assert_eq!(bad, Err(Error::UpParallelToView));
    /// assert_eq!(Camera::new(Vec3::ZERO, Vec3::ZERO, up, 60.0, 4, 3), Err(Error::EyeAtLookAt));
    /// ```
    pub fn new(
        eye: Vec3,
        look_at: Vec3,
        up: Vec3,
        vfov: f32,
        width: u32,
        height: u32,
    ) -> Result<Self, Error> {
        if !(eye.is_finite() && look_at.is_finite() && up.is_finite()) {
            return Err(Error::NotFinite);
        }
        if !(vfov > 0.0 && vfov < 180.0) {
            return Err(Error::InvalidFov);
        }
        if !(1..=MAX_SIZE).contains(&width) || !(1..=MAX_SIZE).contains(&height) {
            return Err(Error::InvalidSize);
        }
        let w = (look_at - eye).normalized().ok_or(Error::EyeAtLookAt)?;
        // `up` is normalised first so that a tiny or huge `up` neither underflows nor overflows
        // the cross product.
        let up = up.normalized().ok_or(Error::UpParallelToView)?;
        let cross = w.cross(up);
        let len = cross.length();
        if !(len > 1e-6) {
            return Err(Error::UpParallelToView);
        }
        let u = cross / len;
        let v = u.cross(w);
        let a = libm::tanf(vfov * (core::f32::consts::PI / 360.0));
        let (wf, hf) = (width as f32, height as f32);
        Ok(Camera {
            eye,
            u,
            v,
            w,
            width,
            height,
            sx: 2.0 * a / hf,
            ox: a * wf / hf,
            sy: 2.0 * a / hf,
            oy: a,
        })
    }

    /// The eye point, where every primary ray starts.
    ///
    /// ```
    /// # use microray::{Camera, Vec3};
    /// let cam = Camera::new(Vec3::ONE, Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 8, 8)?;
    /// assert_eq!(cam.eye(), Vec3::ONE);
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn eye(&self) -> Vec3 {
        self.eye
    }

    /// Image width in pixels.
    ///
    /// ```
    /// # use microray::{Camera, Vec3};
    /// let cam = Camera::new(Vec3::ONE, Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 8, 6)?;
    /// assert_eq!((cam.width(), cam.height()), (8, 6));
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Image height in pixels.
    ///
    /// ```
    /// # use microray::{Camera, Vec3};
    /// let cam = Camera::new(Vec3::ONE, Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 8, 6)?;
    /// assert_eq!(cam.height(), 6);
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The camera basis `(u, v, w)`: right, up and forward unit vectors.
    ///
    /// ```
    /// # use microray::{Camera, Vec3};
    /// let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 8, 6)?;
    /// assert_eq!(cam.basis().2, Vec3::new(0.0, 0.0, -1.0));
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn basis(&self) -> (Vec3, Vec3, Vec3) {
        (self.u, self.v, self.w)
    }

    /// `[sx, ox, sy, oy]` of the image-plane coordinates `px = x·sx − ox`, `py = oy − y·sy` of
    /// image point `(x, y)`, as [`Camera::direction`] computes them.
    pub(crate) fn plane_map(&self) -> [f32; 4] {
        [self.sx, self.ox, self.sy, self.oy]
    }

    /// The unnormalised direction `(w + py·v) + px·u` through image point `(x, y)`: summed in
    /// that order so that a row's `w + py·v` is one vector for all its columns.
    ///
    /// ```
    /// # use microray::{Camera, Vec3};
    /// let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 90.0, 2, 2)?;
    /// let d = cam.direction(0.0, 0.0); // top-left corner: one unit left, one up
    /// assert!((d - Vec3::new(-1.0, 1.0, -1.0)).length() < 1e-6);
    /// # Ok::<(), microray::Error>(())
    /// ```
    #[inline]
    pub fn direction(&self, x: f32, y: f32) -> Vec3 {
        self.row(y).direction(x)
    }

    /// What [`Camera::direction`] at `y` shares across `x`: for loops along a row, which keep
    /// these four values in registers (read through `&self`, the camera's fields would be loaded
    /// again for every column: the compiler cannot tell that the row's stores leave them).
    #[inline]
    pub(crate) fn row(&self, y: f32) -> RowRays {
        let py = self.oy - y * self.sy;
        RowRays {
            eye: self.eye,
            base: self.w + self.v * py,
            u: self.u,
            sx: self.sx,
            ox: self.ox,
        }
    }

    /// The primary ray through image point `(x, y)` (pixel (i, j) spans `[i, i+1) × [j, j+1)`),
    /// with a unit direction.
    ///
    /// ```
    /// # use microray::{Camera, Vec3};
    /// let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 60.0, 4, 4)?;
    /// let ray = cam.ray(2.0, 2.0);
    /// assert_eq!((ray.origin, ray.dir), (Vec3::new(0.0, 0.0, 5.0), Vec3::new(0.0, 0.0, -1.0)));
    /// # Ok::<(), microray::Error>(())
    /// ```
    #[inline]
    pub fn ray(&self, x: f32, y: f32) -> Ray {
        Ray::new(self.eye, self.direction(x, y).normalize_fast())
    }

    /// `direction(x[l], y)` for four image points of one row, in vector lanes (`cfg(lanes)`):
    /// `direction`'s operations lane by lane, so the same bits.
    #[cfg(lanes)]
    #[inline(always)]
    pub(crate) fn directions4(&self, x: [f32; 4], y: f32) -> [[f32; 4]; 3] {
        use crate::simd::F;
        let px = F::from(x) * F::splat(self.sx) - F::splat(self.ox);
        let py = F::splat(self.oy - y * self.sy);
        let (u, v, w) = (self.u, self.v, self.w);
        // `(w + v·py) + u·px`, `direction`'s association.
        let axis = |w: f32, u: f32, v: f32| (F::splat(w) + F::splat(v) * py) + F::splat(u) * px;
        [
            axis(w.x, u.x, v.x).to_array(),
            axis(w.y, u.y, v.y).to_array(),
            axis(w.z, u.z, v.z).to_array(),
        ]
    }

    /// The renderer's ray for sample `(sx, sy)` of pixel `(i, j)`: [`Camera::view_ray`]'s, with
    /// the direction [`Camera::direction`] left unnormalised. Every test and shading step takes
    /// a direction of any length, so a primary ray needs no square root and three divides.
    #[inline]
    pub(crate) fn primary_ray(&self, i: u32, j: u32, sx: u32, sy: u32, samples: u32) -> Ray {
        let (x, y) = (
            i as f32 + sample_offset(sx, samples),
            j as f32 + sample_offset(sy, samples),
        );
        Ray::new(self.eye, self.direction(x, y))
    }

    /// The ray for sample `(sx, sy)` of an `samples`×`samples` grid in pixel `(i, j)`: the
    /// textbook view ray, at `x = i + (sx + 0.5)/samples`, `y = j + (sy + 0.5)/samples`.
    ///
    /// ```
    /// # use microray::{Camera, Vec3};
    /// let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 60.0, 4, 4)?;
    /// assert_eq!(cam.view_ray(1, 1, 1, 1, 2), cam.ray(1.75, 1.75)); // second sample of a 2×2 grid
    /// assert_eq!(cam.view_ray(1, 2, 0, 0, 1), cam.ray(1.5, 2.5)); // one sample: the pixel centre
    /// # Ok::<(), microray::Error>(())
    /// ```
    #[inline]
    pub fn view_ray(&self, i: u32, j: u32, sx: u32, sy: u32, samples: u32) -> Ray {
        self.ray(
            i as f32 + sample_offset(sx, samples),
            j as f32 + sample_offset(sy, samples),
        )
    }
}

/// [`Camera::direction`] and [`Camera::ray`] along one row (see [`Camera::row`]).
#[derive(Debug, Clone, Copy)]
pub(crate) struct RowRays {
    eye: Vec3,
    base: Vec3,
    u: Vec3,
    sx: f32,
    ox: f32,
}

impl RowRays {
    /// [`Camera::direction`]`(x, y)`, the same bits.
    #[inline(always)]
    pub(crate) fn direction(&self, x: f32) -> Vec3 {
        self.base + self.u * self.column(x)
    }

    /// The coordinate along `u` of [`RowRays::direction`]`(x)`, which is `base + u·column(x)`:
    /// the row's rays form a fan in the plane of `base` and `u`.
    #[inline(always)]
    pub(crate) fn column(&self, x: f32) -> f32 {
        x * self.sx - self.ox
    }

    /// A box that holds the points `eye + t·direction(x)` for every `t` in `[t0, t1]` (`t0 > 0`)
    /// and `column(x)` in `[c0, c1]`, up to the rounding of those points and of the box (a few
    /// ε of `|eye| + t1 |direction|`): each is `eye + t·base + (t·column)·u`, so with `t` and
    /// `t·column` as intervals `mid ± radius` the box is `eye + t_m base + s_m u ± (t_r |base| +
    /// s_r |u|)`. No branch, and exact (up to rounding) along an axis that `u` has no
    /// component on (a camera without roll: `u` is level); elsewhere wider by about the spread
    /// of `t` times that of the columns.
    #[inline(always)]
    pub(crate) fn fan_box(&self, (t0, t1): (f32, f32), (c0, c1): (f32, f32)) -> (Vec3, Vec3) {
        let (tm, tr) = ((t0 + t1) * 0.5, (t1 - t0) * 0.5);
        let (cm, cr) = ((c0 + c1) * 0.5, libm::fabsf(c1 - c0) * 0.5);
        // (tm ± tr)(cm ± cr) ⊂ tm cm ± (tm cr + tr (|cm| + cr)), as tm > 0.
        let (sm, sr) = (tm * cm, tm * cr + tr * (libm::fabsf(cm) + cr));
        let centre = self.eye + self.base * tm + self.u * sm;
        let radius = self.base.abs() * tr + self.u.abs() * sr;
        (centre - radius, centre + radius)
    }

    /// [`Camera::primary_ray`] at `x`: the eye and [`Camera::direction`]`(x, y)`.
    #[inline(always)]
    pub(crate) fn ray(&self, x: f32) -> Ray {
        Ray::new(self.eye, self.direction(x))
    }
}

/// The offset `(s + 0.5)/samples` of sample `s` of `samples` along one axis of a pixel, as
/// [`Camera::view_ray`] adds it to the pixel's corner: for loops that hoist it out of their
/// pixels.
#[inline]
pub(crate) fn sample_offset(s: u32, samples: u32) -> f32 {
    (s as f32 + 0.5) / samples as f32
}

#[cfg(all(test, lanes))]
mod tests {
    use super::*;

    /// `directions4` is `direction(x, y)`, bit for bit, lane by lane, for cameras of every
    /// orientation, field of view and image size, at pixel centres and supersample offsets.
    #[test]
    fn lane_directions_are_the_scalar_ones() {
        let mut g = crate::math::TestRng(0x2545_f491_4f6c_dd1d);
        let mut checked = 0;
        for _ in 0..2000 {
            let (eye, at, up) = (g.vec(20.0), g.vec(20.0), g.vec(20.0));
            let (w, h) = (
                1 + (g.unit() * 2000.0) as u32,
                1 + (g.unit() * 2000.0) as u32,
            );
            let Ok(cam) = Camera::new(eye, at, up, 1.0 + g.unit() * 170.0, w, h) else {
                continue;
            };
            let y = (g.unit() * h as f32).floor() + g.unit();
            let x0 = (g.unit() * w as f32).floor() + 0.5;
            let x = [x0, x0 + 1.0, x0 + 2.25, x0 + 3.0];
            let lanes = cam.directions4(x, y);
            for (l, &x) in x.iter().enumerate() {
                let d = cam.direction(x, y);
                let lane = Vec3::new(lanes[0][l], lanes[1][l], lanes[2][l]);
                assert_eq!(lane.x.to_bits(), d.x.to_bits(), "{cam:?} ({x}, {y})");
                assert_eq!(lane.y.to_bits(), d.y.to_bits(), "{cam:?} ({x}, {y})");
                assert_eq!(lane.z.to_bits(), d.z.to_bits(), "{cam:?} ({x}, {y})");
                checked += 1;
            }
        }
        assert!(checked > 4000, "{checked}");
    }
}

#[cfg(test)]
mod fan_tests {
    use super::*;
    use crate::math::TestRng;

    /// `RowRays::fan_box` holds the points `eye + t·direction(x)` of a run of columns as the
    /// renderer computes them (`Ray::at` in f32), within 2⁻²² of their distance from the eye
    /// plus 2⁻²² of their coordinates (a quarter of the padding `Frame::gather` gives its
    /// bounds), for cameras with and without roll, near the origin and 10⁴ from it, and `t`
    /// from 10⁻³ to 10⁴ spread by ±15% along the run. Without roll (`u` level) its height is
    /// the points' own range of heights, up to that rounding.
    #[test]
    fn fan_box_holds_the_points_of_the_fan() {
        let mut g = TestRng(0x0fa7_b0c5);
        let mut level = 0;
        for case in 0..4000 {
            let far = if case % 2 == 0 { 1.0 } else { 1e4 };
            let eye = g.vec(2.0) + Vec3::new(far, 0.5 * far, -far);
            let target = eye + Vec3::new(g.unit() - 0.5, g.unit() - 0.8, -1.0) * 10.0;
            let rolled = case % 3 == 0;
            let up = if rolled {
                Vec3::new(g.unit() - 0.5, 1.0, g.unit() - 0.5)
            } else {
                Vec3::new(0.0, 1.0, 0.0)
            };
            let cam = Camera::new(eye, target, up, 10.0 + g.unit() * 120.0, 320, 240).unwrap();
            let (ox, y) = (
                [0.5, 0.25, 0.75][case % 3],
                (g.unit() * 240.0) as u32 as f32 + 0.5,
            );
            let row = cam.row(y);
            let (i0, len) = ((g.unit() * 300.0) as u32, 1 + (g.unit() * 20.0) as usize);
            let t_mid = libm::powf(10.0, g.unit() * 7.0 - 3.0);
            let mut ts = [0.0f32; 21];
            for t in ts.iter_mut().take(len) {
                *t = t_mid * (1.0 + 0.3 * (g.unit() - 0.5));
            }
            let ts = &ts[..len];
            let x = |k: usize| (i0 + k as u32) as f32 + ox;
            let t0 = ts.iter().copied().fold(f32::INFINITY, f32::min);
            let t1 = ts.iter().copied().fold(f32::NEG_INFINITY, f32::max);
            let (lo, hi) = row.fan_box((t0, t1), (row.column(x(0)), row.column(x(len - 1))));
            let (mut ylo, mut yhi, mut pad_max) = (f32::INFINITY, f32::NEG_INFINITY, 0.0f32);
            for (k, &t) in ts.iter().enumerate() {
                let p = row.ray(x(k)).at(t);
                let pad = ((p - eye).length() + p.max_abs()) * (1.0 / 4_194_304.0);
                pad_max = pad_max.max(pad);
                for (v, l, h) in [(p.x, lo.x, hi.x), (p.y, lo.y, hi.y), (p.z, lo.z, hi.z)] {
                    assert!(
                        v >= l - pad && v <= h + pad,
                        "case {case}: {v} outside [{l}, {h}] by more than {pad} ({p:?}, t {t})"
                    );
                }
                (ylo, yhi) = (ylo.min(p.y), yhi.max(p.y));
            }
            if !rolled {
                level += 1;
                let excess = (hi.y - lo.y) - (yhi - ylo);
                assert!(
                    excess <= 4.0 * pad_max,
                    "case {case}: {excess} taller than the points"
                );
            }
        }
        assert!(level > 2000);
    }
}
