#!/usr/bin/env bash
# microray in a browser (web/): the crate's format and lints, the module's build, and the
# page's canvas against the host's pixels in headless Chromium. Installs what it needs itself
# on a fresh Debian machine: Chromium, the wasm32 target, the test's npm packages.
set -euo pipefail
cd "$(dirname "$0")/../web"

if [[ ! -x /usr/bin/chromium ]]; then
  sudo=()
  if [[ $(id -u) -ne 0 ]]; then sudo=(sudo); fi
  "${sudo[@]}" apt-get update
  "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y chromium
fi
rustup target add wasm32-unknown-unknown
rustup component add clippy rustfmt

cargo fmt -- --check
cargo clippy --release --all-targets --target wasm32-unknown-unknown -- -D warnings
cargo clippy --release --all-targets -- -D warnings

bash build.sh
(cd test && npm ci --no-audit --no-fund)
node test/canvas.mjs
