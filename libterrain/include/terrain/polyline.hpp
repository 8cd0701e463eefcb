#pragma once
// Polylines in the plane: Douglas-Peucker simplification, shared by the renderer's vector
// lines and the rivers of a .dv's GeoPackage.
#include <Eigen/Core>

#include <algorithm>
#include <cstddef>
#include <utility>
#include <vector>

namespace terrain {

// The indices of the points of `pts` a Douglas-Peucker simplification within `tolerance`
// keeps, ascending, the ends always: a span's farthest point from its chord (the segment,
// distances in double) is kept while it lies more than `tolerance` off it.
template <class Point>
std::vector<std::size_t> douglas_peucker(const std::vector<Point>& pts, double tolerance) {
  const std::size_t n = pts.size();
  std::vector<char> keep(n, 1);
  std::vector<std::pair<std::size_t, std::size_t>> spans;
  if (n > 2) {
    std::fill(keep.begin() + 1, keep.end() - 1, 0);
    spans.push_back({0, n - 1});
  }
  while (!spans.empty()) {
    const auto [i, j] = spans.back();
    spans.pop_back();
    const Eigen::Vector2d d = (pts[j] - pts[i]).template cast<double>();
    const double len2 = d.squaredNorm();
    double worst = -1;
    std::size_t at = i;
    for (std::size_t k = i + 1; k < j; ++k) {
      const Eigen::Vector2d q = (pts[k] - pts[i]).template cast<double>();
      const double t = len2 > 0 ? std::clamp(q.dot(d) / len2, 0.0, 1.0) : 0.0;
      const double off = (q - t * d).norm();
      if (off > worst) worst = off, at = k;
    }
    if (worst <= tolerance) continue;
    keep[at] = 1;
    if (at - i > 1) spans.push_back({i, at});
    if (j - at > 1) spans.push_back({at, j});
  }
  std::vector<std::size_t> out;
  for (std::size_t k = 0; k < n; ++k)
    if (keep[k]) out.push_back(k);
  return out;
}

}  // namespace terrain
