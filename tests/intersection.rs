//! The basic intersection queries: `ray_intersect` and `find_intersection`.

use microray::{ray_intersect, Material, Ray, Scene, Sphere, Vec3};

const INF: f32 = f32::INFINITY;

fn unit_at(z: f32) -> Sphere {
    Sphere::new(Vec3::new(0.0, 0.0, z), 1.0)
}

fn down_z() -> Ray {
    Ray::new(Vec3::ZERO, Vec3::new(0.0, 0.0, -1.0))
}

#[test]
fn both_roots_through_the_interval() {
    let s = unit_at(-5.0);
    assert_eq!(ray_intersect(&down_z(), &s, 0.0, INF), Some(4.0));
    assert_eq!(
        ray_intersect(&down_z(), &s, 4.0, INF),
        Some(4.0),
        "tmin is inclusive"
    );
    assert_eq!(
        ray_intersect(&down_z(), &s, 4.001, INF),
        Some(6.0),
        "far root when near is cut"
    );
    assert_eq!(ray_intersect(&down_z(), &s, 0.0, 6.0), Some(4.0));
    assert_eq!(
        ray_intersect(&down_z(), &s, 4.5, 6.0),
        Some(6.0),
        "tmax is inclusive"
    );
    assert_eq!(
        ray_intersect(&down_z(), &s, 4.5, 5.9),
        None,
        "both roots outside"
    );
    assert_eq!(ray_intersect(&down_z(), &s, 0.0, 3.9), None);
    assert_eq!(ray_intersect(&down_z(), &s, 6.1, INF), None);
}

#[test]
fn origin_inside_gives_the_exit() {
    let s = Sphere::new(Vec3::ZERO, 2.0);
    assert_eq!(ray_intersect(&down_z(), &s, 0.0, INF), Some(2.0));
    // the root behind the origin (t = -2) is not taken when tmin = 0
    assert_eq!(ray_intersect(&down_z(), &s, -10.0, INF), Some(-2.0));
}

#[test]
fn tangent_and_miss() {
    let s = unit_at(-5.0);
    let tangent = Ray::new(Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 0.0, -1.0));
    assert_eq!(ray_intersect(&tangent, &s, 0.0, INF), Some(5.0));
    let beside = Ray::new(Vec3::new(1.0001, 0.0, 0.0), Vec3::new(0.0, 0.0, -1.0));
    assert_eq!(ray_intersect(&beside, &s, 0.0, INF), None);
    let away = Ray::new(Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0));
    assert_eq!(ray_intersect(&away, &s, 0.0, INF), None);
}

#[test]
fn sphere_behind_the_origin_is_not_hit() {
    let s = unit_at(5.0);
    assert_eq!(ray_intersect(&down_z(), &s, 0.0, INF), None);
    assert_eq!(
        ray_intersect(&down_z(), &s, -INF, INF),
        Some(-6.0),
        "but its roots exist"
    );
}

#[test]
fn direction_need_not_be_unit() {
    let s = unit_at(-5.0);
    for scale in [1e-3f32, 0.5, 2.0, 1e3] {
        let ray = Ray::new(Vec3::ZERO, Vec3::new(0.0, 0.0, -scale));
        let t = ray_intersect(&ray, &s, 0.0, INF).unwrap();
        assert!(
            (t * scale - 4.0).abs() <= 4.0 * f32::EPSILON * 4.0,
            "scale {scale}: t = {t}"
        );
    }
}

#[test]
fn nan_and_inf_are_never_hits() {
    let s = unit_at(-5.0);
    for d in [
        Vec3::new(f32::NAN, 0.0, -1.0),
        Vec3::new(0.0, 0.0, -INF),
        Vec3::ZERO,
    ] {
        assert_eq!(
            ray_intersect(&Ray::new(Vec3::ZERO, d), &s, 0.0, INF),
            None,
            "{d:?}"
        );
    }
}

#[test]
fn find_intersection_takes_the_closest() {
    let mut scene: Scene<3, 0> = Scene::new();
    scene
        .add_sphere(unit_at(-9.0), Material::default())
        .unwrap();
    scene
        .add_sphere(unit_at(-5.0), Material::default())
        .unwrap();
    scene
        .add_sphere(
            Sphere::new(Vec3::new(0.0, 0.0, -7.0), 0.5),
            Material::default(),
        )
        .unwrap();
    let hit = scene.find_intersection(&down_z(), 0.0, INF).unwrap();
    assert_eq!((hit.sphere, hit.t), (1, 4.0));
    assert_eq!(hit.point(), Vec3::new(0.0, 0.0, -4.0));
    assert_eq!(hit.normal, Vec3::new(0.0, 0.0, 1.0));
    let hit = scene.find_intersection(&down_z(), 6.1, INF).unwrap();
    assert_eq!((hit.sphere, hit.t), (2, 6.5));
    assert!(scene.find_intersection(&down_z(), 0.0, 3.0).is_none());
}

#[test]
fn normal_faces_the_viewer_from_inside() {
    let mut scene: Scene<1, 0> = Scene::new();
    scene
        .add_sphere(Sphere::new(Vec3::ZERO, 2.0), Material::default())
        .unwrap();
    let hit = scene.find_intersection(&down_z(), 0.0, INF).unwrap();
    assert_eq!(
        hit.normal,
        Vec3::new(0.0, 0.0, 1.0),
        "outward normal is (0,0,-1); seen from inside it flips"
    );
}
