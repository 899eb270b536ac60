#!/usr/bin/env bash
# Takes a screenshot of MeshLab's GUI showing the given mesh files (for README pictures).
# Usage: scripts/screenshot.sh OUT.png MESH [MESH...]
# Needs (documentation only, not the tests): apt-get install imagemagick x11-apps xdotool
set -euo pipefail
out="$1"; shift
scratch=$(mktemp -d /tmp/fitmap_shot.XXXXXX)
trap 'rm -rf "$scratch"' EXIT
mkdir -p "$scratch/run"; chmod 700 "$scratch/run"
export XDG_CONFIG_HOME="$scratch" XDG_CACHE_HOME="$scratch" XDG_RUNTIME_DIR="$scratch/run"
xvfb-run -a -s "-screen 0 1400x1000x24" sh -c '
  meshlab "$@" >/dev/null 2>&1 & p=$!
  sleep 8
  w=$(xdotool search --onlyvisible --name "MeshLab" | head -1)
  [ -n "$w" ] && xdotool windowsize "$w" 1400 1000 windowmove "$w" 0 0 && sleep 3
  xwd -root -silent > "'"$scratch"'/shot.xwd"
  kill $p; wait $p 2>/dev/null; true' sh "$@"
convert "$scratch/shot.xwd" "$out"
echo "wrote $out"
