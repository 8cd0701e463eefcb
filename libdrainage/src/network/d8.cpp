#include "drainage/d8.hpp"

#include <cmath>
#include <string>

#include <fmt/format.h>

#include "terrain/error.hpp"
#include "terrain/utm.hpp"

namespace drainage {

D8Encoding parse_d8_encoding(std::string_view name) {
  if (name == "taudem") return D8Encoding::Taudem;
  if (name == "esri") return D8Encoding::Esri;
  throw terrain::Error("unknown D8 encoding '" + std::string(name) + "' (use taudem or esri)");
}

std::uint8_t from_foreign_code(double value, D8Encoding enc, bool is_nodata) {
  if (is_nodata || std::isnan(value)) return kNodata;
  if (value == 0.0) return kNoFlow;
  const auto& table = enc == D8Encoding::Taudem ? kTaudemCode : kEsriCode;
  for (std::uint8_t k = 0; k < 8; ++k)
    if (value == double(table[k])) return k;
  throw terrain::Error(
      fmt::format("D8 code {} is not a valid ", value) +
      (enc == D8Encoding::Taudem ? "TauDEM code (1..8)" : "ESRI code (1, 2, 4, ..., 128)"));
}

int to_foreign_code(std::uint8_t code, D8Encoding enc) {
  if (code >= 8) return 0;
  return enc == D8Encoding::Taudem ? kTaudemCode[code] : kEsriCode[code];
}

D8Codes d8_directions(const terrain::Grid& g) {
  const long rows = long(g.rows), cols = long(g.cols);
  D8Codes dirs(g.size());
  const std::vector<terrain::MetricCellSize> cell = terrain::metric_cell_sizes(g.geo, 0, g.rows);
#pragma omp parallel for schedule(static)
  for (long r = 0; r < rows; ++r) {
    double inv_dist[8];
    for (int k = 0; k < 8; ++k)
      inv_dist[k] =
          1.0 / std::hypot(kDCol[k] * cell[std::size_t(r)].dx, kDRow[k] * cell[std::size_t(r)].dy);
    for (long c = 0; c < cols; ++c) {
      const float zc = g.z[std::size_t(r * cols + c)];
      if (std::isnan(zc)) {
        dirs[std::size_t(r * cols + c)] = kNodata;
        continue;
      }
      const bool interior = r > 0 && c > 0 && r + 1 < rows && c + 1 < cols;
      auto value = [&](long rr, long cc) -> float {  // NaN off the grid or in no-data
        if (rr < 0 || cc < 0 || rr >= rows || cc >= cols)
          return std::numeric_limits<float>::quiet_NaN();
        return g.z[std::size_t(rr * cols + cc)];
      };
      double best = 0.0;
      int best_k = -1;
      bool best_virtual = false, boundary = false;
      for (int k : kTryOrder) {
        float zk = interior ? g.z[std::size_t((r + kDRow[k]) * cols + c + kDCol[k])]
                            : value(r + kDRow[k], c + kDCol[k]);
        bool is_virtual = false;
        if (std::isnan(zk)) {
          boundary = is_virtual = true;
          const float opposite = value(r - kDRow[k], c - kDCol[k]);
          zk = std::isnan(opposite) ? zc : 2.0f * zc - opposite;
        }
        const double slope = (double(zc) - double(zk)) * inv_dist[k];
        if (slope > best) {
          best = slope;
          best_k = k;
          best_virtual = is_virtual;
        }
      }
      std::uint8_t code = best_k < 0 ? kNoFlow : std::uint8_t(best_k);
      if (best_virtual || (best_k < 0 && boundary)) code = kOutlet;
      dirs[std::size_t(r * cols + c)] = code;
    }
  }
  return dirs;
}

}  // namespace drainage
