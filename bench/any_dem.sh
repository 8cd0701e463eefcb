#!/usr/bin/env bash
# "A picture of any DEM" (docs/terrain-render.md): each DEM's no-option frame as a new user
# makes it, `dem2mesh X m.ply; build-drainage m.ply m.dv; terrain-render frame m.ply m.dv
# -o x.png --line-stats`, with no option anywhere (issue 50: the mesh at the DEM's own
# spacing, drainage by build-drainage's defaults: sampled at 10 m, depressions breached),
# as a markdown table row. Integer copies by gdal_translate -ot Int16 (rounds); 3-arc-second
# integer copies (what SRTM users have) by gdalwarp -t_srs EPSG:4326 -tr 1/1200 -r average
# -ot Int16, for the DEMs that carry a CRS.
# Usage: bench/any_dem.sh [WORKDIR] [EXTRA RENDER OPTIONS...]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="${TERRAIN_BIN:-$root/build/bin}"
work="${1:-$(mktemp -d)}"
shift || true
mkdir -p "$work"
shared="$root/../shared/data"
declare -A dem=([msh]="$root/data/msh_2007_utm10n_10m.tif" [logan]="$root/data/logan_utm12n_100m.tif"
                [eno]="$(ls "$root"/data/eno*crop*.tif | head -1)" [med]="$root/data/med_01_01_10m.tif"
                [sinmap]="$shared/sinmap_sample_10m.asc" [enofull]="$shared/eno_nad83_geographic_third_arcsec.tif"
                [medpr]="$shared/med_01_01_10m_taudem_pitremove.tif")
echo "| DEM | view | coverage | boundary | flat | valley | connected | ink px | strokes | mean stroke px | relief r | r_tone |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
for name in msh logan eno med sinmap enofull medpr; do
  for kind in as-is rounded 3as; do
    src="${dem[$name]}"
    if [ "$kind" = rounded ]; then
      gdal_translate -q -ot Int16 "$src" "$work/${name}_int.tif"
      src="$work/${name}_int.tif"
    elif [ "$kind" = 3as ]; then
      if ! gdalsrsinfo -o epsg "$src" 2>/dev/null | grep -q EPSG; then
        echo "| $name ($kind) | no CRS: no 3-arc-second copy | | | | | | | | | | |"
        continue
      fi
      gdalwarp -q -overwrite -t_srs EPSG:4326 -tr 0.000833333333 0.000833333333 -r average -ot Int16 "$src" \
        "$work/${name}_3as.tif"
      src="$work/${name}_3as.tif"
    fi
    m="$work/${name}_$kind.ply" d="$work/${name}_$kind.dv"
    # sinmap's DEM is a watershed: no-data all round its irregular edge, inside its extent,
    # which dem2mesh refuses naming the fix (--fill-nodata): the one option of the table.
    fill=""
    [ "$name" = sinmap ] && fill=--fill-nodata
    [ -f "$m" ] || "$bin/dem2mesh" "$src" "$m" $fill -q > /dev/null
    [ -f "$d" ] || "$bin/build-drainage" "$m" "$d" -q > /dev/null
    stats=$("$bin/terrain-render" frame "$m" "$d" -o "$work/${name}_$kind.png" --line-stats "$@")
    "$bin/terrain-render" frame "$m" -o "$work/${name}_${kind}_mask.png" --layers mask -q "$@" > /dev/null
    # Does the picture show the relief (issue 51)? Its ink against the shaded layer at the same
    # camera, blurred by a Gaussian of 12 px (2 hachure spacings): bench/tone_r.py.
    "$bin/terrain-render" frame "$m" -o "$work/${name}_${kind}_shaded.png" --layers shaded -q "$@" > /dev/null
    read -r rel _ceil rtone _share < <(/usr/bin/python3 "$root/bench/tone_r.py" "$work/${name}_$kind.png" \
      "$work/${name}_${kind}_shaded.png" 12)
    # Coverage: the mask (white) over the background (#dde4ec): mean R = bg + cov (1 - bg).
    red=$(oiiotool "$work/${name}_${kind}_mask.png" --printstats 2>/dev/null | awk '/Avg:/{print $3; exit}')
    cov=$(awk -v r="$red" 'BEGIN{if (r > 1) r /= 255; bg=221/255; printf "%.1f %%", 100*(r-bg)/(1-bg)}')
    get() { echo "$stats" | awk -F': ' -v k="$1" '$1==k{print $2}'; }
    pct() { awk -v x="$(get "$1")" 'BEGIN{printf "%.1f %%", 100*x}'; }
    view=$(echo "$stats" | awk '/^view:/{print $3", "$5}')
    echo "| $name ($kind) | $view | $cov | $(pct 'crease boundary share') | $(pct 'crease flat share') | $(pct 'crease valley share') | $(get 'crease connected share') | $(get 'crease length px') | $(get 'crease strokes') | $(get 'crease mean stroke px') | $rel | $rtone |"
  done
done
