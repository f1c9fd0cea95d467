//! Picks the memory layout of the board that the target implies and hands it to cortex-m-rt's
//! `link.x` as `memory.x`: thumbv7em-none-eabihf → mps2-an386, thumbv6m-none-eabi → microbit.

use std::{env, fs, path::PathBuf};

fn main() {
    let target = env::var("TARGET").unwrap_or_default();
    let layout = match target.as_str() {
        "thumbv7em-none-eabihf" => "memory-mps2-an386.x",
        "thumbv6m-none-eabi" => "memory-microbit.x",
        // Any other target (e.g. `cargo check` on the host) gets no linker script.
        _ => return,
    };
    let out = PathBuf::from(env::var("OUT_DIR").unwrap());
    fs::copy(layout, out.join("memory.x")).unwrap();
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed={layout}");
    println!("cargo:rerun-if-changed=build.rs");
}
