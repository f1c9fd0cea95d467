#!/usr/bin/env bash
# Renders scenes with POV-Ray 3.7 and with microray, checks that the pixels agree (the
# conformance statistic: >= 99.9% of pixels within 1 level, <= 0.05% off by more than 8) and
# prints POV-Ray's own trace time against microray's `render:` line.
#
#   bench/povray.sh [SCENE.toml ...]        (default: bench/scenes/target.toml)
#
# Environment: THREADS (default 1: POV-Ray +WT1 and microray --threads 1), RUNS (default 5;
# the runs alternate POV-Ray, microray, POV-Ray, ..., and the median of the RUNS timings of
# each tracer is reported). Installs POV-Ray if it is missing.
#
# A scene with samples = n > 1 or sRGB encoding is traced by POV-Ray at n·W × n·H, one ray a
# pixel (the centres of those pixels are microray's sample points), into a 16-bit linear PNG
# with the lights, ambient and background divided by 4 (toml2pov.py --supersampled --scale 4:
# POV-Ray clamps each pixel it writes, microray averages unclamped samples); the n×n blocks
# are then averaged, multiplied by 4, clamped and encoded here as microray does.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
threads=${THREADS:-1}
runs=${RUNS:-5}
scenes=("$@")
[ ${#scenes[@]} -gt 0 ] || scenes=("$here/scenes/target.toml")

if ! command -v povray >/dev/null; then
  apt-get update && apt-get install -y povray
fi
cargo build --quiet --release --example render --manifest-path "$root/Cargo.toml"
render=$root/target/release/examples/render
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

printf '%-28s %9s %9s %7s  %s\n' scene povray_s microray_s ratio pixels
status=0
for scene in "${scenes[@]}"; do
  name=$(basename "$scene" .toml)
  read -r w h n enc < <(python3 - "$scene" <<'PY'
import sys, tomllib
r = tomllib.load(open(sys.argv[1], "rb")).get("render", {})
print(r.get("width", 640), r.get("height", 480), r.get("samples", 1), r.get("encoding", "linear"))
PY
)
  if [ "$n" = 1 ] && [ "$enc" = linear ]; then
    python3 "$here/toml2pov.py" "$scene" > "$out/$name.pov"
    depth=8
  else
    w=$((w * n)) h=$((h * n)) depth=16
    python3 "$here/toml2pov.py" --supersampled --scale 4 "$scene" "$w" "$h" > "$out/$name.pov"
  fi
  : > "$out/pov.txt"
  : > "$out/mr.txt"
  for _ in $(seq "$runs"); do
    # +Q9 full quality (shadows, reflection), -A no anti-aliasing, no radiosity (none in the
    # file), File_Gamma=1.0 with assumed_gamma 1.0: linear pixels like microray's.
    (cd "$out" && povray "+I$name.pov" "+O$name.pov.png" "+W$w" "+H$h" -A +Q9 "+WT$threads" \
       "+FN$depth" File_Gamma=1.0 -D -P 2>&1) \
      | sed -n 's/.*Trace Time:.*(\([0-9.]*\) seconds).*/\1/p' | head -1 >> "$out/pov.txt"
    "$render" "$scene" -o "$out/$name.microray.png" --threads "$threads" \
      | sed -n 's/^render: \([0-9.]*\) ms/\1/p' >> "$out/mr.txt"
  done
  if [ "$depth" = 16 ]; then
    python3 "$here/supersample.py" "$out/$name.pov.png" "$n" "$enc" 4
  fi
  if cmp=$(python3 "$here/pngdiff.py" "$out/$name.pov.png" "$out/$name.microray.png"); then :; else status=1; fi
  read -r med_pov med_mr ratio < <(python3 - "$out/pov.txt" "$out/mr.txt" <<'PY'
import statistics, sys
pov = statistics.median(float(x) for x in open(sys.argv[1]))
mr = statistics.median(float(x) for x in open(sys.argv[2])) / 1000
print(pov, mr, "%.1f" % (pov / mr))
PY
)
  printf '%-28s %9.4f %9.4f %6sx  %s\n' "$name" "$med_pov" "$med_mr" "$ratio" "$cmp"
done
exit $status
