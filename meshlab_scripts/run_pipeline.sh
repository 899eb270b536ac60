#!/usr/bin/env bash
# The main job, for a newcomer on a fresh Debian 12 machine (as root):
#   meshlab_scripts/run_pipeline.sh [--tau PCT] [INPUT] [OUTDIR]
# Sets up whatever is missing (apt packages, MeshLab sources, build, plugin install, sample
# scans), then runs the pipeline on INPUT (default: the bunny, bunny00.off) into OUTDIR
# (default: out/):
#   OUTDIR/fitmap.ply   the input with per-vertex quality = S-fitmap, colour-mapped
set -euo pipefail
REPO=$(cd "$(dirname "$0")/.." && pwd)
TAU=1
args=()
while [ $# -gt 0 ]; do
  case "$1" in
    --tau) TAU="$2"; shift 2 ;;
    --tau=*) TAU="${1#--tau=}"; shift ;;
    -h|--help) sed -n '2,8p' "$0"; exit 0 ;;
    *) args+=("$1"); shift ;;
  esac
done
INPUT="${args[0]:-$REPO/.deps/data/meshes/bunny00.off}"
OUTDIR="${args[1]:-out}"
[[ "$TAU" =~ ^[0-9]+([.][0-9]+)?$ ]] || { echo "run_pipeline: --tau takes a number (percent)" >&2; exit 2; }

# FITMAP_SKIP_SETUP=1: use the existing build/install (the end-to-end tests do).
[ "${FITMAP_SKIP_SETUP:-0}" = 1 ] || bash "$REPO/scripts/setup.sh"
[ -f "$INPUT" ] || { echo "run_pipeline: input not found: $INPUT" >&2; exit 2; }
INPUT=$(cd "$(dirname "$INPUT")" && pwd)/$(basename "$INPUT")
mkdir -p "$OUTDIR"
OUTDIR=$(cd "$OUTDIR" && pwd)

# The scripts in meshlab_scripts/ hold the defaults; only tau is substituted.
mlx="$OUTDIR/.fitmaps.mlx"
sed -E "s/value=\"[^\"]*\" name=\"tau\"/value=\"$TAU\" name=\"tau\"/" "$REPO/meshlab_scripts/fitmaps.mlx" > "$mlx"
echo "[run_pipeline] Compute Fitmaps (tau = $TAU%) on $INPUT"
start=$(date +%s.%N)
"$REPO/scripts/meshlabserver.sh" -i "$INPUT" -o "$OUTDIR/fitmap.ply" -m vq vc -s "$mlx" > "$OUTDIR/meshlab.log" 2>&1 || {
  tail -30 "$OUTDIR/meshlab.log" >&2; echo "run_pipeline: meshlabserver failed (log: $OUTDIR/meshlab.log)" >&2; exit 1; }
grep -q "Error:" "$OUTDIR/meshlab.log" && { grep "Error:" "$OUTDIR/meshlab.log" >&2; exit 1; }
end=$(date +%s.%N)
grep -E "Compute Fitmaps" "$OUTDIR/meshlab.log" | sed 's/^/[meshlab] /' || true
awk -v a="$start" -v b="$end" -v d="$OUTDIR" 'BEGIN { printf "[run_pipeline] wrote %s/fitmap.ply (%.1f s including meshlabserver start-up)\n", d, b - a }'
rm -f "$mlx"
