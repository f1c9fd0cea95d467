//! The fuzz corpora replayed on the stable toolchain: every input libFuzzer kept in
//! `fuzz/corpus/` (each adds coverage) goes through the same checks as under `cargo fuzz`
//! (`fuzz_cases`), decoded the way `libfuzzer-sys` decodes it. A crash the fuzzer finds is
//! added to its corpus, and so becomes a regression test here.

mod fuzz_cases;

use arbitrary::{Arbitrary, Unstructured};
use fuzz_cases::{check_api, check_scene_bytes, ApiCase, Reached};
use std::path::PathBuf;

/// The corpus of `target`, sorted by name so that a failure names the same file every run.
fn corpus(target: &str) -> Vec<(PathBuf, Vec<u8>)> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("fuzz/corpus")
        .join(target);
    let entries = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e} (the corpora are in the repository)", dir.display()));
    let mut files: Vec<PathBuf> = entries.map(|e| e.unwrap().path()).collect();
    files.sort();
    let inputs: Vec<_> = files
        .into_iter()
        .map(|p| {
            let bytes = std::fs::read(&p).unwrap();
            (p, bytes)
        })
        .collect();
    assert!(
        inputs.len() >= 100,
        "{}: {} inputs",
        dir.display(),
        inputs.len()
    );
    inputs
}

/// Counts per outcome, to show the corpus reaches every one.
#[derive(Default, Debug)]
struct Outcomes {
    refused: u32,
    rendered: u32,
    lit: u32,
}

impl Outcomes {
    fn add(&mut self, r: Reached) {
        match r {
            Reached::Refused => self.refused += 1,
            Reached::Rendered => self.rendered += 1,
            Reached::RenderedLit => self.lit += 1,
        }
    }
}

fn replay(
    target: &str,
    input: &(PathBuf, Vec<u8>),
    check: impl FnOnce(&[u8]) -> Reached,
) -> Reached {
    let (path, bytes) = input;
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| check(bytes)))
        .unwrap_or_else(|_| panic!("{target}: {} panicked", path.display()))
}

#[test]
fn the_scene_file_corpus_replays() {
    let mut seen = Outcomes::default();
    for input in &corpus("scene_file") {
        seen.add(replay("scene_file", input, check_scene_bytes));
    }
    eprintln!("scene_file: {seen:?}");
    assert!(
        seen.lit >= 20 && seen.rendered >= 5 && seen.refused >= 100,
        "{seen:?}"
    );
}

#[test]
fn the_api_corpus_replays() {
    let inputs = corpus("api");
    let mut seen = Outcomes::default();
    let mut undecoded = 0;
    for input in &inputs {
        replay("api", input, |bytes| {
            // As `libfuzzer_sys::fuzz_target!` decodes an input for a typed target.
            if bytes.len() < ApiCase::size_hint(0).0 {
                undecoded += 1;
                return Reached::Refused;
            }
            match ApiCase::arbitrary_take_rest(Unstructured::new(bytes)) {
                Ok(case) => {
                    let (r, _) = check_api(&case);
                    seen.add(r);
                    r
                }
                Err(_) => {
                    undecoded += 1;
                    Reached::Refused
                }
            }
        });
    }
    eprintln!("api: {seen:?}, {undecoded} not decoded");
    assert!(
        undecoded * 10 < inputs.len(),
        "{undecoded} of {} not decoded",
        inputs.len()
    );
    assert!(
        seen.lit >= 50 && seen.rendered >= 5 && seen.refused >= 5,
        "{seen:?}"
    );
}
