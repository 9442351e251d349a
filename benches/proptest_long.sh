#!/usr/bin/env bash
# The property tests' long run: `cargo test` runs each with 64 cases (enough for every edit
# kind on every shape); this runs them with PAPPUS_PROPTEST_CASES cases (default 1 024), in
# release-optimised test builds as `cargo test` makes them. A failing case is saved in
# tests/NAME.proptest-regressions, which `cargo test` then replays first: commit it with the fix.
#
#   benches/proptest_long.sh [CASES]
set -euo pipefail
cd "$(dirname "$0")/.."
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$HOME/.cache/pappus/target}"
export PAPPUS_PROPTEST_CASES="${1:-1024}"
time cargo test --test local_ops_props --test editing_props -- --nocapture
