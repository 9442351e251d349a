#!/usr/bin/env bash
# Frame time and idle CPU of the editor as a person sees it: a real window under Xvfb, drawn by
# Mesa's software Vulkan (lavapipe) when there is no GPU, at 1280x800, driven by PAPPUS_SCRIPT.
#
#   benches/frame_time.sh [BINARY ...]
#
# With several binaries (say the build before a change and after it), every measurement
# alternates between them, run after run, so both see the same machine in the same minutes.
# Default: the release build in $CARGO_TARGET_DIR (or target/).
#
# For each mesh — the default torus (288 quads), the Stanford bunny (69k triangles, from
# ../shared/models) and a 1.3M-triangle icosphere (`shape:icosphere:8`) — it prints the mean
# frame time over FRAMES frames after WAIT frames of settling (the script's `measure:N` step,
# which the editor logs), the process's CPU time per frame (all threads, lavapipe's included),
# and, with PAPPUS_FRAME_STATS=1 set by this script, the per-pass breakdown on stderr when
# VERBOSE=1. Then the idle CPU: the editor opened on the torus and left alone for 10 s once its
# script is done, as a percentage of one core (from /proc/PID/stat).
#
# Beside them, two floors. The editor's own: the same window with its mesh deleted (the torus
# opened, then Ctrl+Delete), every panel and system of the editor running with nothing to draw;
# issue 72's goals are ratios to it, and the table prints them. And Bevy's: Bevy alone in the
# same window, with the editor's two cameras and egui panels but no mesh and no editor systems
# (`benches/window_floor.rs`, built here with `cargo bench --no-run`; FLOOR=0 skips it). No
# change in Pappus takes a frame below that line.
#
# Median of REPEAT runs (default 3) for each figure. Needs xvfb-run and mesa-vulkan-drivers
# (`.ci/run` installs them).
set -euo pipefail

cd "$(dirname "$0")/.."
# Recoveries of this script's own runs (each ends with unsaved edits) go to a folder of their
# own, so no run opens behind the offer to restore the last one's.
XDG_STATE_HOME=$(mktemp -d)
export XDG_STATE_HOME
trap 'rm -rf "$XDG_STATE_HOME"' EXIT
FRAMES=${FRAMES:-40}
WAIT=${WAIT:-15}
REPEAT=${REPEAT:-3}
BINARIES=("$@")
if [ ${#BINARIES[@]} -eq 0 ]; then
  BINARIES=("${CARGO_TARGET_DIR:-target}/release/pappus")
fi
MODELS=../shared/models
TICK=$(getconf CLK_TCK)

median() { sort -g | awk '{a[NR]=$1} END {if (NR) print a[int((NR+1)/2)]; else print "-"}'; }
# The median of a space-separated list of figures.
median_of() { tr ' ' '\n' <<<"$1" | grep -v '^$' | median; }

# One run: prints "FRAME_MS CPU_MS" for BINARY on SOURCE, after the script steps PRELUDE (if
# any) and WAIT frames.
frame_run() {
  local out
  out=$(PAPPUS_FRAME_STATS=1 PAPPUS_SCRIPT="${3:-}wait:$WAIT;measure:$FRAMES;exit" \
    timeout 900 xvfb-run -a -s "-screen 0 1280x800x24" "$1" "$2" 2>&1 || true)
  if [ "${VERBOSE:-0}" = 1 ]; then
    grep -a "frame-stats:" <<<"$out" | sed 's/.*frame-stats: /    /' >&2 || true
  fi
  local ms cpu
  # An older build may not log every figure: a missing one reads "nan".
  ms=$(grep -ao "mean frame time [0-9.]* ms" <<<"$out" | awk '{print $4}' | tail -1 || true)
  cpu=$(grep -ao "process CPU [0-9.]* ms" <<<"$out" | awk '{print $3}' | tail -1 || true)
  echo "${ms:-nan} ${cpu:-nan}"
}

# One run: prints the CPU percentage of one core the editor used over 10 s of idling.
idle_run() {
  local log pid t0 t1
  log=$(mktemp)
  PAPPUS_SCRIPT="wait:$WAIT" xvfb-run -a -s "-screen 0 1280x800x24" "$1" assets/torus.obj \
    >"$log" 2>&1 &
  local runner=$!
  # The editor is the newest process running this binary.
  for _ in $(seq 1 100); do
    pid=$(pgrep -n -f "^$1" || true)
    [ -n "$pid" ] && grep -qa "render sync" "$log" && break
    sleep 0.2
  done
  sleep 5 # the script's frames, then quiet
  t0=$(awk '{print $14 + $15}' "/proc/$pid/stat")
  sleep 10
  t1=$(awk '{print $14 + $15}' "/proc/$pid/stat")
  kill "$pid" 2>/dev/null || true
  wait "$runner" 2>/dev/null || true
  rm -f "$log"
  awk -v a="$t0" -v b="$t1" -v t="$TICK" 'BEGIN {printf "%.1f\n", (b - a) / t / 10 * 100}'
}

# The floor bench's executable, built if need be (empty when FLOOR=0).
floor_binary() {
  [ "${FLOOR:-1}" = 0 ] && return
  cargo bench --bench window_floor --no-run --message-format=json 2>/dev/null |
    grep -o '"executable":"[^"]*window_floor[^"]*"' | tail -1 | cut -d'"' -f4
}

# One run of the floor: prints its mean frame time.
floor_run() {
  timeout 300 xvfb-run -a -s "-screen 0 1280x800x24" "$1" panels 2>/dev/null |
    grep -ao "mean frame time [0-9.]* ms" | awk '{print $4}' | tail -1 || true
}

declare -A FRAME CPU IDLE
FLOOR_BIN=$(floor_binary)
FLOORS=""
SOURCES=("assets/torus.obj" "$MODELS/stanford-bunny.obj" "shape:icosphere:8" "assets/torus.obj")
NAMES=("torus (288 quads)" "bunny (69k triangles)" "icosphere:8 (1.3M triangles)"
  "the editor's floor: its mesh deleted")
# The editor's floor (the last source) deletes its mesh five frames in.
PRELUDES=("" "" "" "wait:5;key:Ctrl+Delete;")
OWN_FLOOR=3
for r in $(seq 1 "$REPEAT"); do
  for i in "${!SOURCES[@]}"; do
    for b in "${!BINARIES[@]}"; do
      read -r ms cpu < <(frame_run "${BINARIES[$b]}" "${SOURCES[$i]}" "${PRELUDES[$i]}")
      FRAME[$b,$i]+="$ms "
      CPU[$b,$i]+="$cpu "
      echo "run $r: ${BINARIES[$b]} ${NAMES[$i]}: $ms ms a frame, $cpu ms CPU" >&2
    done
  done
  for b in "${!BINARIES[@]}"; do
    IDLE[$b]+="$(idle_run "${BINARIES[$b]}") "
  done
  if [ -n "$FLOOR_BIN" ]; then
    f=$(floor_run "$FLOOR_BIN")
    FLOORS+="${f:-nan} "
    echo "run $r: floor (Bevy, cameras and panels, no mesh): ${f:-nan} ms a frame" >&2
  fi
done

echo "| mesh (1280x800, lavapipe) | binary | frame ms (median of $REPEAT) | CPU ms a frame |"
echo "|---|---|---|---|"
for i in "${!SOURCES[@]}"; do
  for b in "${!BINARIES[@]}"; do
    f=$(median_of "${FRAME[$b,$i]}")
    c=$(median_of "${CPU[$b,$i]}")
    echo "| ${NAMES[$i]} | ${BINARIES[$b]} | $f | $c |"
  done
done
BEVY_FLOOR=nan
if [ -n "$FLOOR_BIN" ]; then
  BEVY_FLOOR=$(median_of "$FLOORS")
  echo "| floor: Bevy, the editor's cameras and panels, no mesh | window_floor | $BEVY_FLOOR | — |"
fi
for b in "${!BINARIES[@]}"; do
  d=$(median_of "${IDLE[$b]}")
  echo "| idle 10 s, torus | ${BINARIES[$b]} | — | $d % of a core |"
done
# The ratios of issue 72: each binary's torus and bunny against its own floor (the medians above),
# and against Bevy's.
ratio() { awk -v a="$1" -v b="$2" 'BEGIN {if (a + 0 > 0 && b + 0 > 0) printf "%.2f", a / b; else print "-"}'; }
echo
echo "| binary | torus / its floor | bunny / its floor | torus / Bevy's floor | bunny / Bevy's floor |"
echo "|---|---|---|---|---|"
for b in "${!BINARIES[@]}"; do
  t=$(median_of "${FRAME[$b,0]}")
  n=$(median_of "${FRAME[$b,1]}")
  o=$(median_of "${FRAME[$b,$OWN_FLOOR]}")
  echo "| ${BINARIES[$b]} | $(ratio "$t" "$o") | $(ratio "$n" "$o") | $(ratio "$t" "$BEVY_FLOOR") | $(ratio "$n" "$BEVY_FLOOR") |"
done
