//! Most test targets read scene files, which takes the `scene-file` feature. In this repository
//! the crate's dev-dependency on itself turns it on; a published package has no such line, and
//! there cargo leaves those targets out without a word (their `required-features`). This target
//! says so in the test output instead. It also checks, with `defmt`, what that feature adds.

#[cfg(not(feature = "scene-file"))]
#[test]
#[ignore = "the test targets that read scene files were skipped: `cargo test --features scene-file` runs them"]
fn the_scene_file_tests_need_the_feature() {}

/// With `defmt`, firmware can log the error and the small public types: each is
/// `defmt::Format` (a missing one fails this target's build).
#[cfg(feature = "defmt")]
#[test]
fn the_small_types_are_defmt_format() {
    fn format<T: defmt::Format>() {}
    format::<microray::Error>();
    format::<microray::Vec3>();
    format::<microray::Color>();
    format::<microray::Sphere>();
    format::<microray::Ray>();
    format::<microray::Prepared>();
    format::<microray::Material>();
    format::<microray::Light>();
    format::<microray::Hit>();
    format::<microray::Camera>();
    format::<microray::RenderOptions>();
    format::<microray::Encoding>();
    format::<microray::raster::PixelBox>();
    format::<microray::output::Progress>();
}
