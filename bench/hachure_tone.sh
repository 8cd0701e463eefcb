#!/usr/bin/env bash
# Issue 51's tone-fidelity figure (docs/terrain-render.md, "Hachures"): for each mesh given,
# the frame at its automatic view drawn twice, `--layers mask,hachures` and `--layers
# shaded`; the hachure ink (darkness, 0..1) blurred by a Gaussian of 2 hachure spacings
# is correlated (Pearson r) with the shaded layer's darkness over the terrain's pixels.
# Target: r >= 0.7, at the automatic view and at --view top. Prints one row per mesh, view
# and tone. TONE_VIEWS (default "auto top") and TONES (default "light slope") pick them.
# Usage: bench/hachure_tone.sh WORKDIR MESH.ply [MESH.ply ...]   (/usr/bin/python3 with numpy and GDAL)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="${TERRAIN_BIN:-$root/build/bin}"
work="$1"
shift
mkdir -p "$work"
spacing=6
echo "mesh view tone r hachure_ink_share ceiling r_both_blurred"
for m in "$@"; do
  for view in ${TONE_VIEWS:-auto top}; do
  name=$(basename "$m" .ply)_$view
  "$bin/terrain-render" frame "$m" -o "$work/${name}_shaded.png" --layers shaded --view "$view" -q > /dev/null
  for tone in ${TONES:-light slope}; do
    "$bin/terrain-render" frame "$m" -o "$work/${name}_$tone.png" --layers mask,hachures --hachure-tone "$tone" \
      --hachure-spacing "$spacing" --view "$view" -q > /dev/null
    /usr/bin/python3 - "$work/${name}_$tone.png" "$work/${name}_shaded.png" "$spacing" "$(basename "$m" .ply) $view" "$tone" <<'EOF'
import sys
import numpy as np
from osgeo import gdal
hach, shaded, spacing, name, tone = sys.argv[1], sys.argv[2], float(sys.argv[3]), sys.argv[4], sys.argv[5]
def rgb(path):
    d = gdal.Open(path)
    return np.stack([d.GetRasterBand(b + 1).ReadAsArray().astype(float) / 255 for b in range(3)])
h, s = rgb(hach), rgb(shaded)
bg = np.array([0xdd, 0xe4, 0xec])[:, None, None] / 255
terrain = np.abs(s - bg).max(axis=0) > 0.02          # the shaded layer covers the terrain
ink = 1 - h.mean(axis=0)                              # darkness of the hachure frame (white mask: 0)
ink[~terrain] = 0
sigma = 2 * spacing                                   # a Gaussian of 2 hachure spacings, separable
r = int(3 * sigma)
k = np.exp(-0.5 * (np.arange(-r, r + 1) / sigma) ** 2)
k /= k.sum()
def blur(a):
    a = np.apply_along_axis(lambda v: np.convolve(v, k, mode="same"), 1, a)
    return np.apply_along_axis(lambda v: np.convolve(v, k, mode="same"), 0, a)
w = blur(terrain.astype(float))
b = blur(ink) / np.maximum(w, 1e-6)                   # normalized inside the terrain
dark = 1 - s.mean(axis=0)
sel = terrain & (w > 0.5)
rr = np.corrcoef(b[sel], dark[sel])[0, 1]
dark_terrain = np.where(terrain, dark, 0)
db = blur(dark_terrain) / np.maximum(w, 1e-6)         # the shaded tone at the same scale
ceiling = np.corrcoef(db[sel], dark[sel])[0, 1]       # the best any blurred ink can do against the sharp shade
both = np.corrcoef(b[sel], db[sel])[0, 1]             # both blurred: tone against tone
print(f"{name} {tone} {rr:.3f} {ink[terrain].mean():.4f} {ceiling:.3f} {both:.3f}")
EOF
  done
  done
done
