#!/usr/bin/env bash
# Regenerates the README pictures (docs/img/*.png) from MeshLab GUI screenshots under Xvfb.
# Usage: scripts/readme_pictures.sh [PIPELINE_OUTDIR]   (default: runs the pipeline into out/)
# Needs (documentation only): apt-get install imagemagick x11-apps xdotool
set -euo pipefail
REPO=$(cd "$(dirname "$0")/.." && pwd)
OUT="${1:-$REPO/out}"
IMG="$REPO/docs/img"
mkdir -p "$IMG"
[ -f "$OUT/limit.ply" ] || FITMAP_SKIP_SETUP=1 "$REPO/meshlab_scripts/run_pipeline.sh" "$REPO/.deps/data/meshes/bunny00.off" "$OUT"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
shot() {  # name mesh...: viewport only, 600 px wide
  local name=$1; shift
  bash "$REPO/scripts/screenshot.sh" "$tmp/$name.png" "$@" >/dev/null
  convert "$tmp/$name.png" -crop 900x740+0+70 +repage -resize 600x "$IMG/$name.png"
}
# M-fitmap of the input (the pipeline's fitmap.ply shows S).
sed 's/value="0" name="channel"/value="1" name="channel"/' "$REPO/meshlab_scripts/fitmaps.mlx" > "$tmp/m.mlx"
"$REPO/scripts/meshlabserver.sh" -i "$REPO/.deps/data/meshes/bunny00.off" -o "$tmp/fitmapM.ply" -m vq vc -s "$tmp/m.mlx" >/dev/null 2>&1
shot fitmap_s "$OUT/fitmap.ply"
shot fitmap_m "$tmp/fitmapM.ply"
shot control "$OUT/control.ply"
"$REPO/build/patch_layout" "$OUT/control.ply" "$tmp/patches.ply" >/dev/null
shot patches "$tmp/patches.ply"
shot limit "$OUT/limit.ply"
shot displaced "$OUT/displaced.ply"
convert "$OUT/displacement.png" -contrast-stretch 0.5%x0.5% -resize 300x "$IMG/displacement_atlas.png"
# Loop surrogate: adaptive refinement and mean curvature of fandisk.
"$REPO/scripts/meshlabserver.sh" -i "$REPO/.deps/data/meshes/fandisk.off" -o "$tmp/fandisk_refined.ply" \
  -s "$REPO/meshlab_scripts/loop_refine.mlx" >/dev/null 2>&1
"$REPO/scripts/meshlabserver.sh" -i "$REPO/.deps/data/meshes/fandisk.off" -o "$tmp/fandisk_curv.ply" -m vq vc \
  -s "$REPO/meshlab_scripts/loop_curvature.mlx" >/dev/null 2>&1
shot loop_refined "$tmp/fandisk_refined.ply"
shot loop_curvature "$tmp/fandisk_curv.ply"
ls -la "$IMG"
