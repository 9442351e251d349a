#!/usr/bin/env bash
# A newcomer's first hour, timed (issue 73): a fresh clone of this checkout's HEAD in a folder
# of its own, with its own empty target folder, then the README's build command and the
# README's test command, each timed. The cargo registry is the machine's (downloads are not
# what is measured). Run it on a quiet machine: it takes half an hour on 2 cores.
#
#   benches/cold_test_time.sh [WORKDIR]      (default /tmp/pappus-cold)
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
work=${1:-/tmp/pappus-cold}
rm -rf "$work"
git clone -q "$here" "$work/pappus"
ln -s "$here/../shared" "$work/shared" 2>/dev/null || true
cd "$work/pappus"
export CARGO_TARGET_DIR="$work/target"
unset RUSTFLAGS
stamp() { date +%s; }
t0=$(stamp)
cargo build --release --locked 2>&1 | tail -1
t1=$(stamp)
cargo test --release --features checked --locked --no-run 2>&1 | tail -1
t1b=$(stamp)
cargo test --release --features checked --locked 2>&1 | tee "$work/test.log" | grep -E "^test result|FAILED|panicked" | tail -5 || true
t2=$(stamp)
passed=$(grep -Eo "[0-9]+ passed" "$work/test.log" | awk '{s+=$1} END {print s}')
failed=$(grep -Eo "[0-9]+ failed" "$work/test.log" | awk '{s+=$1} END {print s}')
echo "commit $(git rev-parse --short HEAD), $(nproc) cores"
echo "cargo build --release: $(( (t1 - t0) / 60 )) min $(( (t1 - t0) % 60 )) s"
echo "cargo test --release --features checked: $(( (t2 - t1) / 60 )) min $(( (t2 - t1) % 60 )) s in all (build $(( (t1b - t1) / 60 )) min $(( (t1b - t1) % 60 )) s, run $(( (t2 - t1b) / 60 )) min $(( (t2 - t1b) % 60 )) s), $passed passed, ${failed:-0} failed"
