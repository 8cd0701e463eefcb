#include "terrain/dequantize.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace terrain {

bool is_integer_dem(const Grid& grid) {
  float lo = INFINITY, hi = -INFINITY;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    const float z = grid.z[i];
    if (std::isnan(z)) continue;
    if (z != std::round(z)) return false;
    lo = std::min(lo, z), hi = std::max(hi, z);
  }
  return hi - lo >= 2;
}

double dequantize(Grid& grid, double half_step) {
  const std::size_t R = grid.rows, C = grid.cols;
  std::vector<double> orig(R * C), z(R * C);
  for (std::size_t i = 0; i < R * C; ++i) orig[i] = z[i] = grid.z[i];
  // Summed-area tables of the valid values and of their count: a box mean in O(1).
  std::vector<double> sum((R + 1) * (C + 1)), cnt((R + 1) * (C + 1));
  auto at = [&](std::vector<double>& t, std::size_t r, std::size_t c) -> double& { return t[r * (C + 1) + c]; };
  for (const int radius : {16, 8, 4, 2, 1})
    for (int round = 0; round < (radius == 1 ? 16 : 4); ++round) {
      for (std::size_t r = 0; r < R; ++r) {
        double row_sum = 0, row_cnt = 0;
        for (std::size_t c = 0; c < C; ++c) {
          const double v = z[r * C + c];
          if (!std::isnan(v)) row_sum += v, row_cnt += 1;
          at(sum, r + 1, c + 1) = at(sum, r, c + 1) + row_sum;
          at(cnt, r + 1, c + 1) = at(cnt, r, c + 1) + row_cnt;
        }
      }
      const std::size_t k = std::size_t(radius);
#pragma omp parallel for schedule(static)
      for (std::size_t r = 0; r < R; ++r)
        for (std::size_t c = 0; c < C; ++c) {
          const double o = orig[r * C + c];
          if (std::isnan(o)) continue;
          const std::size_t r0 = r >= k ? r - k : 0, r1 = std::min(R, r + k + 1);
          const std::size_t c0 = c >= k ? c - k : 0, c1 = std::min(C, c + k + 1);
          const double s = at(sum, r1, c1) - at(sum, r0, c1) - at(sum, r1, c0) + at(sum, r0, c0);
          const double n = at(cnt, r1, c1) - at(cnt, r0, c1) - at(cnt, r1, c0) + at(cnt, r0, c0);
          z[r * C + c] = std::clamp(s / n, o - half_step, o + half_step);
        }
    }
  double change = 0;
  for (std::size_t i = 0; i < R * C; ++i) {
    if (std::isnan(orig[i])) continue;
    change = std::max(change, std::abs(z[i] - orig[i]));
    grid.z[i] = float(z[i]);
  }
  return change;
}

}  // namespace terrain
