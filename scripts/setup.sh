#!/usr/bin/env bash
# One-stop, idempotent set-up on Debian 12 (run as root):
#   1. apt packages (build + runtime + headless X),
#   2. MeshLab 2020.09 sources (src/common + vcglib) via `apt-get source meshlab`,
#   3. real scans from Debian's libcgal-demo data (never committed),
#   4. configure + build (Release) + install the plugin where Debian's meshlab loads it.
# Environment: FITMAP_BUILD_DIR (default <repo>/build), FITMAP_SKIP_INSTALL=1 to skip step 4's install,
# FITMAP_SETUP_SOURCES_ONLY=1 to stop after step 2 (scripts/setup_pymeshlab.sh).
set -euo pipefail
REPO=$(cd "$(dirname "$0")/.." && pwd)
DEPS="$REPO/.deps"
BUILD="${FITMAP_BUILD_DIR:-$REPO/build}"
MESHLAB_SRC="$DEPS/meshlab-2020.09+dfsg1"
DATA="$DEPS/data/meshes"
log() { printf '[setup] %s\n' "$*" >&2; }
export DEBIAN_FRONTEND=noninteractive

PKGS=(meshlab dpkg-dev build-essential cmake pkg-config qtbase5-dev libqt5opengl5-dev
      libqt5xmlpatterns5-dev libglew-dev libgl-dev libglu1-mesa-dev libeigen3-dev libgtest-dev
      libembree-dev libosd-dev libpng-dev libsuitesparse-dev libopenblas0-openmp xvfb xauth python3)
missing=()
for p in "${PKGS[@]}"; do dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p"); done
apt_updated=0
apt_update() { [ $apt_updated = 1 ] || { apt-get update -q >/dev/null; apt_updated=1; }; }
if [ ${#missing[@]} -gt 0 ]; then
  log "installing: ${missing[*]}"
  apt_update
  apt-get install -y -q --no-install-recommends "${missing[@]}" >/dev/null
fi

mkdir -p "$DEPS"
if [ ! -f "$MESHLAB_SRC/src/common/interfaces.h" ]; then
  log "fetching MeshLab 2020.09 sources (apt-get source meshlab)"
  # apt-get source needs a deb-src entry next to each deb one.
  for f in /etc/apt/sources.list.d/*.sources; do
    [ -f "$f" ] || continue
    if grep -q '^Types: deb$' "$f"; then sed -i 's/^Types: deb$/Types: deb deb-src/' "$f"; apt_updated=0; fi
  done
  if [ -f /etc/apt/sources.list ] && grep -q '^deb ' /etc/apt/sources.list && ! grep -q '^deb-src ' /etc/apt/sources.list; then
    sed -n 's/^deb /deb-src /p' /etc/apt/sources.list > /etc/apt/sources.list.d/fitmap-deb-src.list; apt_updated=0
  fi
  apt_update
  # Pinned: with Debian unstable's deb-src entry (scripts/setup_pymeshlab.sh adds one for a moment)
  # a bare `apt-get source meshlab` would fetch 2025.07.
  (cd "$DEPS" && apt-get source -q meshlab=2020.09+dfsg1-2 >/dev/null 2>&1)
  [ -f "$MESHLAB_SRC/src/common/interfaces.h" ] || { log "MeshLab sources not found after apt-get source"; exit 1; }
fi
# scripts/setup_pymeshlab.sh needs only these sources (its build decimates with 2020.09's vcglib)
[ "${FITMAP_SETUP_SOURCES_ONLY:-0}" = 1 ] && exit 0

if [ ! -f "$DATA/bunny00.off" ]; then
  log "fetching sample scans (libcgal-demo data)"
  tmp=$(mktemp -d)
  (cd "$tmp" && apt_update && apt-get download -q libcgal-demo >/dev/null 2>&1 && dpkg -x libcgal-demo_*.deb x)
  mkdir -p "$DEPS/data"
  tar xzf "$tmp/x/usr/share/doc/libcgal-dev/data.tar.gz" -C "$DEPS" data/meshes
  rm -rf "$tmp"
  [ -f "$DATA/bunny00.off" ] || { log "sample scans missing"; exit 1; }
fi

log "building in $BUILD"
cmake -S "$REPO" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DMESHLAB_SRC_DIR="$MESHLAB_SRC" \
      -DFITMAP_DATA_DIR="$DATA" >/dev/null
if ! cmake --build "$BUILD" -j"$(nproc)" > "$BUILD/build.log" 2>&1; then
  grep -E 'error|Error' -A3 "$BUILD/build.log" | head -60 >&2; log "build failed (full log: $BUILD/build.log)"; exit 1
fi
if grep -q 'warning:' "$BUILD/build.log"; then log "build has warnings:"; grep 'warning:' "$BUILD/build.log" | sort -u | head -20 >&2; fi
if [ "${FITMAP_SKIP_INSTALL:-0}" != 1 ]; then
  cmake --install "$BUILD" >/dev/null
  log "plugin installed in $(cat "$BUILD/plugin_dir.txt")"
fi
