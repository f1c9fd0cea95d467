//! Secondary rays: the mirror ray and the refracted ray a hit sends, where they meet the scene,
//! and the walk over the tree of rays that sums their colours into a pixel's.

use super::*;
#[cfg(feature = "refraction")]
use crate::scene::MAX_DEPTH;

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

/// The closest hit of a ray that leaves the hit `from` (a mirror or refracted ray): the sphere
/// it starts on is not intersected but left through [`exit_root`], so the ray cannot hit its
/// own origin, and the others are met from the hit's [`Hit::anchor`].
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

/// A closest-hit candidate: `t`, the sphere's index, its `f` and the sphere (which travels
/// with the index: re-indexing `spheres` would link a bounds-check panic).
pub(crate) type Closest<'s> = (f32, usize, Vec3, &'s Sphere);

/// [`find_from`]'s first candidate: the ray's exit from the sphere of `hit`, which it leaves,
/// found analytically (no epsilon), if it heads inside.
#[inline(always)]
pub(crate) fn leaving_own<'s>(spheres: &'s [Sphere], ray: &Ray, hit: &Hit) -> Option<Closest<'s>> {
    let (from, offset) = (hit.sphere, hit.offset);
    if let Some(s) = spheres.get(from) {
        if let Some(t) = exit_root(offset, ray.dir) {
            return Some((t, from, offset, s));
        }
    }
    None
}

/// The hit record of [`find_from`]'s winner `found`, along `ray`, which leaves `hit`.
#[inline(always)]
pub(crate) fn closest_hit<const S: usize, const L: usize>(
    scene: &Scene<S, L>,
    ray: &Ray,
    hit: &Hit,
    (t, j, f, s): Closest<'_>,
) -> Hit {
    let near = offset_is_near(f, s.radius, scene.near2(j));
    make_hit(ray, t, j, f, s, near, hit.anchor, hit.rel)
}

/// How a walk of secondary rays finds each ray's hit: [`find_from`] over every sphere
/// ([`EverySphere`]), or a renderer's culled search for the same hit.
pub(crate) trait FindFrom<const S: usize, const L: usize>: Copy {
    /// The closest hit of `ray`, which leaves the hit `from`: [`find_from`]'s.
    fn find(self, scene: &Scene<S, L>, ray: &Ray, from: &Hit) -> Option<Hit>;
}

/// [`find_from`] itself: every sphere asked. No data, so a walk with it takes no argument more.
#[derive(Debug, Clone, Copy)]
pub(crate) struct EverySphere;

impl<const S: usize, const L: usize> FindFrom<S, L> for EverySphere {
    #[inline(always)]
    fn find(self, scene: &Scene<S, L>, ray: &Ray, from: &Hit) -> Option<Hit> {
        find_from(scene, ray, from)
    }
}

/// The colour seen along a ray: the hit's local colour plus what its mirror and refracted rays
/// see, or the background when nothing is hit.
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
    let local = |hit: &Hit, ray: &Ray, _| shade(scene, ray, hit);
    follow(scene, ray, first, local, EverySphere)
}

/// The colour along a primary ray whose first hit is `first`, each hit shaded with
/// `local(hit, ray, primary)`, its secondary rays followed, each finding its hit with `find`.
#[inline]
pub(crate) fn follow<const S: usize, const L: usize>(
    scene: &Scene<S, L>,
    primary: &Ray,
    first: Option<Hit>,
    mut local: impl FnMut(&Hit, &Ray, bool) -> Color,
    find: impl FindFrom<S, L>,
) -> Color {
    // The primary hit on its own: most hits send no ray, and the walk, out of line, keeps its
    // state out of their registers.
    let Some(h) = first else {
        return scene.background();
    };
    let colour = local(&h, primary, true);
    follow_secondary(scene, primary, &h, colour, local, find)
}

/// [`follow`] after the primary hit `h`, whose local colour is `colour`: its secondary rays.
#[inline]
pub(crate) fn follow_secondary<const S: usize, const L: usize>(
    scene: &Scene<S, L>,
    primary: &Ray,
    h: &Hit,
    colour: Color,
    mut local: impl FnMut(&Hit, &Ray, bool) -> Color,
    find: impl FindFrom<S, L>,
) -> Color {
    if !scene.has_secondary() || !scene.sends_secondary(h.sphere) || scene.max_depth() == 0 {
        return colour;
    }
    walk(scene, primary, h, colour, Start::PRIMARY, &mut local, find)
}

/// A secondary ray still to follow: `ray`, leaving the hit `from`, at `depth` (a primary ray's
/// hit sends rays of depth 1), its colour weighted by `weight`, the product of the mirror and
/// transmission colours on the path to it.
#[derive(Clone, Copy)]
struct Branch {
    ray: Ray,
    from: Hit,
    weight: Color,
    depth: u8,
}

/// The refracted rays put aside while the walk follows a mirror ray from the same hit. Each
/// holds a ray deeper than the one below it (see `walk`), so `MAX_DEPTH` is room enough;
/// without refraction no hit sends two rays, and nothing is put aside.
#[cfg(feature = "refraction")]
type Deferred = heapless::Vec<Branch, { MAX_DEPTH as usize }>;
#[cfg(not(feature = "refraction"))]
type Deferred = heapless::Vec<Branch, 0>;

/// Where a walk starts: at a hit of `depth` on a path that weighs `weight` (a primary hit:
/// depth 0, weight one). On hosts (`cfg(lanes)`) the lanes start walks at secondary hits too
/// (`walk_on`); elsewhere every walk starts at a primary hit, and the empty type costs the
/// callers nothing.
#[cfg(lanes)]
#[derive(Clone, Copy)]
struct Start(Color, u8);
#[cfg(not(lanes))]
#[derive(Clone, Copy)]
struct Start;

impl Start {
    #[cfg(lanes)]
    const PRIMARY: Start = Start(Color::ONE, 0);
    #[cfg(not(lanes))]
    const PRIMARY: Start = Start;

    /// The weight and depth of the hit.
    #[inline(always)]
    fn weight_depth(self) -> (Color, u8) {
        #[cfg(lanes)]
        return (self.0, self.1);
        #[cfg(not(lanes))]
        (Color::ONE, 0)
    }
}

/// The secondary rays after `first`, a hit along `ray` whose colour so far is `colour`, where
/// `start` says.
///
/// `colour = local₀ + k₀ ⊙ (local₁ + k₁ ⊙ (…))`, a sum over the tree of rays, is summed in
/// depth-first order, each hit's local colour weighted by the product of the colours on its
/// path: no recursion, and where no hit sends two rays (mirrors only), a loop along the one
/// path. A hit that sends both follows its mirror ray first and puts the refracted ray aside;
/// rays put aside are deeper than those below them (a ray taken back is deeper than what
/// remains, and the rays its path puts aside deeper still), so at most `MAX_DEPTH` wait.
#[inline(never)]
fn walk<const S: usize, const L: usize>(
    scene: &Scene<S, L>,
    ray: &Ray,
    first: &Hit,
    mut colour: Color,
    start: Start,
    local: &mut impl FnMut(&Hit, &Ray, bool) -> Color,
    find: impl FindFrom<S, L>,
) -> Color {
    let (weight, depth) = start.weight_depth();
    let mut deferred = Deferred::new();
    let mut next = send(scene, ray, first, weight, depth + 1, &mut deferred);
    while let Some(b) = next.or_else(|| deferred.pop()) {
        next = None;
        let Some(h) = find.find(scene, &b.ray, &b.from) else {
            colour += b.weight.mul_elem(scene.background());
            continue;
        };
        colour += b.weight.mul_elem(local(&h, &b.ray, false));
        if b.depth < scene.max_depth() {
            next = send(scene, &b.ray, &h, b.weight, b.depth + 1, &mut deferred);
        }
    }
    colour
}

/// [`follow_secondary`] on from the hit `h` of a secondary ray `ray` of depth `depth` and
/// weight `weight`, once `colour` holds that hit's weighted colour: the rays it sends, and
/// theirs. For a renderer that found and shaded the first secondary rays of several pixels
/// itself, and put nothing aside (their primary hits send one ray each). `walk` itself, so
/// that the renderer's walks share one copy.
#[cfg(lanes)]
#[inline(always)]
pub(crate) fn walk_on<const S: usize, const L: usize>(
    scene: &Scene<S, L>,
    (ray, h): (&Ray, &Hit),
    (colour, weight, depth): (Color, Color, u8),
    mut local: impl FnMut(&Hit, &Ray, bool) -> Color,
    find: impl FindFrom<S, L>,
) -> Color {
    if depth >= scene.max_depth() {
        return colour;
    }
    walk(
        scene,
        ray,
        h,
        colour,
        Start(weight, depth),
        &mut local,
        find,
    )
}

/// The rays that the hit `h` along `ray` sends at `depth`, its path's weight `weight`: the
/// mirror ray, returned, and the refracted ray, returned when there is no mirror ray and put
/// in `deferred` when there is.
#[inline(always)]
#[cfg_attr(not(feature = "refraction"), allow(unused_variables))]
fn send<const S: usize, const L: usize>(
    scene: &Scene<S, L>,
    ray: &Ray,
    h: &Hit,
    weight: Color,
    depth: u8,
    deferred: &mut Deferred,
) -> Option<Branch> {
    let m = scene.materials().get(h.sphere)?;
    let branch = |ray, k: Color| Branch {
        ray,
        from: *h,
        weight: weight.mul_elem(k),
        depth,
    };
    let mirror = (!m.mirror.is_zero()).then(|| branch(reflect(ray, h), m.mirror));
    #[cfg(feature = "refraction")]
    if !m.refraction.is_zero() {
        let refracted = branch(refract(ray, h, m.ior), m.refraction);
        if mirror.is_none() {
            return Some(refracted);
        }
        // Room for it: see `walk`.
        let _ = deferred.push(refracted);
    }
    mirror
}
