#!/usr/bin/env bash
# The README's library example as a user pastes it: a new crate whose [dependencies] are the
# README's own snippet (microray by path instead of from the registry) and whose src/lib.rs is
# `#![no_std]` and the README's Rust example, built for the host and for a Cortex-M4F.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

python3 - "$root/README.md" "$work" "$root" <<'PY'
import re, sys
readme, work, root = sys.argv[1:4]
text = open(readme).read()
blocks = re.findall(r"```(\w*)\n(.*?)```", text, re.S)
# The dependency snippet, and the first Rust example after it.
k = next(i for i, (lang, body) in enumerate(blocks) if lang == "toml" and "[dependencies]" in body)
deps = blocks[k][1]
rust = next(body for lang, body in blocks[k + 1:] if lang == "rust")
deps, n = re.subn(r'^microray = "[^"]*"', 'microray = { path = "%s" }' % root, deps, flags=re.M)
assert n == 1, "the README's snippet has no `microray = \"...\"` line"
open(work + "/Cargo.toml", "w").write(
    '[package]\nname = "readme-example"\nversion = "0.0.0"\nedition = "2021"\npublish = false\n\n'
    "[workspace]\n\n" + deps)
import os
os.mkdir(work + "/src")
open(work + "/src/lib.rs", "w").write("#![no_std]\n\n" + rust)
PY
echo "--- Cargo.toml"; cat "$work/Cargo.toml"
cd "$work"
export CARGO_TARGET_DIR="$root/target/readme-check" RUSTFLAGS="-D warnings"
cargo build
cargo build --target thumbv7em-none-eabihf
echo "the README's example builds as pasted, for the host and thumbv7em-none-eabihf"
