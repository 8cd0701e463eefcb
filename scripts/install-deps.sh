#!/usr/bin/env bash
# Installs the Debian 12 packages the toolkit needs, and only those that are missing.
# Idempotent: checks each package with dpkg first; apt-get runs only when something is absent.
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build ccache pkg-config git
  libcgal-dev libopenmesh-dev libgeographiclib-dev
  libopenimageio-dev libopencv-core-dev openimageio-tools
  libceres-dev libgdal-dev gdal-bin libeigen3-dev zlib1g-dev libzstd-dev libxxhash-dev   # xxhash: the mesh digest that ties a pyramid to its PLY
  libcli11-dev nlohmann-json3-dev libfmt-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libegl-dev libgl-dev libepoxy-dev libglm-dev libtbb-dev
  time valgrind   # valgrind: the sanitizer script's memcheck of the point path
  libopenmpi-dev openmpi-bin   # build-drainage under mpirun (optional at build time; its tests need it)
  clang libclang-rt-14-dev libomp-14-dev   # the sanitizer build of CI, fuzzing (scripts/fuzz.sh)
  libglfw3-dev libimgui-dev xvfb xauth     # terrain-view (GLFW window, Dear ImGui panel) and its tests under Xvfb
  libcairo2-dev libpotrace-dev             # vector line art: SVG and PDF through cairo, the surface mask traced by potrace
  librsvg2-bin poppler-utils               # tests rasterize the SVG (rsvg-convert) and the PDF (pdftoppm)
  clang-format                             # CI checks the sources' layout (scripts/check-format.sh)
  python3-qgis                             # the QGIS Processing provider's test (PyQGIS, headless)
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${#missing[@]} missing package(s): ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install-deps: not root and no sudo; install: ${missing[*]}" >&2; exit 1; }
  SUDO=sudo
fi
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
