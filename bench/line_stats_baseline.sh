#!/usr/bin/env bash
# Issue 13's crease figures before and now on the same cameras: builds the renderer as it
# was before issue 13's work (commit bd698b9, run with --seed-rules on the filled drainage
# its demo built) into build-baseline/, then measures each view with both binaries
# (--line-stats: crease length in pixels, strokes, mean stroke) and prints the ratio of the
# mean strokes. Each camera is given to both binaries in full (eye, view, light), so the
# two draw the same view; the default cameras are the ones each version picks itself.
# Usage: bench/line_stats_baseline.sh   (needs a built tree and out/ from scripts/demo.sh;
# the first run builds the old renderer, a few minutes on 2 cores)
#
# The old binary measured its raw crease layer, which for its pixel-exact lines holds every
# line it drew, hidden or not: its depth test there is against the other lines, and the
# composite removed the hidden ones. So its --line-stats counted the creases behind ridges
# as drawn. The build below applies bench/line_stats_baseline.patch, which makes it test
# each segment's own line against the toward surface by its composite's rule (the line's
# depth not behind the surface's), as today's binary tests its own lines
# (renderer::visible_fraction; docs/terrain-render.md, "Line statistics"). Nothing else of
# the old renderer changes.
set -euo pipefail
cd "$(dirname "$0")/.."
base_commit=bd698b9
old=build-baseline
new=build/bin
for f in out/msh_50m.ply out/logan_100m.ply out/msh_breached.dv out/logan_breached.dv out/msh_path.csv; do
  [ -e "$f" ] || { echo "line_stats_baseline: $f is missing: run scripts/demo.sh first" >&2; exit 1; }
done
if [ ! -x "$old/build/bin/terrain-render" ] || [ ! -x "$old/build/bin/build-drainage" ] ||
   ! grep -q shown_fraction "$old/src/tools/terrain_render.cpp"; then
  echo "== building $base_commit into $old/ (terrain-render, build-drainage)"
  rm -rf "$old" && mkdir -p "$old/src"
  git archive "$base_commit" | tar -x -C "$old/src"
  git apply --directory="$old/src" bench/line_stats_baseline.patch
  grep -q shown_fraction "$old/src/tools/terrain_render.cpp" || { echo "line_stats_baseline: patching $base_commit failed" >&2; exit 1; }
  cmake -S "$old/src" -B "$old/build" -DCMAKE_BUILD_TYPE=Release > "$old/cmake.log"
  cmake --build "$old/build" --parallel 2 --target terrain-render build-drainage > "$old/build.log" 2>&1
fi
# The demo's drainage then: filled, not breached.
[ -e "$old/msh_filled.dv" ] ||
  $old/build/bin/build-drainage out/msh_50m.ply "$old/msh_filled.dv" --spacing 10 --fill -q > /dev/null
[ -e "$old/logan_filled.dv" ] ||
  $old/build/bin/build-drainage out/logan_100m.ply "$old/logan_filled.dv" --spacing 30 --fill -q > /dev/null

stat() {  # KEY < line-stats output
  awk -v k="$1" 'index($0, k ": ") == 1 {print $NF}'
}
camera_of() {  # the camera a frame's output names, as options
  awk '/^eye: / {e = $2 " " $3 " " $4} /^view: / {v = $3 " " $5 " " $7} /^light: / {l = $3 " " $5}
       END {split(v, a, " "); split(l, b, " ");
            printf "--eye %s --view-az %s --view-alt %s --fov %s --light-az %s --light-alt %s", e, a[1], a[2], a[3], b[1], b[2]}'
}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# The last two columns: now, strokes weighted by their mean opacity as their length is
# (docs/terrain-render.md, "Line statistics"; the old binary draws opacities 0 or 1, where
# both counts agree), and its ratio to before.
printf '%-34s %28s %28s %6s %14s %6s\n' view "before: px / strokes / mean" "now: px / strokes / mean" ratio \
  "now: weighted" ratio
print_row() {  # NAME, then px strokes mean before and now, then now's opacity-weighted strokes and mean
  printf '%-34s %12s / %5s / %5s %12s / %5s / %5s %5.2fx %6s / %5s %5.2fx\n' "${@:1:7}" \
    "$(echo "$7 $4" | awk '{print $1 / $2}')" "$8" "$9" "$(echo "$9 $4" | awk '{print $1 / $2}')"
}
row() {  # NAME MESH OLD_DV NEW_DV CAMERA...
  local name=$1 mesh=$2 odv=$3 ndv=$4
  shift 4
  $old/build/bin/terrain-render frame "$mesh" "$odv" -o "$tmp/o.png" "$@" --seed-rules --line-stats > "$tmp/o.txt"
  $new/terrain-render frame "$mesh" "$ndv" -o "$tmp/n.png" "$@" --line-stats > "$tmp/n.txt"
  local f k figures=()
  for f in o n; do
    for k in "crease length px" "crease strokes" "crease mean stroke px"; do figures+=("$(stat "$k" < "$tmp/$f.txt")"); done
  done
  for k in "crease strokes, opacity-weighted" "crease mean stroke px, opacity-weighted"; do
    figures+=("$(stat "$k" < "$tmp/n.txt")")
  done
  print_row "$name" "${figures[@]}"
}
m_old=(out/msh_50m.ply "$old/msh_filled.dv" out/msh_breached.dv)
l_old=(out/logan_100m.ply "$old/logan_filled.dv" out/logan_breached.dv)
logan_demo=(--eye 430000 4628000 4200 --view-az 50 --view-alt 12 --fov 40 --exaggeration 2)
$new/terrain-render frame out/msh_50m.ply -o "$tmp/c.png" --layers mask > "$tmp/c.txt"
read -ra msh_now <<< "$(camera_of < "$tmp/c.txt")"
# The old default camera: framed by the old binary (it prints only the eye), its defaults then.
eye_then=$($old/build/bin/terrain-render frame out/msh_50m.ply -o "$tmp/c.png" --layers mask | awk '/^eye: / {print $2, $3, $4}')
read -ra msh_then <<< "--eye $eye_then --view-az 225 --view-alt 30 --fov 35 --light-az 315 --light-alt 45"
$new/terrain-render frame out/logan_100m.ply -o "$tmp/c.png" --layers mask > "$tmp/c.txt"
read -ra logan_now <<< "$(camera_of < "$tmp/c.txt")"
row "MSH, default view now" "${m_old[@]}" "${msh_now[@]}"
row "MSH, default camera then" "${m_old[@]}" "${msh_then[@]}"
row "Logan, demo camera" "${l_old[@]}" "${logan_demo[@]}"
row "Logan, default view now" "${l_old[@]}" "${logan_now[@]}"

# The demo's flight: sums over its frames' line_stats.csv. The old binary flies the same
# path written by its own path command (the demo's arguments, from the file's first line),
# so each version scores with its own defaults.
read -ra path_args <<< "$(sed -n '1s/^.*: path \(.*\) -o [^ ]*$/\1/p' out/msh_path.csv)"
$old/build/bin/terrain-render path "${path_args[@]}" -o "$tmp/path_old.csv" > /dev/null
$old/build/bin/terrain-render batch out/msh_50m.ply "$old/msh_filled.dv" "$tmp/path_old.csv" -o "$tmp/fo" --size 960x540 \
  --seed-rules --line-stats -q > "$tmp/fo.txt"
$new/terrain-render batch out/msh_50m.ply out/msh_breached.dv out/msh_path.csv -o "$tmp/fn" --size 960x540 \
  --line-stats -q > "$tmp/fn.txt"
sums() { awk -F, 'NR > 1 {l += $2; s += $6; w += $10} END {printf "%.0f %d %.1f %.1f %.1f", l, s, l / s, w, (w > 0 ? l / w : 0)}' "$1"; }
read -r ol os om _ <<< "$(sums "$tmp/fo/line_stats.csv")"
read -r nl ns nm nw nwm <<< "$(sums "$tmp/fn/line_stats.csv")"
print_row "MSH flight, 12 frames" "$ol" "$os" "$om" "$nl" "$ns" "$nm" "$nw" "$nwm"
echo "crease flicker over the flight: before $(stat "crease flicker" < "$tmp/fo.txt"), now $(stat "crease flicker" < "$tmp/fn.txt")"
