//! Sets `cfg(lanes)` on targets with f32 vector registers (x86-64, AArch64 with NEON), where
//! the renderer traces primary rays several columns at a time. Cargo.toml names the same
//! targets for the `wide` dependency, which cannot use this cfg.
fn main() {
    println!("cargo::rustc-check-cfg=cfg(lanes)");
    println!("cargo::rerun-if-changed=build.rs");
    // `MICRORAY_NO_LANES=1`: the scalar path, as Cortex-M runs it, on the host too, so that the
    // host's tests check that path's pixels on every scene (CI does; the firmware's CRC checks
    // one scene).
    println!("cargo::rerun-if-env-changed=MICRORAY_NO_LANES");
    if std::env::var_os("MICRORAY_NO_LANES").is_some_and(|v| !v.is_empty() && v != "0") {
        return;
    }
    let arch = std::env::var("CARGO_CFG_TARGET_ARCH").unwrap_or_default();
    let features = std::env::var("CARGO_CFG_TARGET_FEATURE").unwrap_or_default();
    let neon = features.split(',').any(|f| f == "neon");
    if arch == "x86_64" || (arch == "aarch64" && neon) {
        println!("cargo::rustc-cfg=lanes");
    }
}
