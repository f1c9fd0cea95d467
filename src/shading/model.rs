//! The local colour at a hit: ambient, and Lambert diffuse plus Blinn–Phong specular from every
//! light that reaches it. One definition, [`shade_model`], for one hit (`Vec3`) and for four
//! hits on one sphere in vector lanes (`cfg(lanes)`): each lane does the scalar operations in
//! the scalar order, so it computes the scalar bits, and the scalar instance keeps the early
//! exits (a light behind the surface, a shadowed light, no highlight).

use super::*;
use crate::math::{Ieee, Ieee3, IeeeCmp};

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

/// [`shade_local`] with `blocked(i, light, v)` also given the light and its
/// [`LightKind::to_light`] vector,
/// which the shadow test needs too: [`shade_model`] of one hit.
// Always inlined on hosts, into the closure that shades a span's leftover pixels and their
// secondary hits: left to the compiler, it went out of line there once the frame had a second
// walk of secondary rays (through the hierarchy) beside the first.
#[cfg_attr(lanes, inline(always))]
#[cfg_attr(not(lanes), inline)]
pub(crate) fn shade_lit<const S: usize, const L: usize>(
    scene: &Scene<S, L>,
    hit: &Hit,
    dir: Vec3,
    mut blocked: impl FnMut(usize, &Light, Vec3) -> bool,
) -> Color {
    let at = [hit.normal, hit.anchor, hit.rel, dir];
    // One f32 always shades: `None` only for a hit on no sphere of this scene (black).
    shade_model(scene, hit.sphere, at, 1, |i, light, _, &v| {
        blocked(i, light, v) as u32
    })
    .unwrap_or(Color::ZERO)
}

/// [`shade_model`] of one hit written out for the scalar path, for the Cortex-M4F speed build's
/// primary hits, which shade the hit record where they build it (`Frame::shade_stored`). A copy
/// because it is faster there: `shade_model` inlined in its place costs the M4F about 7 % more
/// instructions a pixel at opt 3 (`examples/firmware/run.sh m4f`);
/// `inline_shading_is_the_model` pins the two together bit for bit.
#[inline(always)]
pub(crate) fn shade_lit_inline<const S: usize, const L: usize>(
    scene: &Scene<S, L>,
    hit: &Hit,
    dir: Vec3,
    mut blocked: impl FnMut(usize, &Light, Vec3) -> bool,
) -> Color {
    // `get` keeps a bounds-check panic out of the render path (an invalid hit shades black).
    let Some(m) = scene.materials().get(hit.sphere) else {
        return Color::ZERO;
    };
    let n = hit.normal;
    let mut colour = m.diffuse.mul_elem(scene.ambient());
    let has_specular = scene.has_specular(hit.sphere);
    let v = if has_specular && !scene.lights().is_empty() {
        -dir.normalize_fast()
    } else {
        Vec3::ZERO
    };
    for (i, light) in scene.lights().iter().enumerate() {
        let to: Vec3 = light.to_light(hit.anchor, hit.rel);
        let l = light.unit_towards(to, 1).unwrap_or(Vec3::ZERO);
        let nl = n.dot(l);
        if !(nl > 0.0) || blocked(i, light, to) {
            continue;
        }
        let mut c = m.diffuse * nl;
        if has_specular {
            let nh = n.dot((v + l).normalize_fast());
            if nh > 0.0 {
                c += m.specular * crate::math::spec_pow(nh, m.shininess);
            }
        }
        colour += light.intensity().mul_elem(c);
    }
    colour
}

/// The local colour of the hits `active` (bits `0..4`; one hit: bit 0) on sphere `sphere`,
/// given `[normal, anchor, rel, dir]` (the [`Hit`] fields and the view direction) of each:
/// `k_d ⊙ ambient + Σ I ⊙ (k_d (n·l) + k_s max(0, n·h)^s)` over the lights with `n·l > 0`
/// that `blocked` does not block, `v = −d/|d|`, `h = normalize(v + l)`. `blocked(i, light,
/// ask, to)` gives, of the lanes `ask` (the active ones facing light `i`, which `to` points
/// to, see [`LightKind::to_light`]), those in shadow. In lanes, the colours of inactive lanes
/// mean nothing, and `None` says an active lane leaves what lanes compute (a light vector whose
/// square leaves the normal range, a specular power that is not a whole number): the scalar
/// instance shades those pixels. Scalar, `None` only for a sphere that is not in the scene.
#[inline(always)]
pub(crate) fn shade_model<P: Ieee3, const S: usize, const L: usize>(
    scene: &Scene<S, L>,
    sphere: usize,
    [n, anchor, rel, dir]: [P; 4],
    active: u32,
    mut blocked: impl FnMut(usize, &Light, u32, &P) -> u32,
) -> Option<P> {
    // `get`: no bounds-check panic on the render path.
    let m = scene.materials().get(sphere)?;
    let lights = scene.lights();
    let zero = <P::S as Ieee>::splat(0.0);
    let mut colour = P::splat(m.diffuse.mul_elem(scene.ambient()));
    let has_specular = scene.has_specular(sphere);
    // Only a highlight needs the view vector (and only when there is a light).
    let v = if has_specular && !lights.is_empty() {
        dir.normalize_fast().neg()
    } else {
        P::splat(Vec3::ZERO)
    };
    for (i, light) in lights.iter().enumerate() {
        let to = light.to_light(anchor, rel);
        let l = light.unit_towards(to, active)?;
        let nl = n.dot(l);
        let facing = nl.gt(zero);
        let ask = <P::S as IeeeCmp>::bits(facing) & active;
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
            facing & !<P::S as IeeeCmp>::mask(shadowed)
        };
        let mut c = P::splat(m.diffuse).mul(nl);
        if has_specular {
            let nh = n.dot(v.add(l).normalize_fast());
            let shine = nh.gt(zero) & lit;
            if <P::S as IeeeCmp>::bits(shine) != 0 {
                let p = nh.spec_pow(m.shininess)?;
                c = P::select(shine, c.add(P::splat(m.specular).mul(p)), c);
            }
        }
        colour = P::select(
            lit,
            colour.add(P::splat(light.intensity()).mul_elem(c)),
            colour,
        );
    }
    Some(colour)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::TestRng;
    use crate::scene::Material;

    /// A scene of a few spheres under both kinds of light, point lights near, far and at
    /// distances whose |v|² leaves the normal range, with and without highlights, whole and
    /// fractional shininess.
    fn scene(g: &mut TestRng, case: usize) -> Scene<4, 4> {
        let mut scene: Scene<4, 4> = Scene::new();
        let scale = [1e-12f32, 1.0, 1e3, 1e12][case % 4];
        for k in 0..4 {
            let material = Material {
                diffuse: g.vec(2.0) + Vec3::splat(1.0),
                specular: if k % 2 == 0 {
                    Vec3::ZERO
                } else {
                    g.vec(2.0) + Vec3::splat(1.0)
                },
                shininess: if case.is_multiple_of(3) {
                    1.0 + 99.0 * g.unit()
                } else {
                    [1.0, 8.0, 32.0, 5000.0][k]
                },
                ..Material::default()
            };
            let sphere = Sphere::new(g.vec(8.0 * scale), (0.2 + g.unit()) * scale);
            scene.add_sphere(sphere, material).unwrap();
        }
        scene.set_ambient(g.vec(0.2) + Vec3::splat(0.1)).unwrap();
        for k in 0..1 + case % 4 {
            let intensity = g.vec(1.0) + Vec3::splat(0.5);
            let light = if k % 2 == 0 {
                Light::Point {
                    position: g.vec(20.0 * scale),
                    intensity,
                }
            } else {
                let direction = g.vec(1.0).normalized().unwrap_or(Vec3::new(0.0, -1.0, 0.0));
                Light::Directional {
                    direction,
                    intensity,
                }
            };
            scene.add_light(light).unwrap();
        }
        scene
    }

    /// `shade_lit_inline`, the M4F's written-out copy, gives `shade_model`'s bits (through
    /// `shade_lit`) on every hit, and asks `blocked` the same questions; and `shade_model` in
    /// lanes gives each lane's scalar bits wherever it shades.
    #[test]
    fn inline_shading_is_the_model() {
        let mut g = TestRng(0x2545_f491_4f6c_dd1d);
        let mut hits = 0;
        // Counted where lanes shade (`cfg(lanes)`).
        #[cfg_attr(not(lanes), allow(unused_mut))]
        let mut lane_hits = 0;
        for case in 0..4_000 {
            let scene = scene(&mut g, case);
            let scale = [1e-12f32, 1.0, 1e3, 1e12][case % 4];
            let eye = g.vec(30.0 * scale);
            // Shadowed by a hash of the light and the vector to it: any answer, the same for both.
            let shadow =
                |i: usize, v: Vec3| (v.x.to_bits() ^ v.y.to_bits() ^ i as u32).is_multiple_of(3);
            let mut four = [None; 4];
            for slot in four.iter_mut() {
                let s = &scene.spheres()[case % 4];
                let dir = (s.center + g.vec(2.0 * s.radius)) - eye;
                let ray = Ray::new(eye, dir);
                let Some(hit) = scene.find_intersection(&ray, 0.0, f32::INFINITY) else {
                    continue;
                };
                hits += 1;
                let (mut asked_a, mut asked_b) = ([0u32; 4], [0u32; 4]);
                let a = shade_lit(&scene, &hit, dir, |i, _, v| {
                    asked_a[i] += 1;
                    shadow(i, v)
                });
                let b = shade_lit_inline(&scene, &hit, dir, |i, _, v| {
                    asked_b[i] += 1;
                    shadow(i, v)
                });
                let bits = |c: Color| [c.x.to_bits(), c.y.to_bits(), c.z.to_bits()];
                assert_eq!(bits(a), bits(b), "case {case}: {hit:?}");
                assert_eq!(asked_a, asked_b);
                *slot = (hit.sphere == case % 4).then_some((hit, dir, a));
            }
            #[cfg(lanes)]
            {
                use crate::simd::V;
                let active = (0..4).fold(0, |b, l| b | (four[l].is_some() as u32) << l);
                let lane = |l: usize| {
                    four[l].map_or(
                        (Vec3::ZERO, Vec3::ZERO, Vec3::ZERO, Vec3::ZERO),
                        |(h, d, _)| (h.normal, h.anchor, h.rel, d),
                    )
                };
                let at = [0, 1, 2, 3].map(|k| {
                    V::from_lanes(core::array::from_fn(|l| {
                        let (n, a, r, d) = lane(l);
                        [n, a, r, d][k]
                    }))
                });
                let blocked = |i: usize, _: &Light, ask: u32, to: &V| {
                    (0..4)
                        .filter(|&l| ask & (1 << l) != 0 && shadow(i, to.lane(l)))
                        .fold(0, |b, l| b | 1 << l)
                };
                if active != 0 {
                    if let Some(c) = shade_model(&scene, case % 4, at, active, blocked) {
                        for l in crate::simd::ones(active) {
                            let want = four[l].map(|(_, _, a)| a).unwrap_or_default();
                            let got = c.lane(l);
                            assert_eq!(
                                [got.x.to_bits(), got.y.to_bits(), got.z.to_bits()],
                                [want.x.to_bits(), want.y.to_bits(), want.z.to_bits()],
                                "case {case} lane {l}"
                            );
                            lane_hits += 1;
                        }
                    }
                }
            }
        }
        assert!(hits > 8_000, "{hits}");
        #[cfg(lanes)]
        assert!(lane_hits > 4_000, "{lane_hits}");
        let _ = lane_hits;
    }
}
