#!/usr/bin/env bash
# cmake --install of the build tree BUILD into a scratch prefix, then a consumer project
# configured, built and run against it: find_package(terrain CONFIG) and the two targets.
#   install_test.sh BUILD_DIR SOURCE_DIR CXX_COMPILER DEM
set -euo pipefail
build=$1 src=$2 cxx=$3 dem=$4
prefix=$(mktemp -d)
trap 'rm -rf "$prefix"' EXIT
cmake --install "$build" --prefix "$prefix/usr" >/dev/null
for f in bin/dem2mesh bin/build-drainage bin/terrain-render include/terrain/grid.hpp include/drainage/d8.hpp \
         lib/cmake/terrain/terrainConfig.cmake; do
  [ -e "$prefix/usr/$f" ] || { echo "not installed: $f"; exit 1; }
done
for t in dem2mesh build-drainage denoise-normals terrain-inspect terrain-render; do
  "$prefix/usr/bin/$t" --version | grep -Eq '^[0-9]+\.[0-9]+\.[0-9]+ \(git [0-9a-f]+' || { echo "$t --version has no version and git hash"; exit 1; }
done
cmake -S "$src/tests/install/consumer" -B "$prefix/build" -DCMAKE_CXX_COMPILER="$cxx" \
  -DCMAKE_PREFIX_PATH="$prefix/usr" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$prefix/build" >/dev/null
"$prefix/build/consumer" "$dem"
