#!/usr/bin/env bash
# Cortex-M4F instructions per pixel (QEMU -icount, the firmware's own count) of the accelerated
# renderer against the brute-force loop, on the firmware's 5-sphere scene and on a 16-sphere
# variant. Works on a copy of the firmware crate (never edits it): its microray dependency is
# pointed at this checkout, MR_SPHERES16 adds 11 small spheres, MR_BRUTE makes the timed pass
# call Frame::render_rows_brute row by row instead of Frame::draw. Both passes fold the same
# bytes into the CRC, so equal CRCs mean equal pixels: the script fails when they differ (or a
# build does not run), so CI runs it (.ci/firmware.sh).
#
#   bench/firmware_speed.sh [FIRMWARE_DIR]     (default: examples/firmware of this checkout)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
src=${1:-$root/examples/firmware}
[ -d "$src/src" ] || { echo "no firmware crate at $src" >&2; exit 2; }
command -v qemu-system-arm >/dev/null || { echo "qemu-system-arm not found" >&2; exit 3; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp -r "$src/." "$work/"
rm -rf "$work/target"
python3 - "$work" "$root" <<'PY'
import sys
work, root = sys.argv[1], sys.argv[2]
p = work + "/Cargo.toml"
s = open(p).read().replace('microray = { path = "../.." }', 'microray = { path = "%s" }' % root)
open(p, "w").write(s)
p = work + "/src/scene.rs"
s = open(p).read()
s = s.replace("pub const SPHERES: usize = 5;", "pub const SPHERES: usize = 16;")
s = s.replace("""    let _ = frame.draw(&mut display);
    (display.crc.value(), display.pixels)""", """    if option_env!("MR_BRUTE").is_some() {
        let mut row = [Rgb888::BLACK; WIDTH as usize];
        for j in 0..frame.height() {
            let _ = frame.render_rows_brute(j, &mut row);
            for &c in row.iter() {
                display.fold(c);
            }
        }
    } else {
        let _ = frame.draw(&mut display);
    }
    (display.crc.value(), display.pixels)""")
import glob
output = "".join(open(f).read() for f in glob.glob(root + "/src/output*.rs") + glob.glob(root + "/src/output/*.rs"))
if "fn render_rows_dithered" not in output:
    s = s.replace("frame.render_rows_dithered(row, strip)?", "frame.render_rows(row, strip)?")
s = s.replace("""    scene.add_light(Light::Point {""", """    if option_env!("MR_SPHERES16").is_some() {
        for k in 0..11 {
            let x = -2.5 + 0.5 * k as f32;
            let z = if k % 2 == 0 { 2.2 } else { -2.4 };
            let r = 0.18 + 0.03 * (k % 3) as f32;
            let m = plastic(0.3 + 0.05 * k as f32, 0.5, 0.7 - 0.05 * k as f32, 24.0);
            scene.add_sphere(Sphere::new(Vec3::new(x, r, z), r), m)?;
        }
    }
    scene.add_light(Light::Point {""", 1)
open(p, "w").write(s)
# A capacity of 16 needs the `Inline` layout: `Small` holds at most 8 spheres.
for f in glob.glob(work + "/src/*.rs") + glob.glob(work + "/src/bin/*.rs"):
    s = open(f).read()
    t = s.replace("microray::render::Small", "microray::render::Inline")
    t = t.replace("LIGHTS, Small>", "LIGHTS, Inline>").replace("FrameStorage::small()", "FrameStorage::new()")
    if t != s:
        open(f, "w").write(t)
PY
cd "$work"
printf '%-8s %-6s %12s %10s %s\n' spheres path instr/pixel crc32 render_stack_bytes
failed=0
for sc in 5 16; do
  crcs=()
  for mode in accelerated brute; do
    envs=(MR_X=1)
    [ "$sc" = 16 ] && envs+=(MR_SPHERES16=1)
    [ "$mode" = brute ] && envs+=(MR_BRUTE=1)
    env "${envs[@]}" cargo build --quiet --release --target thumbv7em-none-eabihf --bin firmware
    out=$(timeout 900 qemu-system-arm -M mps2-an386 -cpu cortex-m4 -nographic -monitor none \
      -serial none -semihosting-config enable=on,target=native -icount shift=0 \
      -kernel target/thumbv7em-none-eabihf/release/firmware || true)
    # (the firmware exits with failure when a CRC differs from the 5-sphere scene's: expected
    # for the 16-sphere variant; the CRCs are compared here instead)
    get() { sed -n "s/^$1=//p" <<<"$out"; }
    printf '%-8s %-6s %12s %10s %s\n' "$sc" "$mode" "$(get instructions_per_pixel)" "$(get crc32)" "$(get render_stack_bytes)"
    crcs+=("$(get crc32)")
  done
  # The culled pixels are brute force's, on a capacity that builds the shadow sweeps.
  if [ -z "${crcs[0]}" ] || [ "${crcs[0]}" != "${crcs[1]}" ]; then
    echo "$sc spheres: the two paths' CRCs differ or are missing" >&2
    failed=1
  fi
done
exit "$failed"
