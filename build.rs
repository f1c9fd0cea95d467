//! Sets `cfg(lanes)` on targets with f32 vector registers (x86-64, AArch64 with NEON, wasm32 with
//! simd128), where the renderer traces primary rays several columns at a time, and `cfg(no_dirs)` on soft-float
//! Arm (Cortex-M0), whose spans keep no view directions. Cargo.toml names the same targets for
//! the `wide` dependency, which cannot use these cfgs.
//!
//! `MICRORAY_HOST_AS=m4f` (or `m0`) builds the host as that Cortex-M's render path runs: no
//! lanes (and for `m0` no kept directions), so that the host's tests check those paths' pixels
//! on every scene; CI does both (the firmware's CRC checks one scene on each board).
//!
//! `cfg(size_opt)` at opt-level "s" or "z": the scalar render path then keeps one out-of-line
//! copy of the hit record and of the shading, which the speed builds also inline into the pixel
//! loop (`Frame::shade_stored`), and no second primary test for an eye outside a sphere: the
//! same operations either way (`src/render/config.rs`: `INLINE_SHADING`, `OUTSIDE_TEST`,
//! which features `inline-shading` and `outside-test` turn on in size builds too).
fn main() {
    println!("cargo::rustc-check-cfg=cfg(lanes, no_dirs, size_opt, docsrs)");
    println!("cargo::rerun-if-changed=build.rs");
    println!("cargo::rerun-if-env-changed=MICRORAY_HOST_AS");
    let env = |k: &str| std::env::var(k).unwrap_or_default();
    let (arch, abi) = (env("CARGO_CFG_TARGET_ARCH"), env("CARGO_CFG_TARGET_ABI"));
    let features = env("CARGO_CFG_TARGET_FEATURE");
    let feature = |name: &str| features.split(',').any(|f| f == name);
    let (lanes, no_dirs) = match env("MICRORAY_HOST_AS").as_str() {
        "m4f" => (false, false),
        "m0" => (false, true),
        "" => (
            arch == "x86_64"
                || (arch == "aarch64" && feature("neon"))
                || (arch == "wasm32" && feature("simd128")),
            arch == "arm" && abi != "eabihf",
        ),
        other => panic!("MICRORAY_HOST_AS={other}: expected m4f or m0"),
    };
    if lanes {
        println!("cargo::rustc-cfg=lanes");
    }
    if no_dirs {
        println!("cargo::rustc-cfg=no_dirs");
    }
    if matches!(env("OPT_LEVEL").as_str(), "s" | "z") {
        println!("cargo::rustc-cfg=size_opt");
    }
}
