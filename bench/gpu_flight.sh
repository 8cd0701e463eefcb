#!/usr/bin/env bash
# The paper's flight on a GPU (issue 40, target 5; docs/performance.md): prepares a folder
# that a machine with a GPU but without this project's libraries runs as it is.
#   bench/gpu_flight.sh [DIR]      (default build/gpu_flight; needs scripts/build.sh first)
# DIR then holds gpu-flight and the three libraries it links (epoxy, fmt, gomp), two scenes
# and their frame lists, and run.sh, which prints the device (GPU and driver) and:
#   1. the paper's scene (as bench/render_creases.sh: 120 x 120 at 50 m from Logan, 10 m
#      drainage), its 99-frame flight at 1280 x 720, full frame (shaded, creases,
#      silhouettes): Tables 3 and 4 from GL timers and the wall clock; target TOTALfps >= 235;
#   2. the PEL pass on the Mount St. Helens 10 m mesh (denoised), 20 frames: Tables 3 and
#      4 and the PEL pass in triangles per second.
# On this project's device tool: run with carry [DIR] and command "DIR/run.sh". Here,
# DIR/run.sh runs on llvmpipe (a check that the folder is complete).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="$root/build/bin"
dir="${1:-$root/build/gpu_flight}"
for b in gpu-flight gpu-flight-scene dem2mesh build-drainage denoise-normals terrain-render; do
  [ -x "$bin/$b" ] || { echo "gpu_flight.sh: $bin/$b is missing: run scripts/build.sh first" >&2; exit 1; }
done
rm -rf "$dir"
mkdir -p "$dir/lib"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# 1. The paper's scene and flight (bench/render_creases.sh's).
"$bin/dem2mesh" "$root/data/logan_utm12n_100m.tif" "$tmp/scene.ply" --center 450000 4640000 --size 6000 6000 \
  --spacing 50 -q > /dev/null
"$bin/build-drainage" "$tmp/scene.ply" "$tmp/scene.dv" --spacing 10 -q > /dev/null
"$bin/gpu-flight-scene" "$tmp/scene.ply" "$tmp/scene.dv" "$dir/logan_creases.scene"
"$bin/terrain-render" path --from 446500 4636500 3400 --to 451500 4641500 3100 --frames 99 --view-alt 18 \
  -o "$dir/logan_flight.csv" > /dev/null
# 2. PELs on the MSH 10 m mesh, denoised (the Voronoi weights PELs need), over the crater.
"$bin/dem2mesh" "$root/data/msh_2007_utm10n_10m.tif" "$tmp/msh_10m.ply" --spacing 10 -q > /dev/null
"$bin/denoise-normals" "$tmp/msh_10m.ply" "$tmp/msh_10m_denoised.ply" -q > /dev/null
"$bin/gpu-flight-scene" "$tmp/msh_10m_denoised.ply" "$dir/msh_pels.scene"
"$bin/terrain-render" path --from 561800 5113500 3300 --to 562900 5116000 3000 --frames 20 --view-alt 25 \
  -o "$dir/msh_flight.csv" > /dev/null

cp "$bin/gpu-flight" "$dir/"
ldd "$bin/gpu-flight" | awk '/=> \// && /lib(epoxy|fmt|gomp)\./ {print $3}' | xargs -I{} cp -L {} "$dir/lib/"
cat > "$dir/run.sh" <<'RUN'
#!/bin/sh
# Runs the flights of bench/gpu_flight.sh on whatever GPU EGL gives.
set -e
here="$(cd "$(dirname "$0")" && pwd)"
export LD_LIBRARY_PATH="$here/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
echo "== 1. the paper's scene, 99 frames, 1280 x 720, full frame (shaded, creases, silhouettes)"
"$here/gpu-flight" "$here/logan_creases.scene" "$here/logan_flight.csv" --layers shaded,creases,silhouettes
echo "== 2. PELs on the MSH 10 m mesh (denoised), 20 frames, 1280 x 720"
"$here/gpu-flight" "$here/msh_pels.scene" "$here/msh_flight.csv" --layers mask,pels
RUN
chmod +x "$dir/run.sh"
echo "gpu_flight.sh: $dir ($(du -sh "$dir" | cut -f1)): run $dir/run.sh there"
