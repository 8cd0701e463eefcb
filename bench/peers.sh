#!/usr/bin/env bash
# Issue 65's peers: every ratio of the issue in one run, as a markdown table (this machine,
# llvmpipe): build-drainage against GRASS r.watershed -s (grass-core installed from Debian
# when missing and we are root); a tiled run against the untiled one on Logan at 10 m and
# 5 m (tiles of 2048) and the peak of a 5 m run with --memory 500; dem2mesh against
# gdalwarp -r cubic for Logan 100 m -> 10 m (a sync before each, so that one's writeback
# does not slow the next); the first frame of the 10 m mesh against the 100 m mesh's (the
# whole terrain-render process, each with its .dv); the full frame against its TFT on the
# Creases paper's scene (bench/render_creases.sh); the viewer's full and cheap frames on
# MSH 50 m (bench/viewer_timings.sh). Wall seconds are the best of PEERS_RUNS (3) runs,
# except GRASS's (one run). Takes about 5 minutes.
# Usage: bench/peers.sh [WORKDIR]   (PEERS_BIN=DIR: another build's tools; PEERS_RUNS=N)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="${PEERS_BIN:-$root/build/bin}"
runs="${PEERS_RUNS:-3}"
work="${1:-$(mktemp -d)}"
mkdir -p "$work"
dem="$root/data/logan_utm12n_100m.tif"

# best CMD...: the smallest wall seconds and the largest peak KiB of $runs runs, "s kib".
# PRE="command": run before each run, off the clock (removing an output that a run would
# replace: freeing a large replaced file's cached pages falls on the process that renames).
best() {
  local s=1e9 k=0 t
  for _ in $(seq "$runs"); do
    [ -z "${PRE:-}" ] || eval "$PRE"
    sync
    /usr/bin/time -f "%e %M" -o "$work/time" "$@" > "$work/out" 2> "$work/err"
    read -r t kib < "$work/time"
    s=$(awk -v a="$s" -v b="$t" 'BEGIN{print (b < a) ? b : a}')
    k=$(awk -v a="$k" -v b="$kib" 'BEGIN{print (b > a) ? b : a}')
  done
  echo "$s $k"
}
ratio() { awk -v a="$1" -v b="$2" 'BEGIN{printf "%.2f", a / b}'; }
mib() { awk -v k="$1" 'BEGIN{printf "%.0f", k / 1024}'; }

[ -f "$work/l10.tif" ] || gdalwarp -q -overwrite -r cubic -tr 10 10 "$dem" "$work/l10.tif"
[ -f "$work/l5.tif" ] || gdalwarp -q -overwrite -r cubic -tr 5 5 "$dem" "$work/l5.tif"

echo "| measure | ours | peer or reference | ratio | target |"
echo "|---|---|---|---|---|"

# build-drainage against r.watershed -s.
read -r u10 u10k < <(best "$bin/build-drainage" --raster "$work/l10.tif" "$work/u.dv" -q)
read -r g10 _ < <("$root/bench/r_watershed.sh" "$work/l10.tif") || true
if [ -n "${g10:-}" ]; then
  echo "| build-drainage --raster, Logan 10 m (14.4 M points) | $u10 s | r.watershed -s $g10 s | $(ratio "$g10" "$u10")x faster | keep it (12.3x) |"
else
  echo "| build-drainage --raster, Logan 10 m | $u10 s | r.watershed: GRASS not installed | | |"
fi

# Tiled against untiled, and the memory bound.
for res in 10 5; do
  read -r u uk < <(best "$bin/build-drainage" --raster "$work/l$res.tif" "$work/u.dv" -q)
  read -r t tk < <(best "$bin/build-drainage" --raster "$work/l$res.tif" "$work/t.dv" --tile-size 2048 -q)
  echo "| tiled (--tile-size 2048) / untiled, Logan $res m | $t s, $(mib "$tk") MiB | $u s, $(mib "$uk") MiB | $(ratio "$t" "$u") | <= 1.5 |"
done
read -r m5 m5k < <(best "$bin/build-drainage" --raster "$work/l5.tif" "$work/m.dv" --memory 500 -q)
echo "| peak of Logan 5 m --memory 500 | $(mib "$m5k") MiB ($m5 s) | 500 MiB bound | $(ratio "$(mib "$m5k")" 500) | <= 1.10 |"
if command -v mpirun > /dev/null; then
  read -r mp mpk < <(best mpirun --allow-run-as-root --oversubscribe -np 2 "$bin/build-drainage" --raster "$work/l10.tif" \
    "$work/mpi.dv" --tile-size 1024 -v)
  rank0=$(grep -o 'peak RSS [0-9]* MiB (rank 0)' "$work/err" | head -1)
  echo "| mpirun -np 2, Logan 10 m, tiles of 1024 | $mp s, $rank0 | untiled $u10 s | $(ratio "$mp" "$u10") | ranks within their share |"
fi

# dem2mesh against gdalwarp.
read -r d _ < <(PRE="rm -f '$work/m10.ply'" best "$bin/dem2mesh" "$dem" "$work/m10.ply" --spacing 10 -q)
read -r g _ < <(PRE="rm -f '$work/g10.tif'" best gdalwarp -q -overwrite -r cubic -tr 10 10 "$dem" "$work/g10.tif")
echo "| dem2mesh Logan 100 m -> 10 m | $d s | gdalwarp -r cubic $g s | $(ratio "$d" "$g") | <= 1.2 |"

# A big mesh's first frame with no options.
"$bin/dem2mesh" "$dem" "$work/m100.ply" -q > /dev/null
[ -f "$work/m100.dv" ] || "$bin/build-drainage" "$work/m100.ply" "$work/m100.dv" -q > /dev/null
[ -f "$work/m10.dv" ] || "$bin/build-drainage" "$work/m10.ply" "$work/m10.dv" -q > /dev/null
read -r f10 _ < <(best "$bin/terrain-render" frame "$work/m10.ply" "$work/m10.dv" -o "$work/f10.png" -q)
read -r f100 _ < <(best "$bin/terrain-render" frame "$work/m100.ply" "$work/m100.dv" -o "$work/f100.png" -q)
echo "| first frame, Logan 10 m mesh with its .dv (whole process) | $f10 s | the 100 m mesh $f100 s | $(ratio "$f10" "$f100") | <= 1.5 |"

# The full frame against its TFT on the paper's scene.
full=$(TERRAIN_BIN="$bin" "$root/bench/render_creases.sh" 30 2>&1 | grep '^ratio full frame / its TFT' || true)
echo "| full frame / its TFT, the paper's scene (30 frames) | ${full#ratio full frame / its TFT: } | | | <= 1.5 |"

# The viewer.
"$bin/dem2mesh" "$root/data/msh_2007_utm10n_10m.tif" "$work/msh50.ply" --spacing 50 -q > /dev/null
[ -f "$work/msh50.dv" ] || "$bin/build-drainage" "$work/msh50.ply" "$work/msh50.dv" -q > /dev/null
v=$(TERRAIN_BIN="$bin" "$root/bench/viewer_timings.sh" "$work/msh50.ply" "$work/msh50.dv")
echo "| terrain-view MSH 50 m, full frames (default layers) | $(echo "$v" | grep '^full' | sed 's/full frame: //') | | | median <= 200 ms |"
echo "| terrain-view MSH 50 m, cheap frames | $(echo "$v" | grep '^cheap' | sed 's/cheap frame: //') | | | >= 12 fps (<= 83 ms) |"
