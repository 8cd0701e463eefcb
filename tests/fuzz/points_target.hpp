#pragma once
// What fuzz_points runs on one input, shared with the regression test: the first byte picks
// the file extension (.xyz or .csv), the rest is the file; then the scattered-point reader
// (content sniffing, the XYZ text parser, GDAL's CSV point layers), and on what was read the
// Delaunay surface and its three interpolants. Throws terrain::Error for a bad file.
#include <string>

#include "fuzz_support.hpp"
#include "terrain/scattered.hpp"

namespace terrain::fuzz {

inline void points_target(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return;
  const InputFile input(data + 1, size - 1, data[0] % 2 ? ".csv" : ".xyz");
  const std::string& path = input.path;
  if (!is_point_input(path)) return;
  const PointCloud p = read_points(path);
  if (p.size() > 5000) return;  // keep each run short: the triangulation is not the reader
  const PointSurface s(p);
  const PointCloudSummary sum = summarize_points(p);
  for (const auto m :
       {PointInterpolation::Linear, PointInterpolation::Natural, PointInterpolation::NaturalC0})
    for (int k = 0; k <= 4; ++k) {
      const double x = sum.xmin + (sum.xmax - sum.xmin) * k / 4,
                   y = sum.ymin + (sum.ymax - sum.ymin) * (4 - k) / 4;
      (void)s.z_at(x, y, m);
      (void)s.z_at(x, y, m, 1.0);
    }
}

}  // namespace terrain::fuzz
