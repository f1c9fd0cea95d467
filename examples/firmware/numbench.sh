#!/usr/bin/env bash
# Builds the `numbench` firmware (release, opt-level 3) for the Cortex-M4F, runs it in QEMU on
# mps2-an386 and prints its key=value lines: instructions per test of each numerical variant of
# examples/speed_vs_error.rs (which runs this script to fill its M4F columns). Counts are QEMU
# -icount instructions timed with SysTick, not cycles. Exits non-zero when a tool is missing
# (status 3, with an `error=` line on stderr) or the firmware fails.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
cd "$here"
target=thumbv7em-none-eabihf

command -v qemu-system-arm >/dev/null || { echo "error=qemu-system-arm not found" >&2; exit 3; }
[ -d "$(rustc --print sysroot)/lib/rustlib/$target" ] ||
  { echo "error=no $target target: rustup target add $target" >&2; exit 3; }

cargo build --quiet --release --target "$target" --bin numbench
set +e
out=$(timeout 600 qemu-system-arm -M mps2-an386 -cpu cortex-m4 -nographic -monitor none \
      -serial none -semihosting-config enable=on,target=native -icount shift=0 \
      -kernel "target/$target/release/numbench")
status=$?
set -e
echo "target=$target"
echo "instructions_note=QEMU -icount instruction counts timed with SysTick, not cycles"
echo "$out"
[ "$status" -eq 0 ] || { echo "error=qemu exit status $status"; exit 1; }
grep -qx "done=1" <<<"$out" || { echo "error=numbench did not finish"; exit 1; }
echo "ok=1"
