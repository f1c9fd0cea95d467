#!/usr/bin/env bash
# Renders FTB's and tinyraytracer's scenes (src/figure_scenes.rs, the same as
# examples/scenes/ftb.toml and tinyraytracer.toml) on one board in QEMU and prints key=value
# lines: per scene its CRC-32 and QEMU -icount instructions a pixel, and seconds a frame
# estimated from them.
#
#   examples/firmware/figures.sh m4f   # mps2-an386, Cortex-M4F, thumbv7em-none-eabihf
#   examples/firmware/figures.sh m0    # microbit,   Cortex-M0,  thumbv6m-none-eabi (soft float)
#
# Builds the `figures` binary at opt 3 (the `release` profile). Exits non-zero when QEMU fails,
# a CRC differs from the one committed in src/figure_scenes.rs (which tests/figure_scenes.rs
# computes on the host from the TOML files), or the panic check finds a panic or an indirect
# call reachable from the render. Honours CARGO_TARGET_DIR.
#
# The estimates assume one instruction a cycle: instructions a pixel × 76 800 pixels / clock,
# at 168 MHz (an STM32F4) for the M4F and 125 MHz (an RP2040) for the M0. They are optimistic:
# QEMU -icount counts instructions, not cycles, and silicon adds flash wait states and
# multi-cycle instructions (loads, branches, divisions, on the M4F `vsqrt.f32` and `vdiv.f32`
# at 14 cycles each).
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
case "${1:-}" in
  m4f) target=thumbv7em-none-eabihf; machine=(-M mps2-an386 -cpu cortex-m4); mhz=168; chip=STM32F4 ;;
  m0)  target=thumbv6m-none-eabi;    machine=(-M microbit);                   mhz=125; chip=RP2040 ;;
  *)   echo "usage: $0 m4f|m0" >&2; exit 2 ;;
esac
cd "$here"

# QEMU, and $objdump for the panic check.
source tools/tools.sh

cargo build --quiet --release --target "$target" --bin figures
elf=${CARGO_TARGET_DIR:-target}/$target/release/figures
fail=0
set +e
out=$(timeout 1800 qemu-system-arm "${machine[@]}" -nographic -monitor none -serial none \
      -semihosting-config enable=on,target=native -icount shift=0 -kernel "$elf")
status=$?
set -e
echo "target=$target"
echo "instructions_note=QEMU -icount instruction counts timed with SysTick, not cycles"
echo "$out"
[ "$status" -eq 0 ] || { echo "error=qemu exit status $status (a CRC differs, or set-up failed)"; fail=1; }

# Seconds a frame from instructions a pixel, at one instruction a cycle.
echo "estimate_note=instructions_per_pixel x pixels / ${mhz} MHz ($chip), assuming one instruction a cycle: optimistic (flash wait states, multi-cycle instructions)"
for name in $(sed -n 's/^\([a-z0-9]*\)_instructions_per_pixel=.*/\1/p' <<<"$out"); do
  ipp=$(sed -n "s/^${name}_instructions_per_pixel=//p" <<<"$out")
  pixels=$(sed -n "s/^${name}_pixels=//p" <<<"$out")
  awk -v n="$name" -v ipp="$ipp" -v px="$pixels" -v mhz="$mhz" -v chip="$chip" \
    'BEGIN { printf "%s_estimated_seconds_per_frame_at_%dmhz_%s=%.3f\n", n, mhz, chip, ipp * px / (mhz * 1e6) }'
done

# The render path panic-free: tools/panic_check.py, rooted at the only render function this
# binary has (scene.rs's crc_rgb888; `firmware` also has the dithered strip's).
python3 tools/panic_check.py "$elf" "$objdump" crc_rgb888 \
  || { echo "error=panic reachable from the render path"; fail=1; }
echo "ok=$((1 - fail))"
exit "$fail"
