#!/usr/bin/env bash
# Issue 51's tone-fidelity figure (docs/terrain-render.md, "Hachures"): for each mesh given,
# the frame at its automatic view drawn twice, `--layers mask,hachures` and `--layers
# shaded`; the hachure ink (darkness, 0..1) blurred by a Gaussian of 2 hachure spacings
# is correlated (Pearson r) with the shaded layer's darkness over the terrain's pixels
# (bench/tone_r.py: r against the sharp shade, its ceiling, and r_tone, both blurred).
# Target: r_tone >= 0.7, at the automatic view and at --view top (the sharp shade's ceiling
# is under 0.7 on detailed relief: docs/terrain-render.md, "Tone"). Prints one row per mesh, view
# and tone. TONE_VIEWS (default "auto top") and TONES (default "light slope") pick them.
# Usage: bench/hachure_tone.sh WORKDIR MESH.ply [MESH.ply ...]   (/usr/bin/python3 with numpy and GDAL)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="${TERRAIN_BIN:-$root/build/bin}"
work="$1"
shift
mkdir -p "$work"
spacing=6
echo "mesh view tone r ceiling r_tone hachure_ink_share"
for m in "$@"; do
  for view in ${TONE_VIEWS:-auto top}; do
  name=$(basename "$m" .ply)_$view
  "$bin/terrain-render" frame "$m" -o "$work/${name}_shaded.png" --layers shaded --view "$view" -q > /dev/null
  for tone in ${TONES:-light slope}; do
    "$bin/terrain-render" frame "$m" -o "$work/${name}_$tone.png" --layers mask,hachures --hachure-tone "$tone" \
      --hachure-spacing "$spacing" --view "$view" -q > /dev/null
    echo "$(basename "$m" .ply) $view $tone $(/usr/bin/python3 "$root/bench/tone_r.py" "$work/${name}_$tone.png" \
      "$work/${name}_shaded.png" "$((2 * spacing))")"
  done
  done
done
