#!/usr/bin/env bash
# Dense copies of many data-set meshes (issue 12; a command that prints figures, not a test).
#
#   bench/dense_sweep.sh [--min-faces N] [MESH.off ...]
#
# Refines each mesh by edge midpoints until it has at least N triangles (default 300 000: scan
# sizes), runs bench/dense_bench.py --runs 1 on the mesh and its dense copy (the whole
# pipeline at tau = 1 %) and prints one row per mesh: x1 -> xL patches, irregular vertices,
# unprojectable %, RMS limit / displaced error (per mille of the diagonal), wall s and peak MB of
# the dense run. Default meshes: the 18 of docs/multires.md "Dense copies of 18 data-set meshes".
# Uses the installed plugin (scripts/setup.sh first). About 15 minutes on 2 idle cores.
set -euo pipefail
REPO=$(cd "$(dirname "$0")/.." && pwd)
DATA=${FITMAP_DATA_DIR:-$REPO/.deps/data/meshes}
min=300000
if [ "${1:-}" = "--min-faces" ]; then min=$2; shift 2; fi
meshes=("$@")
if [ ${#meshes[@]} -eq 0 ]; then
  for m in armadillo bear camel cow femur handle helmet homer joint knot1 lion man mannequin-devil pig pinion \
           rotor triceratops turbine; do meshes+=("$DATA/$m.off"); done
fi
out=$(mktemp -d /tmp/fitmap_dense_sweep.XXXXXX)
echo "Dense sweep $(date '+%F %H:%M'), $(nproc) cores, at least $min triangles per copy; outputs in $out"
printf '%-16s %-14s %-12s %-12s %-14s %-14s %-15s %s\n' mesh "copy" patches irregular "unproj. %" "RMS L" "RMS D" "wall s / MB"
for mesh in "${meshes[@]}"; do
  name=$(basename "$mesh" .off)
  if [ ! -r "$mesh" ]; then echo "$name: cannot read $mesh"; continue; fi
  faces=$(awk '!/^#/ && NF {n++} n == 2 {print $2; exit}' "$mesh")
  level=0
  while [ "$faces" -lt "$min" ]; do faces=$((faces * 4)); level=$((level + 1)); done
  rc=0
  python3 "$REPO/bench/dense_bench.py" --runs 1 --levels "0,$level" --mesh "$mesh" > "$out/$name.txt" 2>&1 || rc=$?
  python3 - "$out/$name.txt" "$name" "$rc" <<'PY'
import re, sys
text, name, rc = open(sys.argv[1]).read(), sys.argv[2], sys.argv[3]
rows = re.findall(r"^(x\d+)\s+(\d+)\s+([\d.]+)\s+(\d+)\s+(\d+)\s+(\d+)\s+([\d.]+)\s+([\d.]+)\s+([\d.]+)", text, re.M)
if len(rows) < 2:
    print(f"{name:16s} FAILED (exit {rc}): see {sys.argv[1]}")
else:
    a, b = rows
    arrow = lambda i, f=str: f"{f(a[i])} -> {f(b[i])}"
    print(f"{name:16s} {b[0] + ' ' + format(int(b[1]) / 1e6, '.2f') + ' M':14s} {arrow(4):12s} {arrow(5):12s} "
          f"{arrow(6):14s} {arrow(7):14s} {arrow(8, lambda x: format(float(x), '.3f')):15s} {b[2]} / {b[3]}")
PY
done
