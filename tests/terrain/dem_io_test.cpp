// DEM input and raster output through GDAL: windows, round trips of every raster type,
// names that are not files, refused inputs, and no-data filling.
#include <gdal_priv.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>

#include "terrain/dem_io.hpp"
#include "test_support.hpp"

namespace terrain {
namespace {

using test::data;

// A window reads the same samples as the whole raster, and knows where it is.
TEST(DemIo, WindowIsAPartOfTheWhole) {
  const std::string path = data("logan_utm12n_100m.tif");
  const Grid whole = read_dem(path);
  const Grid part = read_dem(path, {}, RasterWindow{10, 20, 30, 40});
  ASSERT_EQ(part.rows, 30u);
  ASSERT_EQ(part.cols, 40u);
  for (std::size_t r = 0; r < 30; ++r)
    for (std::size_t c = 0; c < 40; ++c) ASSERT_EQ(part.at(r, c), whole.at(r + 10, c + 20));
  EXPECT_DOUBLE_EQ(part.geo.x_of_col(0), whole.geo.x_of_col(20));
  EXPECT_DOUBLE_EQ(part.geo.y_of_row(0), whole.geo.y_of_row(10));
  EXPECT_THROW(read_dem(path, {}, RasterWindow{0, 0, whole.rows + 1, 10}), Error);
  const DemInfo info = read_dem_info(path);
  EXPECT_EQ(info.rows, whole.rows);
  EXPECT_EQ(info.cols, whole.cols);
  EXPECT_EQ(info.geo.epsg, whole.geo.epsg);
}

// Every raster type round-trips exactly with its geotransform, CRS, no-data value and
// description; write_geotiff's NaN becomes its no-data value and back.
TEST(DemIo, RasterTypesRoundTrip) {
  test::ScratchDir dir;
  const Grid logan = read_dem(data("logan_utm12n_100m.tif"));
  const std::size_t rows = logan.rows, cols = logan.cols, n = logan.size();
  std::vector<std::uint8_t> bytes(n);
  std::vector<std::int16_t> shorts(n);
  std::vector<std::uint32_t> words(n);
  for (std::size_t i = 0; i < n; ++i) {
    bytes[i] = std::uint8_t(i % 251);
    shorts[i] = std::int16_t(int(i % 60000) - 30000);
    words[i] = std::uint32_t(i * 2654435761u);
  }
  write_raster(dir.path("b.tif"), logan.geo, rows, cols, RasterType::Byte, bytes.data(), 255.0,
               "made by dem_io_test");
  write_raster(dir.path("s.tif"), logan.geo, rows, cols, RasterType::Int16, shorts.data(),
               std::nullopt);
  write_raster(dir.path("w.tif"), logan.geo, rows, cols, RasterType::UInt32, words.data(),
               std::nullopt);
  ensure_gdal();
  auto read_back = [&](const std::string& name, GDALDataType type, void* out) {
    std::unique_ptr<GDALDataset> ds(GDALDataset::Open(dir.path(name).c_str(), GDAL_OF_RASTER));
    ASSERT_TRUE(ds);
    ASSERT_EQ(ds->GetRasterBand(1)->RasterIO(GF_Read, 0, 0, int(cols), int(rows), out, int(cols),
                                             int(rows), type, 0, 0),
              CE_None);
    double gt[6];
    ds->GetGeoTransform(gt);
    EXPECT_EQ(gt[0], logan.geo.x0);
    EXPECT_EQ(gt[3], logan.geo.y0);
    EXPECT_EQ(gt[1], logan.geo.dx);
  };
  std::vector<std::uint8_t> b2(n);
  std::vector<std::int16_t> s2(n);
  std::vector<std::uint32_t> w2(n);
  read_back("b.tif", GDT_Byte, b2.data());
  read_back("s.tif", GDT_Int16, s2.data());
  read_back("w.tif", GDT_UInt32, w2.data());
  EXPECT_EQ(b2, bytes);
  EXPECT_EQ(s2, shorts);
  EXPECT_EQ(w2, words);

  Grid holes = logan;
  holes.at(3, 4) = std::numeric_limits<float>::quiet_NaN();
  write_geotiff(holes, dir.path("f.tif"), "x");
  const Grid back = read_dem(dir.path("f.tif"));
  EXPECT_TRUE(std::isnan(back.at(3, 4)));
  EXPECT_EQ(back.count_nodata(), 1u);
  EXPECT_EQ(back.geo.epsg, logan.geo.epsg);
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isnan(holes.z[i])) {
      ASSERT_EQ(back.z[i], holes.z[i]);
    }
  EXPECT_EQ(dir.n_entries(), 4u);  // no temporary files
}

// Names GDAL opens that are not files, and inputs that are refused with one clear message.
TEST(DemIo, GdalNamesAndRefusedInputs) {
  test::ScratchDir dir;
  const Grid logan = read_dem(data("logan_utm12n_100m.tif"));
  {  // a name that is not a file: the DEM's bytes in GDAL's memory file system
    std::string bytes = test::file_bytes(data("logan_utm12n_100m.tif"));
    ensure_gdal();
    VSILFILE* f =
        VSIFileFromMemBuffer("/vsimem/dem_io_test.tif", reinterpret_cast<GByte*>(bytes.data()),
                             vsi_l_offset(bytes.size()), FALSE);
    ASSERT_TRUE(f);
    VSIFCloseL(f);
    EXPECT_EQ(read_dem("/vsimem/dem_io_test.tif").z, logan.z);
    VSIUnlink("/vsimem/dem_io_test.tif");
  }
  auto message = [](const std::string& path) {
    try {
      read_dem(path);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message(dir.path("missing.tif")).find("no such file"), std::string::npos);
  EXPECT_NE(
      message("NETCDF:" + dir.path("missing.nc") + ":Band1").find("not a raster GDAL can open"),
      std::string::npos);
  EXPECT_NE(message(dir.path("")).find("it is a directory"), std::string::npos);
  Grid inf = logan;
  inf.at(7, 9) = -std::numeric_limits<float>::infinity();
  write_raster(dir.path("inf.tif"), inf.geo, inf.rows, inf.cols, RasterType::Float32, inf.z.data(),
               std::nullopt);
  EXPECT_NE(
      message(dir.path("inf.tif")).find("1 samples are infinite (the first at row 7, column 9)"),
      std::string::npos)
      << message(dir.path("inf.tif"));
}

// GDALFillNodata fills every hole and keeps every valid sample.
TEST(DemIo, FillNodataFillsOnlyTheHoles) {
  Grid g = read_dem(data("logan_utm12n_100m.tif"));
  const Grid original = g;
  for (std::size_t r = 20; r < 25; ++r)
    for (std::size_t c = 30; c < 33; ++c) g.at(r, c) = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(fill_nodata(g), 15u);
  EXPECT_EQ(g.count_nodata(), 0u);
  float lo = 1e30f, hi = -1e30f;  // filled values lie within the surrounding range
  for (std::size_t r = 19; r < 26; ++r)
    for (std::size_t c = 29; c < 34; ++c)
      lo = std::min(lo, original.at(r, c)), hi = std::max(hi, original.at(r, c));
  for (std::size_t i = 0; i < g.size(); ++i) {
    const std::size_t r = i / g.cols, c = i % g.cols;
    if (r >= 20 && r < 25 && c >= 30 && c < 33) {
      EXPECT_GE(g.z[i], lo);
      EXPECT_LE(g.z[i], hi);
    } else {
      ASSERT_EQ(g.z[i], original.z[i]);
    }
  }
  Grid empty(4, 4, g.geo, std::numeric_limits<float>::quiet_NaN());
  EXPECT_THROW(fill_nodata(empty), Error);
}

}  // namespace
}  // namespace terrain

namespace terrain {
namespace {

// A progress callback that asks to stop cancels the read; one that goes on sees the end.
TEST(DemIo, ProgressReportsAndCancels) {
  const std::string path = test::data("msh_2007_utm10n_10m.tif");
  EXPECT_THROW(read_dem(path, [](double) { return false; }), Cancelled);
  double last = -1;
  read_dem(path, [&](double f) {
    EXPECT_GE(f, last);
    last = f;
    return true;
  });
  EXPECT_EQ(last, 1.0);
}

}  // namespace
}  // namespace terrain
