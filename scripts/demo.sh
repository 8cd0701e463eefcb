#!/usr/bin/env bash
# Installs what is missing, builds, and runs the pipeline that exists so far on the
# bundled sample DEMs (data/): meshes, previews, drainage databases and their views.
# Outputs go to out/ (or $1).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
out="${1:-out}"
mkdir -p "$out"
bin=build/bin

run() { echo "+ $*"; "$@"; }

echo "== Meshes (dem2mesh)"
run $bin/dem2mesh data/msh_2007_utm10n_10m.tif "$out/msh_10m.ply" --spacing 10
run $bin/dem2mesh data/msh_2007_utm10n_10m.tif "$out/msh_50m.ply" --spacing 50
run $bin/dem2mesh data/logan_utm12n_100m.tif "$out/logan_100m.ply"
run $bin/dem2mesh data/eno_nad83_geographic_crop.tif "$out/eno_utm17n_10m.ply" --spacing 10

echo "== Previews and summaries (terrain-inspect)"
for m in msh_10m msh_50m logan_100m eno_utm17n_10m; do
  run $bin/terrain-inspect preview "$out/$m.ply" -o "$out/$m.png"
  $bin/terrain-inspect info "$out/$m.ply" > "$out/$m.info.txt"
done
run $bin/terrain-inspect export "$out/msh_50m.ply" --to tif -o "$out/msh_50m_elevations.tif"

echo "== Drainage vertex databases (build-drainage: PN surface sampled at 10 m)"
mkdir -p "$out/msh_rasters"
run $bin/build-drainage "$out/msh_50m.ply" "$out/msh.dv" --spacing 10 --rasters "$out/msh_rasters"
run $bin/build-drainage "$out/logan_100m.ply" "$out/logan.dv" --spacing 30   # 1.6 M points (10 m: 14 M, 0.5 GB)
for d in msh logan; do
  run $bin/terrain-inspect preview "$out/$d.dv" -o "$out/${d}_drainage.png"
  $bin/terrain-inspect info "$out/$d.dv" > "$out/$d.dv.info.txt"
done
run $bin/terrain-inspect export "$out/msh.dv" --to gpkg -o "$out/msh_branches.gpkg"

echo
echo "Outputs in $out/:"
ls -l "$out"
