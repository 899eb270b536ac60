#!/usr/bin/env bash
# Sets everything up (apt packages, MeshLab sources, sample scans, build, plugin install) and
# runs every test through ctest: unit, property and end-to-end (meshlabserver + GUI) tests, and
# (issue 14) the PyMeshLab tests (tests/python) after scripts/setup_pymeshlab.sh, and (issue 15)
# the Blender tests (tests/blender) after scripts/setup_blender.sh.
# Then (issue 16) the unit tests again under ASan + UBSan (tests/run_sanitized.sh, build-asan)
# and a short libFuzzer smoke run of tests/fuzz/fuzz_mesh.cpp (scripts/fuzz.sh, build-fuzz).
# Arguments go to every ctest run. Environment: FITMAP_SKIP_SANITIZE=1 skips the sanitizer run,
# FITMAP_FUZZ_SECONDS (default 0 = skip) is the length of an optional fuzz smoke run.
set -euo pipefail
REPO=$(cd "$(dirname "$0")/.." && pwd)
# each phase's start and the total, so that a CI log shows where its 90 minutes went
t0=$(date +%s)
phase() { printf '[run_all] %s at +%d s (%s)\n' "$1" $(( $(date +%s) - t0 )) "$(date -u +%H:%M:%S)"; }
phase "setup"
bash "$REPO/scripts/setup.sh"
phase "setup_pymeshlab"
status=0
# PyMeshLab 2025.7 in .venv/ and the plugin for MeshLab's 2022.02+ interface (build-2025);
# ctest's PyMeshLab.pytest runs tests/python with it. A failure here (no PyPI, a build error)
# fails the run but still lets the MeshLab 2020.09 tests run.
bash "$REPO/scripts/setup_pymeshlab.sh" || { echo "run_all: scripts/setup_pymeshlab.sh failed" >&2; status=1; }
# Debian's Blender for tests/blender (issue 15: ctest's Blender.pytest, with .venv's pytest).
phase "setup_blender"
bash "$REPO/scripts/setup_blender.sh" || { echo "run_all: scripts/setup_blender.sh failed" >&2; status=1; }
phase "ctest"
(cd "${FITMAP_BUILD_DIR:-$REPO/build}" && ctest --output-on-failure -j"$(nproc)" "$@") || status=1
if [ "${FITMAP_SKIP_SANITIZE:-0}" != 1 ]; then
  phase "sanitizers"
  bash "$REPO/tests/run_sanitized.sh" "$@" || status=1
fi
if [ "${FITMAP_FUZZ_SECONDS:-0}" != 0 ]; then
  # from the seeds (tests/fuzz/make_seeds.py) in a scratch corpus, with a fixed libFuzzer seed
  corpus=$(mktemp -d)
  bash "$REPO/scripts/fuzz.sh" "${FITMAP_FUZZ_SECONDS}" "$corpus" -seed=1 || status=1
  rm -rf "$corpus"
fi
phase "done (status $status)"
exit $status
