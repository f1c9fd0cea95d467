//! The library API on structured cases (`tests/fuzz_cases::ApiCase`): an error when the scene,
//! camera or frame is built, or a frame that renders every way to the same pixels.
#![no_main]

#[path = "../../tests/fuzz_cases/mod.rs"]
mod fuzz_cases;

libfuzzer_sys::fuzz_target!(|case: fuzz_cases::ApiCase| {
    fuzz_cases::check_api(&case);
});
