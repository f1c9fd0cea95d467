#!/usr/bin/env bash
# `rust-version` is real: the library, as a dependency resolved for that toolchain (cargo's
# MSRV-aware resolver, falling back to older versions of dependencies where the newest need a
# newer Rust), builds with that toolchain for the host (with and without `scene-file`, and as
# each board's render path) and for both Cortex-M targets (at opt-level 3 and "s").
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
msrv=$(sed -n 's/^rust-version = "\(.*\)"$/\1/p' Cargo.toml)
[[ -n $msrv ]] || { echo "no rust-version in Cargo.toml" >&2; exit 1; }
rustup toolchain install "$msrv" --profile minimal
rustup target add --toolchain "$msrv" thumbv7em-none-eabihf thumbv6m-none-eabi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir "$work/src"
echo '#![no_std]' >"$work/src/lib.rs"
cat >"$work/Cargo.toml" <<TOML
[package]
name = "msrv-check"
version = "0.0.0"
edition = "2021"
rust-version = "$msrv"
publish = false

[dependencies]
microray = { path = "$root" }

[features]
scene-file = ["microray/scene-file"]
defmt = ["microray/defmt"]

[workspace]
TOML
cd "$work"
CARGO_RESOLVER_INCOMPATIBLE_RUST_VERSIONS=fallback cargo generate-lockfile
export CARGO_TARGET_DIR="$root/target/msrv"
build() { echo "== Rust $msrv: $*"; "$@"; }
build cargo "+$msrv" build --release --features scene-file
build env MICRORAY_HOST_AS=m4f cargo "+$msrv" build --release
build env MICRORAY_HOST_AS=m0 cargo "+$msrv" build --release
for target in thumbv7em-none-eabihf thumbv6m-none-eabi; do
  build cargo "+$msrv" build --release --target "$target"
  build env CARGO_PROFILE_RELEASE_OPT_LEVEL=s cargo "+$msrv" build --release --target "$target"
done
build cargo "+$msrv" build --release --target thumbv7em-none-eabihf --features defmt
echo "microray builds with Rust $msrv (its rust-version)"
