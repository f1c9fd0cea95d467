//! [`Hit`]: the record of a ray's closest hit, and where it is built.

use super::*;
use crate::math::{Ieee, Ieee3, IeeeCmp};

/// Where a ray met the scene.
///
/// ```
/// use microray::{Material, Ray, Scene, Sphere, Vec3};
/// let mut scene: Scene<2, 0> = Scene::new();
/// scene.add_sphere(Sphere::new(Vec3::new(0.0, 0.0, -5.0), 1.0), Material::default())?;
/// let hit = scene.find_intersection(&Ray::new(Vec3::ZERO, Vec3::new(0.0, 0.0, -1.0)), 0.0, 100.0)
///     .unwrap();
/// assert_eq!((hit.t, hit.sphere, hit.normal), (4.0, 0, Vec3::new(0.0, 0.0, 1.0)));
/// # Ok::<(), microray::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Hit {
    /// The ray parameter of the hit.
    pub t: f32,
    /// Index of the sphere hit, in the order spheres were added.
    pub sphere: usize,
    /// Unit normal, turned to face the ray's origin (negated when seen from inside).
    pub normal: Vec3,
    /// `point − centre` (the outward normal times the radius), kept because it is more accurate
    /// than `point − centre` recomputed from a rounded point far from the origin.
    pub offset: Vec3,
    /// The hit point as `anchor + rel`, which rays leaving the hit start from: the centre of the
    /// sphere hit and `offset`, or the point where the path to this hit began (the eye, or the
    /// previous hit's anchor for a mirror ray) and `t·d` summed along the path from it,
    /// whichever has the shorter `rel`, hence the smaller error. Differences to other points
    /// (`anchor − m`) are then exact or nearly, and the error is that of `rel`: it scales with
    /// the scene, not with its distance from the origin, and is the same whether the scene sits
    /// at the origin or 10⁴ away.
    ///
    /// ```
    /// use microray::{Material, Ray, Scene, Sphere, Vec3};
    /// let far = Vec3::new(1e4, 0.0, 0.0);
    /// let mut scene: Scene<1, 0> = Scene::new();
    /// scene.add_sphere(Sphere::new(far, 0.5), Material::default())?;
    /// let eye = far + Vec3::new(0.0, 0.0, 3.0);
    /// let ray = Ray::new(eye, Vec3::new(0.0, 0.0, -1.0));
    /// let hit = scene.find_intersection(&ray, 0.0, 9.0).unwrap();
    /// assert_eq!((hit.anchor, hit.rel), (far, Vec3::new(0.0, 0.0, 0.5))); // the offset: shorter
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub anchor: Vec3,
    /// See [`Hit::anchor`].
    pub rel: Vec3,
}

impl Hit {
    /// The hit point, `anchor + rel` rounded once (rays that leave the hit use the two parts).
    ///
    /// ```
    /// use microray::{Material, Ray, Scene, Sphere, Vec3};
    /// let mut scene: Scene<1, 0> = Scene::new();
    /// scene.add_sphere(Sphere::new(Vec3::new(0.0, 0.0, -5.0), 1.0), Material::default())?;
    /// let hit = scene.find_intersection(&Ray::new(Vec3::ZERO, Vec3::new(0.0, 0.0, -1.0)), 0.0, 9.0)
    ///     .unwrap();
    /// assert_eq!(hit.point(), Vec3::new(0.0, 0.0, -4.0));
    /// # Ok::<(), microray::Error>(())
    /// ```
    #[inline]
    pub fn point(&self) -> Vec3 {
        self.anchor + self.rel
    }

    /// Whether the hit is on the inside of its sphere (the facing normal points to the centre):
    /// where shadow rays can meet that sphere again, and glass is left rather than entered.
    ///
    /// ```
    /// use microray::{Material, Ray, Scene, Sphere, Vec3};
    /// let mut scene: Scene<1, 0> = Scene::new();
    /// scene.add_sphere(Sphere::new(Vec3::ZERO, 1.0), Material::default())?;
    /// let out = Ray::new(Vec3::new(0.0, 0.0, 5.0), Vec3::new(0.0, 0.0, -1.0));
    /// assert!(!scene.find_intersection(&out, 0.0, 9.0).unwrap().from_inside());
    /// let from_centre = Ray::new(Vec3::ZERO, Vec3::new(0.0, 0.0, -1.0));
    /// assert!(scene.find_intersection(&from_centre, 0.0, 9.0).unwrap().from_inside());
    /// # Ok::<(), microray::Error>(())
    /// ```
    #[inline(always)]
    pub fn from_inside(&self) -> bool {
        self.normal.dot(self.offset) < 0.0
    }
}

/// The hit record for parameter `t` on sphere `i`, given `f = ray origin − centre`, for a
/// path that began at `origin` and had come `path` from it to the ray's origin (see
/// [`Hit::anchor`]).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn make_hit(
    ray: &Ray,
    t: f32,
    i: usize,
    f: Vec3,
    sphere: &Sphere,
    near: bool,
    origin: Vec3,
    path: Vec3,
) -> Hit {
    let (d, o, p) = (ray.dir, origin, path);
    make_hit_xyz(
        d.x, d.y, d.z, t, i, f.x, f.y, f.z, sphere, near, o.x, o.y, o.z, p.x, p.y, p.z,
    )
}

/// [`make_hit`] on scalars. On Arm out of line: one copy for the renderer's and the shading's
/// callers, which small flash prefers; scalars rather than a `Ray` and `Vec3`s, which would go
/// by address (on a Cortex-M4F its 14 floats travel in s0–s13). Inlined elsewhere: x86-64
/// passes only 8 floats in registers, the rest through the stack. The ray's origin is not
/// needed: the offset is computed from `f`.
#[cfg_attr(target_arch = "arm", inline(never))]
#[cfg_attr(not(target_arch = "arm"), inline)]
#[allow(clippy::too_many_arguments)]
pub(super) fn make_hit_xyz(
    dx: f32,
    dy: f32,
    dz: f32,
    t: f32,
    i: usize,
    fx: f32,
    fy: f32,
    fz: f32,
    sphere: &Sphere,
    near: bool,
    ox: f32,
    oy: f32,
    oz: f32,
    px: f32,
    py: f32,
    pz: f32,
) -> Hit {
    make_hit_inline(
        dx, dy, dz, t, i, fx, fy, fz, sphere, near, ox, oy, oz, px, py, pz,
    )
}

/// [`make_hit_xyz`]'s body, for the renderer's scalar primary hits, which build their record
/// where they shade it (`Frame::shade_stored`). A function of its own, not an inlining
/// attribute of `make_hit_xyz`'s, so that only this caller inlines the body: inlined at every
/// call site, it slows the Cortex-M0 speed build.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn make_hit_inline(
    dx: f32,
    dy: f32,
    dz: f32,
    t: f32,
    i: usize,
    fx: f32,
    fy: f32,
    fz: f32,
    sphere: &Sphere,
    near: bool,
    ox: f32,
    oy: f32,
    oz: f32,
    px: f32,
    py: f32,
    pz: f32,
) -> Hit {
    let ray = Ray::new(Vec3::ZERO, Vec3::new(dx, dy, dz));
    let (f, origin, path) = (
        Vec3::new(fx, fy, fz),
        Vec3::new(ox, oy, oz),
        Vec3::new(px, py, pz),
    );
    // The offset from the centre is computed directly (see `hit_point`): unlike
    // `point − centre` it does not lose the low bits of a point far from the origin.
    let (_, offset) = hit_point_near(&ray, t, f, sphere, near);
    hit_from_offset(ray.dir, t, i, sphere, offset, origin, path)
}

/// The rest of [`make_hit`] once the hit's offset from the centre is known: for the renderer,
/// which has computed the offset already for its shadow bounds (`hit_point_within` of the same
/// arguments, so the same bits).
#[inline(always)]
pub(crate) fn hit_from_offset(
    dir: Vec3,
    t: f32,
    i: usize,
    sphere: &Sphere,
    offset: Vec3,
    origin: Vec3,
    path: Vec3,
) -> Hit {
    let [normal, anchor, rel] = hit_vectors(dir, t, sphere, offset, origin, path);
    Hit {
        t,
        sphere: i,
        normal,
        offset,
        anchor,
        rel,
    }
}

/// [`Hit::normal`], [`Hit::anchor`] and [`Hit::rel`] of the hit at `t` along `dir` whose offset
/// from the centre is `offset`, on a path that began at `origin` and had come `path` from it:
/// for one hit or for four in lanes (the host renderer's, which builds its records so).
#[inline(always)]
pub(crate) fn hit_vectors<P: Ieee3>(
    dir: P,
    t: P::S,
    sphere: &Sphere,
    offset: P,
    origin: P,
    path: P,
) -> [P; 3] {
    let r = sphere.radius;
    let outward = offset.div(<P::S as Ieee>::splat(r));
    let path = path.add(dir.mul(t));
    // |offset| = r: the shorter vector by one comparison of squares.
    let centre = <P::S as Ieee>::splat(r * r).le(path.dot(path));
    let anchor = P::select(centre, P::splat(sphere.center), origin);
    let rel = P::select(centre, offset, path);
    let facing = dir.dot(outward).gt(<P::S as Ieee>::splat(0.0));
    [P::select(facing, outward.neg(), outward), anchor, rel]
}
