#!/usr/bin/env bash
# Makes the QGIS plugin zip of the Processing provider 'terrain' (qgis/terrain_processing):
# install it in QGIS with Plugins > Manage and Install Plugins > Install from ZIP.
# Usage: scripts/make-qgis-plugin.sh [OUT.zip]   (default: out/terrain_processing.zip)
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-out/terrain_processing.zip}"
mkdir -p "$(dirname "$out")"
tmp="$(mktemp "$(cd "$(dirname "$out")" && pwd)/.terrain_processing.XXXXXX.zip")"
rm -f "$tmp"
trap 'rm -f "$tmp"' EXIT
(cd qgis && python3 - "$tmp" <<'PY'
import os, sys, zipfile
with zipfile.ZipFile(sys.argv[1], "w", zipfile.ZIP_DEFLATED) as z:
    for root, _, files in os.walk("terrain_processing"):
        for f in sorted(files):
            if not f.endswith(".pyc"):
                z.write(os.path.join(root, f))
PY
)
mv "$tmp" "$out"
trap - EXIT
echo "plugin: $out"
