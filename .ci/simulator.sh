#!/usr/bin/env bash
# The simulator example (examples/simulator: its own workspace with a committed Cargo.lock):
# rustfmt, clippy and its tests, then its headless frames of the demo scene at two display
# sizes, which must be the desktop renderer's pixels exactly. No display is needed; SDL2's
# development files are (the simulator links SDL2 even headless), installed from apt when
# pkg-config cannot find them.
set -euo pipefail
cd "$(dirname "$0")/.."

missing=()
if ! pkg-config --exists sdl2 2>/dev/null; then
  missing+=(libsdl2-dev pkg-config)
fi
command -v python3 >/dev/null || missing+=(python3)
if ((${#missing[@]})); then
  sudo=()
  [[ $(id -u) -eq 0 ]] || sudo=(sudo)
  "${sudo[@]}" apt-get update -qq
  "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}"
fi
rustup component add clippy rustfmt

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# The decoded RGB pixels of two 8-bit PNGs must be equal: bench/pngdiff.py's stdlib reader,
# independent of both programs' encoders.
same_pixels() {
  python3 - "$1" "$2" <<'PY'
import sys
sys.path.insert(0, "bench")
from pngdiff import read_samples

(wa, ha, ca, da, a), (wb, hb, cb, db, b) = (read_samples(p) for p in sys.argv[1:3])
if (wa, ha, da) != (wb, hb, db):
    sys.exit(f"{sys.argv[1]}: {wa}x{ha} at {da} bits against {wb}x{hb} at {db} bits")
differ = sum(
    ra[x * ca:x * ca + 3] != rb[x * cb:x * cb + 3] for ra, rb in zip(a, b) for x in range(wa)
)
print(f"{sys.argv[1]} against {sys.argv[2]}: {differ} of {wa * ha} pixels differ")
sys.exit(1 if differ else 0)
PY
}

(
  cd examples/simulator
  cargo fmt --check
  cargo clippy --release --locked --all-targets -- -D warnings
  cargo test --release --locked
)

for size in 320x240 240x240; do
  echo "== $size: the simulator headless against the desktop renderer"
  # No display: headless must not need one.
  (cd examples/simulator && env -u DISPLAY -u WAYLAND_DISPLAY cargo run --release --locked -q -- \
    ../scenes/demo.toml --size "$size" --headless "$tmp/simulator-$size.png")
  cargo run --release -q --example render -- examples/scenes/demo.toml \
    -o "$tmp/render-$size.png" --width "${size%x*}" --height "${size#*x}"
  same_pixels "$tmp/simulator-$size.png" "$tmp/render-$size.png"
done
