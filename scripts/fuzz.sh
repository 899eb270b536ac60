#!/usr/bin/env bash
# Builds the libFuzzer target tests/fuzz/fuzz_mesh.cpp (clang, -DFITMAP_FUZZ=ON: vcg_ext under
# ASan + UBSan with coverage) in its own build dir and fuzzes the mesh-facing entry points.
#   scripts/fuzz.sh [SECONDS [CORPUS_DIR [libFuzzer options...]]]
# SECONDS defaults to 600; CORPUS_DIR (default <build>/corpus) is seeded by tests/fuzz/make_seeds.py
# when empty and grows with every run. A crash, sanitizer report, broken invariant (fuzz_mesh
# aborts with a message) or hang (> 10 s per input) stops the run: the input is saved as
# <build>/artifacts/crash-* (or timeout-*), and `<build>/fuzz_mesh FILE` replays it.
# Needs the MeshLab sources that scripts/setup.sh fetches (run that first).
# Environment: FITMAP_FUZZ_BUILD_DIR (default <repo>/build-fuzz).
set -euo pipefail
REPO=$(cd "$(dirname "$0")/.." && pwd)
BUILD="${FITMAP_FUZZ_BUILD_DIR:-$REPO/build-fuzz}"
SECONDS_TO_RUN="${1:-600}"
CORPUS="${2:-$BUILD/corpus}"
shift $(( $# < 2 ? $# : 2 ))
log() { printf '[fuzz] %s\n' "$*" >&2; }

# clang with its sanitizer/libFuzzer runtimes and OpenMP runtime (not in scripts/setup.sh's list).
PKGS=(clang libclang-rt-14-dev libomp-14-dev)
missing=()
for p in "${PKGS[@]}"; do dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p"); done
if [ ${#missing[@]} -gt 0 ]; then
  log "installing: ${missing[*]}"
  apt-get update -q >/dev/null
  DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${missing[@]}" >/dev/null
fi

log "building fuzz_mesh in $BUILD"
# Debug with -O1: asserts (Eigen, vcglib) stay on; still hundreds of inputs a second.
cmake -S "$REPO" -B "$BUILD" -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DFITMAP_FUZZ=ON \
      -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-g -O1" \
      -DMESHLAB_SRC_DIR="$REPO/.deps/meshlab-2020.09+dfsg1" -DFITMAP_DATA_DIR="$REPO/.deps/data/meshes" >/dev/null
if ! cmake --build "$BUILD" --target fuzz_mesh -j"$(nproc)" > "$BUILD/build.log" 2>&1; then
  grep -E 'error' -A3 "$BUILD/build.log" | head -40 >&2; log "build failed (full log: $BUILD/build.log)"; exit 1
fi

mkdir -p "$CORPUS" "$BUILD/artifacts"
if [ -z "$(ls -A "$CORPUS")" ]; then python3 "$REPO/tests/fuzz/make_seeds.py" "$CORPUS"; fi
# One OpenMP thread: a saved input replays the same way. Every sanitizer report stops the run
# (fuzz_mesh frees the attributes it creates, so no leak suppression is needed).
export OMP_NUM_THREADS=1
export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:abort_on_error=0"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
log "fuzzing for ${SECONDS_TO_RUN} s (corpus $CORPUS)"
"$BUILD/fuzz_mesh" -max_total_time="$SECONDS_TO_RUN" -max_len=1200 -timeout=10 -print_final_stats=1 \
  -artifact_prefix="$BUILD/artifacts/" "$@" "$CORPUS"
