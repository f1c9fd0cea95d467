//! A frame's tables live in storage the caller provides: a frame builds and renders on a thread
//! with a small stack, a fraction of its tables, at 1024 spheres (`Scene<1024, 32>`) and at the
//! desktop capacity (`Scene<16384, 32>`), one storage serves frame after frame, and the `Small`
//! layout of at most 8 spheres renders as the others do.

use embedded_graphics::pixelcolor::Rgb888;
use microray::render::Heap;
use microray::scene_file::{self, Desktop, SceneFile};
use microray::{Camera, Frame, FrameStorage};

fn render<const S: usize>(
    file: &SceneFile<S, { scene_file::LIGHTS }>,
    camera: &Camera,
    storage: &mut FrameStorage<S, { scene_file::LIGHTS }, Heap>,
) -> Vec<Rgb888> {
    let frame = Frame::new(&file.scene, camera, file.options, storage).unwrap();
    let mut image = vec![Rgb888::new(0, 0, 0); (camera.width() * camera.height()) as usize];
    frame.render(&mut image).unwrap();
    image
}

/// The small stack of a frame at `Scene<1024, 32>`: 64 KiB, or 256 KiB unoptimised (whose
/// frames are larger); it needs about 31 KiB (111 KiB unoptimised). Either is a fraction of the
/// storage's 0.97 MB, which so cannot be on it.
const SMALL_STACK: usize = if cfg!(debug_assertions) {
    256 << 10
} else {
    64 << 10
};

/// The stack of a frame at the desktop capacity (`Scene<16384, 32>`): 256 KiB, or 512 KiB
/// unoptimised. The per-row candidate lists are sized by the capacity, about 8.75 bytes a
/// sphere on hosts (`Cull`'s three lists of two-byte sphere ids and `Found`'s one, 140 KiB
/// at 16384 spheres), so a frame needs about 147 KiB of stack (366 KiB unoptimised): more than
/// [`SMALL_STACK`], and still a fraction of the storage's 15.4 MB.
const DESKTOP_STACK: usize = if cfg!(debug_assertions) {
    512 << 10
} else {
    256 << 10
};

/// Storage on the heap, each table in a box of its own: `on_heap` puts no storage-sized value
/// on the stack, even unoptimised (`Box::new(FrameStorage::new())` would, 15.4 MB at the
/// desktop capacity).
fn storage<const S: usize>() -> FrameStorage<S, { scene_file::LIGHTS }, Heap> {
    FrameStorage::on_heap()
}

fn desktop_storage() -> FrameStorage<{ scene_file::SPHERES }, { scene_file::LIGHTS }, Heap> {
    storage()
}

fn load<const S: usize>(path: &str) -> (Box<SceneFile<S, { scene_file::LIGHTS }>>, Camera) {
    let file = scene_file::load(path).unwrap();
    let camera = file.view.camera(128, 96).unwrap();
    (file, camera)
}

/// The target scene (25 spheres, three lights, shadows), 256 spheres (which build shadow
/// sweeps) and 1024 mirrors (which build the hierarchy of secondary rays), at capacity `S`,
/// render on a thread with a `stack`-byte stack exactly as on the main thread.
fn renders_on_a_stack_of<const S: usize>(stack: usize) {
    for path in [
        "bench/scenes/target.toml",
        "bench/scenes/spread256_shadowed.toml",
        "bench/scenes/mirrors1024.toml",
    ] {
        let (file, camera) = load::<S>(path);
        let expected = render(&file, &camera, &mut storage());
        assert!(
            expected.iter().any(|&p| p != expected[0]),
            "{path}: a blank image proves nothing"
        );
        let mut storage = storage();
        let small = std::thread::scope(|s| {
            std::thread::Builder::new()
                .stack_size(stack)
                .spawn_scoped(s, || render(&file, &camera, &mut storage))
                .unwrap()
                .join()
                .unwrap()
        });
        assert!(small == expected, "{path}: the small stack's image differs");
    }
}

/// A frame at `Scene<1024, 32>` builds and renders on [`SMALL_STACK`].
#[test]
fn frame_of_1024_spheres_renders_on_a_small_stack() {
    renders_on_a_stack_of::<1024>(SMALL_STACK);
}

/// A frame at the desktop capacity builds and renders on [`DESKTOP_STACK`].
#[test]
fn desktop_capacity_frame_renders_on_a_stated_stack() {
    assert_eq!(
        scene_file::SPHERES,
        16384,
        "DESKTOP_STACK is measured there"
    );
    renders_on_a_stack_of::<{ scene_file::SPHERES }>(DESKTOP_STACK);
}

/// A storage that held another frame's tables (more spheres, other lights) gives the pixels of a
/// fresh one: `Frame::new` overwrites every table it reads.
#[test]
fn reused_storage_renders_as_fresh_storage() {
    let (big, big_camera): (Box<Desktop>, _) = load("bench/scenes/spread256_shadowed.toml");
    let (small, small_camera): (Box<Desktop>, _) = load("tests/data/lit.toml");
    let fresh = render(&small, &small_camera, &mut desktop_storage());
    let mut storage = desktop_storage();
    render(&big, &big_camera, &mut storage);
    assert!(render(&small, &small_camera, &mut storage) == fresh);
    let again = render(&big, &big_camera, &mut desktop_storage());
    assert!(render(&big, &big_camera, &mut storage) == again);
}

/// A scene read at the desktop capacity and copied into `Scene<1024, 32>` (as the desktop
/// renderer renders a small scene) is the scene read at 1024, bit for bit, directional lights
/// included (adding them again would normalise their directions twice), and renders its
/// pixels; a copy that does not fit is an error that leaves the scene as it was.
#[test]
fn a_scene_copied_to_another_capacity_is_the_same_scene() {
    let path = "bench/scenes/spread256_shaded.toml";
    let (read, camera): (Box<SceneFile<1024, { scene_file::LIGHTS }>>, _) = load(path);
    let (desktop, _): (Box<Desktop>, _) = load(path);
    let mut copy: Box<microray::Scene<1024, { scene_file::LIGHTS }>> =
        Box::new(microray::Scene::new());
    copy.copy_from(&desktop.scene).unwrap();
    assert_eq!(format!("{copy:?}"), format!("{:?}", read.scene));
    let mut tables = storage();
    let frame = Frame::new(&copy, &camera, read.options, &mut tables).unwrap();
    let mut image = vec![Rgb888::new(0, 0, 0); (camera.width() * camera.height()) as usize];
    frame.render(&mut image).unwrap();
    assert!(image == render(&read, &camera, &mut storage()));

    let mut few: microray::Scene<8, 1> = microray::Scene::new();
    let ball = microray::Sphere::new(microray::Vec3::ZERO, 1.0);
    few.add_sphere(ball, microray::Material::default()).unwrap();
    let before = format!("{few:?}");
    assert_eq!(
        few.copy_from(&read.scene),
        Err(microray::Error::TooManySpheres)
    );
    assert_eq!(format!("{few:?}"), before);
    let mut dark: microray::Scene<300, 1> = microray::Scene::new();
    assert_eq!(
        dark.copy_from(&read.scene),
        Err(microray::Error::TooManyLights)
    );
    assert!(dark.spheres().is_empty());
}

/// A [`Small`] storage, which holds no sweeps and no hierarchy, renders every test scene of at
/// most 8 spheres (shadows, mirrors, glass, supersampling, one storage for all of them in turn)
/// exactly as an [`Inline`] storage of that capacity does and as the desktop capacity does,
/// whose frames build both; and it takes less than half the memory.
#[test]
fn small_storage_renders_as_inline_storage() {
    use microray::render::{Inline, Small};
    type Few = microray::Scene<8, { scene_file::LIGHTS }>;
    let mut small: FrameStorage<8, { scene_file::LIGHTS }, Small> = FrameStorage::small();
    let mut inline: Box<FrameStorage<8, { scene_file::LIGHTS }, Inline>> =
        Box::new(FrameStorage::new());
    for name in [
        "flat",
        "glass",
        "glass_inside",
        "glass_mirror",
        "lit",
        "mirror",
        "room",
        "supersampled_srgb",
        "tilted",
    ] {
        let path = format!("tests/data/{name}.toml");
        let (file, camera): (Box<Desktop>, _) = load(&path);
        let desktop = render(&file, &camera, &mut desktop_storage());
        assert!(
            desktop.iter().any(|&p| p != desktop[0]),
            "{name}: a blank image proves nothing"
        );
        let mut few: Box<Few> = Box::new(microray::Scene::new());
        few.copy_from(&file.scene).unwrap();
        let image = |frame: Frame<'_, 8, { scene_file::LIGHTS }>| {
            let mut image = vec![Rgb888::new(0, 0, 0); desktop.len()];
            frame.render(&mut image).unwrap();
            image
        };
        let from_small = image(Frame::new(&few, &camera, file.options, &mut small).unwrap());
        let from_inline = image(Frame::new(&few, &camera, file.options, &mut *inline).unwrap());
        assert!(
            from_small == from_inline,
            "{name}: Small differs from Inline"
        );
        assert!(
            from_small == desktop,
            "{name}: Small differs from the desktop capacity"
        );
    }
    let (small, inline) = (size_of_val(&small), size_of_val(&*inline));
    assert!(2 * small < inline, "{small} bytes against {inline}");
}
