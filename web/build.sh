#!/usr/bin/env bash
# Builds the page's module: web/microray.wasm, beside index.html (not committed).
set -euo pipefail
cd "$(dirname "$0")"
rustup target add wasm32-unknown-unknown
cargo build --release --lib --target wasm32-unknown-unknown
cp target/wasm32-unknown-unknown/release/microray_web.wasm microray.wasm
echo "web/microray.wasm: $(wc -c <microray.wasm) bytes"
