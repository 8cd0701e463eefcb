#pragma once
// A drainage network as plain arrays, independent of how it is stored: every point of a
// regular grid with its position, flow and downstream link. libdrainage makes it from a
// .dv (drainage::drainage_links in dv_views.hpp); the renderer draws creases from it, so
// the renderer does not depend on libdrainage.
#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace terrain {

struct DrainageLinks {
  static constexpr std::uint32_t kNone = 0xFFFFFFFFu;  // no downstream point
  int epsg = 0;                                        // CRS of the positions, 0 when unknown
  std::size_t rows = 0, cols = 0;                      // point i = row * cols + col, row 0 north
  double dx = 1, dy = 1;                               // grid spacing (metres)
  Eigen::Vector3d origin{0, 0, 0};         // world = origin + position; point 0 at x = y = 0
  std::vector<float> z;                    // #P, heights relative to origin
  std::vector<std::uint8_t> valid;         // #P: 0 for a no-data point
  std::vector<float> flow;                 // #P: basin-normalized flow in (0, 1]
  std::vector<std::uint32_t> accumulated;  // #P: points draining through (itself included)
  std::vector<std::uint32_t> downstream;   // #P: downstream point or kNone
  std::size_t size() const { return z.size(); }
  // Point i relative to origin: its column and row on the grid (x east, y north), its height
  // (x and y are not stored: 8 bytes a point fewer, 114 MB on a 14 M point database).
  Eigen::Vector3f position(std::size_t i) const {
    return {float(double(i % cols) * dx), float(-double(i / cols) * dy), z[i]};
  }
};

// Strahler's order of each vertex of a drainage forest (0 on a vertex of none): `down` is
// each vertex's downstream vertex in the forest, DrainageLinks::kNone where its flow leaves
// it, and `member` marks the forest's vertices. 1 where none drains in, else the largest
// order draining in, plus one where two or more bring it (every vertex after all that drain
// into it: Kahn's order). The rivers of a .dv's GeoPackage and the drawn creases use it.
std::vector<std::uint8_t> strahler_orders(const std::vector<std::uint32_t>& down,
                                          const std::vector<char>& member);

}  // namespace terrain
