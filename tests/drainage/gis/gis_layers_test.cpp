// Divides and watersheds on hand-made grids (gis_layers.hpp); the GeoPackages on real data
// are checked end to end in tests/tools/build_drainage_tool_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <tuple>

#include "drainage/gis_layers.hpp"

namespace drainage {
namespace {

constexpr std::uint8_t E = 0, N = 2, NW = 3, W = 4;
constexpr std::uint32_t X = kNone;

std::vector<DivideEdge> edges_of(const std::vector<std::uint32_t>& ids, std::size_t rows,
                                 std::size_t cols) {
  std::vector<DivideEdge> e;
  add_divide_edges(ids.data(), 0, rows, cols, false, e);
  return e;
}

// Corner (r, c) of a grid `cols` wide.
std::uint64_t corner(std::size_t r, std::size_t c, std::size_t cols) { return r * (cols + 1) + c; }

TEST(Divides, AStraightDivideIsOneLineOfTwoCorners) {
  // Basin 0 the left column, basin 1 the rest, one no-data cell (no divide along it).
  const std::vector<std::uint32_t> ids = {0, 1, 1,  //
                                          0, 1, X,  //
                                          0, 1, 1};
  const auto e = edges_of(ids, 3, 3);
  ASSERT_EQ(e.size(), 3u);  // three unit edges down the line x = 1
  for (const DivideEdge& d : e) EXPECT_EQ(std::tie(d.a, d.b), std::make_tuple(0u, 1u));
  const auto chains = chain_divide_edges(e, 3);
  ASSERT_EQ(chains.size(), 1u);
  EXPECT_EQ(chains[0], (std::vector<std::uint64_t>{corner(0, 1, 3), corner(3, 1, 3)}));
}

TEST(Divides, AnEnclosedBasinIsAClosedRing) {
  const std::vector<std::uint32_t> ids = {0, 0, 0,  //
                                          0, 7, 0,  //
                                          0, 0, 0};
  const auto chains = chain_divide_edges(edges_of(ids, 3, 3), 3);
  ASSERT_EQ(chains.size(), 1u);
  const auto& ring = chains[0];
  ASSERT_EQ(ring.size(), 5u);  // four corners and the first again
  EXPECT_EQ(ring.front(), ring.back());
  std::vector<std::uint64_t> corners(ring.begin(), ring.end() - 1);
  std::sort(corners.begin(), corners.end());
  EXPECT_EQ(corners, (std::vector<std::uint64_t>{corner(1, 1, 3), corner(1, 2, 3), corner(2, 1, 3),
                                                 corner(2, 2, 3)}));
}

TEST(Divides, ChainsEndWhereFourEdgesMeet) {
  const std::vector<std::uint32_t> ids = {0, 1,  //
                                          1, 0};
  const auto chains = chain_divide_edges(edges_of(ids, 2, 2), 2);
  ASSERT_EQ(chains.size(), 4u);
  for (const auto& c : chains) {
    ASSERT_EQ(c.size(), 2u);
    EXPECT_TRUE(c.front() == corner(1, 1, 2) || c.back() == corner(1, 1, 2));
  }
}

// Bands of rows (as export_dv_gpkg reads a file) find the same edges as the whole grid,
// and the chains use every edge once: their lengths add up to the edge count.
TEST(Divides, BandsFindTheEdgesOfTheWholeGrid) {
  const unsigned seed = 20261126;
  std::mt19937 rng(seed);
  const std::size_t rows = 37, cols = 23;
  std::vector<std::uint32_t> ids(rows * cols);
  for (auto& v : ids) v = rng() % 9 == 0 ? X : std::uint32_t(rng() % 4);
  auto key = [](const DivideEdge& d) { return std::make_tuple(d.a, d.b, d.from, d.to); };
  auto sorted = [&](std::vector<DivideEdge> e) {
    std::sort(e.begin(), e.end(), [&](const auto& p, const auto& q) { return key(p) < key(q); });
    return e;
  };
  const auto whole = sorted(edges_of(ids, rows, cols));
  for (const std::size_t band : {1, 5, 36}) {
    std::vector<DivideEdge> e;
    for (std::size_t r0 = 0; r0 < rows; r0 += band) {
      const std::size_t n = std::min(band, rows - r0);
      add_divide_edges(ids.data() + r0 * cols, r0, n, cols, r0 + n < rows, e);
    }
    const auto b = sorted(e);
    ASSERT_EQ(b.size(), whole.size()) << "band " << band << " seed " << seed;
    for (std::size_t i = 0; i < b.size(); ++i)
      EXPECT_EQ(key(b[i]), key(whole[i])) << "band " << band;
  }
  for (std::uint32_t a = 0; a < 4; ++a)
    for (std::uint32_t b = a + 1; b < 4; ++b) {
      std::vector<DivideEdge> pair;
      for (const DivideEdge& d : whole)
        if (d.a == a && d.b == b) pair.push_back(d);
      std::size_t unit_steps = 0;
      for (const auto& chain : chain_divide_edges(pair, cols))
        for (std::size_t i = 1; i < chain.size(); ++i) {
          const auto r0 = chain[i - 1] / (cols + 1), c0 = chain[i - 1] % (cols + 1);
          const auto r1 = chain[i] / (cols + 1), c1 = chain[i] % (cols + 1);
          EXPECT_TRUE(r0 == r1 || c0 == c1) << "a divide runs along cell edges";
          unit_steps += std::size_t(std::max(r0, r1) - std::min(r0, r1) + std::max(c0, c1) -
                                    std::min(c0, c1));
        }
      EXPECT_EQ(unit_steps, pair.size()) << a << "-" << b << " seed " << seed;
    }
}

// Issue 49: outlet snapping on an in-memory grid (snap_outlets, as write_watersheds snaps
// on the file). 6 x 8 points, 10 m apart, origin (point (0,0)'s centre) at 1000, 2000; the
// accumulation is the column index + 1, but 50 at (2, 5), and (0, 0) is no-data.
TEST(Watersheds, OutletsSnapOnAnInMemoryGrid) {
  DvHeader h;
  h.rows = 6, h.cols = 8, h.dx = h.dy = 10, h.origin_x = 1000, h.origin_y = 2000;
  std::vector<std::uint32_t> acc(48);
  for (std::size_t i = 0; i < acc.size(); ++i) acc[i] = std::uint32_t(i % 8 + 1);
  acc[2 * 8 + 5] = 50;
  const DvWindowReader window = [&](std::size_t r0, std::size_t c0, std::size_t rows,
                                    std::size_t cols) {
    DrainageDb w;
    w.header = h, w.header.rows = rows, w.header.cols = cols;
    w.vertices.resize(rows * cols);
    for (std::size_t r = 0; r < rows; ++r)
      for (std::size_t c = 0; c < cols; ++c) {
        DvVertex& v = w.vertices[r * cols + c];
        v.accumulated = acc[(r0 + r) * 8 + c0 + c];
        v.point_class = (r0 + r == 0 && c0 + c == 0) ? std::uint8_t(PointClass::Nodata)
                                                     : std::uint8_t(PointClass::Channel);
      }
    return w;
  };
  std::vector<std::uint64_t> cells;
  auto snap = [&](std::vector<OutletPoint> pts, double d) {
    return snap_outlets(h, pts, d, window, cells);
  };
  // With 0, the cell holding the point: (1, 3), 3 m from its centre.
  auto ws = snap({{1030, 1990 + 3, 7}}, 0);
  ASSERT_EQ(ws.size(), 1u);
  EXPECT_EQ(ws[0].row, 1u);
  EXPECT_EQ(ws[0].col, 3u);
  EXPECT_NEAR(ws[0].moved, 3.0, 1e-9);
  EXPECT_EQ(cells[0], 1u * 8 + 3);
  // Within 25 m of (1, 3): (2, 5) holds 50, 22.4 m away; within 15 m the highest is column 4.
  ws = snap({{1030, 1990, 7}}, 25);
  EXPECT_EQ(ws[0].row, 2u);
  EXPECT_EQ(ws[0].col, 5u);
  EXPECT_EQ(ws[0].accumulated, 50u);
  EXPECT_NEAR(ws[0].moved, std::hypot(20.0, 10.0), 1e-9);
  ws = snap({{1030, 1990, 7}}, 15);
  EXPECT_EQ(ws[0].col, 4u);
  EXPECT_EQ(ws[0].accumulated, 5u);
  auto error = [&](std::vector<OutletPoint> pts, double d) {
    try {
      (void)snap(std::move(pts), d);
      return std::string();
    } catch (const terrain::Error& e) {
      return std::string(e.what());
    }
  };
  EXPECT_NE(error({{1000, 2000, 1}}, 0).find("no drainage point in its cell"),
            std::string::npos);  // no-data
  EXPECT_NE(error({{900, 2000, 1}}, 0).find("lies outside the grid"), std::string::npos);
  EXPECT_NE(error({{1030, 1990, 1}}, 1000).find("exceeds the grid's size"), std::string::npos);
  EXPECT_NE(error({{1030, 1990, 1}, {1031, 1991, 2}}, 0).find("snap to the same cell"),
            std::string::npos);
}

TEST(Watersheds, EachCellGoesToItsNearestOutletDownstream) {
  // Row 0 flows east off the grid; rows 1 and 2 flow north into it, (1, 4) west and (2, 3)
  // north-west; (2, 0) is a pit, (2, 2) no-data.
  const D8Codes dirs = {E,       E, E,       E,  E, E,  //
                        N,       N, N,       N,  W, N,  //
                        kNoFlow, W, kNodata, NW, N, N};
  const std::size_t rows = 3, cols = 6;
  // Outlets at (0, 2) and (0, 4): (0, 4) is downstream of (0, 2) and keeps only what
  // reaches it past (0, 2); column 5 drains off the grid past both.
  const auto label = nearest_downstream_outlet(dirs, rows, cols, {2, 4});
  const std::vector<std::uint32_t> expected = {0, 0, 0, 1, 1, X,  //
                                               0, 0, 0, 1, 1, X,  //
                                               X, X, X, 0, 1, X};
  EXPECT_EQ(std::vector<std::uint32_t>(label.begin(), label.end()), expected);
  EXPECT_THROW(nearest_downstream_outlet(dirs, rows, cols, {2, 2}), terrain::Error);
  EXPECT_THROW(nearest_downstream_outlet(dirs, rows, cols, {18}), terrain::Error);
  const D8Codes cycle = {E, W};
  EXPECT_THROW(nearest_downstream_outlet(cycle, 1, 2, {}), terrain::Error);
}

}  // namespace
}  // namespace drainage
