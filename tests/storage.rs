//! A frame's tables live in storage the caller provides: a frame at the desktop capacity
//! (`Scene<1024, 32>`) builds and renders on a thread with a small stack, and one storage serves
//! frame after frame.

use embedded_graphics::pixelcolor::Rgb888;
use microray::render::Heap;
use microray::scene_file::{self, Desktop};
use microray::{Camera, Frame, FrameStorage};

fn render(
    file: &Desktop,
    camera: &Camera,
    storage: &mut FrameStorage<{ scene_file::SPHERES }, { scene_file::LIGHTS }, Heap>,
) -> Vec<Rgb888> {
    let frame = Frame::new(&file.scene, camera, file.options, storage).unwrap();
    let mut image = vec![Rgb888::new(0, 0, 0); (camera.width() * camera.height()) as usize];
    frame.render(&mut image).unwrap();
    image
}

/// Storage at the desktop capacity (0.78 MB). Built here, in one place: an unoptimised build
/// gives every `Box::new(FrameStorage::new())` a stack slot of its own in the function that
/// writes it, and three of them overflow a test thread's 2 MiB.
/// The small stack: 64 KiB, or 256 KiB unoptimised (whose frames are larger). Either is a
/// fraction of the storage's 0.78 MB, which so cannot be on it.
const SMALL_STACK: usize = if cfg!(debug_assertions) {
    256 << 10
} else {
    64 << 10
};

fn desktop_storage() -> FrameStorage<{ scene_file::SPHERES }, { scene_file::LIGHTS }, Heap> {
    FrameStorage::on_heap()
}

fn load(path: &str) -> (Box<Desktop>, Camera) {
    let file = scene_file::load(path).unwrap();
    let camera = file.view.camera(128, 96).unwrap();
    (file, camera)
}

/// The target scene (25 spheres, three lights, shadows) and 256 spheres (which build shadow
/// sweeps) render on a small stack exactly as on the main thread.
#[test]
fn desktop_capacity_frame_renders_on_a_small_stack() {
    for path in [
        "bench/scenes/target.toml",
        "bench/scenes/spread256_shadowed.toml",
    ] {
        let (file, camera) = load(path);
        let expected = render(&file, &camera, &mut desktop_storage());
        assert!(
            expected.iter().any(|&p| p != expected[0]),
            "{path}: a blank image proves nothing"
        );
        let mut storage = desktop_storage();
        let small = std::thread::scope(|s| {
            std::thread::Builder::new()
                .stack_size(SMALL_STACK)
                .spawn_scoped(s, || render(&file, &camera, &mut storage))
                .unwrap()
                .join()
                .unwrap()
        });
        assert!(small == expected, "{path}: the small stack's image differs");
    }
}

/// A storage that held another frame's tables (more spheres, other lights) gives the pixels of a
/// fresh one: `Frame::new` overwrites every table it reads.
#[test]
fn reused_storage_renders_as_fresh_storage() {
    let (big, big_camera) = load("bench/scenes/spread256_shadowed.toml");
    let (small, small_camera) = load("tests/data/lit.toml");
    let fresh = render(&small, &small_camera, &mut desktop_storage());
    let mut storage = desktop_storage();
    render(&big, &big_camera, &mut storage);
    assert!(render(&small, &small_camera, &mut storage) == fresh);
    let again = render(&big, &big_camera, &mut desktop_storage());
    assert!(render(&big, &big_camera, &mut storage) == again);
}
