#!/usr/bin/env bash
# The firmware check for CI: installs what it needs, then builds and runs the firmware on both
# QEMU boards (examples/firmware/run.sh), which fails on a CRC mismatch with the host, on a panic
# reachable from the render path, or (M4F) on a missing vsqrt.f32. Then runs the host-side test
# that drives the same script, so an ignored test in `cargo test` is exercised here for real.
set -euo pipefail
cd "$(dirname "$0")/.."

sudo_if_needed() { if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi; }

missing=()
command -v qemu-system-arm >/dev/null || missing+=(qemu-system-arm)
command -v python3 >/dev/null || missing+=(python3)
if ! command -v llvm-objdump >/dev/null && ! command -v arm-none-eabi-objdump >/dev/null \
   && ! ls "$(rustc --print sysroot)"/lib/rustlib/*/bin/llvm-objdump >/dev/null 2>&1; then
  missing+=(binutils-arm-none-eabi)
fi
if [ ${#missing[@]} -gt 0 ]; then
  sudo_if_needed apt-get update
  sudo_if_needed apt-get install -y --no-install-recommends "${missing[@]}"
fi
rustup target add thumbv7em-none-eabihf thumbv6m-none-eabi

for board in m4f m0; do
  echo "== examples/firmware/run.sh $board"
  examples/firmware/run.sh "$board"
done

# The size build with one of the speed build's copies kept (features outside-test and
# inline-shading, one at a time: code no other build has): the same CRCs.
for features in outside-test inline-shading; do
  echo "== FEATURES=$features examples/firmware/run.sh m4f"
  FEATURES=$features examples/firmware/run.sh m4f
done

# A capacity of 16 spheres, which builds the shadow sweeps that the firmware's 5 leave out: the
# culled pixels against brute force on the M4F, 5 and 16 spheres (and the figures docs/speed.md
# quotes).
echo "== bench/firmware_speed.sh"
bench/firmware_speed.sh

# The published scenes people compare with (FTB's, tinyraytracer's): the host's CRCs on both
# boards, and their instructions a pixel.
for board in m4f m0; do
  echo "== examples/firmware/figures.sh $board"
  examples/firmware/figures.sh "$board"
done

echo "== cargo test --release --test firmware -- --include-ignored"
cargo test --release --test firmware -- --include-ignored
