#!/usr/bin/env bash
# Builds the firmware for one board, runs it in QEMU and prints key=value lines.
#
#   examples/firmware/run.sh m4f   # mps2-an386, Cortex-M4F, thumbv7em-none-eabihf
#   examples/firmware/run.sh m0    # microbit,   Cortex-M0,  thumbv6m-none-eabi (soft float)
#
# Two builds: `release` (opt-level 3) and `release-s` (opt-level "s"); both run in QEMU, keys of
# the "s" build end in `_s`. `instructions*` are QEMU -icount instruction counts measured with
# SysTick, not cycles. Sizes come from the linked ELF (tools/elfsize.py by symbol, plus
# tools/inlined.py for microray's code inlined into the firmware's); the panic check walks
# the call graph of the disassembly (tools/panic_check.py). The `scenes` binary renders the 56
# seeded scenes of src/random_scenes.rs (scenes_differing=); the `displays` binary checks the
# one-window, progressive and 1-bit/grey dithered draws (displays_ok=, src/bin/displays.rs). Exits non-zero when a CRC differs
# from the one committed in src/scene.rs or src/random_scenes.rs, the panic check fails, (m4f) vsqrt.f32 is missing, or
# a budget is broken: stack high-water (whole run, render passes, or the display paths) above
# 2 KiB on any build,
# or (m4f) microray's flash above 16 KiB at opt "s" or more than 400 instructions a pixel at
# opt 3.
#
# FEATURES="outside-test inline-shading" builds both with those features of the firmware
# (microray's, which size builds need to keep that code): the same checks, but the flash
# budget, which is the plain size build's, is only reported.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
case "${1:-}" in
  m4f) target=thumbv7em-none-eabihf; machine=(-M mps2-an386 -cpu cortex-m4) ;;
  m0)  target=thumbv6m-none-eabi;    machine=(-M microbit) ;;
  *)   echo "usage: $0 m4f|m0" >&2; exit 2 ;;
esac
cd "$here"

# QEMU, and $objdump for the panic check.
source tools/tools.sh

expected=$(sed -n 's/^pub const EXPECTED_CRC32: u32 = 0x\([0-9a-f]*\);/\1/p' src/scene.rs)
fail=0

within() { # $1 = key, $2 = measured value, $3 = budget; uses $suffix of the caller
  if [ -z "$2" ] || [ "$2" -gt "$3" ]; then
    echo "error$suffix=$1 ${2:-missing}, over the budget of $3 bytes"
    fail=1
  fi
}

qemu() { # $1 = ELF: runs it on the board, its semihosting output on stdout
  timeout 900 qemu-system-arm "${machine[@]}" -nographic -monitor none -serial none \
    -semihosting-config enable=on,target=native -icount shift=0 -kernel "$1"
}

run() { # $1 = cargo profile, $2 = key suffix
  local profile=$1 suffix=$2 out status
  cargo build --quiet --profile "$profile" --target "$target" ${FEATURES:+--features "$FEATURES"}
  local elf=target/$target/$profile/firmware
  set +e
  out=$(qemu "$elf")
  status=$?
  set -e
  # The firmware's own lines, with the suffix of this build.
  sed "s/^\([A-Za-z0-9_]*\)=/\1$suffix=/" <<<"$out"
  [ "$status" -eq 0 ] || { echo "error$suffix=qemu exit status $status"; fail=1; }
  grep -qx "crc32=$expected" <<<"$out" || { echo "error$suffix=crc32 differs from src/scene.rs ($expected)"; fail=1; }
  # The seeded scenes of src/random_scenes.rs, a CRC each (scene_crc=K CRC), each checked by
  # the firmware against the committed list.
  local scenes
  set +e
  scenes=$(qemu "target/$target/$profile/scenes")
  status=$?
  set -e
  grep -v '^scene_crc=' <<<"$scenes" | sed "s/^\([A-Za-z0-9_]*\)=/\1$suffix=/"
  [ "$status" -eq 0 ] || { echo "error$suffix=scenes: qemu exit status $status"; fail=1; }
  grep -qx "scenes_differing=0" <<<"$scenes" || {
    grep "^scene_crc=" <<<"$scenes" > "target/scene_crcs_${target}_$profile.txt"
    echo "error$suffix=scene CRCs differ from src/random_scenes.rs (target/scene_crcs_${target}_$profile.txt)"
    fail=1; }
  # The display paths (src/bin/displays.rs): one window, the progressive draw's final image,
  # its early stop, and the 1-bit and grey dithered CRCs.
  local displays
  set +e
  displays=$(qemu "target/$target/$profile/displays")
  status=$?
  set -e
  sed "s/^\([A-Za-z0-9_]*\)=/\1$suffix=/" <<<"$displays"
  [ "$status" -eq 0 ] && grep -qx "displays_ok=1" <<<"$displays" || {
    echo "error$suffix=displays: a display path differs (qemu exit status $status)"; fail=1; }
  within displays_stack_bytes "$(sed -n 's/^displays_stack_bytes=//p' <<<"$displays")" 2048
  python3 tools/panic_check.py "target/$target/$profile/displays" "$objdump" \
      plain_digest,progressive_digest,progressive_stopped,crc_binary,crc_gray4 \
    | sed -n "s/^render_path_\(panics\|flash_bytes\|indirect_calls\|panic\|indirect\)=/displays_path_\1$suffix=/p" \
    || { echo "error$suffix=panic reachable from a display path"; fail=1; }
  # microray's code in that firmware (draw, progressive, dithering: reported, no budget).
  local dsizes dinl
  dsizes=$(python3 tools/elfsize.py "target/$target/$profile/displays" "$suffix")
  dinl=$(python3 tools/inlined.py "target/$target/$profile/displays" "$objdump" ../../src "$suffix")
  echo "displays_microray_total_flash_bytes$suffix=$(( $(sed -n "s/^microray_flash_bytes$suffix=//p" <<<"$dsizes") + ${dinl##*=} ))"
  local sizes inlined
  sizes=$(python3 tools/elfsize.py "$elf" "$suffix")
  echo "$sizes"
  # microray's code that LLVM inlined into firmware functions (its set-up, mostly `Frame::new`):
  # microray's too, though its symbols do not show it.
  inlined=$(python3 tools/inlined.py "$elf" "$objdump" ../../src "$suffix")
  echo "$inlined"
  local total=$(( $(sed -n "s/^microray_flash_bytes$suffix=//p" <<<"$sizes") + ${inlined##*=} ))
  echo "microray_total_flash_bytes$suffix=$total"
  # The budgets, enforced: a change that breaks one fails here, not in a README.
  # Flash: microray's code (symbols and inlined) at most 16 KiB on thumbv7em at opt "s" (at
  # opt 3 it is only reported: that build trades size for speed).
  if [ "$target" = thumbv7em-none-eabihf ] && [ "$profile" = release-s ] && [ -z "${FEATURES:-}" ]; then
    within microray_total_flash_bytes "$total" 16384
  fi
  # Speed: at most 400 M4F instructions a pixel at opt 3 (QEMU -icount, repeatable).
  if [ "$target" = thumbv7em-none-eabihf ] && [ "$profile" = release ]; then
    local ipp
    ipp=$(sed -n 's/^instructions_per_pixel=//p' <<<"$out")
    if [ -z "$ipp" ] || ! awk -v x="$ipp" 'BEGIN { exit !(x <= 400) }'; then
      echo "error$suffix=instructions_per_pixel ${ipp:-missing}, over the budget of 400"
      fail=1
    fi
  fi
  within stack_bytes "$(sed -n 's/^stack_bytes=//p' <<<"$out")" 2048
  within render_stack_bytes "$(sed -n 's/^render_stack_bytes=//p' <<<"$out")" 2048
  python3 tools/panic_check.py "$elf" "$objdump" | sed "s/^\([A-Za-z0-9_]*\)=/\1$suffix=/" || {
    echo "error$suffix=panic reachable from the render path"; fail=1; }
  if [ "$target" = thumbv7em-none-eabihf ]; then
    local n
    n=$("$objdump" -d "$elf" | grep -c 'vsqrt\.f32' || true)
    echo "vsqrt_f32_sites$suffix=$n"
    [ "$n" -gt 0 ] || { echo "error$suffix=no vsqrt.f32 in the M4F firmware"; fail=1; }
  fi
}

echo "target=$target"
echo "features=${FEATURES:-}"
echo "instructions_note=QEMU -icount instruction counts timed with SysTick, not cycles"
run release ""
run release-s "_s"
echo "ok=$((1 - fail))"
exit "$fail"
