//! The conformance scenes: microray's f32 images against an independent double-precision
//! implementation of the model (checked against POV-Ray), as tests/data/README.md describes.

mod common;

/// At least 99.9% of pixels within 1 level per channel, at most 0.05% off by more than 8.
fn conforms(name: &str) {
    let got = common::render_file(&format!("tests/data/{name}.toml"));
    let want = common::read_png(&format!("tests/data/{name}.png"));
    let d = common::diff(&got, &want);
    let n = d.total as f64;
    println!("{name}: {d:?}");
    assert!(
        d.over1 as f64 <= 0.001 * n,
        "{name}: {} of {} pixels off by more than 1 ({d:?})",
        d.over1,
        d.total
    );
    assert!(
        d.over8 as f64 <= 0.0005 * n,
        "{name}: {} of {} pixels off by more than 8 ({d:?})",
        d.over8,
        d.total
    );
}

#[test]
fn flat() {
    conforms("flat");
}

#[test]
fn lit() {
    conforms("lit");
}

#[test]
fn mirror() {
    conforms("mirror");
}

#[test]
fn room() {
    conforms("room");
}

#[test]
fn supersampled_srgb() {
    conforms("supersampled_srgb");
}

#[test]
fn tilted() {
    conforms("tilted");
}

#[test]
fn glass() {
    conforms("glass");
}

#[test]
fn glass_inside() {
    conforms("glass_inside");
}

#[test]
fn glass_mirror() {
    conforms("glass_mirror");
}

/// The comparison itself must be able to fail: a visibly wrong render is rejected.
#[test]
fn a_wrong_image_fails() {
    let mut file = microray::scene_file::load::<
        { microray::scene_file::SPHERES },
        { microray::scene_file::LIGHTS },
    >("tests/data/lit.toml")
    .unwrap();
    file.scene.set_shadows(false);
    let got = common::render(&file);
    let want = common::read_png("tests/data/lit.png");
    let d = common::diff(&got, &want);
    assert!(
        d.over8 as f64 > 0.0005 * d.total as f64,
        "turning shadows off went unnoticed: {d:?}"
    );
}
