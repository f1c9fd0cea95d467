//! The shading model: ambient, Lambert diffuse and Blinn–Phong specular under point and
//! directional lights, hard shadows and mirror reflection. All of it is in this module: the
//! local colour in `model.rs` (one definition for one hit and for four in lanes), what each
//! kind of light does in `lights.rs`, shadow rays in `shadow.rs`, the shadow tests of four
//! hits at once in `lanes.rs`, mirror bounces here.
//!
//! At a hit `p` with facing normal `n`, seen along `d`:
//! `colour = k_d ⊙ ambient + Σ I ⊙ (k_d (n·l) + k_s max(0, n·h)^s)` over the lights with
//! `n·l > 0` that no sphere blocks, with `v = −d/|d|` and `h = normalize(v + l)`; a mirror adds
//! `k_m ⊙` the colour seen along `d − 2(d·n)n`, up to the scene's `max_depth`.
//!
//! Shadow and mirror rays start on the surface of the sphere that was hit. That sphere is never
//! intersected again; [`exit_root`] says analytically where such a ray leaves it (only when seen
//! from inside), so there is no self-shadowing "acne" and no epsilon to tune.

use crate::geometry::{exit_root, offset_is_near, Prepared, Ray, Sphere};
use crate::math::{Color, Vec3};
use crate::scene::{make_hit, Hit, Light, Scene};

#[cfg(lanes)]
mod lanes;
mod lights;
mod model;
mod shadow;

#[cfg(lanes)]
pub(crate) use lanes::*;
pub(crate) use lights::LightKind;
pub use model::*;
pub use shadow::*;

/// The shading of a hit: the local colour with shadows tested against the scene (when the scene
/// has them on). Mirrors are followed by [`trace`].
///
/// ```
/// use microray::{shade, Color, Material, Ray, Scene, Sphere, Vec3};
/// let mut scene: Scene<1, 0> = Scene::new();
/// scene.set_ambient(Color::splat(0.5))?;
/// scene.add_sphere(Sphere::new(Vec3::ZERO, 1.0), Material { diffuse: Color::new(1.0, 0.0, 0.0), ..Material::default() })?;
/// let ray = Ray::new(Vec3::new(0.0, 0.0, 5.0), Vec3::new(0.0, 0.0, -1.0));
/// let hit = scene.find_intersection(&ray, 0.0, 10.0).unwrap();
/// assert_eq!(shade(&scene, &ray, &hit), Color::new(0.5, 0.0, 0.0));
/// # Ok::<(), microray::Error>(())
/// ```
pub fn shade<const S: usize, const L: usize>(scene: &Scene<S, L>, ray: &Ray, hit: &Hit) -> Color {
    shade_local(scene, hit, ray.dir, |i| {
        scene.shadows() && in_shadow(scene, hit, &scene.lights()[i], None)
    })
}

/// The mirror ray at a hit: from the hit point along `d − 2(d·n)n`.
///
/// ```
/// use microray::{shading::reflect, Material, Ray, Scene, Sphere, Vec3};
/// let mut scene: Scene<1, 0> = Scene::new();
/// scene.add_sphere(Sphere::new(Vec3::ZERO, 1.0), Material::default())?;
/// let ray = Ray::new(Vec3::new(0.0, 0.0, 5.0), Vec3::new(0.0, 0.0, -1.0));
/// let hit = scene.find_intersection(&ray, 0.0, 10.0).unwrap();
/// assert_eq!(reflect(&ray, &hit).dir, Vec3::new(0.0, 0.0, 1.0)); // straight back
/// # Ok::<(), microray::Error>(())
/// ```
#[inline]
pub fn reflect(ray: &Ray, hit: &Hit) -> Ray {
    let d = ray.dir;
    Ray::new(hit.point(), d - hit.normal * (2.0 * d.dot(hit.normal)))
}

/// The closest hit of a ray that leaves the hit `from` (a mirror ray): the sphere it starts on is
/// not intersected but left through [`exit_root`], so the ray cannot hit its own origin, and
/// the others are met from the hit's [`Hit::anchor`].
///
/// ```
/// use microray::{shading::{find_from, reflect}, Material, Ray, Scene, Sphere, Vec3};
/// let mut scene: Scene<2, 0> = Scene::new();
/// scene.add_sphere(Sphere::new(Vec3::ZERO, 1.0), Material::default())?;
/// scene.add_sphere(Sphere::new(Vec3::new(0.0, 0.0, 4.0), 1.0), Material::default())?;
/// let ray = Ray::new(Vec3::new(0.0, 0.0, 2.5), Vec3::new(0.0, 0.0, -1.0));
/// let hit = scene.find_intersection(&ray, 0.0, 10.0).unwrap();
/// let back = find_from(&scene, &reflect(&ray, &hit), &hit).unwrap();
/// assert_eq!(back.sphere, 1);
/// # Ok::<(), microray::Error>(())
/// ```
pub fn find_from<const S: usize, const L: usize>(
    scene: &Scene<S, L>,
    ray: &Ray,
    hit: &Hit,
) -> Option<Hit> {
    let (from, offset) = (hit.sphere, hit.offset);
    let spheres = scene.spheres();
    // The sphere travels with the index: re-indexing `spheres` would link a bounds-check panic.
    let mut best: Option<(f32, usize, Vec3, &Sphere)> = None;
    let mut tmax = f32::INFINITY;
    if let Some(s) = spheres.get(from) {
        if let Some(t) = exit_root(offset, ray.dir) {
            tmax = t;
            best = Some((t, from, offset, s));
        }
    }
    for (j, s) in spheres.iter().enumerate() {
        if j == from {
            continue;
        }
        // From `anchor + rel`, the hit point, whether or not `from` is a sphere of this scene.
        let found = Prepared::leaving_hit(hit.anchor, hit.rel, s, ray.dir, T_EPS, tmax);
        if let Some((t, f)) = found {
            tmax = t;
            best = Some((t, j, f, s));
        }
    }
    best.map(|(t, j, f, s)| {
        let near = offset_is_near(f, s.radius, scene.near2(j));
        make_hit(ray, t, j, f, s, near, hit.anchor, hit.rel)
    })
}

/// The colour seen along a ray: the hit's local colour plus its mirror reflections, or the
/// background when nothing is hit.
///
/// ```
/// use microray::{trace, Color, Ray, Scene, Vec3};
/// let mut scene: Scene<0, 0> = Scene::new();
/// scene.set_background(Color::splat(0.25))?;
/// assert_eq!(trace(&scene, &Ray::new(Vec3::ZERO, Vec3::new(1.0, 0.0, 0.0))), Color::splat(0.25));
/// # Ok::<(), microray::Error>(())
/// ```
pub fn trace<const S: usize, const L: usize>(scene: &Scene<S, L>, ray: &Ray) -> Color {
    let first = scene.find_intersection(ray, T_EPS, f32::INFINITY);
    follow(scene, ray, first, |hit, ray, _| shade(scene, ray, hit))
}

/// Follows mirror bounces from a primary hit, shading each hit with `local(hit, ray, primary)`.
///
/// `colour = local₀ + k_m₀ ⊙ (local₁ + k_m₁ ⊙ (…))` is summed front to back with the product
/// of the mirror colours so far, so the bounces need no recursion and no stack per depth.
#[inline]
pub(crate) fn follow<const S: usize, const L: usize>(
    scene: &Scene<S, L>,
    primary: &Ray,
    first: Option<Hit>,
    mut local: impl FnMut(&Hit, &Ray, bool) -> Color,
) -> Color {
    // The primary hit on its own: most hits are not mirrors, and the bounce loop, out of
    // line, keeps its state out of their registers.
    let Some(h) = first else {
        return scene.background();
    };
    let colour = local(&h, primary, true);
    follow_mirror(scene, primary, &h, colour, local)
}

/// [`follow`] after the primary hit `h`, whose local colour is `colour`: its mirror bounces.
#[inline]
pub(crate) fn follow_mirror<const S: usize, const L: usize>(
    scene: &Scene<S, L>,
    primary: &Ray,
    h: &Hit,
    colour: Color,
    mut local: impl FnMut(&Hit, &Ray, bool) -> Color,
) -> Color {
    if !scene.has_mirrors() || !scene.has_mirror(h.sphere) || scene.max_depth() == 0 {
        return colour;
    }
    let km = scene
        .materials()
        .get(h.sphere)
        .map_or(Color::ZERO, |m| m.mirror);
    bounce(scene, primary, h, colour, km, &mut local)
}

/// The mirror bounces after `first`, a hit along `ray` whose colour so far is `colour` and
/// whose mirror colour is `km` (see [`follow`]).
#[inline(never)]
fn bounce<const S: usize, const L: usize>(
    scene: &Scene<S, L>,
    ray: &Ray,
    first: &Hit,
    mut colour: Color,
    km: Color,
    local: &mut impl FnMut(&Hit, &Ray, bool) -> Color,
) -> Color {
    let mut weight = km;
    let mut ray = reflect(ray, first);
    let mut hit = find_from(scene, &ray, first);
    let mut depth = 1;
    loop {
        let Some(h) = hit else {
            return colour + weight.mul_elem(scene.background());
        };
        colour += weight.mul_elem(local(&h, &ray, false));
        let km = scene
            .materials()
            .get(h.sphere)
            .map_or(Color::ZERO, |m| m.mirror);
        if km.is_zero() || depth >= scene.max_depth() {
            return colour;
        }
        weight = weight.mul_elem(km);
        ray = reflect(&ray, &h);
        hit = find_from(scene, &ray, &h);
        depth += 1;
    }
}
