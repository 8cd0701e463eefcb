#include "drainage/fill.hpp"

#include <cmath>
#include <vector>

#include "drainage/d8.hpp"

namespace drainage {

std::size_t priority_flood_fill(terrain::Grid& g) {
  const long rows = long(g.rows), cols = long(g.cols);
  auto& z = g.z;
  terrain::BigVector<std::uint8_t> closed(g.size(), 0);
  std::vector<std::uint32_t> seeds;
  for (long r = 0; r < rows; ++r)
    for (long c = 0; c < cols; ++c) {
      const std::size_t i = std::size_t(r * cols + c);
      if (std::isnan(z[i])) {
        closed[i] = 1;
        continue;
      }
      bool seed = r == 0 || c == 0 || r == rows - 1 || c == cols - 1;
      for (int k = 0; k < 8 && !seed; ++k) seed = std::isnan(z[std::size_t((r + kDRow[k]) * cols + c + kDCol[k])]);
      if (seed) {
        closed[i] = 1;
        seeds.push_back(std::uint32_t(i));
      }
    }
  return priority_flood(z, rows, cols, seeds, [&](std::uint32_t, std::uint32_t j) {
    if (closed[j]) return false;
    closed[j] = 1;
    return true;
  });
}

}  // namespace drainage
