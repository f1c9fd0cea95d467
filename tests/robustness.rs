//! Malformed and extreme input never panics: scene files mutated at random (extreme, tiny,
//! non-finite, wrong-typed and out-of-range values in place of the test scenes' values) either
//! fail with an error or parse, and what parses renders every way (accelerated, brute force,
//! bands, `draw`, dithered: `fuzz_cases::check_frame`) to the same pixels, without a panic.
//! The render path promises errors, not panics; this pins that down for inputs nobody wrote
//! by hand.

mod common;
mod fuzz_cases;

use common::rng::Rng;
use fuzz_cases::{check_scene_text, Reached};

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
    rendered: u32,
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
            let value = if g.next().is_multiple_of(2) {
                token.to_string()
            } else {
                value.replacen(|c: char| c.is_ascii_digit(), token, 1)
            };
            lines[k] = format!("{key} {value}");
        }
        let text = lines.join("\n");
        let Ok(reached) = std::panic::catch_unwind(|| check_scene_text(&text)) else {
            panic!("case {case} panicked on:\n{text}");
        };
        match reached {
            Reached::Refused => out.rejected += 1,
            _ => out.rendered += 1,
        }
    }
    // Both ways out are taken often: the mutations reach the renderer, and the checks.
    assert!(out.rendered > 500, "{} rendered", out.rendered);
    assert!(out.rejected > 500, "{} rejected", out.rejected);
}
