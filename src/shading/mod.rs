//! The shading model: ambient, Lambert diffuse and Blinn–Phong specular under point and
//! directional lights, hard shadows, mirror reflection and refraction. All of it is in this
//! module: the local colour in `model.rs` (one definition for one hit and for four in lanes),
//! what each kind of light does in `lights.rs`, shadow rays in `shadow.rs`, the shadow tests of
//! four hits at once in `lanes.rs`, the mirror and refracted rays in `secondary.rs`, the
//! refracted direction in `refract.rs`.
//!
//! At a hit `p` with facing normal `n`, seen along `d`:
//! `colour = k_d ⊙ ambient + Σ I ⊙ (k_d (n·l) + k_s max(0, n·h)^s)` over the lights with
//! `n·l > 0` that no sphere blocks, with `v = −d/|d|` and `h = normalize(v + l)`; a mirror adds
//! `k_m ⊙` the colour seen along `d − 2(d·n)n`, glass `k_t ⊙` the colour seen along the
//! refracted ray (`refract`, feature `refraction`), up to the scene's `max_depth`.
//!
//! Shadow, mirror and refracted rays start on the surface of the sphere that was hit. That
//! sphere is never intersected again; [`exit_root`] says analytically where such a ray leaves it
//! (only when it heads inward), so there is no self-shadowing "acne" and no epsilon to tune.

use crate::geometry::{exit_root, offset_is_near, Prepared, Ray, Sphere};
use crate::math::{Color, Vec3};
use crate::scene::{make_hit, Hit, Light, Scene};

#[cfg(lanes)]
mod lanes;
mod lights;
mod model;
#[cfg(feature = "refraction")]
mod refract;
mod secondary;
mod shadow;

#[cfg(lanes)]
pub(crate) use lanes::*;
#[cfg(lanes)]
pub(crate) use lights::in_shadow4_of;
pub(crate) use lights::LightKind;
pub use model::*;
#[cfg(feature = "refraction")]
pub use refract::*;
pub use secondary::*;
pub use shadow::*;

/// The shading of a hit: the local colour with shadows tested against the scene (when the scene
/// has them on). Mirror and refracted rays are followed by [`trace`].
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
