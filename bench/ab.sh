#!/usr/bin/env bash
# A/B timing of two builds of the desktop renderer on one scene: N interleaved pairs of runs
# (one thread each, or `THREADS=N`), medians of each and of the per-pair ratios, and whether the
# PNGs agree.
# Compare only the ratios of one run: the machines here are shared and noisy.
#
#   bench/ab.sh OLD_RENDER NEW_RENDER [N=21] [SCENE=bench/scenes/target.toml]
#
# Times the renderer's `render:` line; `LINE='scene file' bench/ab.sh ...` times another of its
# `NAME: X ms` lines (`scene file:`, reading and checking the TOML); `THREADS=2 bench/ab.sh ...`
# renders on two threads (on an otherwise idle machine).
#
# OLD_RENDER and NEW_RENDER are copies of target/release/examples/render built from the two
# versions (e.g. `git stash; cargo build --release --example render; cp ... /tmp/old`).
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: $0 OLD_RENDER NEW_RENDER [N] [SCENE]" >&2; exit 2; }
a=$1 b=$2 n=${3:-21}
scene=${4:-$(dirname "$0")/scenes/target.toml}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
line=${LINE:-render}
threads=${THREADS:-1}
ms() { "$1" "$scene" -o "$2" --threads "$threads" | sed -n "s/^$line: \(.*\) ms\$/\1/p"; }
for _ in $(seq "$n"); do
  ms "$a" "$out/a.png" >> "$out/a.txt"
  ms "$b" "$out/b.png" >> "$out/b.txt"
done
python3 - "$out/a.txt" "$out/b.txt" <<'PY'
import statistics as st, sys
a = [float(x) for x in open(sys.argv[1])]
b = [float(x) for x in open(sys.argv[2])]
print(f"old_median_ms={st.median(a):.2f} new_median_ms={st.median(b):.2f} "
      f"old_over_new={st.median(a) / st.median(b):.3f} "
      f"per_pair_old_over_new={st.median([x / y for x, y in zip(a, b)]):.3f} pairs={len(a)}")
PY
if cmp -s "$out/a.png" "$out/b.png"; then echo "png=same"; else echo "png=differs"; fi
