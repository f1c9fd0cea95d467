//! The scene, built in code: the one `examples/firmware` renders under QEMU (a ground sphere,
//! four spheres, a point and a directional light, shadows), seen by a camera of this panel's
//! size. Scene, camera, frame tables and frame live in statics, not on the stack.

use microray::render::Small;
use microray::{
    Camera, Color, Error, Frame, FrameStorage, Light, Material, RenderOptions, Scene, Sphere, Vec3,
};

/// Sphere capacity: the ground and four spheres.
pub const SPHERES: usize = 5;
/// Light capacity: one point and one directional light.
pub const LIGHTS: usize = 2;

/// The frame drawn onto the panel.
pub type BoardFrame = Frame<'static, SPHERES, LIGHTS>;

/// Fills the empty `scene`.
fn build_scene(scene: &mut Scene<SPHERES, LIGHTS>) -> Result<(), Error> {
    let plastic = |r, g, b, shininess| Material {
        diffuse: Color::new(r, g, b),
        specular: Color::splat(0.4),
        shininess,
        ..Material::default()
    };
    scene.set_ambient(Color::splat(0.08))?;
    scene.set_background(Color::new(0.10, 0.14, 0.25))?;
    scene.set_shadows(true);
    let ground = Material {
        diffuse: Color::new(0.55, 0.55, 0.5),
        ..Material::default()
    };
    scene.add_sphere(Sphere::new(Vec3::new(0.0, -1000.0, 0.0), 1000.0), ground)?;
    scene.add_sphere(
        Sphere::new(Vec3::new(-1.6, 0.7, 0.0), 0.7),
        plastic(0.8, 0.15, 0.1, 32.0),
    )?;
    scene.add_sphere(
        Sphere::new(Vec3::new(0.1, 1.0, -1.2), 1.0),
        plastic(0.15, 0.7, 0.2, 64.0),
    )?;
    scene.add_sphere(
        Sphere::new(Vec3::new(1.5, 0.5, 0.6), 0.5),
        plastic(0.15, 0.3, 0.85, 16.0),
    )?;
    scene.add_sphere(
        Sphere::new(Vec3::new(0.3, 0.3, 1.4), 0.3),
        plastic(0.9, 0.8, 0.1, 8.0),
    )?;
    scene.add_light(Light::Point {
        position: Vec3::new(4.0, 6.0, 5.0),
        intensity: Color::splat(0.75),
    })?;
    scene.add_light(Light::Directional {
        direction: Vec3::new(-1.0, -2.0, -0.5),
        intensity: Color::new(0.35, 0.33, 0.3),
    })
}

/// Builds the frame of `width × height` pixels in statics. Call it once: a second call panics.
/// Nothing here fails with this scene; the panics only stand for "cannot happen".
pub fn frame(width: u32, height: u32) -> &'static BoardFrame {
    // `singleton!` gives each value a static of its own, handed out once, without `unsafe`.
    let scene = cortex_m::singleton!(: Scene<SPHERES, LIGHTS> = Scene::new()).unwrap();
    build_scene(scene).unwrap();
    let scene: &'static Scene<SPHERES, LIGHTS> = scene;
    let eye = Vec3::new(0.0, 1.6, 6.0);
    let look_at = Vec3::new(0.0, 0.7, 0.0);
    let up = Vec3::new(0.0, 1.0, 0.0);
    let camera = Camera::new(eye, look_at, up, 45.0, width, height).unwrap();
    let camera = cortex_m::singleton!(: Camera = camera).unwrap();
    // The layout of at most 8 spheres: no room for the tables only larger scenes use.
    let storage =
        cortex_m::singleton!(: FrameStorage<SPHERES, LIGHTS, Small> = FrameStorage::small())
            .unwrap();
    let frame = Frame::new(scene, camera, RenderOptions::default(), storage).unwrap();
    cortex_m::singleton!(: BoardFrame = frame).unwrap()
}
