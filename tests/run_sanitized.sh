#!/usr/bin/env bash
# The unit tests under AddressSanitizer + UndefinedBehaviorSanitizer (issue 16), run by
# tests/run_all.sh after the normal ctest run; needs scripts/setup.sh's packages and sources.
# Builds vcg_ext and the unit tests with -DFITMAP_SANITIZE=ON (Debug at -O1: asserts on) in their
# own build dir and runs them through ctest; any sanitizer report (memory error, undefined
# behaviour, leak) fails its test. The plugin and the e2e tests are not part of this build (Debian's
# meshlabserver is not sanitized). Arguments go to ctest (e.g. -L fitmaps, -R 'Fitmaps\.').
# Environment: FITMAP_ASAN_BUILD_DIR (default <repo>/build-asan); FITMAP_ASAN_ALL=1 runs every unit
# test. By default the 19 unit tests that take more than 12 s in Release on a slow 2-core machine
# (2026-12-05; 3-6 times that under ASan: 224 s for the count-pass test) are left out here: they
# rerun, on real scans and many times over, the code paths the other tests run under the
# sanitizers on small inputs, and with them the CI's sanitizer run took more than 30 min and CI its
# 90-min limit. They still run in the Release ctest.
ASAN_SLOW='^(QuadSimplify\.(ThreadCountDoesNotChangeTheResult|BudgetNotReachedFromAStartTooCoarseIsRefined|CountPassBesideTheLayoutPassGivesTheSequentialCage|CountOnARefusedCountStartRunsBesideTheLayoutPass|StartTooCoarseForTheInputIsRefined|BudgetStoppedByTheThinPartGuardGoesDownTheLadder|EqualizedLayoutKeepsTheCloserOfTheTwoCagesOnSmallMeshes|EqualizedLayoutSpendsThePaperCountByTheSFitmap|RealScansKeepTheGuarantees)|CCFit\.(KeepsTheIterateWithTheLowestDataRms|DampingRetriesRecoverFromAnOvershootingSolve)|LayoutTrials\.(KeepTheLayoutThatFitsClosest|EachTrialGoesDownItsOwnLadder)|TriToQuadProperty\.(EveryManifoldMeshOfTheDataSet|MidpointRefinedMeshes)|LoopSurface\.AgreesWithOpenSubdivSmooth|LoopVcg\.EntryPointsOnVcgMesh|LoopInterpolate\.ResidualAndCusps|Fitmaps\.WorkingResolutionAgreesWithTheFullComputation)$'
set -euo pipefail
REPO=$(cd "$(dirname "$0")/.." && pwd)
BUILD="${FITMAP_ASAN_BUILD_DIR:-$REPO/build-asan}"
log() { printf '[sanitize] %s\n' "$*" >&2; }

log "building vcg_ext and the unit tests with ASan + UBSan in $BUILD"
cmake -S "$REPO" -B "$BUILD" -DFITMAP_SANITIZE=ON -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-g -O1" \
      -DMESHLAB_SRC_DIR="$REPO/.deps/meshlab-2020.09+dfsg1" -DFITMAP_DATA_DIR="$REPO/.deps/data/meshes" >/dev/null
if ! cmake --build "$BUILD" -j"$(nproc)" > "$BUILD/build.log" 2>&1; then
  grep -E 'error|Error' -A3 "$BUILD/build.log" | head -60 >&2; log "build failed (full log: $BUILD/build.log)"; exit 1
fi

# halt_on_error: the first report ends the test with a non-zero exit (UBSan is also built with
# -fno-sanitize-recover); detect_leaks: LeakSanitizer at exit; tests/lsan.supp names the
# third-party leaks that are expected.
export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:abort_on_error=0:strict_string_checks=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
export LSAN_OPTIONS="suppressions=$REPO/tests/lsan.supp:print_suppressions=0"
cd "$BUILD"
leave_out=()
if [ "${FITMAP_ASAN_ALL:-0}" != 1 ]; then
  log "leaving out the 19 slowest unit tests (FITMAP_ASAN_ALL=1 runs them too)"
  leave_out=(-E "$ASAN_SLOW")
fi
ctest --output-on-failure -j"$(nproc)" "${leave_out[@]}" "$@"
