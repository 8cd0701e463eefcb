#!/usr/bin/env bash
# Issue 52's second row (docs/performance.md, "Logan at 2 m"): Logan resampled to 2 m
# (gdalwarp -r cubic -tr 2 2: 14 450 x 24 900 = 360 M samples), meshed in bands with its
# pyramid (dem2mesh --memory 1024 --pyramid), drained at 10 m (build-drainage --breach 10),
# drawn at the Logan 100 m mesh's automatic view without and with the .dv (terrain-render's
# default --memory 1024: the mesh read at the level the view draws), and from the whole mesh;
# the Logan 100 m mesh's frames at the same camera beside them. Prints wall seconds, peak resident memory
# and the frame's passes for each step, and the files' sizes. Steps whose outputs exist in
# WORKDIR are not run again (their rows then say so).
# Then a near view of the 2 m mesh, of which terrain-render reads only the blocks in view.
# Usage: bench/lod_2m.sh WORKDIR   (about 28 GB of disk; about 10 minutes on 2 cores)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="${TERRAIN_BIN:-$root/build/bin}"
work="${1:?usage: bench/lod_2m.sh WORKDIR}"
mkdir -p "$work"
timed() {  # LABEL COMMAND...: one table row of wall seconds and peak MB
  local label="$1"; shift
  /usr/bin/time -f "%e %M" -o "$work/time.txt" "$@" > "$work/out.txt" 2>&1
  read -r wall kb < "$work/time.txt"
  local passes
  passes=$(awk -F'[: ]+' '/^(TFT|AFT|DM|SIL|LAY|PEL|EDGE) ms/{s += $3} END {if (s) printf "%.0f", s; else printf "-"}' \
    "$work/out.txt")
  echo "| $label | $wall | $((kb / 1024)) | $passes |"
}
[ -f "$work/logan_2m.tif" ] || gdalwarp -q -r cubic -tr 2 2 "$root/data/logan_utm12n_100m.tif" "$work/logan_2m.tif"
[ -f "$work/logan_100.ply" ] || "$bin/dem2mesh" "$root/data/logan_utm12n_100m.tif" "$work/logan_100.ply" --spacing 100 \
  --pyramid -q > /dev/null
[ -f "$work/logan_100.dv" ] || "$bin/build-drainage" "$work/logan_100.ply" "$work/logan_100.dv" --breach 10 -q > /dev/null
camera=$("$bin/terrain-inspect" info "$work/logan_100.ply" | sed -n 's/^automatic_view: //p')
echo "| step | wall s | peak MB | frame ms (passes) |"
echo "|---|---|---|---|"
if [ -f "$work/logan_2.ply" ]; then echo "| dem2mesh (outputs exist: not run) | - | - | - |"
else timed "dem2mesh --memory 1024 --pyramid" "$bin/dem2mesh" "$work/logan_2m.tif" "$work/logan_2.ply" --pyramid --memory 1024 -v; fi
if [ -f "$work/logan_2.dv" ]; then echo "| build-drainage (output exists: not run) | - | - | - |"
else timed "build-drainage --breach 10" "$bin/build-drainage" "$work/logan_2.ply" "$work/logan_2.dv" --breach 10 -q; fi
# shellcheck disable=SC2086
timed "frame, 2 m mesh" "$bin/terrain-render" frame "$work/logan_2.ply" -o "$work/f2.png" $camera -v
# shellcheck disable=SC2086
timed "frame, 2 m mesh and .dv" "$bin/terrain-render" frame "$work/logan_2.ply" "$work/logan_2.dv" -o "$work/g2.png" $camera -v
# The same frame from the whole mesh (a bound it fits in): what the default bound saves, and
# the creases' agreement between the two (bench/line_agreement.py, the creases drawn apart).
# shellcheck disable=SC2086
timed "frame, 2 m mesh and .dv, whole (--memory 65536)" "$bin/terrain-render" frame "$work/logan_2.ply" \
  "$work/logan_2.dv" -o "$work/g2w.png" $camera --memory 65536 -v
for m in 1024 65536; do
  # shellcheck disable=SC2086
  "$bin/terrain-render" frame "$work/logan_2.ply" "$work/logan_2.dv" -o "$work/c2_$m.png" --layers mask,creases \
    --memory "$m" $camera -q > /dev/null
done
agreement=$(/usr/bin/python3 "$root/bench/line_agreement.py" "$work/c2_1024.png" "$work/c2_65536.png")
# shellcheck disable=SC2086
timed "frame, 100 m mesh" "$bin/terrain-render" frame "$work/logan_100.ply" -o "$work/f100.png" $camera -v
# shellcheck disable=SC2086
timed "frame, 100 m mesh and .dv" "$bin/terrain-render" frame "$work/logan_100.ply" "$work/logan_100.dv" -o "$work/g100.png" \
  $camera -v
# A near view (2.5 km south of Logan Peak, looking north, 25 degrees down): the mesh over
# the bound and the view's blocks a fraction of it, terrain-render frame reads only the
# blocks in view, at the level the view draws (focus_scene's window); against the whole
# mesh at the same camera.
near="--eye 446000 4630000 3800 --view-az 0 --view-alt 25 --fov 35"
# shellcheck disable=SC2086
timed "near frame, 2 m mesh and .dv" "$bin/terrain-render" frame "$work/logan_2.ply" "$work/logan_2.dv" -o "$work/n2.png" \
  $near -v
read_line=$(grep -m1 "mesh read at level" "$work/out.txt" || true)
for m in 1024 65536; do
  # shellcheck disable=SC2086
  "$bin/terrain-render" frame "$work/logan_2.ply" "$work/logan_2.dv" -o "$work/nc2_$m.png" --layers mask,creases \
    --memory "$m" $near -q > /dev/null
done
near_agreement=$(/usr/bin/python3 "$root/bench/line_agreement.py" "$work/nc2_1024.png" "$work/nc2_65536.png")
echo
echo "creases at the default bound against the whole mesh (within 1 px, both ways; line px): $agreement"
echo "near view: $read_line"
echo "near view, creases against the whole mesh (within 1 px, both ways; line px): $near_agreement"
echo "disk: PLY $(du -m "$work/logan_2.ply" | cut -f1) MB, pyramid $(du -m "$work/logan_2.tpyr" | cut -f1) MB, .dv $(du -mL "$work/logan_2.dv" | cut -f1) MB"
