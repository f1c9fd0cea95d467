#!/usr/bin/env bash
# How much longer one scene's frame takes than another's with the same build: N interleaved
# pairs of one-thread renders (A, B, A, B, ...), medians of each and of the per-pair ratios
# B/A with their spread. For 16 -> 256 spheres, against the target of at most 2x per frame:
#
#   bench/ratio.sh bench/scenes/spread16_shadowed.toml bench/scenes/spread256_shadowed.toml
#
# Why not criterion's table: its 10 samples of one benchmark are taken seconds away from the
# other's, and this shared machine's speed moves by 20-40% from second to second, so its
# 16 -> 256 ratios swung from 1.5x to 2.5x between runs of the same build. Interleaved pairs
# see the same load. The scenes are benches/render.rs's, written as files by
# bench/spread_scenes.py. RENDER=path/to/render measures another build. Output: key=value lines (a_median_ms=, b_median_ms=,
# ratio_of_medians=, pair_ratio_median=, pair_ratio_min=, pair_ratio_max=, pairs=).
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: $0 SCENE_A SCENE_B [N=21]" >&2; exit 2; }
root=$(cd "$(dirname "$0")/.." && pwd)
a=$1 b=$2 n=${3:-21}
render=${RENDER:-}
if [ -z "$render" ]; then
  cargo build --quiet --release --example render --manifest-path "$root/Cargo.toml"
  render=$root/target/release/examples/render
fi
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
ms() { "$render" "$1" -o "$out/x.png" --threads 1 | sed -n 's/^render: \(.*\) ms$/\1/p'; }
for _ in 1 2 3; do ms "$a" > /dev/null; ms "$b" > /dev/null; done
for _ in $(seq "$n"); do
  ms "$a" >> "$out/a.txt"
  ms "$b" >> "$out/b.txt"
done
python3 - "$out/a.txt" "$out/b.txt" <<'PY'
import statistics as st, sys
a = [float(x) for x in open(sys.argv[1])]
b = [float(x) for x in open(sys.argv[2])]
r = [y / x for x, y in zip(a, b)]
print(f"a_median_ms={st.median(a):.2f}")
print(f"b_median_ms={st.median(b):.2f}")
print(f"ratio_of_medians={st.median(b) / st.median(a):.3f}")
print(f"pair_ratio_median={st.median(r):.3f}")
print(f"pair_ratio_min={min(r):.3f}")
print(f"pair_ratio_max={max(r):.3f}")
print(f"pairs={len(r)}")
PY
