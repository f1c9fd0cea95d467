//! The scene loader on any bytes: an error or a scene that renders every way to the same
//! pixels (`tests/fuzz_cases`), never a panic.
#![no_main]

#[path = "../../tests/fuzz_cases/mod.rs"]
mod fuzz_cases;

libfuzzer_sys::fuzz_target!(|bytes: &[u8]| {
    fuzz_cases::check_scene_bytes(bytes);
});
