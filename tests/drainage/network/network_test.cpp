// The drainage network: accumulation, Strahler order, classes, basins and branches, on a
// worked example, TauDEM's reference output, analytic surfaces and real DEMs.
#include <gtest/gtest.h>

#include <tuple>

#include "drainage/network.hpp"
#include "drainage/pipeline.hpp"
#include "drainage/rasters.hpp"
#include "drainage_test_support.hpp"
#include "terrain/dem_io.hpp"
#include "terrain/pn_surface.hpp"
#include "test_support.hpp"

namespace drainage {
namespace {

D8Codes from_taudem(std::initializer_list<int> codes) {
  D8Codes d;
  for (int c : codes) d.push_back(from_foreign_code(c, D8Encoding::Taudem, false));
  return d;
}

// docs/algorithms.md 7.8: the directions given there (TauDEM codes, edge cells included).
TEST(AnalyzeNetwork, WorkedExample) {
  const D8Codes d = from_taudem({8, 7, 7, 7, 8, 8, 7, 6, 8, 8, 8, 7, 1, 1, 1, 0});
  const Network net = analyze_network(d, 4, 4);
  test::check_network_properties(net, d);
  const std::uint32_t acc[16] = {1, 1, 1, 1, 1, 3, 2, 2, 1, 2, 8, 1, 1, 3, 6, 16};
  const std::uint8_t order[16] = {1, 1, 1, 1, 1, 2, 1, 1, 1, 1, 2, 1, 1, 2, 2, 3};
  for (int i = 0; i < 16; ++i) {
    EXPECT_EQ(net.accumulated[std::size_t(i)], acc[i]) << i;
    EXPECT_EQ(net.order[std::size_t(i)], order[i]) << i;
  }
  ASSERT_EQ(net.pits.size(), 1u);
  EXPECT_EQ(net.pits[0], 15u);
  EXPECT_EQ(PointClass(net.point_class[15]), PointClass::Pit);
  EXPECT_EQ(PointClass(net.point_class[0]), PointClass::Ridge);
  EXPECT_EQ(PointClass(net.point_class[10]), PointClass::Junction);  // (2,2) receives 5 inflows
  EXPECT_FLOAT_EQ(net.normalized[10], 8.0f / 16.0f);
}

TEST(AnalyzeNetwork, CycleIsAnError) {
  const D8Codes d = from_taudem({1, 5, 0, 0});  // (0,0) -> E, (0,1) -> W
  EXPECT_THROW(analyze_network(d, 2, 2), terrain::Error);
}

// TauDEM's own D8 directions of the Logan DEM, accumulated, equal TauDEM's aread8 on every
// cell where it has a value (1,587,804 cells).
TEST(AnalyzeNetwork, MatchesTaudemAread8OnLogan) {
  terrain::Grid g;
  const D8Codes d =
      read_d8_raster(terrain::test::data("logan_30m_taudem_d8dir.tif"), D8Encoding::Taudem, g);
  const terrain::Grid ref = terrain::read_dem(terrain::test::data("logan_30m_taudem_aread8.tif"));
  ASSERT_EQ(ref.size(), d.size());
  const Network net = analyze_network(d, g.rows, g.cols);
  test::check_network_properties(net, d);
  std::size_t compared = 0, equal = 0;
  for (std::size_t i = 0; i < d.size(); ++i) {
    if (!ref.valid(i)) continue;
    ++compared;
    equal += double(net.accumulated[i]) == double(ref.z[i]);
  }
  EXPECT_EQ(compared, 1587804u);
  EXPECT_EQ(equal, compared);
}

TEST(ComputeDrainage, ConeDrainsOutwardWithoutInteriorPit) {
  const terrain::Grid g =
      test::analytic(41, 10.0, [](double x, double y) { return 1000.0 - std::hypot(x, y); });
  const DrainageResult r = compute_drainage(g, {});
  test::check_network_properties(r.net, r.dirs);
  for (std::uint32_t p : r.net.pits) {
    const std::size_t row = p / 41, col = p % 41;
    EXPECT_TRUE(row == 0 || col == 0 || row == 40 || col == 40)
        << "interior pit at " << row << "," << col;
  }
}

TEST(ComputeDrainage, BowlIsOneBasin) {
  const std::size_t n = 41;
  const terrain::Grid g =
      test::analytic(n, 10.0, [](double x, double y) { return 0.001 * (x * x + y * y); });
  const DrainageResult r = compute_drainage(g, {});
  test::check_network_properties(r.net, r.dirs);
  ASSERT_EQ(r.net.pits.size(), 1u);
  const std::uint32_t pit = r.net.pits[0];
  EXPECT_EQ(pit, (n / 2) * n + n / 2);  // the centre
  EXPECT_EQ(r.net.accumulated[pit], n * n);
  EXPECT_EQ(r.net.normalized[pit], 1.0f);
  for (std::size_t i = 0; i < n * n; ++i) ASSERT_EQ(r.net.basin[i], 0u);
}

TEST(ComputeDrainage, InclinedPlaneAccumulatesUpslopePoints) {
  const std::size_t n = 30;
  const terrain::Grid g =
      test::analytic(n, 10.0, [](double x, double y) { return 500.0 + 0.3 * y + 0.0 * x; });
  const DrainageResult r = compute_drainage(g, {});
  test::check_network_properties(r.net, r.dirs);
  for (std::size_t row = 0; row < n; ++row)
    for (std::size_t c = 0; c < n; ++c)
      ASSERT_EQ(r.net.accumulated[row * n + c], row + 1) << row << "," << c;
  EXPECT_EQ(r.net.pits.size(), n);  // one outlet per column
}

// Invariants on real data: the PN surface of the Mount St. Helens mesh sampled at 10 m,
// and the Logan DEM on its own grid, with and without flat resolution and filling.
TEST(ComputeDrainage, RealDataInvariants) {
  const terrain::GridMesh& msh = terrain::test::msh_50m_mesh();
  const terrain::SampledSurface s = terrain::sample_pn_surface(msh, 10.0);
  EXPECT_EQ(s.fallbacks, 0u);
  EXPECT_EQ(s.grid.count_nodata(), 0u);
  DrainageOptions keep_flats, fill;
  keep_flats.resolve_flats = false;
  fill.fill = true;
  for (const DrainageOptions& opt : {DrainageOptions{}, keep_flats, fill}) {
    const DrainageResult r = compute_drainage(s.grid, opt);
    SCOPED_TRACE(testing::Message() << "msh fill=" << opt.fill << " flats=" << opt.resolve_flats);
    test::check_network_properties(r.net, r.dirs);
    if (opt.fill) {  // filled: every point drains to the grid boundary
      for (std::uint32_t p : r.net.pits) ASSERT_EQ(r.dirs[p], kOutlet);
    }
  }
  const terrain::Grid logan = terrain::read_dem(terrain::test::data("logan_utm12n_100m.tif"));
  const DrainageResult r = compute_drainage(logan, {});
  test::check_network_properties(r.net, r.dirs);
}

// NetworkDetail::Lean lists every field but the normalized flow and the branches, with the
// same values, and counts the branches the full walk lists (MSH PN surface at 10 m and
// TauDEM's Logan 30 m directions).
TEST(AnalyzeNetwork, LeanEqualsFullWhereItLists) {
  const terrain::SampledSurface s = terrain::sample_pn_surface(terrain::test::msh_50m_mesh(), 10.0);
  const D8Codes msh = compute_drainage(s.grid, {}).dirs;
  terrain::Grid g;
  const D8Codes logan =
      read_d8_raster(terrain::test::data("logan_30m_taudem_d8dir.tif"), D8Encoding::Taudem, g);
  for (const auto& [d, rows, cols] :
       {std::tuple{&msh, s.grid.rows, s.grid.cols}, std::tuple{&logan, g.rows, g.cols}}) {
    const Network full = analyze_network(*d, rows, cols),
                  lean = analyze_network(*d, rows, cols, {}, NetworkDetail::Lean);
    EXPECT_EQ(lean.points, full.points);
    EXPECT_EQ(lean.downstream, full.downstream);
    EXPECT_EQ(lean.accumulated, full.accumulated);
    EXPECT_EQ(lean.basin, full.basin);
    EXPECT_EQ(lean.point_class, full.point_class);
    EXPECT_EQ(lean.order, full.order);
    EXPECT_EQ(lean.pits, full.pits);
    EXPECT_GT(full.branches.size(), 1000u);
    EXPECT_EQ(full.branch_count, full.branches.size());
    EXPECT_EQ(lean.branch_count, full.branches.size());
    EXPECT_TRUE(lean.normalized.empty() && lean.branches.empty() && lean.branch_vertices.empty());
  }
}

}  // namespace
}  // namespace drainage
