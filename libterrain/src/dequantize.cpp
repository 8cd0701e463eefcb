#include "terrain/dequantize.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <queue>
#include <utility>
#include <vector>

#include "terrain/neighbours.hpp"

namespace terrain {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
bool diagonal(int k) { return (k & 1) != 0; }

// Geodesic distance within each terrace (8-connected samples of one value) to its edge
// with the lower (sign -1) or the higher (sign +1) neighbours: the contour between them
// lies half a step from the edge sample.
std::vector<double> terrace_distance(const Grid& grid, int sign) {
  const long R = long(grid.rows), C = long(grid.cols);
  const std::size_t n = grid.size();
  constexpr double inf = kInf;
  const Neighbours around{R, C};
  std::vector<double> d(n, inf);
  using Item = std::pair<double, std::uint32_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> heap;
  for (long r = 0; r < R; ++r)
    for (long c = 0; c < C; ++c) {
      const float z = grid.z[r * C + c];
      if (std::isnan(z)) continue;
      double best = inf;
      around.each(r, c, [&](std::size_t j, int k) {
        if (!std::isnan(grid.z[j]) && (grid.z[j] - z) * float(sign) > 0)
          best = std::min(best, diagonal(k) ? 0.5 * std::sqrt(2.0) : 0.5);
      });
      if (best < inf) d[r * C + c] = best, heap.emplace(best, std::uint32_t(r * C + c));
    }
  while (!heap.empty()) {
    const double di = heap.top().first;  // (not structured bindings: clang 14 cannot capture them)
    const std::uint32_t i = heap.top().second;
    heap.pop();
    if (di > d[i]) continue;
    around.each(std::size_t(i), [&](std::size_t j, int k) {
      if (grid.z[j] != grid.z[i]) return;  // another terrace, or no-data (NaN)
      const double dn = di + (diagonal(k) ? std::sqrt(2.0) : 1.0);
      if (dn < d[j]) d[j] = dn, heap.emplace(dn, std::uint32_t(j));
    });
  }
  return d;
}

// Each terrace's label and its largest distances to its lower and higher edges (`lo`, `hi`:
// terrace_distance), for terraces with one kind of edge only (summits, pits).
struct TerraceMaxima {
  std::vector<std::uint32_t> label;
  std::vector<double> max_lo, max_hi;
};
TerraceMaxima terrace_maxima(const Grid& grid, const std::vector<double>& lo,
                             const std::vector<double>& hi) {
  const std::size_t n = grid.size();
  constexpr double inf = kInf;
  const Neighbours around{long(grid.rows), long(grid.cols)};
  TerraceMaxima t;
  t.label.assign(n, std::numeric_limits<std::uint32_t>::max());
  std::vector<std::uint32_t>& label = t.label;
  std::vector<double>&max_lo = t.max_lo, &max_hi = t.max_hi;
  std::vector<std::uint32_t> stack;
  for (std::size_t s = 0; s < n; ++s) {
    if (std::isnan(grid.z[s]) || label[s] != std::numeric_limits<std::uint32_t>::max()) continue;
    const std::uint32_t id = std::uint32_t(max_lo.size());
    double mlo = 0, mhi = 0;
    label[s] = id, stack.push_back(std::uint32_t(s));
    while (!stack.empty()) {
      const std::uint32_t i = stack.back();
      stack.pop_back();
      if (lo[i] < inf) mlo = std::max(mlo, lo[i]);
      if (hi[i] < inf) mhi = std::max(mhi, hi[i]);
      around.each(std::size_t(i), [&](std::size_t j, int) {
        if (grid.z[j] == grid.z[i] && label[j] != id)
          label[j] = id, stack.push_back(std::uint32_t(j));
      });
    }
    max_lo.push_back(mlo), max_hi.push_back(mhi);
  }
  return t;
}

}  // namespace

std::vector<double> terrace_interpolation(const Grid& grid, double h) {
  const std::size_t n = grid.size();
  constexpr double inf = std::numeric_limits<double>::infinity();
  const std::vector<double> lo = terrace_distance(grid, -1), hi = terrace_distance(grid, +1);
  const TerraceMaxima t = terrace_maxima(grid, lo, hi);
  const std::vector<std::uint32_t>& label = t.label;
  const std::vector<double>&max_lo = t.max_lo, &max_hi = t.max_hi;
  std::vector<double> z(n, std::numeric_limits<double>::quiet_NaN());
  for (std::size_t i = 0; i < n; ++i) {
    if (std::isnan(grid.z[i])) continue;
    const double k = grid.z[i];
    if (lo[i] < inf && hi[i] < inf)
      z[i] = k - h + 2 * h * lo[i] / (lo[i] + hi[i]);
    else if (lo[i] < inf)
      z[i] = k - h + 2 * h * lo[i] / (max_lo[label[i]] + 0.5);
    else if (hi[i] < inf)
      z[i] = k + h - 2 * h * hi[i] / (max_hi[label[i]] + 0.5);
    else
      z[i] = k;
  }
  return z;
}

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

double dequantize(Grid& grid, double half_step, double within) {
  const std::size_t R = grid.rows, C = grid.cols;
  const std::vector<double> ref = terrace_interpolation(grid, half_step);
  std::vector<double> z = ref;
  // Summed-area tables of the valid values and of their count: a box mean in O(1).
  std::vector<double> sum((R + 1) * (C + 1)), cnt((R + 1) * (C + 1));
  auto at = [&](std::vector<double>& t, std::size_t r, std::size_t c) -> double& {
    return t[r * (C + 1) + c];
  };
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
          const double o = ref[r * C + c];
          if (std::isnan(o)) continue;
          const std::size_t r0 = r >= k ? r - k : 0, r1 = std::min(R, r + k + 1);
          const std::size_t c0 = c >= k ? c - k : 0, c1 = std::min(C, c + k + 1);
          const double s = at(sum, r1, c1) - at(sum, r0, c1) - at(sum, r1, c0) + at(sum, r0, c0);
          const double n = at(cnt, r1, c1) - at(cnt, r0, c1) - at(cnt, r1, c0) + at(cnt, r0, c0);
          z[r * C + c] = std::clamp(s / n, o - within, o + within);
        }
    }
  double change = 0;
  for (std::size_t i = 0; i < R * C; ++i) {
    if (std::isnan(ref[i])) continue;
    change = std::max(change, std::abs(z[i] - double(grid.z[i])));
    grid.z[i] = float(z[i]);
  }
  return change;
}

}  // namespace terrain
