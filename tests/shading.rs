//! The shading model: cosine law, lights behind the surface, the Blinn–Phong highlight,
//! shadows and mirror depth.

use microray::shading::shade_local;
use microray::{shade, trace, Color, Light, Material, Ray, Scene, Sphere, Vec3};

/// A unit sphere at the origin, seen from +z, lit by a directional light at `angle` degrees
/// from the normal at the point hit (0, 0, 1).
fn lit_at(angle_deg: f32, material: Material) -> (Scene<2, 1>, Ray) {
    let mut scene: Scene<2, 1> = Scene::new();
    scene
        .add_sphere(Sphere::new(Vec3::ZERO, 1.0), material)
        .unwrap();
    let a = angle_deg.to_radians();
    // direction is where the light travels: towards -l
    let l = Vec3::new(a.sin(), 0.0, a.cos());
    scene
        .add_light(Light::Directional {
            direction: -l,
            intensity: Color::ONE,
        })
        .unwrap();
    (
        scene,
        Ray::new(Vec3::new(0.0, 0.0, 5.0), Vec3::new(0.0, 0.0, -1.0)),
    )
}

fn white() -> Material {
    Material {
        diffuse: Color::ONE,
        ..Material::default()
    }
}

#[test]
fn lambert_follows_the_cosine_law() {
    for deg in [0.0f32, 30.0, 60.0, 80.0] {
        let (scene, ray) = lit_at(deg, white());
        let hit = scene.find_intersection(&ray, 0.0, 10.0).unwrap();
        let c = shade(&scene, &ray, &hit);
        let want = deg.to_radians().cos();
        assert!((c.x - want).abs() < 1e-6, "{deg}°: {} vs {want}", c.x);
        assert_eq!((c.x, c.x), (c.y, c.z));
    }
}

#[test]
fn no_light_from_behind_the_surface() {
    for deg in [90.0f32, 120.0, 180.0] {
        let (mut scene, ray) = lit_at(deg, white());
        scene.set_ambient(Color::splat(0.1)).unwrap();
        let hit = scene.find_intersection(&ray, 0.0, 10.0).unwrap();
        let c = shade(&scene, &ray, &hit);
        assert!(
            (c.x - 0.1).abs() < 1e-6,
            "{deg}°: only ambient expected, got {c:?}"
        );
    }
}

#[test]
fn highlight_peaks_at_the_mirror_configuration() {
    let shiny = Material {
        diffuse: Color::ZERO,
        specular: Color::ONE,
        shininess: 50.0,
        ..Material::default()
    };
    // Light from straight ahead: h = n, the highlight is at full strength.
    let (scene, ray) = lit_at(0.0, shiny);
    let hit = scene.find_intersection(&ray, 0.0, 10.0).unwrap();
    let peak = shade(&scene, &ray, &hit).x;
    assert!((peak - 1.0).abs() < 1e-6, "peak {peak}");
    // Off the mirror direction it falls off as (n·h)^s with h halfway between v and l.
    let (scene, ray) = lit_at(20.0, shiny);
    let hit = scene.find_intersection(&ray, 0.0, 10.0).unwrap();
    let off = shade(&scene, &ray, &hit).x;
    let want = 10f32.to_radians().cos().powf(50.0);
    assert!((off - want).abs() < 1e-5, "{off} vs {want}");
    assert!(off < peak);
}

#[test]
fn shadows_block_point_and_directional_lights() {
    for light in [
        Light::Point {
            position: Vec3::new(0.0, 10.0, 0.0),
            intensity: Color::ONE,
        },
        Light::Directional {
            direction: Vec3::new(0.0, -1.0, 0.0),
            intensity: Color::ONE,
        },
    ] {
        let mut scene: Scene<2, 1> = Scene::new();
        scene
            .add_sphere(Sphere::new(Vec3::ZERO, 1.0), white())
            .unwrap();
        scene
            .add_sphere(Sphere::new(Vec3::new(0.0, 3.0, 0.0), 0.5), white())
            .unwrap();
        scene.add_light(light).unwrap();
        // the top of the big sphere, seen from just above it
        let top = Ray::new(Vec3::new(0.0, 1.5, 0.0), Vec3::new(0.0, -1.0, 0.0));
        let h = scene.find_intersection(&top, 0.0, 10.0).unwrap();
        assert_eq!(h.sphere, 0);
        assert_eq!(
            shade(&scene, &top, &h),
            Color::ZERO,
            "{light:?}: the small sphere shadows the top"
        );
        assert!(
            shade_local(&scene, &h, top.dir, |_| false).x > 0.9,
            "unblocked it is lit"
        );
        scene.set_shadows(false);
        assert!(shade(&scene, &top, &h).x > 0.9, "{light:?}: shadows off");
    }
}

#[test]
fn a_point_light_between_the_spheres_is_not_blocked() {
    let mut scene: Scene<2, 1> = Scene::new();
    scene
        .add_sphere(Sphere::new(Vec3::ZERO, 1.0), white())
        .unwrap();
    scene
        .add_sphere(Sphere::new(Vec3::new(0.0, 4.0, 0.0), 0.5), white())
        .unwrap();
    // the blocker is beyond the light: 0 < t < distance excludes it
    scene
        .add_light(Light::Point {
            position: Vec3::new(0.0, 2.0, 0.0),
            intensity: Color::ONE,
        })
        .unwrap();
    let top = Ray::new(Vec3::new(0.0, 1.5, 0.0), Vec3::new(0.0, -1.0, 0.0));
    let h = scene.find_intersection(&top, 0.0, 10.0).unwrap();
    assert!((shade(&scene, &top, &h).x - 1.0).abs() < 1e-6);
}

/// Two facing mirrors with the eye between them: each bounce adds k_m^depth of the far wall's
/// ambient colour, so the colour counts the bounces.
#[test]
fn reflection_depth_is_respected() {
    let mut scene: Scene<2, 0> = Scene::new();
    scene.set_ambient(Color::ONE).unwrap();
    let m = Material {
        diffuse: Color::splat(0.1),
        mirror: Color::splat(0.5),
        ..Material::default()
    };
    scene
        .add_sphere(Sphere::new(Vec3::new(0.0, 0.0, -3.0), 1.0), m)
        .unwrap();
    scene
        .add_sphere(Sphere::new(Vec3::new(0.0, 0.0, 3.0), 1.0), m)
        .unwrap();
    let ray = Ray::new(Vec3::ZERO, Vec3::new(0.0, 0.0, -1.0));
    for depth in 0..=6u8 {
        scene.set_max_depth(depth).unwrap();
        let got = trace(&scene, &ray).x;
        let want: f32 = (0..=depth as i32).map(|k| 0.1 * 0.5f32.powi(k)).sum();
        assert!((got - want).abs() < 1e-6, "depth {depth}: {got} vs {want}");
    }
}

#[test]
fn a_mirror_ray_that_escapes_sees_the_background() {
    let mut scene: Scene<1, 0> = Scene::new();
    scene.set_background(Color::new(0.0, 0.0, 1.0)).unwrap();
    let m = Material {
        diffuse: Color::ZERO,
        mirror: Color::ONE,
        ..Material::default()
    };
    scene
        .add_sphere(Sphere::new(Vec3::new(0.0, 0.0, -3.0), 1.0), m)
        .unwrap();
    let c = trace(&scene, &Ray::new(Vec3::ZERO, Vec3::new(0.0, 0.0, -1.0)));
    assert_eq!(c, Color::new(0.0, 0.0, 1.0));
    scene.set_max_depth(0).unwrap();
    assert_eq!(
        trace(&scene, &Ray::new(Vec3::ZERO, Vec3::new(0.0, 0.0, -1.0))),
        Color::ZERO
    );
}

/// Inside a mirrored sphere a reflected ray must come back to the same sphere (its far side),
/// which the renderer finds analytically rather than by intersecting its own origin.
#[test]
fn mirror_inside_a_sphere_sees_its_far_wall() {
    let mut scene: Scene<1, 0> = Scene::new();
    scene.set_ambient(Color::ONE).unwrap();
    let m = Material {
        diffuse: Color::splat(0.2),
        mirror: Color::splat(0.5),
        ..Material::default()
    };
    scene.add_sphere(Sphere::new(Vec3::ZERO, 2.0), m).unwrap();
    scene.set_max_depth(1).unwrap();
    let c = trace(&scene, &Ray::new(Vec3::ZERO, Vec3::new(0.0, 0.0, -1.0)));
    assert!((c.x - (0.2 + 0.5 * 0.2)).abs() < 1e-6, "{c:?}");
}
