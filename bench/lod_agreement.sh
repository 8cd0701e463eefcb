#!/usr/bin/env bash
# Issue 52's picture target (docs/performance.md, "Levels of detail"): a mesh drawn with
# levels of detail (--lod-error, default or LOD_ERROR) against full detail (--lod-error 0)
# at one camera, the creases and the silhouettes drawn apart (--layers mask,creases and
# mask,silhouettes): the share of each frame's line pixels within 1 px of the other's
# (bench/line_agreement.py), the patches and crease segments drawn, TFT's and DM's times. Target: >= 95 % both ways,
# for each layer. Usage: bench/lod_agreement.sh WORKDIR MESH.ply DV [terrain-render camera options...]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="${TERRAIN_BIN:-$root/build/bin}"
work="$1" mesh="$2" dv="$3"
shift 3
mkdir -p "$work"
name=$(basename "$mesh" .ply)
echo "| mesh | layer | LOD in full | full in LOD | line px (LOD / full) | patches (LOD / full) | crease segments (LOD / full) | TFT ms (LOD / full) | DM ms (LOD / full) |"
echo "|---|---|---|---|---|---|---|---|---|"
for layer in creases silhouettes; do
  for e in "${LOD_ERROR:-0.25}" 0; do
    "$bin/terrain-render" frame "$mesh" "$dv" -o "$work/${name}_${layer}_$e.png" --layers "mask,$layer" \
      --lod-error "$e" -v "$@" > "$work/${name}_${layer}_$e.txt"
  done
  lod="$work/${name}_${layer}_${LOD_ERROR:-0.25}" full="$work/${name}_${layer}_0"
  read -r a b na nb < <(/usr/bin/python3 "$root/bench/line_agreement.py" "$lod.png" "$full.png")
  p() { sed -n 's/^surface patches drawn: \([0-9]*\) of.*/\1/p' "$1.txt"; }
  c() { sed -n 's/^crease segments drawn: \([0-9]*\).*/\1/p' "$1.txt"; }
  t() { awk -F'[: ]+' -v pass="$2" '$1 == pass && $2 == "ms" {printf "%.0f", $3}' "$1.txt"; }
  echo "| $name | $layer | $a | $b | $na / $nb | $(p "$lod") / $(p "$full") | $(c "$lod") / $(c "$full") |" \
    "$(t "$lod" TFT) / $(t "$full" TFT) | $(t "$lod" DM) / $(t "$full" DM) |"
done
