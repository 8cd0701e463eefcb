// Scattered points to a grid (scattered.hpp): analytic surfaces with known answers, points
// sampled from a real DEM, the readers (XYZ text, CSV, GeoPackage) recognised by content,
// duplicates and the one-line errors.
#include <gtest/gtest.h>

#include <gdal_alg.h>
#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>

#include <fmt/format.h>

#include "terrain/dem_io.hpp"
#include "terrain/error.hpp"
#include "terrain/scattered.hpp"
#include "test_support.hpp"

namespace terrain {
namespace {

PointCloud random_points(std::size_t n, double size, const std::function<double(double, double)>& f,
                         unsigned seed = 7) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, size);
  PointCloud p;
  for (std::size_t i = 0; i < n; ++i) {
    const double x = u(rng), y = u(rng);
    p.x.push_back(x);
    p.y.push_back(y);
    p.z.push_back(f(x, y));
  }
  p.crs_kind = CrsKind::Projected;
  return p;
}

double plane(double x, double y) { return 3.0 + 0.02 * x - 0.05 * y; }
double paraboloid(double x, double y) {
  return ((x - 500) * (x - 500) + (y - 500) * (y - 500)) / 1000.0;
}

// Both methods reproduce a plane (linear precision) to 1e-9 everywhere inside the hull.
TEST(Scattered, PlaneIsReproducedExactly) {
  const PointSurface s(random_points(500, 1000, plane));
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(150, 850);
  for (int i = 0; i < 2000; ++i) {
    const double x = u(rng), y = u(rng);
    for (const auto m :
         {PointInterpolation::Linear, PointInterpolation::NaturalC0, PointInterpolation::Natural})
      ASSERT_NEAR(s.z_at(x, y, m), plane(x, y), 1e-9) << x << " " << y;
  }
  EXPECT_TRUE(std::isnan(s.z_at(-10, 500, PointInterpolation::NaturalC0)));  // outside the hull
}

// A paraboloid. Natural (Sibson's C1 interpolant, gradients fitted by Sibson's method)
// reproduces spherical quadratics: where every natural neighbour has a fitted gradient it
// is exact, and it beats linear by far. Linear and Sibson's C0 interpolant are convex
// combinations of vertex values with linear precision, so by Jensen's inequality neither
// falls below the convex surface; C0 is not better than linear here (docs/dem2mesh.md).
TEST(Scattered, NaturalReproducesTheParaboloid) {
  const PointCloud pts = random_points(400, 1000, paraboloid);
  const PointSurface s(pts);
  double se[3] = {0, 0, 0};
  std::size_t n = 0;
  for (double y = 200; y <= 800; y += 10)
    for (double x = 200; x <= 800; x += 10) {
      const PointInterpolation methods[3] = {
          PointInterpolation::Linear, PointInterpolation::NaturalC0, PointInterpolation::Natural};
      for (int k = 0; k < 3; ++k) {
        const double e = s.z_at(x, y, methods[k]) - paraboloid(x, y);
        if (k < 2) {
          ASSERT_GE(e, -1e-9) << x << " " << y;
        }
        se[k] += e * e;
      }
      ++n;
    }
  for (std::size_t i = 0; i < 20; ++i)
    for (const auto m : {PointInterpolation::NaturalC0, PointInterpolation::Natural})
      EXPECT_NEAR(s.z_at(pts.x[i], pts.y[i], m), pts.z[i], 1e-9);
  const double rmse[3] = {std::sqrt(se[0] / double(n)), std::sqrt(se[1] / double(n)),
                          std::sqrt(se[2] / double(n))};
  std::printf("paraboloid RMSE: linear %.4f m, natural-c0 %.4f m, natural %.3g m\n", rmse[0],
              rmse[1], rmse[2]);
  EXPECT_LT(rmse[2], 1e-6);
  EXPECT_LT(rmse[2], rmse[0]);
}

// The grid: samples on multiples of the spacing, no-data outside the hull, and --max-edge
// blanks the long triangles of a gap.
TEST(Scattered, GridExtentHullAndMaxEdge) {
  PointCloud p;  // points below the diagonal x + y = 1000: the box's far corner is outside the hull
  p.crs_kind = CrsKind::Projected;
  const PointCloud all = random_points(600, 1000, plane);
  for (std::size_t i = 0; i < all.size(); ++i)
    if (all.x[i] + all.y[i] < 1000 || std::abs(all.x[i] - 500) + std::abs(all.y[i] - 500) < 1) {
      p.x.push_back(all.x[i]);
      p.y.push_back(all.y[i]);
      p.z.push_back(all.z[i]);
    }
  PointGridRequest req;
  req.spacing = 50;
  const PointGridResult r = points_to_grid(p, req);
  EXPECT_DOUBLE_EQ(std::fmod(r.grid.geo.x_of_col(0), 50.0), 0.0);
  EXPECT_DOUBLE_EQ(std::fmod(r.grid.geo.y_of_row(0), 50.0), 0.0);
  EXPECT_GT(r.nodata, 0u);  // the bounding box's corners lie outside the hull
  for (std::size_t i = 0; i < r.grid.size(); ++i)
    if (r.grid.valid(i)) {
      const double x = r.grid.geo.x_of_col(double(i % r.grid.cols)),
                   y = r.grid.geo.y_of_row(double(i / r.grid.cols));
      EXPECT_NEAR(r.grid.z[i], plane(x, y), 1e-4);
    }
  // A gap: no points in the middle square; with max-edge 150 its samples are no-data.
  PointCloud gap;
  gap.crs_kind = CrsKind::Projected;
  for (std::size_t i = 0; i < all.size(); ++i)
    if (std::abs(all.x[i] - 500) > 200 || std::abs(all.y[i] - 500) > 200) {
      gap.x.push_back(all.x[i]);
      gap.y.push_back(all.y[i]);
      gap.z.push_back(all.z[i]);
    }
  const PointSurface s(gap);
  EXPECT_FALSE(std::isnan(s.z_at(500, 500, PointInterpolation::Linear)));
  EXPECT_TRUE(std::isnan(s.z_at(500, 500, PointInterpolation::Linear, 150)));
  EXPECT_TRUE(std::isnan(s.z_at(500, 500, PointInterpolation::NaturalC0, 150)));
}

// Points sampled from the Mount St. Helens DEM (a random 1-in-7 subset of its cells)
// interpolated back onto the DEM's own 10 m grid: RMSE at the cells not sampled, beside
// GDAL's own linear gridding (GDALGridCreate GGA_Linear, what gdal_grid -a linear runs) of
// the same points on the same grid.
TEST(Scattered, MountStHelensSubsetReproducesTheDem) {
  const Grid dem = read_dem(test::data("msh_2007_utm10n_10m.tif"));
  std::mt19937_64 rng(2024);
  std::uniform_int_distribution<int> one_in_7(0, 6);
  PointCloud p;
  p.crs_kind = CrsKind::Projected;
  std::vector<std::uint8_t> sampled(dem.size(), 0);
  for (std::size_t i = 0; i < dem.size(); ++i)
    if (dem.valid(i) && one_in_7(rng) == 0) {
      p.x.push_back(dem.geo.x_of_col(double(i % dem.cols)));
      p.y.push_back(dem.geo.y_of_row(double(i / dem.cols)));
      p.z.push_back(dem.z[i]);
      sampled[i] = 1;
    }
  const PointSurface s(p);
  // GDAL: nodes at the DEM's cell centres (gdal_grid's convention).
  ensure_gdal();
  GDALGridLinearOptions opt{};
  opt.nSizeOfStructure = sizeof opt;
  opt.dfRadius = 0;  // outside every triangle: no-data
  opt.dfNoDataValue = std::nan("");
  std::vector<double> gdal(dem.size());
  const double x0 = dem.geo.x0, x1 = dem.geo.x0 + double(dem.cols) * dem.geo.dx;
  const double y1 = dem.geo.y0, y0 = dem.geo.y0 - double(dem.rows) * dem.geo.dy;
  ASSERT_EQ(GDALGridCreate(GGA_Linear, &opt, GUInt32(p.size()), p.x.data(), p.y.data(), p.z.data(),
                           x0, x1, y1, y0, GUInt32(dem.cols), GUInt32(dem.rows), GDT_Float64,
                           gdal.data(), nullptr, nullptr),
            CE_None);
  // Squared errors over the cells not sampled where all three have a value.
  double se[4] = {0, 0, 0, 0};
  std::size_t n = 0;
  for (std::size_t i = 0; i < dem.size(); ++i) {
    if (sampled[i] || !dem.valid(i) || std::isnan(gdal[i])) continue;
    const double x = dem.geo.x_of_col(double(i % dem.cols)),
                 y = dem.geo.y_of_row(double(i / dem.cols));
    const double zl = s.z_at(x, y, PointInterpolation::Linear),
                 zn = s.z_at(x, y, PointInterpolation::NaturalC0);
    if (std::isnan(zl) || std::isnan(zn)) continue;
    se[0] += (zl - dem.z[i]) * (zl - dem.z[i]);
    se[1] += (zn - dem.z[i]) * (zn - dem.z[i]);
    se[2] += (gdal[i] - dem.z[i]) * (gdal[i] - dem.z[i]);
    const double zc = s.z_at(x, y, PointInterpolation::Natural);
    se[3] += (zc - dem.z[i]) * (zc - dem.z[i]);
    ++n;
  }
  const double rmse[3] = {std::sqrt(se[0] / double(n)), std::sqrt(se[1] / double(n)),
                          std::sqrt(se[3] / double(n))};
  const double rmse_gdal = std::sqrt(se[2] / double(n));
  ASSERT_GT(n, dem.size() / 2);
  std::printf(
      "MSH 1-in-7 (%zu points) back at 10 m: RMSE linear %.3f m, natural-c0 %.3f m, natural %.3f "
      "m, "
      "GDAL linear %.3f m\n",
      p.size(), rmse[0], rmse[1], rmse[2], rmse_gdal);
  // Natural neighbours (both interpolants) beat GDAL's linear. Our linear is the same interpolant
  // on another Delaunay triangulation: the sampled cells lie on a lattice, whose co-circular
  // quadruples CGAL (symbolic perturbation) and qhull split differently; within 1 %.
  EXPECT_LE(rmse[1], rmse_gdal);
  EXPECT_LE(rmse[2], rmse_gdal);
  EXPECT_LT(rmse[2], rmse[1]);
  EXPECT_NEAR(rmse[0], rmse_gdal, 0.01 * rmse_gdal);
}

// Duplicate x, y: one vertex, z the mean; counted.
TEST(Scattered, DuplicatesAreAveraged) {
  PointCloud p = random_points(50, 100, plane);
  p.x.push_back(p.x[3]);
  p.y.push_back(p.y[3]);
  p.z.push_back(p.z[3] + 10);
  const PointSurface s(p);
  EXPECT_EQ(s.duplicates(), 1u);
  EXPECT_EQ(s.vertices(), 50u);
  EXPECT_DOUBLE_EQ(s.z_at(p.x[3], p.y[3], PointInterpolation::NaturalC0), p.z[3] + 5);
  EXPECT_EQ(summarize_points(p).duplicates, 1u);
}

TEST(Scattered, DegenerateInputsAreErrors) {
  PointCloud two;
  two.x = {0, 1};
  two.y = {0, 1};
  two.z = {0, 1};
  EXPECT_THROW(PointSurface{two}, Error);
  PointCloud line;
  for (int i = 0; i < 10; ++i) {
    line.x.push_back(i);
    line.y.push_back(2 * i);
    line.z.push_back(i);
  }
  try {
    PointSurface s(line);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("collinear"), std::string::npos);
  }
  PointCloud nan = random_points(10, 10, plane);
  nan.z[4] = std::nan("");
  EXPECT_THROW(PointSurface{nan}, Error);
}

// The same points as XYZ text (with a header), CSV and GeoPackage are recognised by
// content and read alike; a raster (even a regular XYZ grid) is not points.
TEST(Scattered, ReadersRecogniseContent) {
  test::ScratchDir dir;
  const PointCloud p = random_points(20, 1000, plane);
  {
    std::ofstream xyz(dir.path("pts.dat"));
    xyz << "# survey\nE N H\n";
    for (std::size_t i = 0; i < p.size(); ++i)
      xyz << fmt::format("{:.17g} {:.17g} {:.17g}\n", p.x[i], p.y[i], p.z[i]);
    std::ofstream csv(dir.path("pts.csv"));
    csv << "id,x,y,z\n";
    for (std::size_t i = 0; i < p.size(); ++i)
      csv << fmt::format("{},{:.17g},{:.17g},{:.17g}\n", i, p.x[i], p.y[i], p.z[i]);
  }
  ensure_gdal();
  {
    GDALDriver* drv = GetGDALDriverManager()->GetDriverByName("GPKG");
    GDALDataset* ds = drv->Create(dir.path("pts.gpkg").c_str(), 0, 0, 0, GDT_Unknown, nullptr);
    OGRSpatialReference srs;
    srs.importFromEPSG(32610);
    OGRLayer* layer = ds->CreateLayer("pts", &srs, wkbPoint25D, nullptr);
    for (std::size_t i = 0; i < p.size(); ++i) {
      OGRFeature f(layer->GetLayerDefn());
      OGRPoint pt(p.x[i], p.y[i], p.z[i]);
      f.SetGeometry(&pt);
      ASSERT_EQ(layer->CreateFeature(&f), OGRERR_NONE);
    }
    GDALClose(ds);
  }
  for (const char* name : {"pts.dat", "pts.csv", "pts.gpkg"}) {
    SCOPED_TRACE(name);
    ASSERT_TRUE(is_point_input(dir.path(name)));
    const PointCloud q = read_points(dir.path(name));
    ASSERT_EQ(q.size(), p.size());
    for (std::size_t i = 0; i < p.size(); ++i) {
      EXPECT_DOUBLE_EQ(q.x[i], p.x[i]);
      EXPECT_DOUBLE_EQ(q.z[i], p.z[i]);
    }
  }
  EXPECT_EQ(read_points(dir.path("pts.gpkg")).epsg, 32610);
  EXPECT_FALSE(is_point_input(test::data("msh_2007_utm10n_10m.tif")));
  EXPECT_FALSE(is_point_input(test::data("sinmap_crop_10m.asc")));
  {
    std::ofstream grid(dir.path("grid.xyz"));
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) grid << 10 * c << " " << 100 - 10 * r << " " << r + c << "\n";
  }
  EXPECT_FALSE(is_point_input(dir.path("grid.xyz")));  // GDAL's XYZ raster driver opens it
  {
    std::ofstream bad(dir.path("bad.dat"));
    bad << "1 2 3\n4 5 nan\n6 7 8\n";
  }
  try {
    read_points(dir.path("bad.dat"));
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("point 2"), std::string::npos) << e.what();
  }
}

// Geographic points go to UTM with GeographicLib, as grids do (docs/algorithms.md 10.5).
TEST(Scattered, GeographicPointsAreProjectedToUtm) {
  PointCloud p;
  p.x = {7.5, 7.51, 7.49};
  p.y = {46.5, 46.49, 46.51};
  p.z = {1, 2, 3};
  project_points(p, "EPSG:4326", std::nullopt);
  EXPECT_EQ(p.crs_kind, CrsKind::Projected);
  EXPECT_EQ(p.epsg, 32632);
  EXPECT_NEAR(p.x[0], 384902.837, 1e-3);
  EXPECT_NEAR(p.y[0], 5150696.346, 1e-3);
  PointCloud none = p;
  none.crs_kind = CrsKind::None;
  EXPECT_THROW(project_points(none, "", std::nullopt), Error);
}

}  // namespace
}  // namespace terrain
