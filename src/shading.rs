//! The shading model: ambient, Lambert diffuse and Blinn–Phong specular under point and
//! directional lights, hard shadows and mirror reflection. All of it is in this file.
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
use crate::math::{spec_pow, Color, Vec3};
use crate::scene::{make_hit, Hit, Light, Scene};

/// Just above zero: "t > 0" for closed-interval queries.
pub(crate) const T_EPS: f32 = f32::MIN_POSITIVE;
/// Just below one: a point light's shadow ray covers `0 < t < 1` of `light − p`.
const T_BELOW_ONE: f32 = 1.0 - f32::EPSILON / 2.0;
/// Point-light constants are used for spheres with `|light − m|² − r² ≤ NEAR_LIGHT r²`
/// (within 32 radii of the light), see [`in_shadow`].
const NEAR_LIGHT: f32 = 1023.0;

/// Where the light comes from at the hit point `anchor + rel` (see [`Hit::anchor`]): the
/// vector from the hit to a point light (the shadow ray, `0 < t < 1`) or the unit vector
/// towards a directional one.
#[inline]
fn to_light(light: &Light, anchor: Vec3, rel: Vec3) -> Vec3 {
    match *light {
        Light::Point { position, .. } => (position - anchor) - rel,
        Light::Directional { direction, .. } => -direction,
    }
}

/// Below this `|v|²` (2⁻⁴⁰, as bits) a point light's shadow ray is scaled up by 2⁶⁴.
const SMALL_VV: u32 = (127 - 40) << 23;

/// A point light's shadow ray: `v` (the test covers `0 < t < 1`, see [`to_light`]), `|v|²`
/// and the largest t below 1, all three scaled by 2⁶⁴ (t by 2⁻⁶⁴) when `|v|² < 2⁻⁴⁰`. `v` is
/// as small as the scene, and the tests multiply `|v|²` by squares of distances (`a c`,
/// `a (|f|² + r²)`), which underflow from a scene of ~10⁻¹¹ (their margins from ~10⁻⁸):
/// shadows came out wrong in ~5% of the pixels of a scene scaled by 2⁻⁴⁰. Every step of the
/// tests scales exactly with `v`, and t with its inverse, so a scaled ray gets the answer the
/// unscaled one gets wherever nothing underflows (`scaled_by_powers_of_two_is_bit_identical`,
/// 2⁻⁶⁰ … 2⁶⁰). One fixed factor rather than one fitted to `v`: fewer instructions in the
/// firmware's flash, and 2⁶⁴ serves scenes from 2⁻²⁰ down to where `c` itself underflows.
#[inline(always)]
fn shadow_ray(v: Vec3) -> (Vec3, f32, f32) {
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

/// The unit vector `l` along [`to_light`]'s `v`.
#[inline]
fn unit_towards(light: &Light, v: Vec3) -> Vec3 {
    match *light {
        Light::Point { .. } => {
            let ll = v.dot(v);
            // |v|² overflows beyond ~10¹⁹ and underflows below ~10⁻¹⁹: then the guarded form
            // (and no light at all from a light exactly at p). A bit test (M4F: 3 instructions
            // fewer than the float comparisons, as `vsqrt` takes the bits in a core register).
            if crate::math::positive_normal(ll) {
                v / crate::math::sqrt(ll)
            } else {
                v.normalized().unwrap_or(Vec3::ZERO)
            }
        }
        Light::Directional { .. } => v,
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
        to_light(light, hit.anchor, hit.rel),
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
/// sphere instead of 20. `v` is [`to_light`] of the hit, which shading has computed already.
#[inline]
pub(crate) fn in_shadow_among<const S: usize, const L: usize>(
    scene: &Scene<S, L>,
    hit: &Hit,
    light: &Light,
    v: Vec3,
    light_c: impl Fn(usize) -> Option<f32>,
    candidates: impl Iterator<Item = usize>,
) -> bool {
    let spheres = scene.spheres();
    // Rays leave the hit at `anchor + rel`, not at the rounded point: differences to other
    // points stay accurate however far from the origin the scene is.
    let (anchor, rel) = (hit.anchor, hit.rel);
    // Its own sphere can block a ray only when the hit is seen from inside: from outside,
    // a light is asked about only when n·l > 0, and the ray heads out (`exit_root` is None, up
    // to the rounding of a ray that grazes the tangent plane, which is lit by a zero n·l).
    let inside = hit.normal.dot(hit.offset) < 0.0;
    let blocks = |s, d, tmax| Prepared::leaving_blocks(anchor, rel, s, d, tmax);
    let mut others = candidates.filter(|&j| j != hit.sphere);
    match *light {
        Light::Point { position, .. } => {
            // `a`: `|d|²` for `d = −to_light`, the same bits. `t < 1` is `t ≤ below_one`.
            let (to_light, a, below_one) = shadow_ray(v);
            if inside && exit_root(hit.offset, to_light).is_some_and(|t| t <= below_one) {
                return true;
            }
            let d = -to_light;
            // `get`, not `[j]`: no bounds-check panic linked into the render path.
            others.any(|j| {
                let Some(s) = spheres.get(j) else {
                    return false;
                };
                match light_c(j) {
                    Some(c) if c <= NEAR_LIGHT * (s.radius * s.radius) => {
                        let k = Prepared {
                            f: position - s.center,
                            c,
                            r: s.radius,
                        };
                        k.hit_ab(d, a, k.f.dot(d), T_EPS, below_one).is_some()
                    }
                    _ => blocks(s, to_light, below_one),
                }
            })
        }
        Light::Directional { .. } => {
            let l = v;
            (inside && exit_root(hit.offset, l).is_some())
                || others.any(|j| spheres.get(j).is_some_and(|s| blocks(s, l, f32::INFINITY)))
        }
    }
}

/// The local colour at a hit seen along `dir`: ambient plus every light for which
/// `blocked(light_index)` is false. `blocked` is asked only for lights with `n·l > 0`.
///
/// ```
/// use microray::{shading::shade_local, Color, Light, Material, Ray, Scene, Sphere, Vec3};
/// let mut scene: Scene<1, 1> = Scene::new();
/// scene.add_sphere(Sphere::new(Vec3::ZERO, 1.0), Material::default())?;
/// // a light straight above: the cosine law gives n·l = 1 at the top
/// scene.add_light(Light::Directional { direction: Vec3::new(0.0, -1.0, 0.0), intensity: Color::ONE })?;
/// let down = Ray::new(Vec3::new(0.0, 5.0, 0.0), Vec3::new(0.0, -1.0, 0.0));
/// let hit = scene.find_intersection(&down, 0.0, 10.0).unwrap();
/// assert_eq!(shade_local(&scene, &hit, down.dir, |_| false), Color::ONE);
/// assert_eq!(shade_local(&scene, &hit, down.dir, |_| true), Color::ZERO);
/// # Ok::<(), microray::Error>(())
/// ```
pub fn shade_local<const S: usize, const L: usize>(
    scene: &Scene<S, L>,
    hit: &Hit,
    dir: Vec3,
    mut blocked: impl FnMut(usize) -> bool,
) -> Color {
    shade_lit(scene, hit, dir, |i, _, _| blocked(i))
}

/// [`shade_local`] with `blocked(i, light, v)` also given the light and its [`to_light`] vector,
/// which the shadow test needs too.
#[inline]
pub(crate) fn shade_lit<const S: usize, const L: usize>(
    scene: &Scene<S, L>,
    hit: &Hit,
    dir: Vec3,
    blocked: impl FnMut(usize, &Light, Vec3) -> bool,
) -> Color {
    shade_lit_inline(scene, hit, dir, blocked)
}

/// [`shade_lit`]'s body, for the renderer's scalar primary hits, which shade the hit record
/// where they build it (`Frame::shade_stored`).
#[inline(always)]
pub(crate) fn shade_lit_inline<const S: usize, const L: usize>(
    scene: &Scene<S, L>,
    hit: &Hit,
    dir: Vec3,
    mut blocked: impl FnMut(usize, &Light, Vec3) -> bool,
) -> Color {
    // A hit always names a sphere of this scene; `get` keeps a bounds-check panic out of the
    // render path (an invalid hit shades black).
    let Some(m) = scene.materials().get(hit.sphere) else {
        return Color::ZERO;
    };
    let n = hit.normal;
    let mut colour = m.diffuse.mul_elem(scene.ambient());
    let has_specular = scene.has_specular(hit.sphere);
    // Only a highlight needs the view vector (and only when there is a light).
    let v = if has_specular && !scene.lights().is_empty() {
        -dir.normalize_fast()
    } else {
        Vec3::ZERO
    };
    for (i, light) in scene.lights().iter().enumerate() {
        let to = to_light(light, hit.anchor, hit.rel);
        let l = unit_towards(light, to);
        let nl = n.dot(l);
        if !(nl > 0.0) || blocked(i, light, to) {
            continue;
        }
        let mut c = m.diffuse * nl;
        if has_specular {
            let nh = n.dot((v + l).normalize_fast());
            if nh > 0.0 {
                c += m.specular * spec_pow(nh, m.shininess);
            }
        }
        colour += light.intensity().mul_elem(c);
    }
    colour
}

/// Four hits on one sphere, in vector lanes (`cfg(lanes)`): [`Hit`]'s fields and the view
/// direction of each, for [`shade_lit4`].
#[cfg(lanes)]
#[derive(Debug, Clone, Copy)]
pub(crate) struct Hits4 {
    pub t: F,
    pub sphere: usize,
    pub normal: V,
    pub offset: V,
    pub anchor: V,
    pub rel: V,
    pub dir: V,
}

#[cfg(lanes)]
use crate::math::lanes::{bits, mask, ones, F, V};

#[cfg(lanes)]
impl Hits4 {
    /// Lane `l` as a [`Hit`], for the scalar shadow test.
    #[inline]
    pub(crate) fn hit(&self, l: usize) -> Hit {
        Hit {
            t: self.t.as_array_ref()[l & 3],
            sphere: self.sphere,
            normal: self.normal.lane(l),
            offset: self.offset.lane(l),
            anchor: self.anchor.lane(l),
            rel: self.rel.lane(l),
        }
    }
}

/// [`shade_lit`] of four hits on one sphere (one material) at once, in vector lanes: lane `l`
/// is `shade_lit(scene, &h.hit(l), h.dir.lane(l), …)`, bit for bit. Each step is the scalar
/// step lane by lane (the same IEEE operations in the same order), a branch a selection
/// between both arms. Only the lanes in `active` are asked for and checked; the others may
/// hold any values (another sphere's hits), and their colours mean nothing.
/// `blocked(i, light, ask, to)` answers for the lanes in `ask` (active ones with `n·l > 0`,
/// which the scalar loop would ask) which are in shadow. `None` where an active lane leaves
/// the common case (a light vector whose square leaves the normal range, a specular power
/// that is not a whole number): the caller shades those pixels with the scalar code.
#[cfg(lanes)]
#[inline(always)]
pub(crate) fn shade_lit4<const S: usize, const L: usize>(
    scene: &Scene<S, L>,
    h: &Hits4,
    active: u32,
    mut blocked: impl FnMut(usize, &Light, u32, &V) -> u32,
) -> Option<V> {
    use wide::{CmpGt, CmpLe};
    let m = scene.materials().get(h.sphere)?;
    let lights = scene.lights();
    let n = h.normal;
    let mut colour = V::splat(m.diffuse.mul_elem(scene.ambient()));
    let has_specular = scene.has_specular(h.sphere);
    let v = if has_specular && !lights.is_empty() {
        h.dir.normalize_fast().neg()
    } else {
        V::splat(Vec3::ZERO)
    };
    let (kd, ks) = (V::splat(m.diffuse), V::splat(m.specular));
    for (i, light) in lights.iter().enumerate() {
        // `to_light` and `unit_towards`.
        let (to, l) = match *light {
            Light::Point { position, .. } => {
                let to = V::splat(position).sub(h.anchor).sub(h.rel);
                let ll = to.dot(to);
                let normal = F::splat(f32::MIN_POSITIVE).cmp_le(ll) & ll.cmp_le(F::splat(f32::MAX));
                if bits(normal) & active != active {
                    return None;
                }
                (to, to.div(ll.sqrt()))
            }
            Light::Directional { direction, .. } => {
                let to = V::splat(-direction);
                (to, to)
            }
        };
        let nl = n.dot(l);
        let facing = nl.cmp_gt(F::ZERO);
        let ask = bits(facing) & active;
        if ask == 0 {
            continue;
        }
        let shadowed = blocked(i, light, ask, &to);
        if ask & !shadowed == 0 {
            continue;
        }
        let lit = if shadowed == 0 {
            facing
        } else {
            facing & !mask(shadowed)
        };
        let mut c = kd.mul(nl);
        if has_specular {
            let nh = n.dot(v.add(l).normalize_fast());
            let shine = nh.cmp_gt(F::ZERO) & lit;
            if bits(shine) != 0 {
                let p = crate::math::lanes::spec_pow(nh, m.shininess)?;
                c = V::select(shine, c.add(ks.mul(p)), c);
            }
        }
        colour = V::select(
            lit,
            colour.add(V::splat(light.intensity()).mul_elem(c)),
            colour,
        );
    }
    Some(colour)
}

/// [`in_shadow_among`] for the lanes `ask` of four hits on one sphere (`to` their
/// [`to_light`] vectors): the bits of those in shadow. Each candidate is weighed for the four
/// lanes at once as far as lanes decide it (`fused`'s steps lane by lane, and the point light's
/// constants through [`Prepared::hit4`]); the lanes that remain get the scalar test of
/// that sphere, so every answer is the scalar one. Lanes that see their sphere from inside
/// take the whole scalar test.
#[cfg(lanes)]
#[inline(always)]
pub(crate) fn in_shadow4<const S: usize, const L: usize>(
    scene: &Scene<S, L>,
    h: &Hits4,
    light: &Light,
    to: &V,
    ask: u32,
    light_c: impl Fn(usize) -> Option<f32>,
    candidates: &[u16],
) -> u32 {
    use crate::geometry::leaving_blocks4;
    use wide::CmpLt;
    let spheres = scene.spheres();
    let inside = bits(h.normal.dot(h.offset).cmp_lt(F::ZERO));
    // The lanes whose shadow ray `shadow_ray` scales up take the scalar test too.
    let small = match *light {
        Light::Point { .. } => bits(to.dot(*to).cmp_lt(F::splat(f32::from_bits(SMALL_VV)))),
        Light::Directional { .. } => 0,
    };
    let inside = inside | small;
    let mut out = 0;
    for l in ones(ask & inside) {
        let cands = candidates.iter().map(|&j| j as usize);
        if in_shadow_among(scene, &h.hit(l), light, to.lane(l), &light_c, cands) {
            out |= 1 << l;
        }
    }
    let mut open = ask & !inside;
    // `leaving_blocks` of the lanes in `open`: in lanes, the undecided ones scalar.
    let leaving = |s: &Sphere, d: &V, tmax: f32, open: u32| {
        let (mut hit, maybe) = leaving_blocks4(h.anchor, h.rel, s, *d, tmax, open);
        for l in ones(maybe) {
            let (anchor, rel) = (h.anchor.lane(l), h.rel.lane(l));
            if Prepared::leaving_blocks(anchor, rel, s, d.lane(l), tmax) {
                hit |= 1 << l;
            }
        }
        hit
    };
    let d = match *light {
        Light::Point { .. } => to.neg(),
        Light::Directional { .. } => *to,
    };
    for &j in candidates {
        if open == 0 {
            break;
        }
        let j = j as usize;
        let Some(s) = spheres.get(j) else { continue };
        if j == h.sphere {
            continue;
        }
        let hit = match *light {
            Light::Point { position, .. } => match light_c(j) {
                Some(c) if c <= NEAR_LIGHT * (s.radius * s.radius) => {
                    let k = Prepared {
                        f: position - s.center,
                        c,
                        r: s.radius,
                    };
                    k.hit_bits4(&d, T_EPS, T_BELOW_ONE, open)
                }
                _ => leaving(s, to, T_BELOW_ONE, open),
            },
            Light::Directional { .. } => leaving(s, &d, f32::INFINITY, open),
        };
        out |= hit;
        open &= !hit;
    }
    out
}

/// The lecture's shading of a hit: the local colour with shadows tested against the scene (when
/// the scene has them on). Mirrors are followed by [`trace`].
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
