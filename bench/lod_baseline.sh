#!/usr/bin/env bash
# Issue 52's table (docs/performance.md): Logan meshed at 100 m and at 10 m (dem2mesh
# --spacing, with its pyramid: --pyramid, which the renderer reads the mesh from; the
# "before" rows had none), drained with build-drainage --breach 10, each drawn by
# terrain-render frame at the same camera (the 100 m mesh's automatic view, from
# terrain-inspect info), 1280 x 720: the passes' sum and TFT (ms), the whole process (wall
# seconds, peak resident memory), the hachure pass, the mesh (vertices, PLY size). Then the
# viewer's full and cheap frames at that camera: the median of four `timings` replay
# commands (the first frames warm up).
# Usage: bench/lod_baseline.sh [WORKDIR]   (about 2.5 GB of disk for the 10 m files)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="${TERRAIN_BIN:-$root/build/bin}"
work="${1:-$(mktemp -d)}"
mkdir -p "$work"
for s in 100 10; do
  [ -f "$work/logan_$s.ply" ] || "$bin/dem2mesh" "$root/data/logan_utm12n_100m.tif" "$work/logan_$s.ply" --spacing "$s" \
    --pyramid -q > /dev/null
  [ -f "$work/logan_$s.dv" ] || "$bin/build-drainage" "$work/logan_$s.ply" "$work/logan_$s.dv" --breach 10 -q > /dev/null
done
camera=$("$bin/terrain-inspect" info "$work/logan_100.ply" | sed -n 's/^automatic_view: //p')
printf "timings\ntimings\ntimings\ntimings\nquit\n" > "$work/timings.txt"
echo "| mesh | vertices | PLY MB | frame ms (passes) | TFT ms | hachures ms | process s | peak MB | viewer full ms | viewer cheap ms |"
echo "|---|---|---|---|---|---|---|---|---|---|"
for s in 100 10; do
  m="$work/logan_$s.ply" d="$work/logan_$s.dv"
  /usr/bin/time -f "%e %M" -o "$work/time.txt" "$bin/terrain-render" frame "$m" "$d" -o "$work/f$s.png" $camera \
    > "$work/out.txt"
  read -r wall kb < "$work/time.txt"
  passes=$(awk -F'[: ]+' '/^(TFT|AFT|DM|SIL|LAY|PEL|EDGE) ms/{s += $3} END {printf "%.0f", s}' "$work/out.txt")
  hach=$(awk -F'[: ]+' '/^hachures ms/{printf "%.0f", $3}' "$work/out.txt")
  tft=$(awk -F'[: ]+' '/^TFT ms/{printf "%.0f", $3}' "$work/out.txt")
  verts=$("$bin/terrain-inspect" info "$m" | sed -n 's/^vertices: //p')
  mb=$(du -m "$m" | cut -f1)
  view=$("$bin/terrain-view" "$m" "$d" $camera --replay "$work/timings.txt" --offscreen 2>&1)
  median() { grep "$1" | awk '{print $4}' | sort -n | awk '{v[NR] = $1} END {printf "%.1f", (v[2] + v[3]) / 2}'; }
  full=$(echo "$view" | median "full frame") cheap=$(echo "$view" | median "cheap frame")
  echo "| Logan ${s} m | $verts | $mb | $passes | $tft | $hach | $wall | $((kb / 1024)) | $full | $cheap |"
done
