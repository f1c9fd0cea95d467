//! Most test targets read scene files, which takes the `scene-file` feature. In this repository
//! the crate's dev-dependency on itself turns it on; a published package has no such line, and
//! there cargo leaves those targets out without a word (their `required-features`). This target
//! says so in the test output instead.

#[cfg(not(feature = "scene-file"))]
#[test]
#[ignore = "the test targets that read scene files were skipped: `cargo test --features scene-file` runs them"]
fn the_scene_file_tests_need_the_feature() {}
