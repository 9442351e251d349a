#!/usr/bin/env bash
# The editor on a 1.3 M-triangle icosphere (`shape:icosphere:8`) as a person uses it: opened,
# orbited, an edge flipped, a vertex moved — each frame as long as it lasts on screen, in a real
# window under Xvfb drawn by Mesa's software Vulkan (lavapipe) when there is no GPU, 1280x800.
#
#   benches/large_mesh_frames.sh [BINARY ...]
#
# With several binaries, each run alternates between them. For each it prints the open (the
# read and build the editor logs, then the first render sync), and for each phase the mean and
# the longest frame (the script's `measure:N` step times each frame on the wall clock): the mesh
# standing still, the ten frames after the camera turned 90° (each draws the whole mesh anew,
# as every frame of an orbit does), the frame of a flip and the 40 after it (the panel's
# figures are counted, and 2 s on the mesh written for recovery), the frame of a move (G, Z,
# 0.1, Enter) and the 40 after it.
# Median of REPEAT runs (default 3). Needs xvfb-run and mesa-vulkan-drivers.
set -euo pipefail

cd "$(dirname "$0")/.."
# Recoveries of this script's own runs (each ends with unsaved edits) go to a folder of their
# own, so no run opens behind the offer to restore the last one's.
XDG_STATE_HOME=$(mktemp -d)
export XDG_STATE_HOME
trap 'rm -rf "$XDG_STATE_HOME"' EXIT
REPEAT=${REPEAT:-3}
BINARIES=("$@")
if [ ${#BINARIES[@]} -eq 0 ]; then
  BINARIES=("${CARGO_TARGET_DIR:-target}/release/pappus")
fi
# Vertex 0 and its neighbour 163842 are a corner of the icosahedron and its first split point.
SCRIPT="wait:20;measure:20;orbit:90,-20;measure:10;"
SCRIPT+="select-edge:0,163842;wait:5;key:Alt+R;measure:1;measure:40;"
SCRIPT+="select-vertex:0;wait:5;key:G;key:Z;key:0;key:Period;key:1;key:Enter;measure:1;measure:40;exit"
PHASES=("still" "orbit" "flip" "after flip" "move" "after move")

median() { sort -g | awk '{a[NR]=$1} END {if (NR) print a[int((NR+1)/2)]; else print "-"}'; }

declare -A MEAN LONGEST OPEN SYNC
for r in $(seq 1 "$REPEAT"); do
  for b in "${!BINARIES[@]}"; do
    out=$(PAPPUS_SCRIPT="$SCRIPT" \
      timeout 900 xvfb-run -a -s "-screen 0 1280x800x24" "${BINARIES[$b]}" shape:icosphere:8 2>&1 || true)
    OPEN[$b]+="$(grep -ao 'open shape:icosphere:8: .*(\([0-9.]*\) ms)' <<<"$out" | grep -o '([0-9.]* ms)' | tr -d '(ms)' | head -1) "
    SYNC[$b]+="$(grep -ao 'render sync [^:]*: 1310720 triangles in [0-9.]* ms' <<<"$out" | awk '{print $(NF-1)}' | head -1) "
    # One frame_time line per measure step, in the script's order.
    i=0
    while read -r mean longest; do
      MEAN[$b,$i]+="$mean "
      LONGEST[$b,$i]+="$longest "
      i=$((i + 1))
    done < <(grep -ao 'mean frame time [0-9.]* ms over [0-9]* frames (the longest [0-9.]* ms)' <<<"$out" |
      sed 's/mean frame time \([0-9.]*\) ms.*longest \([0-9.]*\) ms)/\1 \2/')
    echo "run $r: ${BINARIES[$b]} done ($i phases)" >&2
  done
done

echo "| icosphere:8 (1.3M triangles), lavapipe 1280x800 | binary | ms: mean / longest frame (median of $REPEAT) |"
echo "|---|---|---|"
for b in "${!BINARIES[@]}"; do
  o=$(tr ' ' '\n' <<<"${OPEN[$b]}" | grep -v '^$' | median)
  s=$(tr ' ' '\n' <<<"${SYNC[$b]}" | grep -v '^$' | median)
  echo "| open (read and build / first render sync) | ${BINARIES[$b]} | $o / $s |"
done
for i in "${!PHASES[@]}"; do
  for b in "${!BINARIES[@]}"; do
    m=$(tr ' ' '\n' <<<"${MEAN[$b,$i]:-}" | grep -v '^$' | median)
    l=$(tr ' ' '\n' <<<"${LONGEST[$b,$i]:-}" | grep -v '^$' | median)
    echo "| ${PHASES[$i]} | ${BINARIES[$b]} | $m / $l |"
  done
done
