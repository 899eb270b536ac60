#!/usr/bin/env bash
# The main job, for a newcomer on a fresh Debian 12 machine (as root):
#   meshlab_scripts/run_pipeline.sh [--tau PCT] [--patches N] [--regularity W] [--swap-sweep S] [--sweep-tolerance PCT] [--trials K] [--normal-map] [--blender] [INPUT] [OUTDIR]
# Sets up whatever is missing (apt packages, MeshLab sources, build, plugin install, sample
# scans), then runs meshlab_scripts/pipeline.mlx through meshlabserver on INPUT (default: the
# bunny scan bunny00.off) into OUTDIR (default: out/). tau defaults to 1 (percent). --patches N
# stops the simplification at N patches (a budget; default: when no feasible collapse is left).
# --regularity W weighs collapses by the valence defect they remove (fewer irregular vertices;
# default 0 = off; docs/quad.md "Regularity").
# --swap-sweep S: after the simplification, chains of up to S edge swaps that cancel pairs of
# irregular vertices (default 0 = off, the paper; 3 when regular cages matter; docs/quad.md
# "Swap sweep"). The chains are undone unless the swept cage fits at most --sweep-tolerance PCT
# percent farther (default 2; negative: kept unchecked) and leaves no more unprojectable.
# --trials K (with --patches, 1-5) lays the patches out K times with different regularity
# weights (yours, then 0, 0.25, 1, 0.05) and keeps the cage that fits closest (default 1;
# docs/quad.md "Layout trials").
# --blender bakes the displacement for the surface Blender rebuilds (rendererGrid: its uniform
# subdivision and mesh normals; then scripts/blender_fitmap.py shows the reported error,
# docs/blender.md).
# Writes into OUTDIR:
#   fitmap.ply             the input, per-vertex quality = S-fitmap, colour-mapped
#   control.obj + .mtl     the fitted Catmull-Clark control mesh, real quads, per-wedge UVs
#   control.ply            the same control mesh as a quad PLY (what MeshLab 2020.09 can open)
#   limit.ply              the limit surface (8x8 per patch), quality = signed distance, coloured
#   displaced.ply          the displaced limit surface, quality = signed distance, coloured
#   displacement.png/.json 16-bit displacement atlas (one tile per patch) + scale/offset/layout
#   normal.png             object-space normal map, same layout (with --normal-map)
#   report.json            patches, irregular vertices, unprojectable area, RMS/max errors
#                          (1/1000 of the bbox diagonal), time per stage, peak memory
# and prints the report.
set -euo pipefail
REPO=$(cd "$(dirname "$0")/.." && pwd)
TAU=1
PATCHES=0
REGULARITY=0
SWEEP=0
SWEEP_TOL=2
TRIALS=1
NORMAL=false
BLENDER=false
args=()
while [ $# -gt 0 ]; do
  case "$1" in
    --tau) [ $# -ge 2 ] || { echo "run_pipeline: --tau takes a number (percent)" >&2; exit 2; }
           TAU="$2"; shift 2 ;;
    --tau=*) TAU="${1#--tau=}"; shift ;;
    --patches) [ $# -ge 2 ] || { echo "run_pipeline: --patches takes a whole number" >&2; exit 2; }
               PATCHES="$2"; shift 2 ;;
    --patches=*) PATCHES="${1#--patches=}"; shift ;;
    --regularity) [ $# -ge 2 ] || { echo "run_pipeline: --regularity takes a number >= 0" >&2; exit 2; }
                  REGULARITY="$2"; shift 2 ;;
    --regularity=*) REGULARITY="${1#--regularity=}"; shift ;;
    --swap-sweep) [ $# -ge 2 ] || { echo "run_pipeline: --swap-sweep takes a whole number from 0 to 5" >&2; exit 2; }
                  SWEEP="$2"; shift 2 ;;
    --swap-sweep=*) SWEEP="${1#--swap-sweep=}"; shift ;;
    --sweep-tolerance) [ $# -ge 2 ] || { echo "run_pipeline: --sweep-tolerance takes a number (percent)" >&2; exit 2; }
                       SWEEP_TOL="$2"; shift 2 ;;
    --sweep-tolerance=*) SWEEP_TOL="${1#--sweep-tolerance=}"; shift ;;
    --trials) [ $# -ge 2 ] || { echo "run_pipeline: --trials takes a whole number from 1 to 5" >&2; exit 2; }
              TRIALS="$2"; shift 2 ;;
    --trials=*) TRIALS="${1#--trials=}"; shift ;;
    --normal-map) NORMAL=true; shift ;;
    --blender) BLENDER=true; shift ;;
    -h|--help) sed -n '2,30p' "$0"; exit 0 ;;
    -*) echo "run_pipeline: unknown option $1 (see --help)" >&2; exit 2 ;;
    *) args+=("$1"); shift ;;
  esac
done
[ ${#args[@]} -le 2 ] || { echo "run_pipeline: too many arguments (see --help)" >&2; exit 2; }
[[ "$TAU" =~ ^[0-9]+([.][0-9]+)?$ ]] || { echo "run_pipeline: --tau takes a number (percent)" >&2; exit 2; }
[[ "$PATCHES" =~ ^[0-9]+$ ]] || { echo "run_pipeline: --patches takes a whole number" >&2; exit 2; }
[[ "$REGULARITY" =~ ^[0-9]+([.][0-9]+)?$ ]] || { echo "run_pipeline: --regularity takes a number >= 0" >&2; exit 2; }
[[ "$SWEEP" =~ ^[0-5]$ ]] || { echo "run_pipeline: --swap-sweep takes a whole number from 0 to 5" >&2; exit 2; }
[[ "$SWEEP_TOL" =~ ^-?[0-9]+([.][0-9]+)?$ ]] || { echo "run_pipeline: --sweep-tolerance takes a number (percent)" >&2; exit 2; }
[[ "$TRIALS" =~ ^[1-5]$ ]] || { echo "run_pipeline: --trials takes a whole number from 1 to 5" >&2; exit 2; }
[ "$TRIALS" = 1 ] || [ "$PATCHES" != 0 ] || echo "run_pipeline: --trials needs --patches N: one layout" >&2

# FITMAP_SKIP_SETUP=1: use the existing build/install (the end-to-end tests do).
[ "${FITMAP_SKIP_SETUP:-0}" = 1 ] || bash "$REPO/scripts/setup.sh"
INPUT="${args[0]:-$REPO/.deps/data/meshes/bunny00.off}"
OUTDIR="${args[1]:-out}"
[ -f "$INPUT" ] || { echo "run_pipeline: input not found: $INPUT" >&2; exit 2; }
INPUT=$(cd "$(dirname "$INPUT")" && pwd)/$(basename "$INPUT")
mkdir -p "$OUTDIR"
OUTDIR=$(cd "$OUTDIR" && pwd)
rm -f "$OUTDIR"/{fitmap.ply,control.obj,control.mtl,control.ply,limit.ply,displaced.ply,displacement.png,displacement.json,normal.png,report.json}

# pipeline.mlx holds the defaults; tau, the patch budget, the normal map switch and the output
# folder are set here.
mlx="$OUTDIR/.pipeline.mlx"
sed -E -e "s|value=\"[^\"]*\" name=\"tau\"|value=\"$TAU\" name=\"tau\"|" \
       -e "s|value=\"[^\"]*\" name=\"normalMap\"|value=\"$NORMAL\" name=\"normalMap\"|" \
       -e "s|value=\"[^\"]*\" name=\"targetPatches\"|value=\"$PATCHES\" name=\"targetPatches\"|" \
       -e "s|value=\"[^\"]*\" name=\"regularity\"|value=\"$REGULARITY\" name=\"regularity\"|" \
       -e "s|value=\"[^\"]*\" name=\"swapSweep\"|value=\"$SWEEP\" name=\"swapSweep\"|" \
       -e "s|value=\"[^\"]*\" name=\"sweepTolerance\"|value=\"$SWEEP_TOL\" name=\"sweepTolerance\"|" \
       -e "s|value=\"[^\"]*\" name=\"layoutTrials\"|value=\"$TRIALS\" name=\"layoutTrials\"|" \
       -e "s|value=\"[^\"]*\" name=\"outputDir\"|value=\"$OUTDIR\" name=\"outputDir\"|" \
       -e "s|value=\"[^\"]*\" name=\"rendererGrid\"|value=\"$BLENDER\" name=\"rendererGrid\"|" \
       "$REPO/meshlab_scripts/pipeline.mlx" > "$mlx"
echo "[run_pipeline] Fitmaps -> quad simplification -> Catmull-Clark fit + displacement (tau = $TAU%) on $INPUT"
start=$(date +%s.%N)
# Layers after the script: 0 input (Fitmaps), 1 control mesh, 2 fitted control, 3 limit, 4 displaced.
if ! "$REPO/scripts/meshlabserver.sh" -i "$INPUT" -o "$OUTDIR/fitmap.ply" -l 0 -m vq vc \
     -o "$OUTDIR/limit.ply" -l 3 -m vq vc -o "$OUTDIR/displaced.ply" -l 4 -m vq vc \
     -s "$mlx" > "$OUTDIR/meshlab.log" 2>&1; then
  if ! grep -q "loaded has" "$OUTDIR/meshlab.log"; then
    # MeshLab 2020.09's own readers crash on some valid files (an OFF with comment lines inside
    # its data, some OBJ/PLY variants) before any filter runs: say so instead of a bare crash.
    echo "run_pipeline: MeshLab could not read $INPUT: its file reader failed before any filter ran" \
         "(MeshLab 2020.09's readers crash on some valid files, e.g. an OFF with comment lines among its" \
         "vertices or faces); re-save the mesh (another format, or without comments) and run again" >&2
  else
    grep -E "Error|error" "$OUTDIR/meshlab.log" | grep -v "trying to save" | sort -u >&2 || tail -30 "$OUTDIR/meshlab.log" >&2
  fi
  echo "run_pipeline: meshlabserver failed (full log: $OUTDIR/meshlab.log)" >&2
  exit 1
fi
end=$(date +%s.%N)
rm -f "$mlx"
# the filters' log lines, warnings included, once each in the order they came
filters="(Compute Fitmaps|Fitmap Quad Simplification|Fit Catmull-Clark)"
grep -E "^(Warning: )?$filters" "$OUTDIR/meshlab.log" |
  awk '!seen[$0]++' | sed 's/^/[meshlab] /' || true
for f in fitmap.ply control.obj control.ply limit.ply displaced.ply displacement.png displacement.json report.json; do
  [ -s "$OUTDIR/$f" ] || { echo "run_pipeline: $OUTDIR/$f was not written (log: $OUTDIR/meshlab.log)" >&2; exit 1; }
done
echo "[run_pipeline] report ($OUTDIR/report.json):"
cat "$OUTDIR/report.json"
# report.json lists the fit's warnings; the Fitmaps' and the simplification's (a budget not
# reached, a precision warning) are only in the log: repeat every warning last, on stderr
warnings=$(grep -E "^Warning: $filters" "$OUTDIR/meshlab.log" |
  awk '!seen[$0]++' || true)
if [ -n "$warnings" ]; then
  echo "[run_pipeline] $(printf '%s\n' "$warnings" | wc -l) warning(s):" >&2
  printf '%s\n' "$warnings" | sed 's/^Warning: /[run_pipeline] warning: /' >&2
fi
awk -v a="$start" -v b="$end" -v d="$OUTDIR" 'BEGIN { printf "[run_pipeline] outputs in %s (%.1f s wall including meshlabserver start-up and file output)\n", d, b - a }'
