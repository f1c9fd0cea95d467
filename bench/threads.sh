#!/usr/bin/env bash
# Measures how much faster the desktop renderer is on two threads than on one (the target is at
# least 1.8x), from the `render: X ms` line of examples/render.
#
#   bench/threads.sh [SCENE.toml] [RENDER ARGS...]    (default scene: bench/scenes/target.toml)
#   bench/threads.sh bench/scenes/target.toml --width 64 --height 48    # ~fixed overhead only
#
# Environment: RUNS (default 21) measured pairs, WARMUP (default 3) pairs run first and
# discarded. Extra arguments after the scene are passed to every render (e.g. a tiny frame).
#
# Why this shape: the machine is a shared 2-vCPU VM whose load changes from second to second, so
# one timing (or the best of a few) says little, and timings of 1 and 2 threads taken minutes
# apart are not comparable. The runs are therefore interleaved (1,2,1,2,...) so that both see
# the same background, and reported as medians, which ignore the occasional run hit by another
# process. Two ratios are given: of the two medians, and the median of the per-pair ratios
# (each 2-thread run against the 1-thread run just before it), with the pair ratios' min/max
# to show the spread. Quote ratios from one run of this script, never across runs.
#
# Output: key=value lines (cpus=, runs=, warmup=, threads1_median_ms=, threads2_median_ms=,
# ratio_of_medians=, pair_ratio_median=, pair_ratio_min=, pair_ratio_max=, and the raw
# timings threads1_ms= / threads2_ms=). With fewer than 2 CPUs it says so and exits 0.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
runs=${RUNS:-21}
warmup=${WARMUP:-3}
scene=${1:-$here/scenes/target.toml}
if [ $# -gt 0 ]; then shift; fi
extra=("$@")

cpus=$(nproc)
echo "cpus=$cpus"
if [ "$cpus" -lt 2 ]; then
  echo "fewer than 2 CPUs: a 1- against 2-thread comparison means nothing here; not measuring"
  exit 0
fi

cargo build --quiet --release --example render --manifest-path "$root/Cargo.toml"
render=$root/target/release/examples/render
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

# Prints the `render:` time in ms of one run on $1 threads.
time_ms() {
  local line
  line=$("$render" "$scene" -o "$out/t$1.png" --threads "$1" "${extra[@]}" | grep '^render: ')
  line=${line#render: }
  echo "${line% ms}"
}

t1=()
t2=()
for i in $(seq $((warmup + runs))); do
  a=$(time_ms 1)
  b=$(time_ms 2)
  if [ "$i" -gt "$warmup" ]; then
    t1+=("$a")
    t2+=("$b")
  fi
done

echo "runs=$runs"
echo "warmup=$warmup"
echo "scene=$scene${extra[*]:+ ${extra[*]}}"
python3 - "${t1[*]}" "${t2[*]}" <<'PY'
import statistics, sys
t1 = [float(x) for x in sys.argv[1].split()]
t2 = [float(x) for x in sys.argv[2].split()]
pairs = [a / b for a, b in zip(t1, t2)]
m1, m2 = statistics.median(t1), statistics.median(t2)
print(f"threads1_median_ms={m1:.2f}")
print(f"threads2_median_ms={m2:.2f}")
print(f"ratio_of_medians={m1 / m2:.3f}")
print(f"pair_ratio_median={statistics.median(pairs):.3f}")
print(f"pair_ratio_min={min(pairs):.3f}")
print(f"pair_ratio_max={max(pairs):.3f}")
print("threads1_ms=" + " ".join(f"{x:g}" for x in t1))
print("threads2_ms=" + " ".join(f"{x:g}" for x in t2))
PY
