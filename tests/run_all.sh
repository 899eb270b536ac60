#!/usr/bin/env bash
# Sets everything up (apt packages, MeshLab sources, sample scans, build, plugin install) and
# runs every test through ctest: unit, property and end-to-end (meshlabserver + GUI) tests.
set -euo pipefail
REPO=$(cd "$(dirname "$0")/.." && pwd)
bash "$REPO/scripts/setup.sh"
cd "${FITMAP_BUILD_DIR:-$REPO/build}"
ctest --output-on-failure -j"$(nproc)" "$@"
