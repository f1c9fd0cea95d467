#!/usr/bin/env bash
# The crate as a registry ships it builds and tests itself: `cargo package`, then in the
# unpacked crate what a user or a distribution runs, in both builds, with and without the
# `scene-file` feature (without it, the targets that read scene files are skipped and
# tests/features.rs says so).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD

cargo package --no-verify --allow-dirty
crate=$(ls -t target/package/microray-*.crate | head -n 1)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
tar xzf "$crate" -C "$work"
cd "$work"/microray-*/
# One target dir for all of these, beside the repository's: the dependencies build once a profile.
export CARGO_TARGET_DIR="$root/target/package-check"

for features in "" "--features scene-file"; do
  echo "== the package: cargo test --release $features"
  cargo test --release $features
  echo "== the package: cargo test $features (unoptimised)"
  cargo test $features
  echo "== the package: cargo build --examples $features; cargo bench --no-run $features"
  cargo build --examples $features
  cargo bench --no-run $features
done

echo "== the package without scene-file says which tests it skipped"
# (The list is read whole: `grep -q` stopping early would break cargo's pipe.)
skipped=$(cargo test --release --test features -- --ignored --list)
grep -q "the_scene_file_tests_need_the_feature: test" <<<"$skipped"
