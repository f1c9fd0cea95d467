//! Malformed and extreme input never panics: scene files mutated at random (extreme, tiny,
//! non-finite, wrong-typed and out-of-range values in place of the test scenes' values) either
//! fail with an error or parse, and what parses is rendered, accelerated and brute force,
//! without a panic. The render path promises errors, not panics; this pins that down for
//! inputs nobody wrote by hand.

mod common;

use common::rng::Rng;
use embedded_graphics::pixelcolor::Rgb888;
use microray::scene_file::{parse, SceneFile};
use microray::Frame;

/// Values put in place of a field's value or of one digit of it.
const TOKENS: [&str; 20] = [
    "0",
    "-1",
    "1e38",
    "-1e38",
    "1e-45",
    "nan",
    "inf",
    "-inf",
    "1e30",
    "0.0",
    "3",
    "65536",
    "4294967295",
    "[]",
    "[0, 0]",
    "\"x\"",
    "true",
    "1e999",
    "1e-30",
    "-0.0",
];

/// What one mutated scene did: rejected, parsed but refused by the camera or frame, rendered.
#[derive(Default)]
struct Outcomes {
    rejected: u32,
    refused: u32,
    rendered: u32,
}

/// Parses `text` and, where it parses, renders a small frame of it both ways.
fn run(text: &str, out: &mut Outcomes) {
    let Ok(file) = parse::<64, 8>(text) else {
        out.rejected += 1;
        return;
    };
    let file: Box<SceneFile<64, 8>> = Box::new(file);
    let (w, h) = (file.width.min(24), file.height.min(16));
    let Ok(camera) = file.view.camera(w, h) else {
        out.refused += 1;
        return;
    };
    let mut storage = Box::new(microray::FrameStorage::new());
    let Ok(frame) = Frame::new(&file.scene, &camera, file.options, &mut storage) else {
        out.refused += 1;
        return;
    };
    let mut fast = vec![Rgb888::new(0, 0, 0); (w * h) as usize];
    let mut brute = fast.clone();
    assert!(frame.render_rows(0, &mut fast).is_ok());
    assert!(frame.render_rows_brute(0, &mut brute).is_ok());
    assert!(fast == brute, "accelerated and brute force differ:\n{text}");
    out.rendered += 1;
}

#[test]
fn mutated_scene_files_never_panic() {
    let mut seeds = vec![];
    for dir in ["tests/data", "tests/hard"] {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|x| x == "toml") {
                seeds.push(std::fs::read_to_string(path).unwrap());
            }
        }
    }
    seeds.sort();
    assert!(seeds.len() >= 20, "{} seed scenes", seeds.len());
    let mut g = Rng(0x5851_f42d_4c95_7f2d);
    let mut out = Outcomes::default();
    for case in 0..3000 {
        let base = &seeds[(g.next() % seeds.len() as u64) as usize];
        let mut lines: Vec<String> = base.lines().map(String::from).collect();
        for _ in 0..1 + g.next() % 3 {
            let k = (g.next() % lines.len() as u64) as usize;
            let Some(eq) = lines[k].find('=') else {
                continue;
            };
            let token = TOKENS[(g.next() % TOKENS.len() as u64) as usize];
            let (key, value) = lines[k].split_at(eq + 1);
            let value = if g.next() % 2 == 0 {
                token.to_string()
            } else {
                value.replacen(|c: char| c.is_ascii_digit(), token, 1)
            };
            lines[k] = format!("{key} {value}");
        }
        let text = lines.join("\n");
        let before = out.rejected + out.refused + out.rendered;
        let result =
            std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| run(&text, &mut out)));
        assert!(result.is_ok(), "case {case} panicked on:\n{text}");
        assert_eq!(out.rejected + out.refused + out.rendered, before + 1);
    }
    // Both ways out are taken often: the mutations reach the renderer, and the checks.
    assert!(out.rendered > 500, "{} rendered", out.rendered);
    assert!(out.rejected > 500, "{} rejected", out.rejected);
}
