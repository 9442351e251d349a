#!/usr/bin/env bash
# `pappus process` over the shared models three ways, rounds alternating: one process per file
# in turn, one process with -j 1, one with -j 2. Prints the wall-clock seconds of each and the
# ratios.
#
#   benches/batch_process.sh [BINARY] [ROUNDS]     (default: the release build, 3 rounds)
set -euo pipefail
cd "$(dirname "$0")/.."
bin="${1:-${CARGO_TARGET_DIR:-target}/release/pappus}"
rounds="${2:-3}"
models="$(cd ../shared/models && pwd)"
steps=(triangulate simplify:0.5)
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
seconds() {
  local start end
  start=$(date +%s.%N)
  "$@" >/dev/null 2>&1 || true
  end=$(date +%s.%N)
  echo "$end - $start" | bc
}
one_by_one() {
  for f in "$models"/*.obj; do
    "$bin" process "$f" -o "$out/seq-$(basename "$f" .obj).ply" "${steps[@]}"
  done
}
for round in $(seq "$rounds"); do
  seq=$(seconds one_by_one)
  j1=$(seconds "$bin" process "$models/*.obj" -o "$out/j1-{stem}.ply" -j 1 "${steps[@]}")
  j2=$(seconds "$bin" process "$models/*.obj" -o "$out/j2-{stem}.ply" -j 2 "${steps[@]}")
  printf 'round %s: one by one %.3f s, -j 1 %.3f s, -j 2 %.3f s; -j 2 / one by one %.3f, -j 2 / -j 1 %.3f\n' \
    "$round" "$seq" "$j1" "$j2" "$(echo "$j2 / $seq" | bc -l)" "$(echo "$j2 / $j1" | bc -l)"
done
