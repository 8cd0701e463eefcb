#!/usr/bin/env bash
# The share of each frame that shows terrain: pixels other than terrain-render's background
# (#dde4ec, to within 1/255 per channel), counted by oiiotool --colorcount. Usage:
#   bench/frame_coverage.sh [PNG...]   (default: the demo's frames, out/render_*.png and
#                                       out/msh_flight/*.png)
# Prints one line per frame, and exits 1 when one shows terrain in less than 60 % of it
# (issue 50: every demo frame >= 60 %).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
[ $# -gt 0 ] || set -- "$root"/out/render_*.png "$root"/out/msh_flight/*.png
low=0
for f in "$@"; do
  read -r w h < <(oiiotool --info "$f" | sed -nE 's/.*: *([0-9]+) x +([0-9]+),.*/\1 \2/p')
  bg=$(oiiotool "$f" --colorcount:eps=0.004,0.004,0.004,1 0.866667,0.894118,0.925490,1 | awk '{print $1; exit}')
  cov=$(awk -v b="$bg" -v w="$w" -v h="$h" 'BEGIN{printf "%.1f", 100 * (1 - b / (w * h))}')
  flag=$(awk -v c="$cov" 'BEGIN{print (c < 60) ? "  < 60 %" : ""}')
  [ -z "$flag" ] || low=1
  echo "$cov % terrain  $f$flag"
done
exit $low
