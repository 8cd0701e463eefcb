// Reading real DEMs and the grid coordinate convention.
#include <gdal_utils.h>
#include <gtest/gtest.h>

#include "terrain/dem_io.hpp"
#include "terrain/error.hpp"
#include "test_support.hpp"

namespace terrain {
namespace {

using test::data;

TEST(GridConvention, SampleCentresAndRowsGrowSouth) {
  Georef g;
  g.x0 = 1000.0;
  g.y0 = 2000.0;
  g.dx = 10.0;
  g.dy = 20.0;
  EXPECT_DOUBLE_EQ(g.x_of_col(0), 1005.0);  // centre of the first cell
  EXPECT_DOUBLE_EQ(g.y_of_row(0), 1990.0);  // row 0 is the northern row
  EXPECT_DOUBLE_EQ(g.y_of_row(2), 1950.0);  // rows grow southwards
  EXPECT_DOUBLE_EQ(g.col_of_x(1005.0), 0.0);
  EXPECT_DOUBLE_EQ(g.row_of_y(1950.0), 2.0);
}

TEST(ReadDem, MountStHelens) {
  const Grid g = read_dem(data("msh_2007_utm10n_10m.tif"));
  EXPECT_EQ(g.cols, 303u);
  EXPECT_EQ(g.rows, 442u);
  EXPECT_EQ(g.geo.epsg, 26910);  // NAD83 / UTM zone 10N
  EXPECT_EQ(g.geo.crs_kind, CrsKind::Projected);
  EXPECT_EQ(crs_name(g.geo), "NAD83 / UTM zone 10N");
  // Extent from gdalinfo: origin (561194.998500889982097, 5119474.988851799629629), 10 m.
  EXPECT_DOUBLE_EQ(g.geo.x0, 561194.998500889982097);
  EXPECT_DOUBLE_EQ(g.geo.y0, 5119474.988851799629629);
  EXPECT_DOUBLE_EQ(g.geo.dx, 10.0);
  EXPECT_DOUBLE_EQ(g.geo.dy, 10.0);
  EXPECT_EQ(g.count_nodata(), 0u);
  const ElevationStats s = elevation_stats(g.z);
  EXPECT_GT(s.min, 1300.0);  // crater floor and dome of Mount St. Helens
  EXPECT_LT(s.max, 2550.0);  // the rim is below the 2,549 m summit
}

TEST(ReadDem, Logan) {
  const Grid g = read_dem(data("logan_utm12n_100m.tif"));
  EXPECT_EQ(g.cols, 289u);
  EXPECT_EQ(g.rows, 498u);
  EXPECT_EQ(g.geo.epsg, 26912);  // NAD83 / UTM zone 12N
  EXPECT_DOUBLE_EQ(g.geo.x0, 432705.554750000010245);
  EXPECT_DOUBLE_EQ(g.geo.y0, 4662454.140879999846220);
  EXPECT_DOUBLE_EQ(g.geo.dx, 100.0);
  EXPECT_DOUBLE_EQ(g.geo.dy, 100.0);
}

TEST(ReadDem, GeographicEno) {
  const Grid g = read_dem(data("eno_nad83_geographic_crop.tif"));
  EXPECT_EQ(g.cols, 300u);
  EXPECT_EQ(g.rows, 300u);
  EXPECT_EQ(g.geo.crs_kind, CrsKind::Geographic);
  EXPECT_EQ(g.geo.epsg, 4269);
  EXPECT_NEAR(g.geo.dx, 1.0 / 3.0 / 3600.0, 1e-15);  // 1/3 arc-second
  EXPECT_NEAR(g.geo.x0, -79.137621830863793, 1e-12);
  EXPECT_NEAR(g.geo.y0, 36.215996754089545, 1e-12);
}

TEST(ReadDem, AsciiGridWithoutCrsAndWithNodata) {
  const Grid g = read_dem(data("sinmap_crop_10m.asc"));
  // Header: ncols 200, nrows 150, xllcorner 634592, yllcorner 5590375, cellsize 10, NODATA -9999.
  EXPECT_EQ(g.cols, 200u);
  EXPECT_EQ(g.rows, 150u);
  EXPECT_EQ(g.geo.crs_kind, CrsKind::None);
  EXPECT_DOUBLE_EQ(g.geo.x0, 634592.0);
  EXPECT_DOUBLE_EQ(g.geo.y0, 5590375.0 + 150 * 10.0);
  EXPECT_TRUE(std::isnan(g.at(0, 0)));  // first value in the file is -9999
  EXPECT_GT(g.count_nodata(), 0u);
  EXPECT_LT(g.count_nodata(), g.size());
  const auto mask = g.nodata_mask();
  EXPECT_EQ(std::size_t(std::count(mask.begin(), mask.end(), 1)), g.count_nodata());
}

TEST(ReadDem, VrtMosaic) {
  // A VRT mosaic of two GeoTIFF halves (west and east) reads as the whole DEM.
  test::ScratchDir dir;
  const Grid g = read_dem(data("msh_2007_utm10n_10m.tif"));
  Grid west = g, east = g;
  west.cols = 150;
  east.cols = g.cols - 150;
  east.geo.x0 += 150 * g.geo.dx;
  west.z.clear();
  east.z.clear();
  for (std::size_t r = 0; r < g.rows; ++r)
    for (std::size_t c = 0; c < g.cols; ++c) (c < 150 ? west.z : east.z).push_back(g.at(r, c));
  write_geotiff(west, dir.path("w.tif"));
  write_geotiff(east, dir.path("e.tif"));
  const char* inputs[] = {nullptr, nullptr};
  const std::string w = dir.path("w.tif"), e = dir.path("e.tif");
  inputs[0] = w.c_str();
  inputs[1] = e.c_str();
  GDALDatasetH vrt = GDALBuildVRT(dir.path("m.vrt").c_str(), 2, nullptr, inputs, nullptr, nullptr);
  ASSERT_NE(vrt, nullptr);
  GDALClose(vrt);
  const Grid m = read_dem(dir.path("m.vrt"));
  EXPECT_EQ(m.cols, g.cols);
  EXPECT_EQ(m.rows, g.rows);
  EXPECT_EQ(m.geo.epsg, 26910);
  EXPECT_DOUBLE_EQ(m.geo.x0, g.geo.x0);
  EXPECT_EQ(m.z, g.z);
}

TEST(ReadDem, ErrorsNameTheFile) {
  try {
    read_dem("/nonexistent/dem.tif");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/dem.tif"), std::string::npos);
  }
  EXPECT_THROW(read_dem(data("PROVENANCE.md")), Error);  // a file GDAL cannot read as raster
}

TEST(WriteGeotiff, RoundTripKeepsValuesCrsAndNodata) {
  test::ScratchDir dir;
  Grid g = read_dem(data("msh_2007_utm10n_10m.tif"));
  g.at(5, 7) = std::numeric_limits<float>::quiet_NaN();
  write_geotiff(g, dir.path("out.tif"), "test");
  const Grid back = read_dem(dir.path("out.tif"));
  EXPECT_EQ(back.geo.epsg, 26910);
  EXPECT_DOUBLE_EQ(back.geo.x0, g.geo.x0);
  EXPECT_DOUBLE_EQ(back.geo.y0, g.geo.y0);
  ASSERT_EQ(back.size(), g.size());
  EXPECT_TRUE(std::isnan(back.at(5, 7)));
  for (std::size_t i = 0; i < g.size(); ++i) {
    if (g.valid(i)) {
      ASSERT_EQ(back.z[i], g.z[i]) << i;
    }
  }
  EXPECT_EQ(dir.n_entries(), 1u);  // no temporary file left behind
}

}  // namespace
}  // namespace terrain
