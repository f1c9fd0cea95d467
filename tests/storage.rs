//! A frame's tables live in storage the caller provides: a frame at the desktop capacity
//! (`Scene<1024, 32>`) builds and renders on a thread with a small stack, and one storage serves
//! frame after frame.

use embedded_graphics::pixelcolor::Rgb888;
use microray::scene_file::{self, Desktop};
use microray::{Camera, Frame, FrameStorage};

fn render(file: &Desktop, camera: &Camera, storage: &mut FrameStorage<1024, 32>) -> Vec<Rgb888> {
    let frame = Frame::new(&file.scene, camera, file.options, storage).unwrap();
    let mut image = vec![Rgb888::new(0, 0, 0); (camera.width() * camera.height()) as usize];
    frame.render(&mut image).unwrap();
    image
}

fn load(path: &str) -> (Box<Desktop>, Camera) {
    let file = Box::new(scene_file::load(path).unwrap());
    let camera = file.view.camera(128, 96).unwrap();
    (file, camera)
}

/// The target scene (25 spheres, three lights, shadows) and 256 spheres (which build shadow
/// sweeps) render on a 64 KiB stack exactly as on the main thread.
#[test]
fn desktop_capacity_frame_renders_on_a_64_kib_stack() {
    for path in [
        "bench/scenes/target.toml",
        "bench/scenes/spread256_shadowed.toml",
    ] {
        let (file, camera) = load(path);
        let expected = render(&file, &camera, &mut Box::new(FrameStorage::new()));
        assert!(
            expected.iter().any(|&p| p != expected[0]),
            "{path}: a blank image proves nothing"
        );
        let mut storage = Box::new(FrameStorage::new());
        let small = std::thread::scope(|s| {
            std::thread::Builder::new()
                .stack_size(64 << 10)
                .spawn_scoped(s, || render(&file, &camera, &mut storage))
                .unwrap()
                .join()
                .unwrap()
        });
        assert!(
            small == expected,
            "{path}: the 64 KiB thread's image differs"
        );
    }
}

/// A storage that held another frame's tables (more spheres, other lights) gives the pixels of a
/// fresh one: `Frame::new` overwrites every table it reads.
#[test]
fn reused_storage_renders_as_fresh_storage() {
    let (big, big_camera) = load("bench/scenes/spread256_shadowed.toml");
    let (small, small_camera) = load("tests/data/lit.toml");
    let fresh = render(&small, &small_camera, &mut Box::new(FrameStorage::new()));
    let mut storage = Box::new(FrameStorage::new());
    render(&big, &big_camera, &mut storage);
    assert!(render(&small, &small_camera, &mut storage) == fresh);
    let again = render(&big, &big_camera, &mut Box::new(FrameStorage::new()));
    assert!(render(&big, &big_camera, &mut storage) == again);
}
