//! The numerical variants that examples/speed_vs_error.rs compares, shared with the firmware's
//! `numbench` (examples/firmware/src/bin/numbench.rs), which counts their instructions on a
//! Cortex-M4F: both include this file with `#[path]`, so they measure the same code. no_std:
//! core and libm only.

// `!(x >= 0.0)` is deliberate, as in the library: NaN must fail.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use microray::{ray_intersect, Prepared, Ray, Sphere, Vec3};

// ---- the intersection variants ----------------------------------------------------------------

/// The textbook quadratic: `(−b ± √(b² − 4ac)) / 2a` with `b = 2 f·d`, its square root
/// `libm::sqrtf` as a port of it would call (a software routine on thumbv7em).
#[inline(always)]
pub fn textbook(o: Vec3, d: Vec3, s: &Sphere) -> Option<f32> {
    textbook_with(o, d, s, libm::sqrtf)
}

/// [`textbook`] with microray's square root (`vsqrt.f32` on the Cortex-M4F, `libm::sqrtf`
/// elsewhere: the same bits): the formula's own cost on the M4F, for ratios that compare
/// formulas rather than square roots. On hosts the two are one instruction.
#[inline(always)]
pub fn textbook_vsqrt(o: Vec3, d: Vec3, s: &Sphere) -> Option<f32> {
    textbook_with(o, d, s, microray::math::sqrt)
}

#[inline(always)]
fn textbook_with(o: Vec3, d: Vec3, s: &Sphere, sqrt: impl Fn(f32) -> f32) -> Option<f32> {
    let f = o - s.center;
    let a = d.dot(d);
    let b = 2.0 * f.dot(d);
    let c = f.dot(f) - s.radius * s.radius;
    let disc = b * b - 4.0 * a * c;
    if !(disc >= 0.0) {
        return None;
    }
    let sq = sqrt(disc);
    let t0 = (-b - sq) / (2.0 * a);
    if t0 > 0.0 {
        return Some(t0);
    }
    let t1 = (-b + sq) / (2.0 * a);
    (t1 > 0.0).then_some(t1)
}

/// The geometric form: `t_m ± Δt` with `t_m` the projection of the centre on the ray and
/// `Δt² = r² − (|f|² − t_m²)` (unit `d`).
#[inline(always)]
pub fn geometric(o: Vec3, d: Vec3, s: &Sphere) -> Option<f32> {
    let f = s.center - o;
    let tm = f.dot(d);
    let h2 = f.dot(f) - tm * tm;
    let dt2 = s.radius * s.radius - h2;
    if !(dt2 >= 0.0) {
        return None;
    }
    let dt = libm::sqrtf(dt2);
    let t0 = tm - dt;
    if t0 > 0.0 {
        return Some(t0);
    }
    let t1 = tm + dt;
    (t1 > 0.0).then_some(t1)
}

/// Stable roots `c/q`, `q/a` with the Hearn–Baker discriminant, everything in f32 (no
/// compensation of `c`); `sqrt` is the square root to use.
#[inline(always)]
pub fn hearn_baker_with(o: Vec3, d: Vec3, s: &Sphere, sqrt: impl Fn(f32) -> f32) -> Option<f32> {
    let f = o - s.center;
    let r = s.radius;
    let a = d.dot(d);
    let b = f.dot(d);
    let c = f.dot(f) - r * r;
    let l = f - d * (b / a);
    let disc = a * (r * r - l.dot(l));
    if !(disc >= 0.0) {
        return None;
    }
    let sq = sqrt(disc);
    let q = if b > 0.0 { -(b + sq) } else { sq - b };
    let (t0, t1) = (c / q, q / a);
    let (t0, t1) = if t0 <= t1 { (t0, t1) } else { (t1, t0) };
    if t0 > 0.0 {
        Some(t0)
    } else {
        (t1 > 0.0).then_some(t1)
    }
}

#[inline(always)]
pub fn hearn_baker(o: Vec3, d: Vec3, s: &Sphere) -> Option<f32> {
    hearn_baker_with(o, d, s, libm::sqrtf)
}

/// microray's default for a ray of its own origin (secondary rays): `ray_intersect`.
#[inline(always)]
pub fn default_per_ray(o: Vec3, d: Vec3, s: &Sphere) -> Option<f32> {
    ray_intersect(&Ray::new(o, d), s, f32::MIN_POSITIVE, f32::INFINITY)
}

/// The default's roots with the plain f32 `c`, never compensated: wrong on the grounds (as the
/// Hearn–Baker row), and not a variant to use. It is the floor under any per-ray remedy for `c`:
/// what a ray of its own origin costs when the compensation costs nothing.
#[inline(always)]
pub fn f32_c_per_ray(o: Vec3, d: Vec3, s: &Sphere) -> Option<f32> {
    let f = o - s.center;
    let c = f.dot(f) - s.radius * s.radius;
    Prepared { f, c, r: s.radius }.hit(d, f32::MIN_POSITIVE, f32::INFINITY)
}

/// The default's roots with `c` always through f64 (exact squares, one rounding of the sum):
/// the remedy for huge spheres that microray used before its compensated f32 `c`.
#[inline(always)]
pub fn f64_c_per_ray(o: Vec3, d: Vec3, s: &Sphere) -> Option<f32> {
    let (m, r) = (s.center, s.radius as f64);
    let [x, y, z] = [(o.x, m.x), (o.y, m.y), (o.z, m.z)].map(|(a, b)| a as f64 - b as f64);
    let c = (x * x + y * y + z * z - r * r) as f32;
    Prepared {
        f: o - m,
        c,
        r: s.radius,
    }
    .hit(d, f32::MIN_POSITIVE, f32::INFINITY)
}

// ---- the measured loops that both sides share-----------------------------------------------------

/// Every direction against per-frame constants built once from the eye: `Prepared::hit` of
/// every direction and sphere. Its own function, as the other measured loops, so that its code
/// does not depend on its caller's.
#[inline(never)]
pub fn primary_frame(dirs: &[Vec3], prepared: &[Prepared]) -> f32 {
    let mut acc = 0.0;
    for &d in dirs {
        for k in prepared {
            if let Some(t) = core::hint::black_box(k).hit(d, f32::MIN_POSITIVE, f32::INFINITY) {
                acc += t;
            }
        }
    }
    acc
}

/// [`primary_frame`] four directions at a time (`Prepared::hit4`, in vector lanes on hosts
/// that have them): the same tests and hits. A trailing remainder of fewer than four is left
/// out (the timing sets are multiples of four). Host only: the firmware's numbench does not
/// count it (Cortex-M has no f32 vectors; `hit4` is the scalar test there).
#[allow(dead_code)]
#[inline(never)]
pub fn primary_frame4(dirs: &[Vec3], prepared: &[Prepared]) -> f32 {
    let mut acc = 0.0;
    for d in dirs.chunks_exact(4) {
        let d: &[Vec3; 4] = d.try_into().unwrap_or(&[Vec3::ZERO; 4]);
        for k in prepared {
            let inf = f32::INFINITY;
            for t in core::hint::black_box(k)
                .hit4(d, f32::MIN_POSITIVE, [inf; 4])
                .into_iter()
                .flatten()
            {
                acc += t;
            }
        }
    }
    acc
}

/// Every shadow-like ray `(origin, direction, sphere left)` against every sphere but the one it
/// leaves (microray leaves it through its exit root); `f` gets the ray's origin as one point
/// (`o`) and as the hit's centre and offset (`anchor`, `rel`), as microray's shading has it, and
/// returns the hit's t, summed.
#[inline(never)]
pub fn shadow_loop(
    rays: &[(Vec3, Vec3, usize)],
    spheres: &[Sphere],
    f: impl Fn(Vec3, Vec3, Vec3, &Sphere, Vec3) -> Option<f32>,
) -> f32 {
    let mut acc = 0.0;
    for &(o, d, from) in rays {
        let anchor = spheres[from].center;
        let rel = o - anchor;
        for (j, s) in spheres.iter().enumerate() {
            if j != from {
                if let Some(t) = f(o, anchor, rel, s, d) {
                    acc += t;
                }
            }
        }
    }
    acc
}

// ---- square roots ------------------------------------------------------------------------------

/// The "fast inverse square root" bit trick with `n` Newton steps, times x.
#[inline(always)]
pub fn rsqrt_newton(x: f32, n: u32) -> f32 {
    let mut y = f32::from_bits(0x5f37_59df - (x.to_bits() >> 1));
    for _ in 0..n {
        y *= 1.5 - 0.5 * x * y * y;
    }
    x * y
}

// ---- specular powers ---------------------------------------------------------------------------

/// `x^n` by repeated squaring for an integer exponent.
#[inline(always)]
pub fn pow_squaring(x: f32, n: u32) -> f32 {
    let (mut base, mut n, mut acc) = (x, n, 1.0f32);
    while n > 0 {
        if n & 1 == 1 {
            acc *= base;
        }
        base *= base;
        n >>= 1;
    }
    acc
}

/// Schlick's rational approximation of `x^s`.
#[inline(always)]
pub fn pow_schlick(x: f32, s: f32) -> f32 {
    x / (s - s * x + x)
}

// ---- the timing sets ---------------------------------------------------------------------------
// Both sides draw the random numbers (same generator and seeds) and build the rays here, so the
// M4F counts are taken on a prefix of the host's sets.

/// The primary-like set's eye: 1 above the top of the ground sphere below.
pub const EYE: Vec3 = Vec3::new(0.0, 1.0, 0.0);

/// The primary-like set's spheres: a ground of radius 10⁶ just below the eye, ordinary, far and
/// tiny spheres, and one of radius 10⁴ that the eye sits just inside.
pub const PRIMARY_SPHERES: [Sphere; 8] = [
    Sphere::new(Vec3::new(0.0, -1e6, 0.0), 1e6),
    Sphere::new(Vec3::new(0.0, 0.5, -4.0), 0.5),
    Sphere::new(Vec3::new(1.0, 0.3, -3.0), 0.3),
    Sphere::new(Vec3::new(-1.3, 0.4, -5.0), 0.4),
    Sphere::new(Vec3::new(3.0, 2.0, -1e4), 1.0),
    Sphere::new(Vec3::new(0.0, 1.0, -10.0), 1e-4),
    Sphere::new(Vec3::new(0.0, 9999.0, 0.0), 1e4),
    Sphere::new(Vec3::new(2.0, 1.0, -8.0), 2.0),
];

/// Seeds of the primary-like directions, the shadow-like rays and the sqrt/pow arguments.
pub const SEED_PRIMARY: u64 = 99;
pub const SEED_SHADOW: u64 = 5;
pub const SEED_ARGS: u64 = 7;

/// A primary-like direction from two uniform draws, `x` in [−0.6, 0.6) and `y` in [−0.5, 0.3).
pub fn primary_dir(x: f64, y: f64) -> Vec3 {
    let n = libm::sqrt(x * x + y * y + 1.0);
    Vec3::new((x / n) as f32, (y / n) as f32, (-1.0 / n) as f32)
}

/// Shadow-like ray `k` on `spheres`: from the point of sphere `k mod len` along the unit normal
/// `n`, in the unit direction `d` turned away from the surface; `(origin, direction, sphere)`.
pub fn shadow_ray(spheres: &[Sphere], k: usize, n: [f64; 3], d: [f64; 3]) -> (Vec3, Vec3, usize) {
    let i = k % spheres.len();
    let s = spheres[i];
    let d = if d[0] * n[0] + d[1] * n[1] + d[2] * n[2] < 0.0 {
        [-d[0], -d[1], -d[2]]
    } else {
        d
    };
    let r = s.radius as f64;
    let m = [s.center.x as f64, s.center.y as f64, s.center.z as f64];
    let v32 = |v: [f64; 3]| Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32);
    (
        v32([m[0] + r * n[0], m[1] + r * n[1], m[2] + r * n[2]]),
        v32(d),
        i,
    )
}

// ---- secondary rays that a render casts --------------------------------------------------------
// The shadow-like set above draws its directions over the whole hemisphere of each surface
// point, so many of its rays leave the balls' undersides towards the ground, which a light
// above the scene never asks for. These sets are the rays that rendering
// tests/data/lit.toml and mirror.toml actually casts, from the same pixels on both sides.

/// The spheres of tests/data/lit.toml and mirror.toml, in file order (mirror.toml differs in
/// materials and depth; the report checks both files against these).
pub const LIT_SPHERES: [Sphere; 4] = [
    Sphere::new(Vec3::new(0.0, -1000.0, 0.0), 1000.0),
    Sphere::new(Vec3::new(-1.2, 0.8, 0.0), 0.8),
    Sphere::new(Vec3::new(1.0, 0.6, 0.5), 0.6),
    Sphere::new(Vec3::new(0.2, 0.25, 1.8), 0.25),
];

/// The spheres of mirror.toml with a mirror colour: the ground (0.2) and the blue ball (0.5).
pub const MIRROR_SPHERES: [usize; 2] = [0, 2];

/// The unit vector towards lit.toml's and mirror.toml's directional light (`direction = [1, −1,
/// −0.5]`), normalised as microray's scene does it.
pub fn lit_sun() -> Vec3 {
    -Vec3::new(1.0, -1.0, -0.5)
        .normalized()
        .unwrap_or(Vec3::ZERO)
}

/// Which secondary rays [`recorded_rays`] collects.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Secondary {
    /// lit.toml's directional light, from every primary hit whose normal faces it (`n·l > 0`):
    /// the rays shading tests with `Prepared::leaving_blocks`. (Its point light's shadow rays
    /// are cast from the light with per-frame constants, the primary rays' path.)
    Sun,
    /// mirror.toml's first bounces: from every primary hit on a mirror, the reflected direction,
    /// tested with `Prepared::leaving_hit`.
    Mirror,
}

/// Fills `out` with the rays of `kind` that a 160×120 render of lit.toml / mirror.toml casts, as
/// `(hit point, direction, sphere left)` for [`shadow_loop`], and returns how many it filled.
/// Pixels are visited in the order `k·7919 mod 19200`, a permutation that spreads any prefix
/// over the whole image (the firmware keeps only a prefix). The hits come from microray's
/// `Scene::find_intersection`, which both sides share.
pub fn recorded_rays(kind: Secondary, out: &mut [(Vec3, Vec3, usize)]) -> usize {
    let up = Vec3::new(0.0, 1.0, 0.0);
    let (eye, look_at) = (Vec3::new(0.0, 1.0, 6.0), Vec3::new(0.0, 0.5, 0.0));
    let (w, h) = (160u32, 120u32);
    let Ok(camera) = microray::Camera::new(eye, look_at, up, 45.0, w, h) else {
        return 0;
    };
    let sun = lit_sun();
    let mut scene: microray::Scene<4, 0> = microray::Scene::new();
    for s in LIT_SPHERES {
        if scene.add_sphere(s, microray::Material::default()).is_err() {
            return 0;
        }
    }
    let mut n = 0;
    for k in 0..w * h {
        if n == out.len() {
            break;
        }
        let p = (k as u64 * 7919 % (w * h) as u64) as u32;
        let ray = camera.ray((p % w) as f32 + 0.5, (p / w) as f32 + 0.5);
        let Some(hit) = scene.find_intersection(&ray, 0.0, f32::INFINITY) else {
            continue;
        };
        let d = match kind {
            Secondary::Sun if hit.normal.dot(sun) > 0.0 => sun,
            Secondary::Mirror if MIRROR_SPHERES.contains(&hit.sphere) => {
                microray::shading::reflect(&ray, &hit).dir
            }
            _ => continue,
        };
        out[n] = (hit.point(), d, hit.sphere);
        n += 1;
    }
    n
}

// ---- a prototype: per-frame constants for a directional light's shadow rays ---------------------
// Not microray's code path (yet): a measured answer to whether shadow rays that share a
// direction, as primary rays share an origin, can be tested for less than the textbook quadratic
// with the same answers. Every sphere is projected once per frame onto the plane across the
// light's direction `l` (coordinates u, v) and onto `l` (w), from a reference point `e` of the
// scene (the first sphere's centre), so that a test is a 2D distance. Coordinates are taken
// relative to `e` and from `(anchor − e) + rel`, so their error scales with the scene's extent
// `S` around `e`, not with its distance from the origin (the same reason as `Hit::anchor`).
// Each decision is made only where it is certain under that error; elsewhere the test falls
// back to `Prepared::leaving_blocks`. Up to `SUN_MAX` spheres.

/// The prototype's capacity.
pub const SUN_MAX: usize = 8;

/// One sphere's per-frame constants for [`Sun`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SunSphere {
    u: f32,
    v: f32,
    w: f32,
    /// `r²` and the bounds beyond which the line's distance² certainly passes outside (`hi`) or
    /// inside (`lo`) the sphere, whatever the projections' error.
    rr: f32,
    hi: f32,
    lo: f32,
    /// How far from 0 `|f|² − r²` (from the projections) must be to give the origin's side.
    mc: f32,
}

/// Per-frame constants of a directional light's shadow rays (see the section's comment).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sun {
    l: Vec3,
    eu: Vec3,
    ev: Vec3,
    e: Vec3,
    /// The bound on the error of a projected coordinate (and of their differences).
    delta: f32,
    s: [SunSphere; SUN_MAX],
}

impl Sun {
    /// The constants for the unit direction `l` towards the light, or `None` (too many spheres,
    /// or a value that is not finite).
    pub fn new(spheres: &[Sphere], l: Vec3) -> Option<Sun> {
        let e = spheres.first()?.center;
        if spheres.len() > SUN_MAX {
            return None;
        }
        // A unit vector across l from the axis along which l is shortest, and the third axis.
        let (ax, ay, az) = (libm::fabsf(l.x), libm::fabsf(l.y), libm::fabsf(l.z));
        let axis = if ax <= ay && ax <= az {
            Vec3::new(1.0, 0.0, 0.0)
        } else if ay <= az {
            Vec3::new(0.0, 1.0, 0.0)
        } else {
            Vec3::new(0.0, 0.0, 1.0)
        };
        let eu = l.cross(axis).normalized()?;
        let ev = l.cross(eu);
        // The extent around e: every origin (on a sphere) and centre is within `extent` of it.
        let mut extent = 0.0f32;
        for s in spheres {
            extent = extent.max((s.center - e).length() + s.radius);
        }
        // Each projected coordinate is off by a few ε S (the sums that make the point, the
        // dot product, the basis's own ε): 32 ε S bounds that with room to spare, for the
        // coordinates and for their difference. An argued bound, not a proof: the report
        // checks the decisions against the full test, grazing rays included.
        let delta = 32.0 * f32::EPSILON * extent;
        let mut s = [SunSphere {
            u: 0.0,
            v: 0.0,
            w: 0.0,
            rr: 0.0,
            hi: 0.0,
            lo: 0.0,
            mc: 0.0,
        }; SUN_MAX];
        for (k, sphere) in spheres.iter().enumerate() {
            let (d, r) = (sphere.center - e, sphere.radius);
            let rr = r * r;
            // |h2 − h²| ≤ 2√2 h δ + 2δ² + 3ε h² near h ≈ r (see `decide`); rounded up. For
            // |f|² − r² from the projections, t_m² adds 2 |t_m| δ + δ² with |t_m| ≲ r where its
            // sign is in doubt (farther, |f|² − r² is far from 0): twice the margin.
            let m = 3.0 * r * delta + 3.0 * delta * delta + 4.0 * f32::EPSILON * rr;
            s[k] = SunSphere {
                u: d.dot(eu),
                v: d.dot(ev),
                w: d.dot(l),
                rr,
                hi: rr + m,
                lo: rr - m,
                mc: 6.0 * r * delta + 6.0 * delta * delta + 10.0 * f32::EPSILON * rr,
            };
        }
        let finite = |x: f32| x.is_finite();
        let ok = finite(delta)
            && s.iter()
                .all(|k| finite(k.hi) && finite(k.mc) && finite(k.u));
        ok.then_some(Sun {
            l,
            eu,
            ev,
            e,
            delta,
            s,
        })
    }

    /// The light's direction.
    pub fn dir(&self) -> Vec3 {
        self.l
    }

    /// A shadow ray's origin `anchor + rel`, projected: once per ray.
    #[inline(always)]
    pub fn project(&self, anchor: Vec3, rel: Vec3) -> (f32, f32, f32) {
        let p = (anchor - self.e) + rel;
        (p.dot(self.eu), p.dot(self.ev), p.dot(self.l))
    }

    /// Whether sphere `j` blocks the ray from the projected origin `o`: `Some` where that is
    /// certain from the projections, `None` where the full test must decide.
    #[inline(always)]
    pub fn decide(&self, (u, v, w): (f32, f32, f32), j: usize) -> Option<bool> {
        let k = self.s.get(j)?;
        let (du, dv) = (u - k.u, v - k.v);
        let h2 = du * du + dv * dv;
        // The line passes outside the sphere: no hit, from outside or in.
        if h2 > k.hi {
            return Some(false);
        }
        if !(h2 < k.lo) {
            return None; // a graze, or NaN
        }
        // The line crosses the sphere, at t_m ± Δt with t_m = w_m − w_o and 0 < Δt ≤ r.
        let tm = k.w - w;
        if tm > self.delta {
            return Some(true); // the far root is ahead
        }
        if tm < -self.delta {
            // The centre is behind: blocked only from inside, |f|² = h² + t_m² below r².
            let c = (h2 + tm * tm) - k.rr;
            if c > k.mc {
                return Some(false);
            }
            if c < -k.mc {
                return Some(true);
            }
        }
        None
    }
}

/// [`shadow_loop`] for [`Sun`]: each ray projected once, then every sphere but the one it
/// leaves decided by [`Sun::decide`] or, where that cannot, by `fallback`.
#[inline(never)]
pub fn sun_loop(
    rays: &[(Vec3, Vec3, usize)],
    spheres: &[Sphere],
    sun: &Sun,
    fallback: impl Fn(Vec3, Vec3, &Sphere, Vec3) -> bool,
) -> f32 {
    let mut acc = 0.0;
    for &(o, _, from) in rays {
        let anchor = spheres[from].center;
        let rel = o - anchor;
        let p = sun.project(anchor, rel);
        for (j, s) in spheres.iter().enumerate() {
            if j != from {
                let blocked = match sun.decide(p, j) {
                    Some(b) => b,
                    None => fallback(anchor, rel, s, sun.dir()),
                };
                if blocked {
                    acc += 1.0;
                }
            }
        }
    }
    acc
}
