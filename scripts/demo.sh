#!/usr/bin/env bash
# Installs what is missing, builds, and runs the whole pipeline on the bundled sample
# DEMs (data/): meshes, previews, drainage databases and their views, renderings.
# Outputs go to out/ (or $1).
set -euo pipefail
cd "$(dirname "$0")/.."
# TERRAIN_BIN=DIR runs the binaries in DIR instead (no install, no build): the same outputs
# from two builds, compared file by file (docs/architecture.md, "Refactoring").
if [ -z "${TERRAIN_BIN:-}" ]; then
  scripts/install-deps.sh
  scripts/build.sh
fi
out="${1:-out}"
mkdir -p "$out"
bin="${TERRAIN_BIN:-build/bin}"

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
run $bin/terrain-inspect export "$out/logan.dv" --to tif -o "$out/logan_rasters"   # every layer as GeoTIFF

echo "== Renderings (terrain-render: OpenGL through EGL; llvmpipe without a GPU)"
# Depressions breached (cut up to 10 m deep, filled below that), so that channels run on
# to their outlets along the valleys instead of across flat filled reaches.
run $bin/build-drainage "$out/msh_50m.ply" "$out/msh_breached.dv" --spacing 10 --breach 10 -q
run $bin/build-drainage "$out/logan_100m.ply" "$out/logan_breached.dv" --spacing 30 --breach 10 -q
$bin/terrain-render --device > "$out/render_device.txt"
# Mount St. Helens crater: the pen-and-ink mask with creases and silhouettes (default
# camera), the shaded relief, and the crater seen from the north.
run $bin/terrain-render frame "$out/msh_50m.ply" "$out/msh_breached.dv" -o "$out/render_msh_lines.png"
# The same lines as vector paths (layers for Inkscape; docs/terrain-render.md, "Vector output").
run $bin/terrain-render frame "$out/msh_50m.ply" "$out/msh_breached.dv" -o "$out/render_msh_lines.svg"
run $bin/terrain-render frame "$out/msh_50m.ply" "$out/msh_breached.dv" -o "$out/render_msh_lines.pdf"
run $bin/terrain-render frame "$out/msh_50m.ply" "$out/msh_breached.dv" -o "$out/render_msh_shaded.png" \
  --layers shaded,creases,silhouettes --eye 562300 5119450 4300 --view-az 170 --view-alt 38 --fov 28
# Hachures (docs/terrain-render.md, "Hachures"): a hachured landscape (Imhof's rows), and a
# plan-view hachure map in map coordinates, as an SVG and as a GeoPackage layer for QGIS;
# the top view as a map (orthographic, north up; a world file beside the PNG).
run $bin/terrain-render frame "$out/msh_50m.ply" "$out/msh_breached.dv" -o "$out/render_msh_hachures.png" \
  --layers mask,hachures,creases,silhouettes --hachure-style rows
run $bin/terrain-inspect export "$out/msh_10m.ply" --to svg -o "$out/msh_hachure_map.svg"
run $bin/terrain-inspect export "$out/msh_10m.ply" --to gpkg -o "$out/msh_hachure_map.gpkg"
run $bin/terrain-render frame "$out/msh_50m.ply" "$out/msh_breached.dv" -o "$out/render_msh_map.png" --view top
run $bin/terrain-render frame "$out/msh_50m.ply" -o "$out/render_msh_relief.png" --layers shaded \
  --eye 562300 5119450 4300 --view-az 170 --view-alt 38 --fov 28
# Logan: the mountains east of Cache Valley, 2x vertical exaggeration; channels from 9 ha
# (100 points of its 30 m drainage; the default, 1 ha, draws every hillside gully here).
run $bin/terrain-render frame "$out/logan_100m.ply" "$out/logan_breached.dv" -o "$out/render_logan_lines.png" \
  --eye 433000 4624000 5500 --view-az 50 --view-alt 15 --fov 40 --exaggeration 2 --min-area 90000
run $bin/terrain-render frame "$out/logan_100m.ply" "$out/logan_breached.dv" -o "$out/render_logan_shaded.png" \
  --eye 433000 4624000 5500 --view-az 50 --view-alt 15 --fov 40 --exaggeration 2 --layers shaded,creases,silhouettes \
  --min-area 90000
# Object-space edges of the mesh facets (contours, boundary, creases sharper than 25 deg).
run $bin/terrain-render frame "$out/msh_50m.ply" -o "$out/render_msh_edges.png" --layers mask,edges --crease-angle 25 \
  --eye 562300 5119450 4300 --view-az 170 --view-alt 38 --fov 28
# Photic extremum lines: denoised meshes carry the Voronoi weights PELs need.
run $bin/denoise-normals "$out/msh_10m.ply" "$out/msh_10m_denoised.ply" -q
run $bin/denoise-normals "$out/logan_100m.ply" "$out/logan_100m_denoised.ply" -q
run $bin/terrain-inspect preview "$out/msh_10m_denoised.ply" --colour-by normal-change -o "$out/msh_10m_normal_change.png"
run $bin/terrain-render frame "$out/msh_10m_denoised.ply" -o "$out/render_msh_pels.png" --layers mask,pels
# Creases drawn on the 10 m mesh come from its own drainage: the 50 m mesh's channels do
# not follow this finer surface's valleys (terrain-render warns when they are mixed).
run $bin/build-drainage "$out/msh_10m_denoised.ply" "$out/msh_10m_breached.dv" --spacing 10 --breach 10 -q
run $bin/terrain-render frame "$out/msh_10m_denoised.ply" "$out/msh_10m_breached.dv" -o "$out/render_msh_pels_lines.png" \
  --layers mask,pels,creases,silhouettes
run $bin/terrain-render frame "$out/logan_100m_denoised.ply" -o "$out/render_logan_pels.png" --layers mask,pels \
  --eye 433000 4624000 5500 --view-az 50 --view-alt 15 --fov 40 --exaggeration 2
run $bin/terrain-render frame "$out/logan_100m_denoised.ply" "$out/logan_breached.dv" -o "$out/render_logan_pels_lines.png" \
  --layers mask,pels,creases,silhouettes --eye 433000 4624000 5500 --view-az 50 --view-alt 15 --fov 40 --exaggeration 2 \
  --min-area 90000
# Every frame shows terrain in at least 60 % of it, with no look over the DEM's edge
# (bench/frame_coverage.sh measures it). A short flight into the crater: frames,
# timings.csv and the paper's tables.
run $bin/terrain-render path --from 562200 5119450 3800 --to 562500 5118000 3300 --frames 12 --view-alt 35 \
  -o "$out/msh_path.csv"
mkdir -p "$out/msh_flight"
run $bin/terrain-render batch "$out/msh_50m.ply" "$out/msh_breached.dv" "$out/msh_path.csv" -o "$out/msh_flight" \
  --size 960x540 -q | tee "$out/msh_flight/summary.txt"

echo
echo "Outputs in $out/:"
ls -l "$out"
