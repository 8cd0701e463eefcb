// Photic extremum lines: the CPU reference on an analytic surface with a derived answer,
// the threshold, and the GPU passes against the CPU reference.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <tuple>

#include "renderer/core/pel.hpp"
#include "terrain/hillshade.hpp"
#include "terrain/voronoi.hpp"
#include "test_support.hpp"

namespace {

using Eigen::Vector3d;

// A radially symmetric Gaussian bump z = H exp(-r^2 / 2 sigma^2) on a grid h metres apart,
// centred, with its Voronoi weights.
terrain::GridMesh bump_mesh(std::size_t n, double h, double H, double sigma) {
  const double c0 = double(n - 1) / 2 * h;  // the centre is at local (c0, -c0)
  terrain::GridMesh m = terrain::test::function_mesh(n, n, h, [=](double x, double y) {
    return H * std::exp(-((x - c0) * (x - c0) + (y + c0) * (y + c0)) / (2 * sigma * sigma));
  });
  m.voronoi = terrain::voronoi_weights(m);
  return m;
}

// Lit from straight above, f(r) = n_z = 1 / sqrt(1 + h'(r)^2) with h' = -(H r / sigma^2)
// exp(-r^2 / 2 sigma^2). The gradient of f on the surface is radial, of length
// m = |df/ds| = |f'(r)| / sqrt(1 + h'^2) = |f'(r)| f(r) (s: arc length along the profile);
// PELs are the maxima of m along that direction: dm/dr = 0 with m'' < 0, one circle inside
// r = sigma and one outside (H = 60, sigma = 80: r = 33.03 and 126.08).
std::vector<double> derived_pel_radii(double H, double sigma) {
  auto f = [&](double r) {
    const double hp = H * r / (sigma * sigma) * std::exp(-r * r / (2 * sigma * sigma));
    return 1 / std::sqrt(1 + hp * hp);
  };
  auto m = [&](double r) { return std::abs(f(r + 1e-3) - f(r - 1e-3)) / 2e-3 * f(r); };
  std::vector<double> radii;
  const double dr = 0.01;
  for (double r = dr; r < 4 * sigma; r += dr)
    if (m(r) > m(r - dr) && m(r) >= m(r + dr)) radii.push_back(r);
  return radii;
}

TEST(Pel, BumpLitFromAboveGivesCirclesAtTheDerivedRadii) {
  const double h = 2, H = 60, sigma = 80;
  const terrain::GridMesh m = bump_mesh(201, h, H, sigma);
  const auto radii = derived_pel_radii(H, sigma);
  ASSERT_EQ(radii.size(), 2u);
  EXPECT_LT(radii[0], sigma);
  EXPECT_GT(radii[1], sigma);
  const auto fields = renderer::pel_fields(m, Vector3d(0, 0, 1));
  const auto pels = renderer::extract_pels(m, fields, 0.1);
  ASSERT_GT(pels.size(), 200u);
  const double half_edge = 0.5 * (h + h + h * std::sqrt(2.0)) / 3;
  const double c0 = 100 * h;
  std::size_t near[2] = {0, 0}, off = 0;
  for (const auto& p : pels.points) {
    const double r = std::hypot(p.x() - c0, p.y() + c0);
    const int k = std::abs(r - radii[0]) < std::abs(r - radii[1]) ? 0 : 1;
    if (std::abs(r - radii[k]) <= half_edge)
      ++near[k];
    else
      ++off;
  }
  EXPECT_EQ(off, 0u) << "radii " << radii[0] << " " << radii[1];
  EXPECT_GT(near[0], 100u);  // both circles are found
  EXPECT_GT(near[1], 100u);
}

TEST(Pel, LargerThresholdNeverAddsSegments) {
  const terrain::GridMesh m = bump_mesh(101, 4, 60, 80);
  const auto fields = renderer::pel_fields(m, Vector3d(0.3, 0.2, 0.9).normalized());
  std::size_t previous = std::numeric_limits<std::size_t>::max();
  for (int i = 0; i <= 20; ++i) {
    const double tau = i / 20.0;
    const auto pels = renderer::extract_pels(m, fields, tau);
    EXPECT_LE(pels.size(), previous) << tau;
    previous = pels.size();
  }
  EXPECT_EQ(previous, 0u);  // tau = 1: nothing exceeds the maximum
}

// Each PEL circle of the bump is a closed line on the mesh: one piece, its length the
// circle's perimeter (the polyline through the faces, within 1 %).
TEST(PelPieces, BumpCirclesAreOnePieceEach) {
  const double h = 2, H = 60, sigma = 80;
  const terrain::GridMesh m = bump_mesh(201, h, H, sigma);
  const auto radii = derived_pel_radii(H, sigma);
  ASSERT_EQ(radii.size(), 2u);
  const auto fields = renderer::pel_fields(m, Vector3d(0, 0, 1));
  const auto pels = renderer::extract_pels(m, fields, 0.1);
  const auto pieces = renderer::pel_pieces(m.topo, fields, pels);
  ASSERT_EQ(pieces.piece.size(), pels.size());
  ASSERT_EQ(pieces.length.size(), 2u);
  std::vector<double> lengths = pieces.length;
  std::sort(lengths.begin(), lengths.end());
  for (int k = 0; k < 2; ++k)
    EXPECT_NEAR(lengths[std::size_t(k)], 2 * std::numbers::pi * radii[std::size_t(k)],
                0.01 * 2 * std::numbers::pi * radii[std::size_t(k)]);
  // The rule keeps both in full up to their lengths, and fades the short one beyond.
  for (float o : renderer::pel_piece_opacity(pieces, lengths[0])) EXPECT_EQ(o, 1.0f);
  std::size_t faded = 0;
  for (float o : renderer::pel_piece_opacity(pieces, 1.5 * lengths[0]))
    faded += o > 0.0f && o < 1.0f;
  EXPECT_GT(faded, 50u);
}

// Lines of known length on a flat 1 m grid, with fields set by hand: s = col - 2.5 -
// slope row crosses every row; c = 0.5 - |row - 5| (linear in each cell row, so the
// extraction's interpolation is exact) is a maximum (c < 0) except within half a row of
// row 5. A face's segment is kept when c < 0 at both its crossings, so the line is cut into
// two pieces: from row 0 to its last edge crossing before row 4.5, and from its first after
// row 5.5 to row 11. The crossings: rows (y = k), columns (x = j) and cell diagonals
// (x - y = d), x = 2.5 + slope y.
TEST(PelPieces, LinesCutWhereTheMaximumEnds) {
  const std::size_t rows = 12, cols = 8;
  const terrain::GridMesh m =
      terrain::test::function_mesh(rows, cols, 1.0, [](double, double) { return 0.0; });
  for (double slope : {0.0, 0.37}) {
    SCOPED_TRACE(slope);
    renderer::PelFields f;
    const std::size_t nv = m.n_vertices();
    f.f.assign(nv, 0.5f);
    f.m.assign(nv, 1.0f);
    f.s.assign(nv, 0.0f);
    f.c.assign(nv, 0.0f);
    f.g.assign(nv, Eigen::Vector2f(1, 0));
    f.m_max = 1;
    for (std::size_t v = 0; v < nv; ++v) {
      const double r = double(v / cols), c = double(v % cols);
      f.s[v] = float(c - (2.5 + slope * r));
      f.c[v] = float(0.5 - std::abs(r - 5));
    }
    std::vector<double> ys;
    for (int k = 0; k < int(rows); ++k) ys.push_back(k);
    if (slope > 0)
      for (int j = 0; j < int(cols); ++j) ys.push_back((j - 2.5) / slope);
    for (int d = -int(rows); d < int(cols); ++d) ys.push_back((2.5 - d) / (1 - slope));
    double end0 = 0, start1 = double(rows - 1);
    for (double y : ys) {
      if (y >= 0 && y < 4.5) end0 = std::max(end0, y);
      if (y > 5.5 && y <= double(rows - 1)) start1 = std::min(start1, y);
    }
    const double per_row = std::sqrt(1 + slope * slope);
    const auto pels = renderer::extract_pels(m, f, 0.1);
    const auto pieces = renderer::pel_pieces(m.topo, f, pels);
    ASSERT_EQ(pieces.length.size(), 2u);
    EXPECT_NEAR(pieces.length[0], end0 * per_row, 1e-4);
    EXPECT_NEAR(pieces.length[1], (double(rows - 1) - start1) * per_row, 1e-4);
    // Opacity: clamp((L - m/2) / (m/2), 0, 1) for each segment's piece.
    const double min = 1.6 * pieces.length[1];
    const auto o = renderer::pel_piece_opacity(pieces, min);
    std::size_t in_piece[2] = {0, 0};
    for (std::size_t k = 0; k < pels.size(); ++k) {
      const std::size_t p = pieces.piece[k];
      ++in_piece[p];
      EXPECT_NEAR(o[k], std::clamp(2 * pieces.length[p] / min - 1, 0.0, 1.0), 1e-6) << k;
    }
    EXPECT_GT(in_piece[0], 6u);
    EXPECT_GT(in_piece[1], 8u);
    for (float x : renderer::pel_piece_opacity(pieces, 0.0)) EXPECT_EQ(x, 1.0f);
  }
}

}  // namespace

namespace {

// The mean angle between consecutive segments of the PEL lines (degrees): at each segment
// end that coincides (within 1e-4 m) with an end of another segment, the turn from one to
// the other.
double mean_turn_degrees(const renderer::PelSegments& pels) {
  const auto& p = pels.points;
  double sum = 0;
  std::size_t n = 0;
  std::map<std::tuple<long, long, long>, std::vector<std::size_t>>
      at;  // ends by position (0.1 mm cells)
  auto key = [](const Eigen::Vector3f& x) {
    return std::make_tuple(std::lround(x.x() * 1e4), std::lround(x.y() * 1e4),
                           std::lround(x.z() * 1e4));
  };
  for (std::size_t i = 0; i < p.size(); ++i) at[key(p[i])].push_back(i);
  for (const auto& [k, ends] : at) {
    if (ends.size() != 2) continue;
    const std::size_t i = ends[0], j = ends[1];
    const Eigen::Vector3f a = (p[i] - p[i ^ 1u]).normalized(), b = (p[j ^ 1u] - p[j]).normalized();
    sum += std::acos(std::clamp(double(a.dot(b)), -1.0, 1.0)) * 180 / std::numbers::pi;
    ++n;
  }
  return n ? sum / double(n) : 0.0;
}

// A line that zigzags: on a flat 1 m grid, s = col - (2.5 + 0.37 row) + 0.3 (-1)^row puts
// the crossings of the rows 0.3 m either side of the line x = 2.5 + 0.37 y, alternately,
// every segment kept (c < 0). Smoothed three times (the default), the ends on the grid's
// first and last rows stay, every interior end still meets the end of the next segment (the
// line stays one), and the points lie within half their distance from the line before
// (0.217 -> 0.085 m), the mean turn between segments half of it (23.6 -> 8.3 degrees).
TEST(PelSmooth, AZigzagStraightensAndStaysOneLine) {
  const std::size_t rows = 14, cols = 9;
  const terrain::GridMesh m =
      terrain::test::function_mesh(rows, cols, 1.0, [](double, double) { return 0.0; });
  renderer::PelFields f;
  const std::size_t nv = m.n_vertices();
  f.f.assign(nv, 0.5f);
  f.m.assign(nv, 1.0f);
  f.s.assign(nv, 0.0f);
  f.c.assign(nv, -1.0f);
  f.g.assign(nv, Eigen::Vector2f(1, 0));
  f.m_max = 1;
  for (std::size_t v = 0; v < nv; ++v) {
    const double r = double(v / cols), c = double(v % cols);
    f.s[v] = float(c - (2.5 + 0.37 * r) + ((v / cols) % 2 ? -0.3 : 0.3));
  }
  const auto pels = renderer::extract_pels(m, f, 0.1);
  ASSERT_GT(pels.size(), 20u);
  ASSERT_EQ(renderer::pel_pieces(m.topo, f, pels).length.size(), 1u);
  auto smooth = pels;
  renderer::smooth_pels(m.topo, f, smooth, 3);
  // The local frame: x = col, y = -row.
  auto off_line = [](const Eigen::Vector3f& x) {
    return std::abs(double(x.x()) - (2.5 + 0.37 * -double(x.y())));
  };
  double before = 0, after = 0;
  std::size_t ends = 0;
  for (std::size_t i = 0; i < pels.points.size(); ++i) {
    const double row = -double(pels.points[i].y());
    if (row < 1e-6 || row > double(rows - 1) - 1e-6) {  // the line's two ends
      EXPECT_EQ(smooth.points[i], pels.points[i]) << i;
      ++ends;
      continue;
    }
    before += off_line(pels.points[i]), after += off_line(smooth.points[i]);
    std::size_t meets = 0;
    for (std::size_t j = 0; j < smooth.points.size(); ++j)
      meets += j != i && (smooth.points[j] - smooth.points[i]).norm() < 1e-5f;
    EXPECT_EQ(meets, 1u) << i;
  }
  EXPECT_EQ(ends, 2u);
  std::printf(
      "zigzag: mean distance from the line %.3f -> %.3f m, mean turn %.1f -> %.1f degrees\n",
      before / double(pels.points.size() - 2), after / double(pels.points.size() - 2),
      mean_turn_degrees(pels), mean_turn_degrees(smooth));
  EXPECT_LT(after, before / 2);
  EXPECT_LT(mean_turn_degrees(smooth), mean_turn_degrees(pels) / 2);
}

// Smoothing keeps the bump's PEL circles where they are: every point still within half an
// edge of a derived radius, the radial error no larger (0.0384 -> 0.0338 m rms), the
// circles' lengths within 1 % of their perimeters.
TEST(PelSmooth, BumpCirclesStayAtTheirRadii) {
  const double h = 2, H = 60, sigma = 80;
  const terrain::GridMesh m = bump_mesh(201, h, H, sigma);
  const auto radii = derived_pel_radii(H, sigma);
  const auto fields = renderer::pel_fields(m, Vector3d(0, 0, 1));
  const auto pels = renderer::extract_pels(m, fields, 0.1);
  auto smooth = pels;
  renderer::smooth_pels(m.topo, fields, smooth, 3);
  const double half_edge = 0.5 * (h + h + h * std::sqrt(2.0)) / 3, c0 = 100 * h;
  auto radial_error = [&](const renderer::PelSegments& s, std::size_t& off) {
    double sum = 0;
    for (const auto& p : s.points) {
      const double r = std::hypot(p.x() - c0, p.y() + c0);
      const double d = std::min(std::abs(r - radii[0]), std::abs(r - radii[1]));
      sum += d * d;
      off += d > half_edge;
    }
    return std::sqrt(sum / double(s.points.size()));
  };
  std::size_t off_before = 0, off_after = 0;
  const double rms_before = radial_error(pels, off_before),
               rms_after = radial_error(smooth, off_after);
  std::printf("bump: radial rms %.4f -> %.4f m\n", rms_before, rms_after);
  EXPECT_EQ(off_after, 0u);
  EXPECT_LE(rms_after, rms_before * 1.01);
  std::vector<double> lengths = renderer::pel_pieces(m.topo, fields, smooth).length;
  ASSERT_EQ(lengths.size(), 2u);
  std::sort(lengths.begin(), lengths.end());
  for (int k = 0; k < 2; ++k)
    EXPECT_NEAR(lengths[std::size_t(k)], 2 * std::numbers::pi * radii[std::size_t(k)],
                0.01 * 2 * std::numbers::pi * radii[std::size_t(k)]);
}

// On real terrain (the MSH test mesh, 50 m, lit from az 135, alt 40) the lines zigzag from
// face to face; smoothed three times, the mean turn between consecutive segments falls by
// more than half (36.1 -> 12.6 degrees).
TEST(PelSmooth, RealTerrainLinesTurnLess) {
  terrain::GridMesh m = terrain::test::msh_50m_mesh();
  m.voronoi = terrain::voronoi_weights(m);
  const auto fields = renderer::pel_fields(m, terrain::light_direction(135, 40));
  const auto pels = renderer::extract_pels(m, fields, 0.1);
  ASSERT_GT(pels.size(), 500u);
  auto smooth = pels;
  renderer::smooth_pels(m.topo, fields, smooth, 3);
  const double before = mean_turn_degrees(pels), after = mean_turn_degrees(smooth);
  std::printf("MSH 50 m: mean turn %.1f -> %.1f degrees over %zu segments\n", before, after,
              pels.size());
  EXPECT_LT(after, 0.5 * before);
}

}  // namespace
