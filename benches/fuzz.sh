#!/usr/bin/env bash
# Coverage-guided fuzzing (libFuzzer, through cargo-fuzz) of every reader and of the step parser:
# the targets are fuzz/fuzz_targets/*.rs, whose bodies are `pappus::fuzzing::run`.
#
#   benches/fuzz.sh seed [BINARY]             makes the seed corpus (fuzz/corpus/TARGET/) from
#                                             ../shared/models with a built pappus (default: the
#                                             debug build in the target folder)
#   benches/fuzz.sh [MINUTES] [TARGET...]     fuzzes each target for MINUTES (default 10) on its
#                                             corpus, minimises the corpus, and prints each
#                                             target's executions, coverage and crashes
#
# A crash is saved under fuzz/artifacts/TARGET/; copy it into fuzz/regressions/TARGET/ once it
# is fixed, and `cargo test` replays it (with the corpus) from then on. Needs cargo-fuzz
# (`cargo install cargo-fuzz`; installed here if missing) and runs on the stable toolchain with
# `--sanitizer none` (Pappus's own code has no unsafe memory handling to sanitise beyond a few
# libc calls), or on nightly with ASan when FUZZ_SANITIZER=address.
set -euo pipefail
cd "$(dirname "$0")/.."
targets_all=(read_obj read_off read_ply read_stl read_dae read_glb parse_step)

seed() {
  local bin="${1:-${CARGO_TARGET_DIR:-target}/debug/pappus}"
  local models="../shared/models" out="fuzz/corpus"
  mkdir -p "$out"/{read_obj,read_off,read_ply,read_stl,read_dae,read_glb,parse_step}
  # COLLADA: the hand-written documents kept in fuzz/corpus/read_dae (every primitive, input,
  # transform and instance kind); the course scenes are not copied into the repository.
  # OBJ: the head of every shared model as it is (comments, groups, vt/vn, faces that name
  # vertices past the cut), cut at a line end.
  for f in "$models"/*.obj; do
    head -c 3000 "$f" | sed '$d' >"$out/read_obj/head-$(basename "$f")"
  done
  # Every format, from small simplified models; PLY with quality and colours, OBJ and PLY with
  # normals and UVs.
  for f in spot cow fandisk suzanne teapot; do
    for ext in obj off ply stl glb; do
      "$bin" process "$models/$f.obj" -o "$out/read_$ext/$f.$ext" triangulate simplify-faces:48 \
        >/dev/null 2>&1 || true
    done
  done
  "$bin" process "$models/bunny-disk.obj" -o "$out/read_obj/disk-uv.obj" --normals angle \
    simplify-faces:40 param:mean-value >/dev/null
  "$bin" process "$models/bunny-disk.obj" -o "$out/read_ply/disk-uv.ply" --normals angle \
    simplify-faces:40 param:lscm >/dev/null
  "$bin" process "$models/spot.obj" -o "$out/read_ply/spot-quality.ply" --quantity mean \
    simplify-faces:40 >/dev/null
  printf 'ply\nformat ascii 1.0\ncomment hand-written\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0 255 0 0\n1 0 0 0 255 0\n1 1 0 0 0 255\n0 1 0 9 9 9\n3 0 1 2\n3 0 2 3\n' \
    >"$out/read_ply/ascii.ply"
  printf 'solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n' \
    >"$out/read_stl/ascii.stl"
  printf 'COFF\n3 1 0\n0 0 0 1 0 0 1\n1 0 0 0 1 0 1\n0 1 0 0 0 1 1\n3 0 1 2\n' >"$out/read_off/coff.off"
  # Steps: every form the syntax names.
  local i=0
  for step in validate triangulate flip:3,17 split:0,1 bisect:0,1 collapse:2,5 dissolve:4,7 \
    split-face:1,3 fill-hole:0,9 seam:1,2 loop loop:2 catmull-clark:3 simplify:0.25 \
    simplify-faces:500 refine refine:5000 remesh remesh:3:0.5 smooth:uniform smooth:cotan:3 \
    smooth:implicit:2:0.5 smooth:taubin param:lscm param:harmonic:square extrude:0,1,2:0.5 \
    inset:0,1,2/1,2,3:0.2:0.1 bevel:0,1:0.2 erase:0,1,2 dissolve:4 collapse:0,1,2 weld:0,1/2,3; do
    printf '%s' "$step" >"$out/parse_step/step-$i"
    i=$((i + 1))
  done
  echo "seeded: $(find "$out" -type f | wc -l) files"
}

if [[ "${1:-}" == seed ]]; then
  shift
  seed "$@"
  exit 0
fi

minutes="${1:-10}"
shift || true
targets=("$@")
((${#targets[@]})) || targets=("${targets_all[@]}")
command -v cargo-fuzz >/dev/null || cargo install cargo-fuzz --locked
sanitizer="${FUZZ_SANITIZER:-none}"
toolchain=()
[[ "$sanitizer" == none ]] || toolchain=(+nightly)

# Build every target once, then run the binaries: the source may change while they run.
cargo "${toolchain[@]}" fuzz build --sanitizer "$sanitizer"
bin_dir="fuzz/target/$(rustc -vV | sed -n 's/^host: //p')/release"

summary=()
for t in "${targets[@]}"; do
  log="$(mktemp)"
  mkdir -p "fuzz/corpus/$t" "fuzz/artifacts/$t"
  before=$(find "fuzz/artifacts/$t" -type f | wc -l)
  "$bin_dir/$t" "fuzz/corpus/$t" -artifact_prefix="fuzz/artifacts/$t/" \
    -max_total_time=$((minutes * 60)) -max_len=8192 -timeout=10 -rss_limit_mb=2048 \
    -print_final_stats=1 2>"$log" || true
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' | tail -1)
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*')
  features=$(grep -o 'ft: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*')
  crashes=$(($(find "fuzz/artifacts/$t" -type f | wc -l) - before))
  grep -E '^(==|thread|panicked|SUMMARY)' "$log" | head -20 || true
  # Keep the corpus small: only the inputs that add coverage (libFuzzer's merge).
  minimised="$(mktemp -d)"
  "$bin_dir/$t" -merge=1 "$minimised" "fuzz/corpus/$t" >/dev/null 2>&1 &&
    rm -rf "fuzz/corpus/$t" && mv "$minimised" "fuzz/corpus/$t" || rm -rf "$minimised"
  summary+=("$(printf '%-11s %3s min  %12s execs  cov %6s  ft %6s  crashes %s  corpus %s' \
    "$t" "$minutes" "${execs:-?}" "${cov:-?}" "${features:-?}" "$crashes" \
    "$(find "fuzz/corpus/$t" -type f | wc -l)")")
  rm -f "$log"
done
printf '%s\n' "${summary[@]}"
