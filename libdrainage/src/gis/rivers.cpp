// The rivers of a .dv as a cartographer's lines (gis_layers.hpp, river_lines): the D8
// network where enough area drains, its Strahler orders counted on that network, chains of
// one order, smoothed as the renderer smooths creases.
#include <algorithm>
#include <cmath>

#include "drainage/dv_views.hpp"
#include "drainage/gis_layers.hpp"
#include "terrain/drainage_links.hpp"
#include "terrain/polyline.hpp"
#include "terrain/resample.hpp"
#include "terrain/utm.hpp"

namespace drainage {

namespace {

// Which points are rivers: valid, and at least min_area_m2 drains through them (their
// accumulated points times their row's cell area in square metres).
std::vector<char> river_points(const DrainageDb& db, double min_area_m2) {
  const DvHeader& h = db.header;
  const std::vector<terrain::MetricCellSize> cell =
      terrain::metric_cell_sizes(dv_georef(h), 0, h.rows);
  std::vector<char> kept(db.vertices.size(), 0);
  for (std::size_t i = 0; i < kept.size(); ++i) {
    const DvVertex& v = db.vertices[i];
    const auto& s = cell[i / h.cols];
    kept[i] = PointClass(v.point_class) != PointClass::Nodata &&
              double(v.accumulated) * s.dx * s.dy >= min_area_m2;
  }
  return kept;
}

}  // namespace

std::vector<RiverLine> river_lines(const DrainageDb& db, double min_area_m2) {
  const std::vector<char> kept = river_points(db, min_area_m2);
  std::vector<std::uint32_t> down(kept.size(), kNone);  // the river network's links
  for (std::size_t i = 0; i < kept.size(); ++i)
    if (kept[i] && db.vertices[i].downstream != kNone && kept[db.vertices[i].downstream])
      down[i] = db.vertices[i].downstream;
  const std::vector<std::uint8_t> order = terrain::strahler_orders(down, kept);
  // A chain goes on through the point it drains into while that has its order: a point
  // has at most one such predecessor (two of one order make the next order).
  std::vector<char> continued(kept.size(), 0);
  for (std::size_t i = 0; i < kept.size(); ++i)
    if (down[i] != kNone && order[down[i]] == order[i]) continued[down[i]] = 1;
  std::vector<RiverLine> lines;
  for (std::uint32_t head = 0; head < kept.size(); ++head) {
    if (!kept[head] || continued[head]) continue;
    RiverLine line;
    line.strahler = order[head];
    std::uint32_t v = head;
    for (;;) {
      line.points.push_back(v);
      line.max_flow = std::max(line.max_flow, db.vertices[v].accumulated);
      const std::uint32_t d = down[v];
      if (d == kNone) break;
      if (order[d] != line.strahler) {  // the junction: the line ends on the river it joins
        line.points.push_back(d);
        break;
      }
      v = d;
    }
    if (line.points.size() >= 2) lines.push_back(std::move(line));
  }
  return lines;
}

std::vector<Eigen::Vector3d> river_shape(const DrainageDb& db, const terrain::Grid& surface,
                                         const RiverLine& line, double sigma_samples) {
  const DvHeader& h = db.header;
  const std::size_t n = line.points.size();
  std::vector<Eigen::Vector3d> p(n);
  for (std::size_t k = 0; k < n; ++k) {
    const DvVertex& v = db.vertices[line.points[k]];
    p[k] = {v.x, v.y, v.z};
  }
  if (!(sigma_samples > 0) || n < 3) return p;
  // x, y: the Gaussian mean over the line, a window symmetric about the point (so its ends
  // stay), up to 2 sigma each way; z: the surface there (bilinear; the point's own height
  // beside no-data).
  const int reach = int(std::ceil(2 * sigma_samples));
  std::vector<Eigen::Vector3d> q = p;
  auto height = [&](double x, double y, double fallback) {
    const float z =
        terrain::sample_grid(surface, -y / h.dy, x / h.dx, terrain::Resampling::Bilinear);
    return std::isnan(z) ? fallback : double(z) - h.origin_z;
  };
  for (std::size_t k = 1; k + 1 < n; ++k) {
    const int r = std::min({reach, int(k), int(n - 1 - k)});
    double w_sum = 0;
    Eigen::Vector2d sum(0, 0);
    for (int j = -r; j <= r; ++j) {
      const double w = std::exp(-0.5 * double(j * j) / (sigma_samples * sigma_samples));
      sum += w * p[std::size_t(long(k) + j)].head<2>(), w_sum += w;
    }
    q[k].head<2>() = sum / w_sum;
    q[k].z() = height(q[k].x(), q[k].y(), p[k].z());
  }
  return q;
}

std::vector<std::size_t> kept_points(const std::vector<Eigen::Vector3d>& line, double tolerance) {
  std::vector<Eigen::Vector2d> xy(line.size());
  for (std::size_t k = 0; k < line.size(); ++k) xy[k] = line[k].head<2>();
  return terrain::douglas_peucker(xy, tolerance);
}

}  // namespace drainage
