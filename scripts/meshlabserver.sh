#!/usr/bin/env bash
# Runs Debian's meshlabserver headless (it needs an X server) with a private config/cache dir.
# Usage: scripts/meshlabserver.sh <meshlabserver arguments...>
# Exit status: meshlabserver's own (128 + N if a signal N ended it). xvfb-run's status is used only
# when meshlabserver did not get to finish (xvfb-run could not start the X server, or the run was
# killed). xvfb-run exits 5 when it cannot remove its temporary folder after the command has ended
# ("problem while cleaning up temporary directory"); that once turned a finished run into a
# "crash" in the corpus test (CI 2026-12-04, lion.off), so it is only warned about here.
set -euo pipefail
scratch=$(mktemp -d /tmp/fitmap_mls.XXXXXX)
trap 'rm -rf "$scratch"' EXIT
mkdir -p "$scratch/config" "$scratch/cache" "$scratch/run"
chmod 700 "$scratch/run"
export XDG_CONFIG_HOME="$scratch/config" XDG_CACHE_HOME="$scratch/cache" XDG_RUNTIME_DIR="$scratch/run"
# OpenMP threads that wait at a barrier sleep instead of spinning (unless the caller chose): the
# same results, the same speed on idle cores, and 6 % less wall time on bunny00 when the machine's
# other core is busy (5.95 against 6.32 s, medians of 3, 2026-12-05; docs/multires.md "Waiting
# threads under load"): a spinning thread takes the CPU its partner and the other load need.
# Set OMP_WAIT_POLICY (empty: libgomp's default) to choose otherwise.
[ -n "${OMP_WAIT_POLICY+set}" ] || export OMP_WAIT_POLICY=PASSIVE
# no exec: the EXIT trap must run after meshlabserver to remove the scratch folder
status=0
xvfb-run -a -s "-screen 0 1280x1024x24" \
  sh -c 'rc=0; meshlabserver "$@" || rc=$?; echo "$rc" > "$0"; exit "$rc"' "$scratch/status" "$@" || status=$?
if [ -s "$scratch/status" ]; then
  own=$(cat "$scratch/status")
  if [ "$own" != "$status" ]; then
    echo "meshlabserver.sh: warning: xvfb-run exited $status after meshlabserver had exited $own" \
         "(xvfb-run's own clean-up failed); meshlabserver's status $own is returned" >&2
  fi
  status=$own
fi
exit "$status"
