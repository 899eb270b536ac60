#!/usr/bin/env bash
# Idempotent: Debian 12's Blender (3.4.1, package `blender`), for scripts/blender_fitmap.py and
# its tests (tests/blender, ctest Blender.pytest; issue 15). As root on Debian 12. The main job
# does not need it, so scripts/setup.sh leaves it out (~90 MB installed plus its libraries).
set -euo pipefail
export DEBIAN_FRONTEND=noninteractive
if ! dpkg-query -W -f='${Status}' blender 2>/dev/null | grep -q "install ok installed"; then
  printf '[setup_blender] installing Debian'"'"'s blender\n' >&2
  apt-get update -q >/dev/null
  apt-get install -y -q --no-install-recommends blender >/dev/null
fi
blender --version | head -1
