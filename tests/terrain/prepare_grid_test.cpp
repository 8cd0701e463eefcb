// Reprojection, cropping, resampling and the no-data policy (prepare_grid), checked
// against hand-worked values, exact identities and gdalwarp.
#include <gdal_priv.h>
#include <gdal_utils.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "terrain/dem_io.hpp"
#include "terrain/grid_mesh.hpp"
#include "terrain/prepare_grid.hpp"
#include "terrain/resample.hpp"
#include "terrain/utm.hpp"
#include "test_support.hpp"

namespace terrain {

void PrintTo(Resampling r, std::ostream* os) {
  *os << (r == Resampling::Bilinear ? "bilinear" : "cubic");
}

namespace {

using test::data;

// docs/algorithms.md 10.3 worked numbers: 4 x 4 grid, sample at (row 1.25, col 1.5).
TEST(SampleGrid, WorkedExample) {
  Grid g(4, 4, Georef{});
  const float v[16] = {100, 102, 104, 106, 101, 104, 107, 110,
                       103, 107, 111, 115, 106, 111, 116, 121};
  std::copy(v, v + 16, g.z.begin());
  EXPECT_NEAR(sample_grid(g, 1.25, 1.5, Resampling::Bilinear), 106.375, 1e-5);
  EXPECT_NEAR(sample_grid(g, 1.25, 1.5, Resampling::Cubic), 106.28125, 1e-5);
  // At sample centres both kernels reproduce the sample.
  EXPECT_EQ(sample_grid(g, 2, 1, Resampling::Bilinear), 107.0f);
  EXPECT_EQ(sample_grid(g, 2, 1, Resampling::Cubic), 107.0f);
  // A no-data sample with non-zero weight makes the result no-data; with zero weight not.
  g.at(1, 2) = std::numeric_limits<float>::quiet_NaN();
  EXPECT_TRUE(std::isnan(sample_grid(g, 1.25, 1.5, Resampling::Bilinear)));
  EXPECT_EQ(sample_grid(g, 1.0, 1.0, Resampling::Bilinear), 104.0f);
}

// docs/algorithms.md 10.5 (GeographicLib 2.1.2 values).
TEST(Utm, StandardZonesIncludingExceptions) {
  EXPECT_EQ(standard_utm_zone(46.5, 7.5).zone, 32);
  EXPECT_EQ(standard_utm_zone(60.0, 5.0).zone, 32);   // Norway exception (plain rule: 31)
  EXPECT_EQ(standard_utm_zone(78.0, 20.0).zone, 33);  // Svalbard exception (plain rule: 34)
  EXPECT_FALSE(standard_utm_zone(-33.9, 18.4).north);
  EXPECT_EQ(standard_utm_zone(-33.9, 18.4).zone, 34);
  EXPECT_THROW(standard_utm_zone(85.0, 10.0), Error);  // UPS territory
  EXPECT_EQ(parse_utm_zone("17", 36.0).zone, 17);
  EXPECT_TRUE(parse_utm_zone("17", 36.0).north);
  EXPECT_FALSE(parse_utm_zone("17s", 36.0).north);
  EXPECT_THROW(parse_utm_zone("61N", 0.0), Error);
  EXPECT_THROW(parse_utm_zone("17X", 0.0), Error);
}

// gdalwarp (the GDAL library call behind the command) with the given arguments, to MEM.
Grid gdalwarp(const std::string& src, std::vector<std::string> args) {
  GDALAllRegister();
  args.insert(args.end(), {"-of", "MEM", "-et", "0"});
  CPLStringList argv;
  for (const auto& a : args) argv.AddString(a.c_str());
  GDALWarpAppOptions* opts = GDALWarpAppOptionsNew(argv.List(), nullptr);
  GDALDatasetH in = GDALOpen(src.c_str(), GA_ReadOnly);
  int usage_error = 0;
  GDALDatasetH out = GDALWarp("", nullptr, 1, &in, opts, &usage_error);
  GDALWarpAppOptionsFree(opts);
  EXPECT_NE(out, nullptr);
  auto* ds = GDALDataset::FromHandle(out);
  Grid g(std::size_t(ds->GetRasterYSize()), std::size_t(ds->GetRasterXSize()), Georef{});
  EXPECT_EQ(ds->GetRasterBand(1)->RasterIO(GF_Read, 0, 0, int(g.cols), int(g.rows), g.z.data(),
                                           int(g.cols), int(g.rows), GDT_Float32, 0, 0),
            CE_None);
  GDALClose(out);
  GDALClose(in);
  return g;
}

// The Eno geographic DEM lands on UTM zone 17N at the requested spacing and agrees with
// gdalwarp doing the same resampling. Tolerance 1 mm: both evaluate the same bilinear or
// Keys-cubic kernel at the same inverse-mapped points (GeographicLib vs PROJ differ by
// nanometres); measured differences are ~1e-4 m (float rounding). The spacing (8 m) is
// finer than the source's (8.3 m E-W, 10.3 m N-S) because gdalwarp widens its kernel
// when downsampling, which dem2mesh does not (docs/dem2mesh.md).
class EnoVsGdalwarp : public ::testing::TestWithParam<Resampling> {};

TEST_P(EnoVsGdalwarp, AgreesAtSampledCells) {
  const Resampling method = GetParam();
  const Grid src = read_dem(data("eno_nad83_geographic_crop.tif"));
  GridRequest req;
  req.spacing = 8.0;
  req.resampling = method;
  const PreparedGrid p = prepare_grid(src, req);
  const Grid& g = p.grid;
  EXPECT_EQ(g.geo.epsg, 26917);  // NAD83 / UTM zone 17N
  EXPECT_EQ(crs_name(g.geo), "NAD83 / UTM zone 17N");
  EXPECT_DOUBLE_EQ(g.geo.dx, 8.0);
  EXPECT_DOUBLE_EQ(g.geo.dy, 8.0);
  EXPECT_DOUBLE_EQ(std::fmod(g.geo.x0, 8.0), 0.0);  // aligned to the spacing (-tap)
  EXPECT_EQ(g.count_nodata(), 0u);                  // inner rectangle: no sample outside the DEM
  EXPECT_GT(g.rows, 100u);
  EXPECT_GT(g.cols, 100u);

  const double xmax = g.geo.x0 + double(g.cols) * g.geo.dx,
               ymin = g.geo.y0 - double(g.rows) * g.geo.dy;
  const Grid ref =
      gdalwarp(data("eno_nad83_geographic_crop.tif"),
               {"-t_srs", "EPSG:26917", "-te", std::to_string(g.geo.x0), std::to_string(ymin),
                std::to_string(xmax), std::to_string(g.geo.y0), "-tr", "8", "8", "-r",
                method == Resampling::Bilinear ? "bilinear" : "cubic"});
  ASSERT_EQ(ref.rows, g.rows);
  ASSERT_EQ(ref.cols, g.cols);
  const unsigned seed = 20261122;
  std::mt19937 rng(seed);
  // Cubic near the border needs samples beyond the DEM, which gdalwarp and we treat
  // differently (it renormalizes, we clamp): compare 2 cells in from the border.
  std::uniform_int_distribution<std::size_t> rr(2, g.rows - 3), cc(2, g.cols - 3);
  double worst = 0.0;
  for (int k = 0; k < 400; ++k) {
    const std::size_t r = rr(rng), c = cc(rng);
    worst = std::max(worst, double(std::abs(g.at(r, c) - ref.at(r, c))));
  }
  EXPECT_LT(worst, 1e-3) << "seed " << seed;
  RecordProperty("max_abs_difference_m", std::to_string(worst));
}

INSTANTIATE_TEST_SUITE_P(Kernels, EnoVsGdalwarp,
                         ::testing::Values(Resampling::Bilinear, Resampling::Cubic),
                         [](const auto& info) {
                           return info.param == Resampling::Bilinear ? "bilinear" : "cubic";
                         });

TEST(PrepareGrid, EnoZoneOverride) {
  const Grid src = read_dem(data("eno_nad83_geographic_crop.tif"));
  GridRequest req;
  req.spacing = 30.0;
  req.utm_zone = "18";
  const PreparedGrid p = prepare_grid(src, req);
  EXPECT_EQ(p.grid.geo.epsg, 26918);
  EXPECT_EQ(p.grid.count_nodata(), 0u);
}

TEST(PrepareGrid, EnoDefaultSpacingIsTheNorthSouthSpacing) {
  const Grid src = read_dem(data("eno_nad83_geographic_crop.tif"));
  const PreparedGrid p = prepare_grid(src, {});
  // 1/3 arc-second of latitude at 36.2 N is 10.28 m (30.87 m per arc-second there).
  EXPECT_NEAR(p.grid.geo.dx, 10.28, 0.011);
  EXPECT_DOUBLE_EQ(p.grid.geo.dx, p.grid.geo.dy);
}

TEST(PrepareGrid, ProjectedAtOwnSpacingIsTheSourceItself) {
  const Grid src = read_dem(data("logan_utm12n_100m.tif"));
  const PreparedGrid p = prepare_grid(src, {});
  EXPECT_EQ(p.grid.rows, src.rows);
  EXPECT_EQ(p.grid.cols, src.cols);
  EXPECT_DOUBLE_EQ(p.grid.geo.x0, src.geo.x0);
  EXPECT_DOUBLE_EQ(p.grid.geo.y0, src.geo.y0);
  EXPECT_EQ(p.grid.geo.epsg, 26912);
  EXPECT_EQ(p.grid.z, src.z);
  EXPECT_TRUE(p.warnings.empty());
}

TEST(PrepareGrid, ResampleKeepsTheSourceLattice) {
  const Grid src = read_dem(data("msh_2007_utm10n_10m.tif"));
  GridRequest req;
  req.spacing = 50.0;
  const PreparedGrid p = prepare_grid(src, req);
  // Target cells are source-aligned (x0 = source x0 + k * 50 m), so a 50 m centre, 25 m
  // in from a cell corner, falls on the source sample centre 2.5 cells in: the output
  // samples are source samples. Centres 25 + 50 k m from the corner must lie within the
  // source centres (5 .. 3025 m E-W, 5 .. 4415 m N-S): k = 0..60 and 0..87.
  EXPECT_DOUBLE_EQ(std::fmod(p.grid.geo.x0 - src.geo.x0, 50.0), 0.0);
  EXPECT_EQ(p.grid.cols, 61u);
  EXPECT_EQ(p.grid.rows, 88u);
  const double col = src.geo.col_of_x(p.grid.geo.x_of_col(3)),
               row = src.geo.row_of_y(p.grid.geo.y_of_row(4));
  EXPECT_DOUBLE_EQ(col, 17.0);  // 25 m + 3*50 m from the corner: sample 17 (centre 175 m)
  EXPECT_DOUBLE_EQ(row, 22.0);
  EXPECT_EQ(p.grid.at(4, 3), src.at(22, 17));
}

// A projected source maps rows to rows and columns to columns: the resampling takes each
// column's kernel taps once. It must give sample_grid's values bit for bit, no-data
// neighbours included (a geographic source goes through sample_grid per sample).
TEST(PrepareGrid, SeparableTapsEqualSampleGridPerSample) {
  Grid src = read_dem(data("logan_utm12n_100m.tif"));
  for (std::size_t r = 40; r < 44; ++r)
    for (std::size_t c = 100; c < 103; ++c) src.at(r, c) = std::numeric_limits<float>::quiet_NaN();
  const DemInfo eno = read_dem_info(data("eno_nad83_geographic_crop.tif"));
  EXPECT_FALSE(plan_grid(eno.geo, eno.rows, eno.cols, {}).separable);
  for (Resampling k : {Resampling::Bilinear, Resampling::Cubic})
    for (double spacing : {7.0, 100.0, 130.0}) {
      GridRequest req;
      req.resampling = k;
      req.spacing = spacing;
      req.fill_nodata = true;
      GridPlan plan = plan_grid(src.geo, src.rows, src.cols, req);
      plan.source_window = {0, 0, src.rows, src.cols};
      ASSERT_TRUE(plan.separable);
      const PreparedGrid taps = resample_to_plan(src, plan, req);
      plan.separable = false;
      const PreparedGrid each = resample_to_plan(src, plan, req);
      EXPECT_GT(taps.filled, 0u);
      EXPECT_EQ(taps.filled, each.filled);
      ASSERT_EQ(taps.grid.size(), each.grid.size());
      EXPECT_EQ(
          std::memcmp(taps.grid.z.data(), each.grid.z.data(), taps.grid.size() * sizeof(float)), 0)
          << spacing << " m";
    }
}

TEST(PrepareGrid, CropByBboxAndByCenterAgree) {
  const Grid src = read_dem(data("msh_2007_utm10n_10m.tif"));
  GridRequest a;
  a.bbox = std::array<double, 4>{562000.0, 5116000.0, 563000.0, 5117500.0};
  GridRequest b;
  b.center = std::array<double, 2>{562500.0, 5116750.0};
  b.size = std::array<double, 2>{1000.0, 1500.0};
  const Grid ga = prepare_grid(src, a).grid, gb = prepare_grid(src, b).grid;
  EXPECT_EQ(ga.z, gb.z);
  EXPECT_DOUBLE_EQ(ga.geo.x0, gb.geo.x0);
  EXPECT_EQ(ga.cols, 100u);  // centres inside a 1000 m box at 10 m: exactly 100
  EXPECT_EQ(ga.rows, 150u);
  // Every sample is the source sample at the same place.
  const std::size_t c0 = std::size_t(std::lround(src.geo.col_of_x(ga.geo.x_of_col(0))));
  const std::size_t r0 = std::size_t(std::lround(src.geo.row_of_y(ga.geo.y_of_row(0))));
  for (std::size_t r = 0; r < ga.rows; ++r)
    for (std::size_t c = 0; c < ga.cols; ++c) ASSERT_EQ(ga.at(r, c), src.at(r0 + r, c0 + c));
}

// No-data by default (docs/dem2mesh.md, "No-data"): sinmap's no-data lies around its data,
// at the grid's edge: every no-data sample is outside (no face), filled for the normals
// beside it, and the data untouched. With fill_nodata, every one is filled and invented.
TEST(PrepareGrid, NodataAtTheEdgeIsOutsideOrFilled) {
  const Grid src = read_dem(data("sinmap_crop_10m.asc"));
  const PreparedGrid out = prepare_grid(src, {});
  EXPECT_EQ(out.grid.count_nodata(), 0u);
  EXPECT_EQ(out.outside, src.count_nodata());
  EXPECT_EQ(out.voids, 0u);
  for (std::size_t i = 0; i < src.size(); ++i) {
    ASSERT_EQ(out.filled_mask[i], src.valid(i) ? kFromData : kOutside) << i;
    if (src.valid(i)) {
      ASSERT_EQ(out.grid.z[i], src.z[i]);
    }
  }
  GridRequest fill;
  fill.fill_nodata = true;
  const PreparedGrid p = prepare_grid(src, fill);
  EXPECT_EQ(p.grid.count_nodata(), 0u);
  EXPECT_EQ(p.filled, src.count_nodata());
  // Valid samples are untouched; filled ones lie within the valid range.
  const ElevationStats s = elevation_stats(src.z);
  for (std::size_t i = 0; i < src.size(); ++i) {
    if (src.valid(i))
      ASSERT_EQ(p.grid.z[i], src.z[i]);
    else
      ASSERT_TRUE(p.grid.z[i] >= s.min - 1e-3 && p.grid.z[i] <= s.max + 1e-3);
  }
  ASSERT_EQ(p.warnings.size(), 1u);  // no CRS: taken as metres
}

// Which no-data is a void (classify_nodata): on a disc of data (radius 40 samples in 101 x
// 101) with a 3 x 3 void and a 20 x 20 one inside it, the 9 samples are a void (filled, flow
// runs through), the 400 exceed max_void (256) and stay outside like the ring around the
// disc, which reaches the grid's edge; with max_void 400 both voids are filled.
TEST(PrepareGrid, SmallVoidsInsideTheDataAreFilledTheRestIsOutside) {
  Georef geo;
  geo.dx = geo.dy = 10;
  Grid g(101, 101, geo);
  std::size_t ring = 0;
  for (long r = 0; r < 101; ++r)
    for (long c = 0; c < 101; ++c) {
      const bool out = std::hypot(double(r - 50), double(c - 50)) > 40;
      const bool small = r >= 49 && r < 52 && c >= 20 && c < 23;
      const bool big = r >= 40 && r < 60 && c >= 55 && c < 75;
      g.at(std::size_t(r), std::size_t(c)) =
          out || small || big ? std::numeric_limits<float>::quiet_NaN() : float(r + c);
      ring += out;
    }
  std::vector<std::uint8_t> m = classify_nodata(g, 256);
  std::size_t counts[4] = {0, 0, 0, 0};
  for (const std::uint8_t v : m) ++counts[v];
  EXPECT_EQ(counts[kVoidFilled], 9u);
  EXPECT_EQ(counts[kOutside], ring + 400);
  EXPECT_EQ(m[50 * 101 + 21], kVoidFilled);
  EXPECT_EQ(m[50 * 101 + 60], kOutside);
  m = classify_nodata(g, 400);
  EXPECT_EQ(m[50 * 101 + 60], kVoidFilled);
  EXPECT_EQ(m[0], kOutside);
}

TEST(PrepareGrid, ImpossibleRequests) {
  const Grid src = read_dem(data("msh_2007_utm10n_10m.tif"));
  auto fails = [&](GridRequest r) { EXPECT_THROW(prepare_grid(src, r), Error); };
  GridRequest r;
  r.spacing = 0.0;
  fails(r);
  r.spacing = -10.0;
  fails(r);
  r = {};
  r.bbox = std::array<double, 4>{0.0, 0.0, 1000.0, 1000.0};  // outside
  fails(r);
  r.bbox = std::array<double, 4>{561000.0, 5116000.0, 562000.0,
                                 5117000.0};  // reaches beyond the west edge
  fails(r);
  r.bbox = std::array<double, 4>{562000.0, 5116000.0, 562005.0, 5117000.0};  // fewer than 2 columns
  fails(r);
  r = {};
  r.utm_zone = "10";  // projected DEM
  fails(r);
  Grid empty = src;
  std::fill(empty.z.begin(), empty.z.end(), std::numeric_limits<float>::quiet_NaN());
  EXPECT_THROW(prepare_grid(empty, {}), Error);
}

}  // namespace
}  // namespace terrain

namespace terrain {
namespace {

// Reading only the plan's source window gives exactly the grid prepare_grid makes from
// the whole DEM: projected and geographic sources, bilinear and cubic, with and without a
// crop, at, above and below the source spacing.
TEST(PrepareGrid, WindowedReadEqualsTheWholeSource) {
  struct Case {
    std::string file;
    GridRequest req;
  };
  std::vector<Case> cases;
  for (Resampling k : {Resampling::Bilinear, Resampling::Cubic}) {
    GridRequest a;
    a.resampling = k;
    a.spacing = 30.0;
    a.bbox = std::array<double, 4>{562000, 5116000, 563000, 5117500};
    cases.push_back({"msh_2007_utm10n_10m.tif", a});
    GridRequest b;
    b.resampling = k;
    b.spacing = 7.0;
    b.center = std::array<double, 2>{451000, 4641000};
    b.size = std::array<double, 2>{900, 700};
    cases.push_back({"logan_utm12n_100m.tif", b});
    GridRequest c;  // geographic, default area (the inner UTM rectangle)
    c.resampling = k;
    cases.push_back({"eno_nad83_geographic_crop.tif", c});
  }
  const Grid eno = read_dem(data("eno_nad83_geographic_crop.tif"));
  GridRequest d;  // geographic with a crop in UTM: the centre of the default area
  const PreparedGrid whole = prepare_grid(eno, d);
  const auto& g = whole.grid.geo;
  d.center = std::array<double, 2>{g.x_of_col(double(whole.grid.cols) / 2),
                                   g.y_of_row(double(whole.grid.rows) / 2)};
  d.size = std::array<double, 2>{300, 200};
  cases.push_back({"eno_nad83_geographic_crop.tif", d});

  for (const Case& c : cases) {
    const std::string path = data(c.file);
    const Grid src = read_dem(path);
    const PreparedGrid expected = prepare_grid(src, c.req);
    const DemInfo info = read_dem_info(path);
    const GridPlan plan = plan_grid(info.geo, info.rows, info.cols, c.req);
    const RasterWindow& w = plan.source_window;
    const Grid window = read_dem(path, {}, w);
    if (c.req.bbox || c.req.center) {
      EXPECT_LT(window.size(), src.size() / 4) << c.file;  // a crop reads a part
    }
    const PreparedGrid got = resample_to_plan(window, plan, c.req);
    EXPECT_EQ(got.grid.z, expected.grid.z) << c.file;
    EXPECT_EQ(got.grid.rows, expected.grid.rows);
    EXPECT_EQ(got.grid.geo.x0, expected.grid.geo.x0);
    EXPECT_EQ(got.grid.geo.y0, expected.grid.geo.y0);
    EXPECT_EQ(got.grid.geo.crs_wkt, expected.grid.geo.crs_wkt);
  }
}

}  // namespace
}  // namespace terrain
