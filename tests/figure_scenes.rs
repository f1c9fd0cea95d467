//! The figure scenes: `examples/scenes/ftb.toml` and `examples/scenes/tinyraytracer.toml` are the
//! scenes that the `figures` firmware builds in code (`examples/firmware/src/figure_scenes.rs`,
//! compiled here unchanged), value for value, and each file's frame has the CRC-32 committed
//! there, which the firmware checks on both boards (`examples/firmware/figures.sh`, which
//! `.ci/firmware.sh` runs).

#[path = "../examples/firmware/src/figure_scenes.rs"]
mod figure_scenes;
#[allow(dead_code)]
#[path = "../examples/firmware/src/scene.rs"]
mod scene;

use embedded_graphics::pixelcolor::{Rgb888, RgbColor};
use figure_scenes::{FigureScene, FIGURES, HEIGHT, LIGHTS, SPHERES, WIDTH};
use microray::scene_file::{self, SceneFile};
use microray::{Frame, FrameStorage};

fn load(k: usize) -> Box<SceneFile<SPHERES, LIGHTS>> {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/").to_owned() + FIGURES[k].file;
    scene_file::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

/// The CRC-32 the firmware computes (`scene::crc_rgb888`: bytes r, g, b per pixel, rows from
/// the top), here over the frame `Frame::render` writes.
fn crc_of_file(k: usize) -> u32 {
    let file = load(k);
    let mut storage = FrameStorage::new();
    let frame = Frame::new(&file.scene, &file.camera, file.options, &mut storage).unwrap();
    let mut pixels = vec![Rgb888::BLACK; (file.width * file.height) as usize];
    frame.render(&mut pixels).unwrap();
    let mut crc = scene::Crc32::new();
    for p in &pixels {
        crc.update(&[p.r(), p.g(), p.b()]);
    }
    crc.value()
}

#[test]
fn the_firmware_builds_the_files_scenes() {
    for (k, figure) in FIGURES.iter().enumerate() {
        let file = load(k);
        let mut scene = FigureScene::new();
        let camera = figure_scenes::build(k, &mut scene).unwrap();
        let name = figure.name;
        assert_eq!((file.width, file.height), (WIDTH, HEIGHT), "{name}");
        assert_eq!(file.camera, camera, "{name}: camera");
        assert_eq!(file.options, figure_scenes::options(), "{name}: options");
        let (a, b) = (&file.scene, &scene);
        assert_eq!(a.spheres(), b.spheres(), "{name}: spheres");
        assert_eq!(a.materials(), b.materials(), "{name}: materials");
        assert_eq!(a.lights(), b.lights(), "{name}: lights");
        assert_eq!(a.ambient(), b.ambient(), "{name}: ambient");
        assert_eq!(a.background(), b.background(), "{name}: background");
        assert_eq!(a.shadows(), b.shadows(), "{name}: shadows");
        assert_eq!(a.max_depth(), b.max_depth(), "{name}: max_depth");
    }
}

#[test]
fn host_crcs_match_the_committed_firmware_crcs() {
    let crcs: Vec<u32> = (0..FIGURES.len()).map(crc_of_file).collect();
    let differ: Vec<_> = FIGURES
        .iter()
        .zip(&crcs)
        .filter(|(f, &c)| f.crc32 != c)
        .map(|(f, c)| format!("{} 0x{c:08x}", f.name))
        .collect();
    assert!(differ.is_empty(), "host CRCs differ: {differ:?}");
}

/// The frame the firmware checksums (`Frame::draw` into the CRC display) is `Frame::render`'s.
#[test]
fn draw_gives_the_rendered_frame() {
    for (k, figure) in FIGURES.iter().enumerate() {
        let file = load(k);
        let mut storage = FrameStorage::new();
        let frame = Frame::new(&file.scene, &file.camera, file.options, &mut storage).unwrap();
        let (crc, pixels) = scene::crc_rgb888::<WIDTH, HEIGHT, SPHERES, LIGHTS>(&frame);
        assert_eq!(pixels, WIDTH * HEIGHT, "{}", figure.name);
        assert_eq!(crc, crc_of_file(k), "{}", figure.name);
    }
}
