#!/usr/bin/env bash
# Runs Debian's meshlabserver headless (it needs an X server) with a private config/cache dir.
# Usage: scripts/meshlabserver.sh <meshlabserver arguments...>
set -euo pipefail
scratch=$(mktemp -d /tmp/fitmap_mls.XXXXXX)
trap 'rm -rf "$scratch"' EXIT
mkdir -p "$scratch/config" "$scratch/cache" "$scratch/run"
chmod 700 "$scratch/run"
export XDG_CONFIG_HOME="$scratch/config" XDG_CACHE_HOME="$scratch/cache" XDG_RUNTIME_DIR="$scratch/run"
# no exec: the EXIT trap must run after meshlabserver to remove the scratch folder
status=0
xvfb-run -a -s "-screen 0 1280x1024x24" meshlabserver "$@" || status=$?
exit "$status"
