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
    /// these four values in registers (read through `&self`, the camera's fields were loaded
    /// again for every column: the compiler could not tell that the row's stores leave them).
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
        use wide::f32x4 as F;
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
    /// lecture's view ray, at `x = i + (sx + 0.5)/samples`, `y = j + (sy + 0.5)/samples`.
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
        self.base + self.u * (x * self.sx - self.ox)
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
