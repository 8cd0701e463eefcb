#!/usr/bin/env bash
# Pictures that show the mountains (issue 64): every DEM of ../shared/data meshed, drained
# and drawn with no option (`dem2mesh X m.ply; build-drainage m.ply m.dv; terrain-render
# frame m.ply m.dv -o x.png --line-stats`), beside its shaded frame at the same camera
# (`--layers shaded`), and each line layer alone (`--layers mask,L`). For each, how well its
# ink follows the shaded frame's darkness (bench/bandpass_r.py): the band-pass r (a
# difference of Gaussians, 3 px - 12 px: the forms) and r8 (both blurred by 8 px: the tone);
# the silhouettes' mean piece; and the balance of the layers, each layer's share of the
# picture's ink (bench/ink_share.py: creases, hachures, silhouettes). A DEM dem2mesh refuses with no option (no-data inside
# its extent) is meshed with --fill-nodata, one in degrees without a CRS with --src-crs
# EPSG:4326, and the table says so.
# Usage: bench/pictures.sh [WORKDIR] [EXTRA RENDER OPTIONS...]   (a markdown table)
#   PICTURES_DEMS="a.tif b.asc" bench/pictures.sh W   # only these DEMs; TERRAIN_BIN=DIR: other tools
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="${TERRAIN_BIN:-$root/build/bin}"
work="${1:-$(mktemp -d)}"
shift || true
mkdir -p "$work"
shared="$root/../shared/data"
r() { /usr/bin/python3 "$root/bench/bandpass_r.py" "$1" "$2"; }
echo "| DEM | mesh | picture band-pass | picture r8 | hachures band-pass | creases band-pass | silhouettes band-pass | silhouette mean piece px | crease connected | ink: creases / hachures / silhouettes | frame s |"
echo "|---|---|---|---|---|---|---|---|---|---|---|"
for src in ${PICTURES_DEMS:-"$shared"/*.tif "$shared"/*.asc "$shared"/*.bil}; do
  name=$(basename "${src%.*}")
  case "$name" in *taudem* | *aread8* | *d8dir*) continue ;; esac  # TauDEM's outputs, not DEMs
  m="$work/$name.ply" d="$work/$name.dv" how="no option"
  # A mesh made before (WORKDIR reused) is kept, with the option it was made with.
  if [ -f "$m" ] && [ -f "$work/$name.how" ]; then
    how=$(cat "$work/$name.how")
  elif ! "$bin/dem2mesh" "$src" "$m" -q > /dev/null 2> "$work/$name.err"; then
    # The option dem2mesh's refusal names: --fill-nodata, or the CRS of a DEM in degrees
    # without one (the SRTM Front Range tile).
    how="--fill-nodata"
    grep -q -- "--src-crs EPSG:4326" "$work/$name.err" && how="--src-crs EPSG:4326"
    "$bin/dem2mesh" "$src" "$m" $how -q > /dev/null 2>> "$work/$name.err" || {
      echo "| $name | refused: $(tail -1 "$work/$name.err") | | | | | | | | | |"
      continue
    }
  fi
  echo "$how" > "$work/$name.how"
  [ -f "$d" ] || "$bin/build-drainage" "$m" "$d" -q > /dev/null
  t0=$(date +%s.%N)
  stats=$("$bin/terrain-render" frame "$m" "$d" -o "$work/$name.png" --line-stats "$@")
  t1=$(date +%s.%N)
  "$bin/terrain-render" frame "$m" -o "$work/${name}_shaded.png" --layers shaded -q "$@" > /dev/null
  for layer in hachures creases silhouettes; do
    "$bin/terrain-render" frame "$m" "$d" -o "$work/${name}_$layer.png" --layers "mask,$layer" -q "$@" > /dev/null
  done
  read -r band r8 _ < <(r "$work/$name.png" "$work/${name}_shaded.png")
  read -r hb _ _ < <(r "$work/${name}_hachures.png" "$work/${name}_shaded.png")
  read -r cb _ _ < <(r "$work/${name}_creases.png" "$work/${name}_shaded.png")
  read -r sb _ _ < <(r "$work/${name}_silhouettes.png" "$work/${name}_shaded.png")
  share() { /usr/bin/python3 "$root/bench/ink_share.py" "$work/${name}_$1.png" "$work/$name.png"; }
  get() { echo "$stats" | awk -F': ' -v k="$1" '$1==k{print $2}'; }
  echo "| $name | $how | $band | $r8 | $hb | $cb | $sb | $(get 'silhouette mean piece px') | $(get 'crease connected share') | $(share creases) / $(share hachures) / $(share silhouettes) | $(awk -v a="$t0" -v b="$t1" 'BEGIN{printf "%.1f", b-a}') |"
done
