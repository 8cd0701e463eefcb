// Views of a drainage database: the summary counts the network, the elevations are the
// surface, the preview marks channels, and the rivers are the network's lines.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "drainage/dv_file.hpp"
#include "drainage/dv_views.hpp"
#include "drainage/gis_layers.hpp"
#include "drainage/pipeline.hpp"
#include "terrain/dem_io.hpp"
#include "test_support.hpp"

namespace drainage {
namespace {

DrainageResult logan_drainage() {
  return compute_drainage(terrain::read_dem(terrain::test::data("logan_utm12n_100m.tif")), {});
}

DrainageDb round_trip(const DrainageResult& r, const terrain::test::ScratchDir& dir) {
  write_dv(dir.path("a.dv"), make_dv_header(r.surface, r.net, r.dv_flags, ""), r.surface, r.dirs,
           r.net);
  return read_dv(dir.path("a.dv"));
}

TEST(DvViews, SummaryElevationsAndPreview) {
  terrain::test::ScratchDir dir;
  const DrainageResult r = logan_drainage();
  const DrainageDb db = round_trip(r, dir);
  const DvSummary s = summarize(db);
  std::size_t counts[4] = {0, 0, 0, 0};
  for (std::uint8_t c : r.net.point_class)
    if (c < 4) ++counts[c];
  EXPECT_EQ(s.points, r.net.points);
  EXPECT_EQ(s.ridges, counts[0]);
  EXPECT_EQ(s.channels, counts[1]);
  EXPECT_EQ(s.junctions, counts[2]);
  EXPECT_EQ(s.pits, counts[3]);
  std::size_t branches = 0;
  for (const auto& [order, count] : s.branches_per_order) branches += count;
  EXPECT_EQ(branches, r.net.branches.size());

  const terrain::Grid z = dv_elevations(db);
  ASSERT_EQ(z.size(), r.surface.size());
  EXPECT_NEAR(z.geo.x0, r.surface.geo.x0, 1e-6);
  EXPECT_NEAR(z.geo.y0, r.surface.geo.y0, 1e-6);
  for (std::size_t i = 0; i < z.size(); ++i) ASSERT_NEAR(z.z[i], r.surface.z[i], 1e-3) << i;

  // The preview draws the 4 % of points with the most flow in blue over a grey hillshade.
  const auto rgb = dv_preview(db);
  ASSERT_EQ(rgb.size(), 3 * z.size());
  std::size_t blue = 0;
  for (std::size_t i = 0; i < z.size(); ++i) blue += rgb[3 * i + 2] > rgb[3 * i] + 20;
  EXPECT_GT(blue, z.size() / 40);
  EXPECT_LT(blue, z.size() / 20);
}

// The rivers with no channel-initiation area are the .dv's own network: Strahler's orders
// counted again on it equal the .dv's at every point, and the chains are its branches.
TEST(DvViews, RiversOfEveryLinkAreTheDvsBranches) {
  terrain::test::ScratchDir dir;
  const DrainageDb db = round_trip(logan_drainage(), dir);
  const std::vector<RiverLine> all = river_lines(db, 0);
  std::vector<std::vector<std::uint32_t>> mine, theirs;
  for (const RiverLine& l : all) {
    mine.push_back(l.points);
    for (std::size_t k = 0; k + 1 < l.points.size(); ++k)  // the last: the river it joins
      ASSERT_EQ(int(db.vertices[l.points[k]].order), l.strahler) << l.points[k];
  }
  for (const DvBranch& b : db.branches) {
    std::vector<std::uint32_t> p(db.branch_vertices.begin() + b.first,
                                 db.branch_vertices.begin() + b.first + b.count);
    if (b.drains_into != kNone) p.push_back(b.drains_into);
    if (p.size() >= 2) theirs.push_back(p);
  }
  std::sort(mine.begin(), mine.end()), std::sort(theirs.begin(), theirs.end());
  EXPECT_EQ(mine, theirs);
  EXPECT_EQ(export_branches_gpkg(db, dir.path("all.gpkg"), {1, 0, 0}), all.size());
  EXPECT_EQ(dir.n_entries(), 2u);  // no temporary left
}

// With a channel-initiation area (1 ha = 1 point at 100 m; 50 ha here): every point where
// that much drains lies on one line, no other does; Strahler's rule holds at every head on
// that network; smoothed lines keep their ends and stay within a cell's diagonal of the
// D8 path.
TEST(DvViews, RiversStartWhereTheirAreaDrains) {
  terrain::test::ScratchDir dir;
  const DrainageDb db = round_trip(logan_drainage(), dir);
  const double area = 50 * 1e4, cell = db.header.dx * db.header.dy;
  const std::vector<RiverLine> lines = river_lines(db, area);
  const terrain::Grid surface = dv_elevations(db);
  std::vector<int> inner(db.vertices.size(), 0), any(db.vertices.size(), 0);
  std::map<std::uint32_t, std::vector<int>> ending_at;  // a point: the orders of lines ending there
  for (const RiverLine& l : lines) {
    for (std::size_t k = 0; k < l.points.size(); ++k)
      ++any[l.points[k]], inner[l.points[k]] += k + 1 < l.points.size();
    ending_at[l.points.back()].push_back(l.strahler);
  }
  auto is_river = [&](std::uint32_t i) {
    const DvVertex& v = db.vertices[i];
    return PointClass(v.point_class) != PointClass::Nodata && double(v.accumulated) * cell >= area;
  };
  std::vector<char> fed(db.vertices.size(), 0);  // a river drains into it
  for (std::uint32_t i = 0; i < db.vertices.size(); ++i)
    if (is_river(i) && db.vertices[i].downstream != kNone) fed[db.vertices[i].downstream] = 1;
  std::size_t rivers = 0;
  for (std::uint32_t i = 0; i < db.vertices.size(); ++i) {
    const bool river = is_river(i),
               alone = river && !fed[i] &&
                       (db.vertices[i].downstream == kNone || !is_river(db.vertices[i].downstream));
    rivers += river;
    ASSERT_EQ(any[i] > 0, river && !alone) << i;  // a river of one point has no line
    ASSERT_LE(inner[i], 1) << i;
  }
  EXPECT_GT(rivers, 1000u);
  EXPECT_LT(rivers, db.vertices.size() / 10);
  for (const RiverLine& l : lines) {
    const auto in = ending_at.find(l.points.front());
    const std::vector<int> inflow = in == ending_at.end() ? std::vector<int>{} : in->second;
    const int top = inflow.empty() ? 0 : *std::max_element(inflow.begin(), inflow.end());
    EXPECT_EQ(l.strahler,
              inflow.empty() ? 1 : top + (std::count(inflow.begin(), inflow.end(), top) >= 2))
        << "line from " << l.points.front();
    const std::vector<Eigen::Vector3d> d8 = river_shape(db, surface, l, 0),
                                       smooth = river_shape(db, surface, l, 1.5);
    ASSERT_EQ(smooth.size(), d8.size());
    EXPECT_EQ(smooth.front(), d8.front());
    EXPECT_EQ(smooth.back(), d8.back());
    for (std::size_t k = 0; k < d8.size(); ++k)
      EXPECT_LT((smooth[k] - d8[k]).head<2>().norm(), std::sqrt(2.0) * db.header.dx) << k;
  }
  // The coarser the area, the fewer and higher-order-first lines: 1 point a line at least.
  EXPECT_LT(river_lines(db, 4 * area).size(), lines.size());
}

// Douglas-Peucker: a straight run keeps its ends; a bend keeps its corner; every point left
// out lies within the tolerance of the kept polyline.
TEST(DvViews, RiverPointsKeptWithinTheTolerance) {
  std::vector<Eigen::Vector3d> straight, bend, wave;
  for (int k = 0; k <= 10; ++k) straight.push_back({double(k), 2.0 * k, 0});
  EXPECT_EQ(kept_points(straight, 0.01), (std::vector<std::size_t>{0, 10}));
  for (int k = 0; k <= 10; ++k)
    bend.push_back({double(std::min(k, 5)), double(std::max(k - 5, 0)), 0});
  EXPECT_EQ(kept_points(bend, 0.01), (std::vector<std::size_t>{0, 5, 10}));
  for (int k = 0; k <= 200; ++k) wave.push_back({0.1 * k, std::sin(0.1 * k), 0});
  const double tol = 0.02;
  const std::vector<std::size_t> kept = kept_points(wave, tol);
  EXPECT_LT(kept.size(), wave.size() / 4);
  for (std::size_t j = 0; j + 1 < kept.size(); ++j)
    for (std::size_t k = kept[j] + 1; k < kept[j + 1]; ++k) {
      const Eigen::Vector2d a = wave[kept[j]].head<2>(), d = wave[kept[j + 1]].head<2>() - a,
                            q = wave[k].head<2>() - a;
      EXPECT_LE(std::abs(d.x() * q.y() - d.y() * q.x()) / d.norm(), tol) << k;
    }
}

// The links of a world rectangle (a small mesh over a large database) are the points
// under it, with the full database's positions and flow; a rectangle over the whole grid
// gives the whole grid, one outside it an error.
TEST(DvViews, LinksOfAnExtentAreThePointsUnderIt) {
  terrain::test::ScratchDir dir;
  const DrainageResult r = logan_drainage();
  const DrainageDb db = round_trip(r, dir);
  const terrain::DrainageLinks full = drainage_links(db);
  const DvHeader& h = db.header;
  const std::size_t r0 = 120, c0 = 40, rows = 101,
                    cols = 77;  // sample rows 120..220, columns 40..116
  const double west = h.origin_x + double(c0) * h.dx - 0.3 * h.dx,
               east = h.origin_x + double(c0 + cols - 1) * h.dx;
  const double north = h.origin_y - double(r0) * h.dy,
               south = h.origin_y - double(r0 + rows - 1) * h.dy + 0.2 * h.dy;
  const terrain::DrainageLinks part = drainage_links_in(dir.path("a.dv"), west, south, east, north);
  ASSERT_EQ(part.rows, rows - 1);  // the southern row lies 0.2 cell outside
  ASSERT_EQ(part.cols, cols);
  EXPECT_DOUBLE_EQ(part.origin.x(), h.origin_x + double(c0) * h.dx);
  EXPECT_DOUBLE_EQ(part.origin.y(), h.origin_y - double(r0) * h.dy);
  for (std::size_t rr = 0; rr < part.rows; ++rr)
    for (std::size_t cc = 0; cc < part.cols; ++cc) {
      const std::size_t i = rr * part.cols + cc, j = (r0 + rr) * full.cols + c0 + cc;
      ASSERT_EQ(part.flow[i], full.flow[j]);
      ASSERT_EQ(part.accumulated[i], full.accumulated[j]);
      ASSERT_EQ(part.valid[i], full.valid[j]);
      ASSERT_EQ(part.z[i], full.z[j]);
      ASSERT_NEAR(part.position(i).x() + part.origin.x(), full.position(j).x() + full.origin.x(),
                  1e-3);
    }
  const terrain::DrainageLinks all = drainage_links_in(dir.path("a.dv"), -1e9, -1e9, 1e9, 1e9);
  EXPECT_EQ(all.size(), full.size());
  EXPECT_THROW(drainage_links_in(dir.path("a.dv"), 0, 0, 10, 10), terrain::Error);
}

// Read in bands (a few rows each, their downstream links across the bands' seams), the
// links equal those of the window read whole, array for array, downstream links
// included: over a partial window and over the whole grid, version 2 with blocks of 37 rows.
TEST(DvViews, LinksReadInBandsEqualTheWindowReadWhole) {
  terrain::test::ScratchDir dir;
  const DrainageResult r = logan_drainage();
  DvHeader hh = make_dv_header(r.surface, r.net, r.dv_flags, "");
  hh.version = 2, hh.block_rows = hh.block_cols = 37;
  write_dv(dir.path("a.dv"), hh, r.surface, r.dirs, r.net);
  const DvHeader h = read_dv_header(dir.path("a.dv"));
  struct Window {
    std::size_t r0, c0, rows, cols;
  };
  for (const Window& w :
       {Window{120, 40, 101, 77}, Window{0, 0, std::size_t(h.rows), std::size_t(h.cols)}}) {
    const double west = h.origin_x + double(w.c0) * h.dx,
                 east = h.origin_x + double(w.c0 + w.cols - 1) * h.dx;
    const double north = h.origin_y - double(w.r0) * h.dy,
                 south = h.origin_y - double(w.r0 + w.rows - 1) * h.dy;
    const terrain::DrainageLinks whole =
        drainage_links(read_dv_window(dir.path("a.dv"), w.r0, w.c0, w.rows, w.cols));
    for (const std::size_t band_points : {std::size_t(1) << 40, 3 * w.cols, 1000 * w.cols / 7}) {
      SCOPED_TRACE("window " + std::to_string(w.rows) + " x " + std::to_string(w.cols) +
                   ", bands of " + std::to_string(band_points) + " points");
      const terrain::DrainageLinks l =
          drainage_links_in(dir.path("a.dv"), west, south, east, north, band_points);
      ASSERT_EQ(l.rows, whole.rows);
      ASSERT_EQ(l.cols, whole.cols);
      EXPECT_EQ(l.origin, whole.origin);
      std::size_t differ = 0, links = 0;
      for (std::size_t i = 0; i < l.size(); ++i) {
        differ += l.z[i] != whole.z[i] || l.valid[i] != whole.valid[i] ||
                  l.flow[i] != whole.flow[i] || l.accumulated[i] != whole.accumulated[i] ||
                  l.downstream[i] != whole.downstream[i];
        links += l.downstream[i] != terrain::DrainageLinks::kNone;
      }
      EXPECT_EQ(differ, 0u);
      EXPECT_GT(links, l.size() / 2);
    }
  }
}

// The streamed summary equals the summary of the whole database: version 1, version 2
// in one band, and version 2 with blocks of 37 rows (14 bands on Logan's 498 rows).
TEST(DvViews, StreamedSummaryEqualsTheWholeOne) {
  terrain::test::ScratchDir dir;
  const DrainageResult r = logan_drainage();
  for (const auto& [version, block] : {std::pair{1u, 0u}, std::pair{2u, 0u}, std::pair{2u, 37u}}) {
    DvHeader h = make_dv_header(r.surface, r.net, r.dv_flags, "");
    h.version = version, h.block_rows = h.block_cols = block;
    write_dv(dir.path("a.dv"), h, r.surface, r.dirs, r.net);
    const DvSummary a = summarize(read_dv(dir.path("a.dv"))),
                    b = summarize_dv_file(dir.path("a.dv"));
    SCOPED_TRACE("version " + std::to_string(version) + ", blocks " + std::to_string(block));
    EXPECT_EQ(b.points, a.points);
    EXPECT_EQ(b.pits, a.pits);
    EXPECT_EQ(b.ridges, a.ridges);
    EXPECT_EQ(b.channels, a.channels);
    EXPECT_EQ(b.junctions, a.junctions);
    EXPECT_EQ(b.branches_per_order, a.branches_per_order);
    EXPECT_EQ(b.max_accumulated, a.max_accumulated);
    EXPECT_EQ(b.basins_over_1pct, a.basins_over_1pct);
    EXPECT_NEAR(b.mean_normalized, a.mean_normalized, 1e-12);
  }
}

}  // namespace
}  // namespace drainage
