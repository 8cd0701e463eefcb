#!/usr/bin/env bash
# Issue 38, item 4 (docs/terrain-render.md, "Density across mesh resolutions"): a 50 m and
# a 25 m mesh of the same DEM (dem2mesh --spacing 50 / 25, each drained at 10 m with
# --breach 10) drawn at the 50 m mesh's automatic view (its eye, view and light given to
# the 25 m mesh's frame); prints each frame's crease ink (--line-stats) and the change.
# Target: within 25 %. Usage: bench/density_by_resolution.sh [WORKDIR] [RENDER OPTIONS...]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="$root/build/bin"
work="${1:-$(mktemp -d)}"
shift || true
mkdir -p "$work"
declare -A dem=([msh]="$root/data/msh_2007_utm10n_10m.tif" [logan]="$root/data/logan_utm12n_100m.tif")
ink() { awk -F': ' '$1 == "crease length px" {print $2}'; }
for name in msh logan; do
  for sp in 50 25; do
    m="$work/${name}_$sp.ply" d="$work/${name}_$sp.dv"
    [ -f "$m" ] || "$bin/dem2mesh" "${dem[$name]}" "$m" --spacing "$sp" -q > /dev/null
    [ -f "$d" ] || "$bin/build-drainage" "$m" "$d" --spacing 10 --breach 10 -q > /dev/null
  done
  out=$("$bin/terrain-render" frame "$work/${name}_50.ply" "$work/${name}_50.dv" -o "$work/${name}_50.png" --line-stats "$@")
  read -r ex ey ez < <(echo "$out" | awk '/^eye:/ {print $2, $3, $4}')
  read -r az alt fov < <(echo "$out" | awk '/^view:/ {print $3, $5, $7}')
  read -r laz lalt < <(echo "$out" | awk '/^light:/ {print $3, $5}')
  out25=$("$bin/terrain-render" frame "$work/${name}_25.ply" "$work/${name}_25.dv" -o "$work/${name}_25.png" --line-stats \
    --eye "$ex" "$ey" "$ez" --view-az "$az" --view-alt "$alt" --fov "$fov" --light-az "$laz" --light-alt "$lalt" "$@")
  a=$(echo "$out" | ink) b=$(echo "$out25" | ink)
  awk -v n="$name" -v a="$a" -v b="$b" 'BEGIN {printf "%-6s 50 m mesh %6d px, 25 m mesh %6d px: %+.1f %%\n", n, a, b, 100 * (b - a) / a}'
done
