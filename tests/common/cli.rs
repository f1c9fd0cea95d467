//! Running the desktop renderer from tests (`tests/cli.rs`, `tests/animation.rs`).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

/// The renderer, built from the current source with this test's profile (and target, features
/// and environment), once per run. `cargo test` builds the examples too, but `cargo test --test
/// cli` does not, and whatever binary an earlier build left would be tested in its place.
pub fn renderer() -> PathBuf {
    static BUILT: OnceLock<PathBuf> = OnceLock::new();
    BUILT.get_or_init(build_renderer).clone()
}

fn build_renderer() -> PathBuf {
    // This test runs from <target dir>[/<triple>]/<profile dir>/deps/; cargo marks the target
    // dir with CACHEDIR.TAG.
    let exe = std::env::current_exe().unwrap();
    let profile_dir = exe.parent().and_then(Path::parent).unwrap();
    let target_dir = profile_dir
        .ancestors()
        .skip(1)
        .find(|d| d.join("CACHEDIR.TAG").is_file())
        .unwrap_or_else(|| panic!("no target dir above {}", profile_dir.display()));
    let profile = match profile_dir.file_name().and_then(|n| n.to_str()) {
        Some("debug") => "dev",
        Some(name) => name,
        None => panic!("{}: no profile", profile_dir.display()),
    };
    let mut cargo = Command::new(std::env::var_os("CARGO").unwrap_or("cargo".into()));
    cargo
        .args(["build", "--example", "render", "--features", "scene-file"])
        .args(["--profile", profile])
        .arg("--manifest-path")
        .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("Cargo.toml"))
        .arg("--target-dir")
        .arg(target_dir);
    let triple = profile_dir.parent().filter(|&d| d != target_dir);
    if let Some(triple) = triple.and_then(Path::file_name) {
        cargo.arg("--target").arg(triple);
    }
    let built = cargo.output().unwrap();
    assert!(
        built.status.success(),
        "building the renderer failed:\n{}",
        String::from_utf8_lossy(&built.stderr)
    );
    profile_dir
        .join("examples")
        .join(format!("render{}", std::env::consts::EXE_SUFFIX))
}

pub fn run(args: &[&str]) -> Output {
    Command::new(renderer()).args(args).output().unwrap()
}

pub fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("microray-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Fails with `code`, one line on stderr naming `needle`, no PNG created, an existing one kept.
pub fn fails(dir: &Path, args: &[&str], code: i32, needle: &str) {
    fails_as(dir, args, code, needle, run);
}

/// `fails`, with the renderer started by `start` (given the arguments with `-o`).
pub fn fails_as(
    dir: &Path,
    args: &[&str],
    code: i32,
    needle: &str,
    start: impl FnOnce(&[&str]) -> Output,
) {
    let out = dir.join("keep.png");
    std::fs::write(&out, b"precious").unwrap();
    let mut all: Vec<&str> = args.to_vec();
    all.extend(["-o", out.to_str().unwrap()]);
    let o = start(&all);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(code), "{args:?}: {err}");
    assert!(
        err.contains(needle),
        "{args:?}: {err:?} should mention {needle:?}"
    );
    assert!(
        !err.contains("panicked") && !err.contains("backtrace"),
        "{err}"
    );
    assert_eq!(
        std::fs::read(&out).unwrap(),
        b"precious",
        "{args:?} touched the existing file"
    );
    let others: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .filter(|n| n != "keep.png" && !n.to_string_lossy().ends_with(".toml"))
        .collect();
    assert!(others.is_empty(), "{args:?} left files behind: {others:?}");
}
