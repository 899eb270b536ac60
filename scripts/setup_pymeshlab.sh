#!/usr/bin/env bash
# Idempotent set-up of the MeshLab 2022.02+ plugin for PyMeshLab (issue 14), on Debian 12 as root:
#   1. MeshLab 2025.07's sources (src/common + src/vcglib) from Debian unstable's SOURCE package:
#      a deb-src entry for unstable is added only for `apt-get source --download-only` and removed
#      again (nothing from unstable is installed; no binary entry, no pin). The .dsc is 404 on the
#      mirror, so the upstream tarball (checked by its sha256) is unpacked with tar into
#      .deps/meshlab-2025.07.
#   2. .venv/ at the repository root: PyMeshLab 2025.7.post1 from PyPI, and pytest.
#   3. build-2025: cmake -DFITMAP_MESHLAB_API=2025 (vcg_ext + the FilterPlugin plugin, double;
#      decimate.cpp against MeshLab 2020.09's vcglib, fetched by scripts/setup.sh if missing).
#   4. The plugin copied into the venv's pymeshlab/lib/plugins/, so `import pymeshlab` loads it.
# Needs the build packages of scripts/setup.sh (installs the ones it uses if missing).
# Environment: FITMAP_JOBS (default nproc) build jobs.
set -euo pipefail
REPO=$(cd "$(dirname "$0")/.." && pwd)
DEPS="$REPO/.deps"
SRC="$DEPS/meshlab-2025.07"
VENV="$REPO/.venv"
BUILD="$REPO/build-2025"
PYMESHLAB_VERSION=2025.7.post1
ORIG=meshlab_2025.07~dfsg.orig.tar.xz
ORIG_SHA256=d22c98d362f2a284e481af8dbfc272b2222f5b9c67b3cf8bec57d1c3161886f4
UNSTABLE_LIST=/etc/apt/sources.list.d/fitmap-unstable-src.list
log() { printf '[setup_pymeshlab] %s\n' "$*" >&2; }
export DEBIAN_FRONTEND=noninteractive

PKGS=(build-essential cmake pkg-config qtbase5-dev libqt5opengl5-dev libeigen3-dev libembree-dev
      libosd-dev libpng-dev libsuitesparse-dev libopenblas0-openmp python3 python3-venv xz-utils dpkg-dev)
missing=()
for p in "${PKGS[@]}"; do dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p"); done
if [ ${#missing[@]} -gt 0 ]; then
  log "installing: ${missing[*]}"
  apt-get update -q >/dev/null
  apt-get install -y -q --no-install-recommends "${missing[@]}" >/dev/null
fi

# ------------------------------------------------------------------ 1. MeshLab 2025.07 sources
if [ ! -f "$SRC/src/common/plugins/interfaces/filter_plugin.h" ]; then
  mkdir -p "$DEPS"
  tmp=$(mktemp -d)
  cleanup() {
    if [ -f "$UNSTABLE_LIST" ]; then rm -f "$UNSTABLE_LIST"; apt-get update -q >/dev/null 2>&1 || true; fi
    rm -rf "$tmp"
  }
  trap cleanup EXIT
  if [ ! -f "$DEPS/$ORIG" ]; then
    log "fetching MeshLab 2025.07 sources (Debian unstable, source package only)"
    echo 'deb-src http://deb.debian.org/debian unstable main' > "$UNSTABLE_LIST"
    apt-get update -q >/dev/null
    # The .dsc and .debian.tar.xz are 404 on deb.debian.org; the orig tarball is what we need.
    (cd "$tmp" && apt-get source -q --download-only meshlab/unstable >/dev/null 2>&1) || true
    rm -f "$UNSTABLE_LIST"
    apt-get update -q >/dev/null
    [ -f "$tmp/$ORIG" ] || { log "$ORIG not fetched (has unstable moved past 2025.07? apt-cache showsrc meshlab)"; exit 1; }
    mv "$tmp/$ORIG" "$DEPS/$ORIG"
  fi
  echo "$ORIG_SHA256  $DEPS/$ORIG" | sha256sum -c --quiet - || { log "$ORIG: wrong sha256"; exit 1; }
  tar xJf "$DEPS/$ORIG" -C "$tmp"
  rm -rf "$SRC"
  mv "$tmp"/meshlab-* "$SRC"
  grep -q '^2025.07' "$SRC/ML_VERSION" || { log "unexpected ML_VERSION: $(cat "$SRC/ML_VERSION")"; exit 1; }
  log "MeshLab $(cat "$SRC/ML_VERSION") sources in $SRC"
fi

# ------------------------------------------------------------------ 2. the virtual environment
if ! "$VENV/bin/python" -c "import sys; from importlib.metadata import version as v; sys.exit(v('pymeshlab') != '$PYMESHLAB_VERSION' or v('pytest') != '8.3.5')" 2>/dev/null; then
  log "creating $VENV (pymeshlab==$PYMESHLAB_VERSION from PyPI, pytest)"
  /usr/bin/python3 -m venv "$VENV"
  "$VENV/bin/pip" install -q "pymeshlab==$PYMESHLAB_VERSION" "pytest==8.3.5"
fi
PYML=$("$VENV/bin/python" -c "import os, pymeshlab; print(os.path.dirname(pymeshlab.__file__))" 2>/dev/null) ||
  PYML=$(echo "$VENV"/lib/python3*/site-packages/pymeshlab)
[ -f "$PYML/lib/libmeshlab-common.so" ] || { log "no libmeshlab-common.so in $PYML/lib"; exit 1; }

# ------------------------------------------------------------------ 3. build-2025
# vcg_ext/core/decimate.cpp is compiled against MeshLab 2020.09's vcglib in this build too (same
# decimation, same cages: CMakeLists.txt, vcgx_decimate2020): its sources come from scripts/setup.sh.
if [ ! -f "$DEPS/meshlab-2020.09+dfsg1/vcglib/vcg/complex/algorithms/local_optimization/tri_edge_collapse_quadric.h" ]; then
  log "fetching MeshLab 2020.09's sources for its vcglib (scripts/setup.sh)"
  FITMAP_SETUP_SOURCES_ONLY=1 bash "$REPO/scripts/setup.sh"
fi
log "building the 2022.02+ plugin in $BUILD"
cmake -S "$REPO" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DFITMAP_MESHLAB_API=2025 \
      -DMESHLAB_SRC_DIR="$SRC" -DPYMESHLAB_LIB_DIR="$PYML/lib" >/dev/null
if ! cmake --build "$BUILD" -j"${FITMAP_JOBS:-$(nproc)}" > "$BUILD/build.log" 2>&1; then
  grep -E 'error|Error' -A3 "$BUILD/build.log" | head -60 >&2; log "build failed (full log: $BUILD/build.log)"; exit 1
fi
if grep -q 'warning:' "$BUILD/build.log"; then log "build has warnings:"; grep 'warning:' "$BUILD/build.log" | sort -u | head -20 >&2; fi

# ------------------------------------------------------------------ 4. into PyMeshLab's plugins
# copy, then rename: a PyMeshLab process that has the old file mapped keeps it intact
cp "$BUILD/libfilter_fitmap_quad.so" "$PYML/lib/plugins/.libfilter_fitmap_quad.so.new"
mv -f "$PYML/lib/plugins/.libfilter_fitmap_quad.so.new" "$PYML/lib/plugins/libfilter_fitmap_quad.so"
"$VENV/bin/python" - <<'EOF' || { log "PyMeshLab does not load the plugin"; exit 1; }
import pymeshlab
ms = pymeshlab.MeshSet()
assert hasattr(ms, "compute_scalar_by_fitmaps_per_vertex"), "the filters are not MeshSet methods"
EOF
log "plugin installed in $PYML/lib/plugins (pymeshlab.load_plugin('$BUILD/libfilter_fitmap_quad.so') for other environments)"
