//! Sets `cfg(lanes)` on targets with f32 vector registers (x86-64, AArch64 with NEON), where
//! the renderer traces primary rays several columns at a time. Cargo.toml names the same
//! targets for the `wide` dependency, which cannot use this cfg.
fn main() {
    println!("cargo::rustc-check-cfg=cfg(lanes)");
    println!("cargo::rerun-if-changed=build.rs");
    let arch = std::env::var("CARGO_CFG_TARGET_ARCH").unwrap_or_default();
    let features = std::env::var("CARGO_CFG_TARGET_FEATURE").unwrap_or_default();
    let neon = features.split(',').any(|f| f == "neon");
    if arch == "x86_64" || (arch == "aarch64" && neon) {
        println!("cargo::rustc-cfg=lanes");
    }
}
