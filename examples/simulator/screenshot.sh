#!/usr/bin/env bash
# Writes docs/simulator.png: the simulator's real SDL window on the demo scene at 320×240, with
# its title bar, once its first frame is drawn. It runs under Xvfb with Openbox for the window's
# decoration, captures the screen with xwd and crops it to the window's frame (xwd on the window
# itself misreads the colours of SDL's 32-bit visual). Installs what it needs from apt.
set -euo pipefail
cd "$(dirname "$0")"
self=$(pwd)/$(basename "$0")
out=../../docs/simulator.png

if [[ ${1:-} != --in-xvfb ]]; then
  need=()
  pkg-config --exists sdl2 2>/dev/null || need+=(libsdl2-dev pkg-config)
  for tool in xvfb-run:xvfb xauth:xauth xwd:x11-apps xwininfo:x11-utils xprop:x11-utils \
    xwdtopnm:netpbm openbox:openbox; do
    command -v "${tool%%:*}" >/dev/null || need+=("${tool#*:}")
  done
  if ((${#need[@]})); then
    sudo=()
    [[ $(id -u) -eq 0 ]] || sudo=(sudo)
    "${sudo[@]}" apt-get update -qq
    "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${need[@]}"
  fi
  cargo build --release --locked
  exec xvfb-run -a -s '-screen 0 800x600x24' "$self" --in-xvfb
fi

# From here on inside Xvfb (DISPLAY is set). Every process started here is ended on the way out.
tmp=$(mktemp -d)
pids=()
cleanup() {
  for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null && wait "$pid" 2>/dev/null || true; done
  rm -rf "$tmp"
}
trap cleanup EXIT

# Polls a command for up to $1 seconds.
wait_for() {
  local limit=$1
  shift
  for ((i = 0; i < limit * 5; i++)); do
    if "$@" >/dev/null 2>&1; then return 0; fi
    sleep 0.2
  done
  echo "timed out waiting for: $*" >&2
  return 1
}

openbox >"$tmp/openbox.log" 2>&1 &
pids+=($!)
# Openbox is up once it names its check window (xprop exits 0 either way).
wm_ready() { xprop -root _NET_SUPPORTING_WM_CHECK | grep -q 'window id'; }
wait_for 20 wm_ready

# It closes 5 s after its frame: time enough for the capture.
"${CARGO_TARGET_DIR:-target}/release/microray-simulator" --exit-after-frame 5 >"$tmp/sim.log" &
sim=$!
pids+=("$sim")
# The simulator prints the frame's time once the frame is on screen.
wait_for 120 grep -q '^frame:' "$tmp/sim.log"

tree=$(xwininfo -root -tree)
id=$(awk '/"microray [0-9]+x[0-9]+"/ { print $1 }' <<<"$tree" | head -n 1)
[[ -n $id ]] || { echo "no simulator window" >&2; exit 1; }
framed() { xprop -id "$id" _NET_FRAME_EXTENTS | grep -q '= '; }
wait_for 10 framed
sleep 0.5 # the window manager's last repaint of the frame
info=$(xwininfo -id "$id")
field() { awk -F: -v key="$1" '$1 ~ key { gsub(/ /, "", $2); print $2 }' <<<"$info"; }
x=$(field "Absolute upper-left X")
y=$(field "Absolute upper-left Y")
w=$(field "Width")
h=$(field "Height")
# left, right, top, bottom: the decoration around the window.
read -r l r t b < <(xprop -id "$id" _NET_FRAME_EXTENTS | sed 's/.*= //; s/,//g')

xwd -silent -root -out "$tmp/screen.xwd"
xwdtopnm "$tmp/screen.xwd" 2>/dev/null |
  pamcut -left $((x - l)) -top $((y - t)) -width $((w + l + r)) -height $((h + t + b)) |
  pnmtopng >"$tmp/simulator.png"
mv "$tmp/simulator.png" "$out"
wait "$sim"
echo "wrote docs/simulator.png ($((w + l + r))x$((h + t + b))): $(cat "$tmp/sim.log")"
