#!/usr/bin/env bash
# Benchmark: the PEL pass of terrain-render on the Mount St. Helens mesh at 10 m (~134 k
# vertices) and the Logan mesh (100 m, ~144 k vertices), 1280 x 720, 10 frames turning
# around each terrain; in the same run, the plain shaded frame (TFT + LAY). Prints mean ms
# over frames 4-10 (GL timer queries and wall clock). Needs a built tree (scripts/build.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
bin=build/bin
printf 'view_az\n' > "$tmp/frames.csv"
for az in 180 200 220 240 260 280 300 320 340 360; do echo "$az" >> "$tmp/frames.csv"; done

for name in msh logan; do
  if [ "$name" = msh ]; then
    $bin/dem2mesh data/msh_2007_utm10n_10m.tif "$tmp/m.ply" --spacing 10 -q > "$tmp/mesh.txt"
  else
    $bin/dem2mesh data/logan_utm12n_100m.tif "$tmp/m.ply" -q > "$tmp/mesh.txt"
  fi
  $bin/denoise-normals "$tmp/m.ply" "$tmp/d.ply" -q > /dev/null
  echo "== $name: $(grep -E '^vertices:' "$tmp/mesh.txt"), layers shaded,pels, 1280x720"
  $bin/terrain-render batch "$tmp/d.ply" "$tmp/frames.csv" -o "$tmp/out_$name" --layers shaded,pels -q > /dev/null
  awk -F, 'NR > 4 {tft += $2; lay += $6; pel += $12; wtft += $7; wlay += $11; wpel += $13; n++}
    END {printf "  frames 4-10: PEL %.1f ms (wall %.1f); plain shaded frame TFT+LAY %.1f ms (wall %.1f)\n",
                pel / n, wpel / n, (tft + lay) / n, (wtft + wlay) / n}' "$tmp/out_$name/timings.csv"
done
