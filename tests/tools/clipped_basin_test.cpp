// A DEM clipped to one of its own basins, as a hydrologist clips one: the clipped run's
// accumulation equals the whole DEM's wherever the clip cannot change it; a catchment clipped
// to its watershed draws rivers, not dashes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <string>
#include <vector>

#include "ink.hpp"
#include "terrain/dem_io.hpp"
#include "terrain/neighbours.hpp"
#include "test_support.hpp"

namespace {

using terrain::test::data;
using terrain::test::run;
using terrain::test::tool;

// The cells whose accumulation a clip to `inside` cannot change, given the unclipped run
// (its DEM, filled surface and D8 codes, TauDEM encoding). A cell's D8 code depends on its
// 3 x 3 neighbourhood, so a cell is safe when no cell of its neighbourhood is `touched`:
// outside the clip, beside it (the data's edge), or in a filled depression that reaches a
// touched cell (the clipped run may drain that lake over the cut). A cell keeps its
// accumulation when its whole upstream area is safe.
std::vector<bool> unchanged_by_the_clip(const terrain::Grid& dem, const terrain::Grid& filled,
                                        const terrain::Grid& d8, const terrain::Grid& acc,
                                        const std::vector<bool>& inside) {
  const long R = long(dem.rows), C = long(dem.cols);
  const terrain::Neighbours nb{R, C};
  const std::size_t n = dem.size();
  std::vector<bool> touched(n);
  for (std::size_t i = 0; i < n; ++i) {
    touched[i] = !inside[i];
    nb.each(i, [&](std::size_t j, int) { touched[i] = touched[i] || !inside[j]; });
  }
  std::vector<bool> seen(n);
  for (std::size_t s = 0; s < n; ++s) {  // the lakes: 8-connected raised cells
    if (seen[s] || !(filled.z[s] > dem.z[s])) continue;
    std::vector<std::size_t> lake{s};
    seen[s] = true;
    bool reaches = false;
    for (std::size_t k = 0; k < lake.size(); ++k) {
      reaches = reaches || touched[lake[k]];
      nb.each(lake[k], [&](std::size_t j, int) {
        if (!seen[j] && filled.z[j] > dem.z[j]) seen[j] = true, lake.push_back(j);
      });
    }
    for (std::size_t i : lake) touched[i] = touched[i] || reaches;
  }
  std::vector<bool> safe(n);
  for (std::size_t i = 0; i < n; ++i) {
    safe[i] = !touched[i];
    nb.each(i, [&](std::size_t j, int) { safe[i] = safe[i] && !touched[j]; });
  }
  std::vector<std::size_t> order(n);  // upstream before downstream
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::sort(order.begin(), order.end(), [&](auto a, auto b) { return acc.z[a] < acc.z[b]; });
  for (std::size_t i : order) {
    const float code = d8.z[i];
    if (safe[i] || !(code >= 1 && code <= 8)) continue;
    const long r = long(i) / C + terrain::kDRow[std::size_t(code) - 1],
               c = long(i) % C + terrain::kDCol[std::size_t(code) - 1];
    if (r >= 0 && c >= 0 && r < R && c < C) safe[std::size_t(r * C + c)] = false;
  }
  return safe;
}

// Logan 100 m clipped to its largest basin (gdalwarp -cutline with the basin's polygon from
// terrain-inspect export, on the same grid); "clip.tif" in `dir`.
std::string clip_to_the_largest_basin(const terrain::test::ScratchDir& dir) {
  const std::string dem = data("logan_utm12n_100m.tif");
  auto r =
      run(tool("build-drainage") + " --raster " + dem + " " + dir.path("basins.dv") + " --fill -q");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  r = run(tool("terrain-inspect") + " export " + dir.path("basins.dv") + " --to gpkg -o " +
          dir.path("basins.gpkg") + " --layers basins -q");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  r = run("gdalwarp -q -overwrite -cutline " + dir.path("basins.gpkg") +
          " -csql 'SELECT * FROM basins ORDER BY cells DESC LIMIT 1' -te 432705.55475 " +
          "4612654.14088 461605.55475 4662454.14088 -tr 100 100 -dstnodata -9999 " + dem + " " +
          dir.path("clip.tif"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return dir.path("clip.tif");
}

// Logan 100 m clipped, with gdalwarp -cutline, to its largest basin's polygon from
// terrain-inspect export, on the same grid: in raster mode with --fill, the accumulation
// equals the unclipped run's on every cell the clip cannot change (issue 67's target).
TEST(ClippedBasin, AccumulationInsideEqualsTheWholeDemsRun) {
  terrain::test::ScratchDir dir;
  const std::string dem = data("logan_utm12n_100m.tif");
  auto drainage = [&](const std::string& in, const std::string& name) {
    std::filesystem::create_directory(dir.path(name));
    const auto r = run(tool("build-drainage") + " --raster " + in + " " + dir.path(name + ".dv") +
                       " --fill --rasters " + dir.path(name) + " -q");
    ASSERT_EQ(r.exit_code, 0) << r.err;
  };
  drainage(dem, "whole");
  const std::string clip = clip_to_the_largest_basin(dir);
  drainage(clip, "clip");

  const terrain::Grid z = terrain::read_dem(dem), clipped = terrain::read_dem(clip);
  ASSERT_EQ(clipped.size(), z.size());
  std::vector<bool> inside(z.size());
  std::size_t n_inside = 0;
  for (std::size_t i = 0; i < z.size(); ++i) {
    inside[i] = !std::isnan(clipped.z[i]);
    n_inside += inside[i];
    if (inside[i]) {
      ASSERT_EQ(clipped.z[i], z.z[i]);  // the cut moves no height
    }
  }
  ASSERT_GT(n_inside, z.size() / 3);  // the largest basin: 56,055 of 143,922 cells
  auto whole = [&](const char* f) { return terrain::read_dem(dir.path("whole/") + f); };
  const terrain::Grid acc = whole("accumulation.tif");
  const terrain::Grid acc_clip = terrain::read_dem(dir.path("clip/accumulation.tif"));
  const std::vector<bool> safe =
      unchanged_by_the_clip(z, whole("surface.tif"), whole("d8.tif"), acc, inside);
  std::size_t n_safe = 0, n_equal = 0;
  for (std::size_t i = 0; i < z.size(); ++i)
    if (safe[i]) ++n_safe, n_equal += acc_clip.z[i] == acc.z[i];
  EXPECT_GT(n_safe, n_inside * 8 / 10);  // 47,136 of 56,055 when written
  EXPECT_EQ(n_equal, n_safe);
}

// The same clip in mesh mode, both meshes made and drained with no options and drawn as a
// map at one camera: the creases the clipped mesh draws inside the basin lie within 1 px
// of the whole DEM's there.
TEST(ClippedBasin, MeshModeCreasesMatchTheWholeDemsInsideTheBasin) {
  terrain::test::ScratchDir dir;
  const std::string clip = clip_to_the_largest_basin(dir);
  auto picture = [&](const std::string& dem, const std::string& name) {
    const std::string mesh = dir.path(name + ".ply"), dv = dir.path(name + ".dv");
    const auto r =
        run(tool("dem2mesh") + " " + dem + " " + mesh + " -q && " + tool("build-drainage") + " " +
            mesh + " " + dv + " -q && " + tool("terrain-render") + " frame " + mesh + " " + dv +
            " -o " + dir.path(name + ".png") +
            " --view top --eye 446805 4639054 5000 --map-scale 40 --size 760x1100 "
            "--exaggeration 1 --layers mask,creases -q");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return terrain::test::ink_of(dir.path(name + ".png"));
  };
  const terrain::test::Ink whole = picture(data("logan_utm12n_100m.tif"), "whole"),
                           clipped = picture(clip, "clip");
  // The whole DEM's ink where the clipped mesh is drawn (not the background).
  terrain::test::Ink whole_inside = whole;
  const terrain::test::Ink drawn = terrain::test::drawn_of(dir.path("clip.png"));
  for (std::size_t i = 0; i < whole_inside.on.size(); ++i) whole_inside.on[i] &= drawn.on[i];
  const double precision = terrain::test::near_share(clipped, whole),
               recall = terrain::test::near_share(whole_inside, clipped);
  std::printf("clipped ink %zu px, near the whole's %.4f; the whole's inside %zu px, near %.4f\n",
              terrain::test::count(clipped), precision, terrain::test::count(whole_inside), recall);
  EXPECT_GT(terrain::test::count(clipped), 5000u);
  EXPECT_GE(precision, 0.95);
  EXPECT_GE(recall, 0.9);
}

// A DEM clipped to its watershed, as users have one (Mandakini, SRTM 90 m, 45 % no-data
// round the catchment), meshed, drained and drawn with no option: its creases are rivers
// that reach the river they join, not dashes. Far off, a tributary's flat, lit mouth and
// the trunk's floor score below the distance-raised threshold; the crease bridge (28 px at
// the page scale) joins those gaps: 0.92 connected, 0.59 with the 2 px bridge before.
TEST(ClippedBasin, ACatchmentsCreasesReachTheirRivers) {
  terrain::test::ScratchDir dir;
  const std::string mesh = dir.path("m.ply"), dv = dir.path("m.dv");
  const auto r = run(tool("dem2mesh") + " " + data("mandakini_srtm90_utm44n.tif") + " " + mesh +
                     " -q && " + tool("build-drainage") + " " + mesh + " " + dv + " -q && " +
                     tool("terrain-render") + " frame " + mesh + " " + dv + " -o " +
                     dir.path("m.png") + " --layers mask,creases --line-stats");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string key = "crease connected share: ";
  const auto at = r.out.find(key);
  ASSERT_NE(at, std::string::npos) << r.out;
  const double connected = std::stod(r.out.substr(at + key.size()));
  std::printf("Mandakini, no option: crease connected share %.4f\n", connected);
  EXPECT_GE(connected, 0.9);
}

}  // namespace
