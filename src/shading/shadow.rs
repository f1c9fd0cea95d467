//! Shadow rays: the direction to each light, the ray set up exactly, and the test against the
//! spheres that can block it.

use super::*;

/// Just above zero: "t > 0" for closed-interval queries.
pub(crate) const T_EPS: f32 = f32::MIN_POSITIVE;
/// Just below one: a point light's shadow ray covers `0 < t < 1` of `light − p`.
pub(super) const T_BELOW_ONE: f32 = 1.0 - f32::EPSILON / 2.0;
/// Point-light constants are used for spheres with `|light − m|² − r² ≤ NEAR_LIGHT r²`
/// (within 32 radii of the light), see [`in_shadow`].
pub(super) const NEAR_LIGHT: f32 = 1023.0;

/// Below this `|v|²` (2⁻⁴⁰, as bits) a point light's shadow ray is scaled up by 2⁶⁴.
pub(super) const SMALL_VV: u32 = (127 - 40) << 23;

/// A point light's shadow ray: `v` (the test covers `0 < t < 1`, see [`LightKind::to_light`]), `|v|²`
/// and the largest t below 1, all three scaled by 2⁶⁴ (t by 2⁻⁶⁴) when `|v|² < 2⁻⁴⁰`. `v` is
/// as small as the scene, and the tests multiply `|v|²` by squares of distances (`a c`,
/// `a (|f|² + r²)`), which underflow from a scene of ~10⁻¹¹ (their margins from ~10⁻⁸):
/// without this scaling, ~5% of the pixels of a scene shrunk by 2⁻⁴⁰ get their shadows wrong.
/// Every step of the tests scales exactly with `v`, and t with its inverse, so a scaled ray gets
/// the answer the unscaled one gets wherever nothing underflows
/// (`scaled_by_powers_of_two_is_bit_identical`, 2⁻⁶⁰ … 2⁶⁰). One fixed factor rather than one
/// fitted to `v`: fewer instructions in the firmware's flash, and 2⁶⁴ serves scenes from 2⁻²⁰
/// down to where `c` itself underflows.
#[inline(always)]
pub(super) fn shadow_ray(v: Vec3) -> (Vec3, f32, f32) {
    let vv = v.dot(v);
    if vv.to_bits() >= SMALL_VV {
        (v, vv, T_BELOW_ONE)
    } else {
        // 2⁶⁴. |v|² anew, not vv·2¹²⁸: squares that were subnormal (a coordinate below
        // 2⁻⁶³) are rounded differently once scaled, and `a` must be `d·d`'s bits.
        const UP: f32 = 18_446_744_073_709_551_616.0;
        let v = v * UP;
        (v, v.dot(v), T_BELOW_ONE / UP)
    }
}

/// Whether a sphere blocks `light` at `hit` (the model's hard shadow).
///
/// `from_light`, when given, holds [`Prepared::exact`] constants of a point light for every
/// sphere: the shadow ray is then cast from the light towards `p`, sharing its origin with all
/// other shadow rays of that light. Only for spheres within 32 radii of the light, though: the
/// direction `p − light` is rounded, so the ray cast from the light passes `p` (and any sphere
/// near it) off by up to ~ε |light − p|, which is nothing next to such a sphere but would move
/// the shadow of a sphere of radius 1 by a whole unit for a light 10⁷ away. Spheres farther from
/// the light are tested from `p`, where the error is at the light's end.
///
/// ```
/// use microray::{shading::in_shadow, Color, Light, Material, Ray, Scene, Sphere, Vec3};
/// let mut scene: Scene<2, 1> = Scene::new();
/// scene.add_sphere(Sphere::new(Vec3::ZERO, 1.0), Material::default())?;
/// scene.add_sphere(Sphere::new(Vec3::new(0.0, 3.0, 0.0), 1.0), Material::default())?;
/// let sun = Light::Directional { direction: Vec3::new(0.0, -1.0, 0.0), intensity: Color::ONE };
/// let down = Ray::new(Vec3::new(0.0, 1.5, 0.0), Vec3::new(0.0, -1.0, 0.0));
/// let top = scene.find_intersection(&down, 0.0, 10.0).unwrap(); // top of the lower sphere
/// assert!(in_shadow(&scene, &top, &sun, None)); // the upper sphere is in the way
/// # Ok::<(), microray::Error>(())
/// ```
pub fn in_shadow<const S: usize, const L: usize>(
    scene: &Scene<S, L>,
    hit: &Hit,
    light: &Light,
    from_light: Option<&[Prepared]>,
) -> bool {
    in_shadow_among(
        scene,
        hit,
        light,
        light.to_light(hit.anchor, hit.rel),
        |j| from_light.and_then(|k| k.get(j)).map(|k| k.c),
        0..scene.spheres().len(),
    )
}

/// [`in_shadow`] over a subset of the spheres: `candidates` (sphere indices) must contain every
/// sphere that can block the shadow ray, as the renderer's per-span shadow lists do (the
/// brute-force path passes them all). The tests are those of [`in_shadow`], so the answer is
/// the same bit for bit; only fewer spheres are asked. `light_c(j)`, for a point light, is
/// `c = |light − m|² − r²` of [`Prepared::exact`] for sphere `j`: the rest of those constants is
/// rebuilt exactly as `Prepared::exact` computes it, so a frame stores 4 bytes per light and
/// sphere instead of 20. `v` is [`LightKind::to_light`] of the hit, which shading has computed
/// already.
#[inline]
pub(crate) fn in_shadow_among<const S: usize, const L: usize>(
    scene: &Scene<S, L>,
    hit: &Hit,
    light: &impl LightKind,
    v: Vec3,
    light_c: impl Fn(usize) -> Option<f32>,
    candidates: impl Iterator<Item = usize>,
) -> bool {
    let spheres = scene.spheres();
    // Rays leave the hit at `anchor + rel` (the light kinds' `blocked`), not at the rounded
    // point: differences to other points stay accurate however far from the origin the scene is.
    // Its own sphere can block a ray only when the hit is seen from inside: from outside,
    // a light is asked about only when n·l > 0, and the ray heads out (`exit_root` is None, up
    // to the rounding of a ray that grazes the tangent plane, which is lit by a zero n·l).
    let inside = hit.from_inside();
    let others = candidates.filter(|&j| j != hit.sphere);
    light.blocked(spheres, hit, inside, v, light_c, others)
}
