#!/usr/bin/env bash
# Host instructions per pixel of one render (x86 callgrind), repeatable on a noisy machine:
# the same binary and scene give the same count whatever else runs. Not a time: a change can
# cut instructions and cost time (or the reverse), so confirm a gain with bench/ab.sh too.
#
#   bench/instructions.sh [SCENE.toml ...]     (default: bench/scenes/target.toml)
#
# Prints, per scene, key=value lines: instructions= (of `render_once` in
# examples/instructions.rs: `Frame::render_rows` over the whole frame, one thread, without
# parsing, `Frame::new` or PNG encoding), instructions_per_pixel=, and pixel_hash= (FNV-1a of
# the pixels, so that two builds can be checked to render the same image). Installs valgrind if
# it is missing. Counts the portable x86-64 build (`-C target-cpu=x86-64`, in target/portable),
# not the repository's native one (.cargo/config.toml): counts that do not depend on the machine,
# and valgrind decodes no AVX-512.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
scenes=("$@")
[ ${#scenes[@]} -gt 0 ] || scenes=("$root/bench/scenes/target.toml")
command -v valgrind >/dev/null || { apt-get update && apt-get install -y valgrind; }
RUSTFLAGS="-C target-cpu=x86-64" cargo build --quiet --release --example instructions \
  --manifest-path "$root/Cargo.toml" --target-dir "$root/target/portable"
bin=$root/target/portable/release/examples/instructions
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for scene in "${scenes[@]}"; do
  valgrind --tool=callgrind --toggle-collect='instructions::render_once' \
    --callgrind-out-file="$out/cg.out" "$bin" "$scene" > "$out/stdout" 2> "$out/stderr" || {
    cat "$out/stderr" >&2; exit 1; }
  n=$(sed -n 's/^summary: *//p' "$out/cg.out")
  px=$(sed -n 's/^pixels=//p' "$out/stdout")
  echo "scene=$(basename "$scene" .toml)"
  echo "instructions=$n"
  python3 -c "print(f'instructions_per_pixel={$n / $px:.1f}')"
  grep '^pixel_hash=' "$out/stdout"
done
