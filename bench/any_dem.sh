#!/usr/bin/env bash
# "A picture of any DEM" (docs/terrain-render.md): each DEM's no-option frame, by
# `terrain-render frame MESH DV -o x.png --line-stats`, as a markdown table row. Meshes by
# dem2mesh at the DEM's own spacing (MSH at 50 m), drainage by build-drainage's defaults
# (depressions breached, as --breach 10; Logan at 30 m as the demo drains it, the others at 10 m); integer copies by
# gdal_translate -ot Int16 (rounds). Usage: bench/any_dem.sh [WORKDIR] [EXTRA RENDER OPTIONS...]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="${TERRAIN_BIN:-$root/build/bin}"
work="${1:-$(mktemp -d)}"
shift || true
mkdir -p "$work"
shared="$root/../shared/data"
declare -A spacing=([msh]="--spacing 50" [logan]="" [eno]="" [med]="" [sinmap]="--fill-nodata")
declare -A drain=([msh]=10 [logan]=30 [eno]=10 [med]=10 [sinmap]=10)
declare -A dem=([msh]="$root/data/msh_2007_utm10n_10m.tif" [logan]="$root/data/logan_utm12n_100m.tif"
                [eno]="$(ls "$root"/data/eno*crop*.tif | head -1)" [med]="$root/data/med_01_01_10m.tif"
                [sinmap]="$shared/sinmap_sample_10m.asc")
echo "| DEM | view | coverage | boundary | flat | valley | ink px | strokes |"
echo "|---|---|---|---|---|---|---|---|"
for name in msh logan eno med sinmap; do
  for kind in as-is rounded; do
    src="${dem[$name]}"
    if [ "$kind" = rounded ]; then
      gdal_translate -q -ot Int16 "$src" "$work/${name}_int.tif"
      src="$work/${name}_int.tif"
    fi
    m="$work/${name}_$kind.ply" d="$work/${name}_$kind.dv"
    [ -f "$m" ] || "$bin/dem2mesh" "$src" "$m" ${spacing[$name]} -q > /dev/null
    [ -f "$d" ] || "$bin/build-drainage" "$m" "$d" --spacing "${drain[$name]}" -q > /dev/null
    stats=$("$bin/terrain-render" frame "$m" "$d" -o "$work/${name}_$kind.png" --line-stats "$@")
    "$bin/terrain-render" frame "$m" -o "$work/${name}_${kind}_mask.png" --layers mask -q "$@" > /dev/null
    # Coverage: the mask (white) over the background (#dde4ec): mean R = bg + cov (1 - bg).
    red=$(oiiotool "$work/${name}_${kind}_mask.png" --printstats 2>/dev/null | awk '/Avg:/{print $3; exit}')
    cov=$(awk -v r="$red" 'BEGIN{if (r > 1) r /= 255; bg=221/255; printf "%.1f %%", 100*(r-bg)/(1-bg)}')
    get() { echo "$stats" | awk -F': ' -v k="$1" '$1==k{print $2}'; }
    pct() { awk -v x="$(get "$1")" 'BEGIN{printf "%.1f %%", 100*x}'; }
    view=$(echo "$stats" | awk '/^view:/{print $3", "$5}')
    echo "| $name ($kind) | $view | $cov | $(pct 'crease boundary share') | $(pct 'crease flat share') | $(pct 'crease valley share') | $(get 'crease length px') | $(get 'crease strokes') |"
  done
done
