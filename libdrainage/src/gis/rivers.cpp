// The rivers of a .dv as a cartographer's lines (gis_layers.hpp, river_lines): the D8
// network where enough area drains, its Strahler orders counted on that network, chains of
// one order, smoothed as the renderer smooths creases.
#include <algorithm>
#include <cmath>
#include <numeric>

#include "drainage/dv_views.hpp"
#include "drainage/gis_layers.hpp"
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

// Strahler's order of each river point on the river network (0 elsewhere): 1 where no
// river drains in, else the largest order draining in, plus one where two or more bring
// it. Points in ascending accumulation: every point after all that drain into it.
std::vector<std::uint8_t> strahler_orders(const DrainageDb& db, const std::vector<char>& kept) {
  std::vector<std::uint32_t> order_of;
  for (std::uint32_t i = 0; i < kept.size(); ++i)
    if (kept[i]) order_of.push_back(i);
  std::stable_sort(order_of.begin(), order_of.end(), [&](std::uint32_t a, std::uint32_t b) {
    return db.vertices[a].accumulated < db.vertices[b].accumulated;
  });
  std::vector<std::uint8_t> order(kept.size(), 0), in_max(kept.size(), 0), in_n(kept.size(), 0);
  for (const std::uint32_t i : order_of) {
    order[i] = in_max[i] == 0 ? 1 : std::uint8_t(std::min(255, in_max[i] + (in_n[i] >= 2)));
    const std::uint32_t d = db.vertices[i].downstream;
    if (d == kNone || !kept[d]) continue;
    if (order[i] > in_max[d])
      in_max[d] = order[i], in_n[d] = 1;
    else if (order[i] == in_max[d])
      in_n[d] = std::uint8_t(std::min(2, in_n[d] + 1));
  }
  return order;
}

}  // namespace

std::vector<RiverLine> river_lines(const DrainageDb& db, double min_area_m2) {
  const std::vector<char> kept = river_points(db, min_area_m2);
  const std::vector<std::uint8_t> order = strahler_orders(db, kept);
  // A chain goes on through the point it drains into while that has its order: a point
  // has at most one such predecessor (two of one order make the next order).
  std::vector<char> continued(kept.size(), 0);
  for (std::size_t i = 0; i < kept.size(); ++i) {
    const std::uint32_t d = db.vertices[i].downstream;
    if (kept[i] && d != kNone && kept[d] && order[d] == order[i]) continued[d] = 1;
  }
  std::vector<RiverLine> lines;
  for (std::uint32_t head = 0; head < kept.size(); ++head) {
    if (!kept[head] || continued[head]) continue;
    RiverLine line;
    line.strahler = order[head];
    std::uint32_t v = head;
    for (;;) {
      line.points.push_back(v);
      line.max_flow = std::max(line.max_flow, db.vertices[v].accumulated);
      const std::uint32_t d = db.vertices[v].downstream;
      if (d == kNone || !kept[d]) break;
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

std::vector<Eigen::Vector3d> river_shape(const DrainageDb& db, const RiverLine& line,
                                         double sigma_samples) {
  const DvHeader& h = db.header;
  const std::size_t n = line.points.size();
  std::vector<Eigen::Vector3d> p(n);
  for (std::size_t k = 0; k < n; ++k) {
    const DvVertex& v = db.vertices[line.points[k]];
    p[k] = {v.x, v.y, v.z};
  }
  if (!(sigma_samples > 0) || n < 3) return p;
  // x, y: the Gaussian mean over the line, a window symmetric about the point (so its ends
  // stay), up to 2 sigma each way; z: the surface there (bilinear over the grid's points).
  const int reach = int(std::ceil(2 * sigma_samples));
  std::vector<Eigen::Vector3d> q = p;
  auto height = [&](double x, double y, double fallback) {
    const double fc = x / h.dx, fr = -y / h.dy;
    const long c0 = long(std::floor(fc)), r0 = long(std::floor(fr));
    if (c0 < 0 || r0 < 0 || c0 + 1 >= long(h.cols) || r0 + 1 >= long(h.rows)) return fallback;
    double z = 0;
    for (int dr = 0; dr < 2; ++dr)
      for (int dc = 0; dc < 2; ++dc) {
        const DvVertex& v = db.vertices[std::size_t(r0 + dr) * h.cols + std::size_t(c0 + dc)];
        if (PointClass(v.point_class) == PointClass::Nodata) return fallback;
        z += v.z * (dr ? fr - double(r0) : 1 - (fr - double(r0))) *
             (dc ? fc - double(c0) : 1 - (fc - double(c0)));
      }
    return z;
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
  const std::size_t n = line.size();
  std::vector<char> keep(n, 1);
  std::vector<std::pair<std::size_t, std::size_t>> spans;
  if (n > 2) {
    std::fill(keep.begin() + 1, keep.end() - 1, 0);
    spans.push_back({0, n - 1});
  }
  while (!spans.empty()) {  // the farthest point from each span's chord, while beyond
    const auto [a, b] = spans.back();
    spans.pop_back();
    const Eigen::Vector2d p = line[a].head<2>(), d = line[b].head<2>() - p;
    const double len = d.norm();
    double worst = -1;
    std::size_t at = a;
    for (std::size_t k = a + 1; k < b; ++k) {
      const Eigen::Vector2d q = line[k].head<2>() - p;
      const double off = len > 0 ? std::abs(d.x() * q.y() - d.y() * q.x()) / len : q.norm();
      if (off > worst) worst = off, at = k;
    }
    if (worst <= tolerance) continue;
    keep[at] = 1;
    if (at - a > 1) spans.push_back({a, at});
    if (b - at > 1) spans.push_back({at, b});
  }
  std::vector<std::size_t> out;
  for (std::size_t k = 0; k < n; ++k)
    if (keep[k]) out.push_back(k);
  return out;
}

}  // namespace drainage
