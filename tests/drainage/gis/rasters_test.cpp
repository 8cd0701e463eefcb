// The GeoTIFF views of a drainage result read back to the same directions and counts, in
// both encodings.
#include <gtest/gtest.h>

#include <filesystem>

#include "drainage/pipeline.hpp"
#include "drainage/rasters.hpp"
#include "terrain/dem_io.hpp"
#include "test_support.hpp"

namespace drainage {
namespace {

TEST(Rasters, DirectionsAndAccumulationRoundTrip) {
  const DrainageResult r =
      compute_drainage(terrain::read_dem(terrain::test::data("logan_utm12n_100m.tif")), {});
  for (D8Encoding enc : {D8Encoding::Taudem, D8Encoding::Esri}) {
    terrain::test::ScratchDir dir;
    write_drainage_rasters(dir.path(""), r, enc, "rasters_test");
    for (const char* name : kDrainageRasterNames)
      EXPECT_TRUE(std::filesystem::exists(dir.path(name))) << name;
    EXPECT_EQ(dir.n_entries(), std::size(kDrainageRasterNames));
    terrain::Grid grid;
    const D8Codes back = read_d8_raster(dir.path("d8.tif"), enc, grid);
    ASSERT_EQ(back.size(), r.dirs.size());
    for (std::size_t i = 0; i < back.size(); ++i) {
      const std::uint8_t expected = r.dirs[i] < 8          ? r.dirs[i]
                                    : r.dirs[i] == kNodata ? kNodata
                                                           : kNoFlow;
      ASSERT_EQ(back[i], expected)
          << i;  // outlets and pits are both "no direction" (0) in the file
    }
    const terrain::Grid acc = terrain::read_dem(dir.path("accumulation.tif"));
    for (std::size_t i = 0; i < acc.size(); ++i) ASSERT_EQ(acc.z[i], float(r.net.accumulated[i]));
    EXPECT_EQ(grid.geo.x0, r.surface.geo.x0);
    EXPECT_EQ(grid.geo.epsg, r.surface.geo.epsg);
  }
}

}  // namespace
}  // namespace drainage
