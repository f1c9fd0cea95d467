//! The refracted direction ([`microray::shading::refract`]) against Snell's law in f64, on the
//! same f32 inputs (the ray's direction and the hit's normal): near the critical angle, at
//! grazing incidence, and for an index of 1.

mod common;

use common::reference::{dot, norm, refracted, V};
use microray::shading::{find_from, reflect, refract};
use microray::{Color, Hit, Material, Ray, Scene, Sphere, Vec3};

const EPS: f64 = f32::EPSILON as f64;

fn v(p: Vec3) -> V {
    [p.x as f64, p.y as f64, p.z as f64]
}

fn glass(ior: f32) -> Scene<1, 0> {
    let mut scene = Scene::new();
    let m = Material {
        refraction: Color::ONE,
        ior,
        ..Material::default()
    };
    scene
        .add_sphere(Sphere::new(Vec3::new(0.25, -0.5, 0.125), 1.0), m)
        .unwrap();
    scene
}

/// The ray that meets the unit sphere of `glass` at the top of its centre, at `theta` from the
/// normal: from inside (`inside`) or from outside; with its hit.
fn at_angle(scene: &Scene<1, 0>, theta: f64, inside: bool) -> (Ray, Hit) {
    let c = scene.spheres()[0].center;
    let top = [c.x as f64, c.y as f64 + 1.0, c.z as f64];
    let (s, k) = (theta.sin(), theta.cos());
    // Inside: heading up and out; outside: heading down and in.
    let d = if inside { [s, k, 0.0] } else { [s, -k, 0.0] };
    let o = [
        top[0] - 0.5 * d[0],
        top[1] - 0.5 * d[1],
        top[2] - 0.5 * d[2],
    ];
    let ray = Ray::new(
        Vec3::new(o[0] as f32, o[1] as f32, o[2] as f32),
        Vec3::new(d[0] as f32, d[1] as f32, d[2] as f32),
    );
    let hit = scene.find_intersection(&ray, 0.0, 10.0).unwrap();
    (ray, hit)
}

/// `refract`'s direction, unit, and the angle between it and f64's from the same f32 inputs;
/// whether each totally reflects; f64's `k = 1 − η²(1 − cos²)`.
fn compare(ray: &Ray, hit: &Hit, ior: f32) -> (f64, bool, bool, f64) {
    let got = norm(v(refract(ray, hit, ior).dir));
    let (d, n) = (norm(v(ray.dir)), v(hit.normal));
    let entering = dot(n, v(hit.offset)) > 0.0;
    let eta = if entering {
        1.0 / ior as f64
    } else {
        ior as f64
    };
    let cos_i = -dot(d, n);
    let k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
    let want = norm(refracted(v(ray.dir), n, entering, ior as f64));
    let angle = (1.0 - dot(got, want).min(1.0)).max(0.0).sqrt() * std::f64::consts::SQRT_2;
    let tir_got = refract(ray, hit, ior) == reflect(ray, hit);
    (angle, tir_got, k < 0.0, k)
}

/// Within 10⁻⁶ of the critical angle, on both sides: total reflection exactly where Snell's law
/// puts it, and the direction off by what an error of a few ε in `cos_i` makes of `√k` there
/// (`refract`'s documentation), never more.
#[test]
fn near_the_critical_angle() {
    for ior in [1.5f32, 1.33, 2.4] {
        let scene = glass(ior);
        let critical = (1.0 / ior as f64).asin();
        for delta in [
            -1e-3, -1e-4, -1e-5, -3e-6, -1e-6, 1e-6, 3e-6, 1e-5, 1e-4, 1e-3,
        ] {
            let (ray, hit) = at_angle(&scene, critical + delta, true);
            let (angle, tir, tir64, k) = compare(&ray, &hit, ior);
            assert_eq!(tir, delta > 0.0, "ior {ior}, critical angle {delta:+e}");
            assert_eq!(tir, tir64, "ior {ior}, critical angle {delta:+e}");
            if !tir {
                let bound = 8.0 * EPS / k.sqrt() + 8.0 * EPS;
                assert!(
                    angle <= bound,
                    "ior {ior}, {delta:+e}: off by {angle:e} rad, more than {bound:e}"
                );
            }
        }
    }
}

/// Away from the critical angle the direction is as good as its inputs: a few ε.
#[test]
fn at_ordinary_angles() {
    for ior in [1.5f32, 1.0001, 0.75, 2.4] {
        let scene = glass(ior);
        for deg in [0.0f64, 1.0, 10.0, 30.0, 45.0, 60.0, 80.0, 89.0] {
            for inside in [false, true] {
                let (ray, hit) = at_angle(&scene, deg.to_radians(), inside);
                let (angle, tir, tir64, k) = compare(&ray, &hit, ior);
                assert_eq!(tir, tir64, "ior {ior}, {deg}°, inside {inside}");
                if !tir && k > 1e-2 {
                    assert!(angle <= 16.0 * EPS, "ior {ior}, {deg}°: off by {angle:e}");
                }
            }
        }
    }
}

/// An index near 1 bends rays by little, at every angle up to grazing, where `k` is nearly
/// `ior² − 1` (scaled): that difference is not lost to rounding. The inputs are clean (the
/// normal is nearly an axis), so `cos_i` is good to ε of itself; the bound is that error
/// (`2 cos_i δ` in `k`) and ε of `ior² − 1`, over `√k`, plus 2 ε. `ior²` rounded before the
/// difference would be off by up to ε/2 of `ior²`, 10 to 100 times the bound at grazing angles
/// for some of these indices.
#[test]
fn index_near_one() {
    let mut near = vec![0.9999f32, 1.0 - 1.0 / 1048576.0, 1.01];
    // 1 + 2⁻¹² and neighbours: squares that round by up to half an ulp.
    near.extend((0..16).map(|j| 1.0 + 1.0 / 4096.0 + j as f32 * f32::EPSILON));
    for ior in near {
        let scene = glass(ior);
        for deg in [0.0f64, 45.0, 80.0, 89.0, 89.9, 89.99] {
            for inside in [false, true] {
                let (ray, hit) = at_angle(&scene, deg.to_radians(), inside);
                let (angle, tir, tir64, k) = compare(&ray, &hit, ior);
                assert_eq!(tir, tir64, "ior {ior}, {deg}°, inside {inside}");
                let cos_i = -dot(norm(v(ray.dir)), v(hit.normal));
                let i2 = (ior as f64 * ior as f64 - 1.0).abs();
                if !tir && k > 64.0 * EPS {
                    let bound = (2.0 * EPS * cos_i + 2.0 * EPS * i2) / k.sqrt() + 2.0 * EPS;
                    assert!(
                        angle <= bound,
                        "ior {ior}, {deg}°, {inside}: off by {angle:e}"
                    );
                }
            }
        }
    }
}

/// An index of 1 bends nothing: the refracted direction is the ray's, normalised, exactly.
#[test]
fn index_one_goes_straight_on() {
    let scene = glass(1.0);
    for deg in [0.0f64, 20.0, 60.0, 89.0, 89.999] {
        for inside in [false, true] {
            let (ray, hit) = at_angle(&scene, deg.to_radians(), inside);
            let dir = refract(&ray, &hit, 1.0).dir;
            assert_eq!(dir, ray.dir.normalize_fast(), "{deg}°, inside {inside}");
        }
    }
}

/// Entering at grazing incidence (10⁻⁵ to 10⁻² rad from the tangent), the ray bends to just
/// inside the critical angle, crosses the sphere and meets the far wall at the angle at which
/// it entered, where `k = sin²(gap)`. Each step is checked: the refracted direction, the exit on
/// the sphere, and the way out: as f64 decides it where `k` is above its f32 error (about 20 ε,
/// from an error of a few ε in `cos_i`), and otherwise out along the wall or reflected back in,
/// which no f32 tracer can tell apart.
#[test]
fn grazing_in_and_out() {
    let ior = 1.5f32;
    let scene = glass(ior);
    let r = scene.spheres()[0].radius;
    for gap in [1e-2f64, 1e-3, 1e-4, 1e-5] {
        let (ray, hit) = at_angle(&scene, std::f64::consts::FRAC_PI_2 - gap, false);
        let (angle, tir, _, _) = compare(&ray, &hit, ior);
        assert!(
            !tir && angle <= 16.0 * EPS,
            "gap {gap:e}: entering off by {angle:e}"
        );
        let inside = refract(&ray, &hit, ior);
        let exit = find_from(&scene, &inside, &hit).expect("the ray leaves the sphere");
        assert_eq!(exit.sphere, 0);
        let off = v(exit.offset);
        let radial = dot(off, off).sqrt() - r as f64;
        assert!(
            radial.abs() <= 4.0 * EPS,
            "gap {gap:e}: exit {radial:e} off the surface"
        );
        // Seen from inside, the exit's angle equals the entry's refracted angle.
        let (cos_in, cos_out) = (
            -dot(norm(v(inside.dir)), v(hit.normal)),
            -dot(norm(v(inside.dir)), v(exit.normal)),
        );
        assert!((cos_in - cos_out).abs() <= 1e-6, "{cos_in} {cos_out}");
        let (angle, tir, tir64, k) = compare(&inside, &exit, ior);
        if k.abs() > 64.0 * EPS {
            assert_eq!(tir, tir64, "gap {gap:e}");
            let bound = 8.0 * EPS / k.sqrt() + 8.0 * EPS;
            assert!(
                tir || angle <= bound,
                "gap {gap:e}: leaving off by {angle:e}"
            );
        } else if !tir {
            // Out along the wall: in the tangent plane, to within what √k's error allows.
            let out = norm(v(refract(&inside, &exit, ior).dir));
            let along = dot(out, v(exit.normal));
            assert!(along.abs() <= (64.0 * EPS).sqrt(), "gap {gap:e}: {along}");
        }
    }
}
