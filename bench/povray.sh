#!/usr/bin/env bash
# Renders scenes with POV-Ray 3.7 and with microray, checks that the pixels agree (the
# conformance statistic: >= 99.9% of pixels within 1 level, <= 0.05% off by more than 8) and
# prints POV-Ray's own trace time against microray's `render:` line.
#
#   bench/povray.sh [SCENE.toml ...]        (default: bench/scenes/target.toml)
#
# Environment: THREADS (default 1: POV-Ray +WT1 and microray --threads 1), RUNS (default 5;
# the best of RUNS timings of each tracer is reported). Installs POV-Ray if it is missing.
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
  python3 "$here/toml2pov.py" "$scene" > "$out/$name.pov"
  read -r w h < <(python3 - "$scene" <<'PY'
import sys, tomllib
r = tomllib.load(open(sys.argv[1], "rb")).get("render", {})
print(r.get("width", 640), r.get("height", 480))
PY
)
  best_pov=
  best_mr=
  for _ in $(seq "$runs"); do
    # +Q9 full quality (shadows, reflection), -A no anti-aliasing, no radiosity (none in the
    # file), File_Gamma=1.0 with assumed_gamma 1.0: linear pixels like microray's.
    t=$(cd "$out" && povray "+I$name.pov" "+O$name.pov.png" "+W$w" "+H$h" -A +Q9 "+WT$threads" \
          +FN8 File_Gamma=1.0 -D -P 2>&1 | sed -n 's/.*Trace Time:.*(\([0-9.]*\) seconds).*/\1/p' | head -1)
    best_pov=$(python3 -c "print(min(x for x in [$t, ${best_pov:-1e9}]))")
    ms=$("$render" "$scene" -o "$out/$name.microray.png" --threads "$threads" | sed -n 's/^render: \([0-9.]*\) ms/\1/p')
    best_mr=$(python3 -c "print(min(x for x in [$ms / 1000, ${best_mr:-1e9}]))")
  done
  if cmp=$(python3 "$here/pngdiff.py" "$out/$name.pov.png" "$out/$name.microray.png"); then :; else status=1; fi
  ratio=$(python3 -c "print('%.1f' % ($best_pov / $best_mr))")
  printf '%-28s %9.4f %9.4f %6sx  %s\n' "$name" "$best_pov" "$best_mr" "$ratio" "$cmp"
done
exit $status
