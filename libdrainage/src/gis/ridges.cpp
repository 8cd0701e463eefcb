#include "drainage/ridges.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

#include "drainage/d8.hpp"
#include "drainage/gis_layers.hpp"

namespace drainage {

namespace {

// Each point's catchment: the branch its flow first reaches, or its outlet's basin. Per
// label, the area through its outlet (points) and the outlet's height.
struct Catchments {
  std::vector<std::uint32_t> label;  // kNone: no-data
  std::vector<std::uint32_t> outlet_accumulated;
  std::vector<float> outlet_z;
  std::vector<std::uint32_t> parent;  // per label: the branch its outlet drains into, or kNone
  std::vector<std::uint32_t> depth;   // per label: branches down to its tree's root
};

// Each branch's depth in the tree of `parent` links: branches down to its tree's root.
std::vector<std::uint32_t> tree_depths(const std::vector<std::uint32_t>& parent) {
  std::vector<std::uint32_t> depth(parent.size(), kNone), chain;
  for (std::uint32_t b = 0; b < depth.size(); ++b) {
    chain.clear();
    std::uint32_t x = b;
    while (x != kNone && depth[x] == kNone) chain.push_back(x), x = parent[x];
    std::uint32_t d = x == kNone ? 0 : depth[x] + 1;
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) depth[*it] = d++;
  }
  return depth;
}

// The channel points, upstream first (accumulation grows downstream); `inflow` counts each
// one's channel inflows, up to 2.
template <class Channel, class Down>
std::vector<std::uint32_t> channels_upstream_first(const terrain::DrainageLinks& l,
                                                   const Channel& channel, const Down& down,
                                                   std::vector<std::uint8_t>& inflow) {
  std::vector<std::uint32_t> channels;
  for (std::size_t i = 0; i < l.size(); ++i)
    if (channel(i)) {
      channels.push_back(std::uint32_t(i));
      const std::size_t d = down(i);
      if (d != kNone && channel(d) && inflow[d] < 2) ++inflow[d];
    }
  std::stable_sort(channels.begin(), channels.end(), [&](std::uint32_t a, std::uint32_t b) {
    return l.accumulated[a] < l.accumulated[b];
  });
  return channels;
}

Catchments catchments(const terrain::DrainageLinks& l, double channel_area) {
  const std::size_t n = l.size();
  const double cell = l.dx * l.dy;
  auto valid = [&](std::size_t i) { return l.valid.empty() || l.valid[i]; };
  auto channel = [&](std::size_t i) {
    return valid(i) && double(l.accumulated[i]) * cell >= channel_area;
  };
  auto down = [&](std::size_t i) -> std::size_t {
    const std::uint32_t d = l.downstream[i];
    return d == terrain::DrainageLinks::kNone || !valid(d) ? std::size_t(kNone) : std::size_t(d);
  };
  Catchments c;
  c.label.assign(n, kNone);
  std::vector<std::uint8_t> inflow(n, 0);
  const std::vector<std::uint32_t> channels = channels_upstream_first(l, channel, down, inflow);
  std::vector<std::size_t> outlet;  // per label: its lowest point
  auto new_label = [&](std::size_t i) {
    c.outlet_accumulated.push_back(l.accumulated[i]);
    c.outlet_z.push_back(l.z[i]);
    outlet.push_back(i);
    return std::uint32_t(c.outlet_accumulated.size() - 1);
  };
  for (const std::uint32_t i : channels) {
    if (c.label[i] == kNone) c.label[i] = new_label(i);  // a head or a junction: a branch begins
    const std::uint32_t b = c.label[i];
    c.outlet_accumulated[b] = l.accumulated[i], c.outlet_z[b] = l.z[i],
    outlet[b] = i;  // its lowest point so far
    const std::size_t d = down(i);
    if (d != kNone && channel(d) && inflow[d] == 1) c.label[d] = b;
  }
  const std::size_t n_branches =
      outlet.size();  // the labels of basins that reach no channel come after
  std::vector<std::size_t> path;
  for (std::size_t i = 0; i < n; ++i) {
    if (c.label[i] != kNone || !valid(i)) continue;
    path.clear();
    std::size_t p = i;
    while (c.label[p] == kNone) {
      path.push_back(p);
      const std::size_t d = down(p);
      if (d == kNone) break;
      p = d;
    }
    const std::uint32_t b = c.label[p] != kNone ? c.label[p] : new_label(p);
    for (const std::size_t q : path) c.label[q] = b;
  }
  // The branch tree: a branch drains into the branch of the junction below its outlet.
  c.parent.assign(outlet.size(), kNone);
  for (std::size_t b = 0; b < n_branches; ++b) {
    const std::size_t d = down(outlet[b]);
    if (d != kNone) c.parent[b] = c.label[d];
  }
  c.depth = tree_depths(c.parent);
  return c;
}

// The basins a divide between the catchments of branches a and b parts: the two arms of the
// branch tree that meet where their flows first join (the branches just above that
// junction; a itself when b drains into a, or the two trees' roots when the flows never
// join on the grid). The smaller arm: the area through its outlet and its outlet's height.
struct Parted {
  double accumulated = 0;
  float base = 0;
};
Parted parted(const Catchments& c, std::uint32_t a, std::uint32_t b) {
  std::uint32_t x = a, y = b, arm_x = kNone, arm_y = kNone;
  auto up = [&](std::uint32_t& v, std::uint32_t& arm) { arm = v, v = c.parent[v]; };
  while (x != kNone && y != kNone && c.depth[x] > c.depth[y]) up(x, arm_x);
  while (x != kNone && y != kNone && c.depth[y] > c.depth[x]) up(y, arm_y);
  while (x != y) {
    if (x != kNone) up(x, arm_x);
    if (y != kNone) up(y, arm_y);
  }
  auto of = [&](std::uint32_t arm) {
    return Parted{double(c.outlet_accumulated[arm]), c.outlet_z[arm]};
  };
  if (arm_x == kNone) return of(arm_y);
  if (arm_y == kNone) return of(arm_x);
  return c.outlet_accumulated[arm_x] <= c.outlet_accumulated[arm_y] ? of(arm_x) : of(arm_y);
}

// Points every `step` metres along a polyline (its corners kept), then smoothed.
std::vector<Eigen::Vector2d> resampled(const std::vector<Eigen::Vector2d>& corners, double step) {
  std::vector<Eigen::Vector2d> p;
  for (std::size_t k = 0; k + 1 < corners.size(); ++k) {
    const Eigen::Vector2d a = corners[k], b = corners[k + 1];
    const int m = std::max(1, int(std::ceil((b - a).norm() / step - 1e-9)));
    for (int j = 0; j < m; ++j) p.push_back(a + (b - a) * (double(j) / m));
  }
  p.push_back(corners.back());
  const bool closed = p.size() > 2 && (p.front() - p.back()).norm() < 1e-9;
  for (int pass = 0; pass < 3 && p.size() >= 3; ++pass) {
    const std::vector<Eigen::Vector2d> q = p;
    const std::size_t n = p.size();
    for (std::size_t i = 0; i < n; ++i) {
      if (closed) {
        const std::size_t prev = i == 0 ? n - 2 : i - 1, next = i + 1 == n ? 1 : i + 1;
        p[i] = 0.25 * q[prev] + 0.5 * q[i] + 0.25 * q[next];
      } else if (i > 0 && i + 1 < n) {
        p[i] = 0.25 * q[i - 1] + 0.5 * q[i] + 0.25 * q[i + 1];
      }
    }
  }
  return p;
}

// The height of the crest's side at a point: the highest valid network point of the cell
// about it.
double crest_z(const terrain::DrainageLinks& l, const Eigen::Vector2d& p) {
  const double col = p.x() / l.dx, row = -p.y() / l.dy;
  const long c0 = std::clamp(long(std::floor(col)), 0L, long(l.cols) - 2);
  const long r0 = std::clamp(long(std::floor(row)), 0L, long(l.rows) - 2);
  double z = -std::numeric_limits<double>::infinity();
  for (long r = r0; r <= r0 + 1; ++r)
    for (long cc = c0; cc <= c0 + 1; ++cc) {
      const std::size_t i = std::size_t(r) * l.cols + std::size_t(cc);
      if (l.valid.empty() || l.valid[i]) z = std::max(z, double(l.z[i]));
    }
  return z;
}

// The runs of a divide's points `pts` above a quarter of its relief over `base` (its top
// `top`), each a ridge line parting basins of `area`.
void add_runs_above(const std::vector<Eigen::Vector3d>& pts, double base, double top, double area,
                    std::vector<RidgeLine>& out) {
  const double relief = top - base, cut = base + 0.25 * relief;
  // The runs above the cut, each a line.
  RidgeLine run;
  auto flush = [&] {
    if (run.points.size() >= 2) {
      run.basin_area = area;
      run.relief = relief;
      out.push_back(std::move(run));
    }
    run = RidgeLine{};
  };
  for (const Eigen::Vector3d& p : pts) {
    if (p.z() >= cut)
      run.points.push_back(p);
    else
      flush();
  }
  flush();
}

}  // namespace

std::vector<RidgeLine> ridge_lines(const terrain::DrainageLinks& l, double channel_area,
                                   double min_basin_area) {
  std::vector<RidgeLine> out;
  if (l.rows < 2 || l.cols < 2) return out;
  const Catchments c = catchments(l, channel_area);
  const double cell = l.dx * l.dy;
  std::vector<DivideEdge> edges;
  add_divide_edges(c.label.data(), 0, l.rows, l.cols, false, edges);
  std::sort(edges.begin(), edges.end(), [](const DivideEdge& x, const DivideEdge& y) {
    return std::tie(x.a, x.b, x.from, x.to) < std::tie(y.a, y.b, y.from, y.to);
  });
  for (std::size_t g0 = 0; g0 < edges.size();) {
    std::size_t g1 = g0;
    while (g1 < edges.size() && edges[g1].a == edges[g0].a && edges[g1].b == edges[g0].b) ++g1;
    const Parted basins = parted(c, edges[g0].a, edges[g0].b);
    const double base = basins.base, area = basins.accumulated * cell;
    if (area < min_basin_area) {
      g0 = g1;
      continue;
    }
    for (const auto& chain :
         chain_divide_edges({edges.begin() + long(g0), edges.begin() + long(g1)}, l.cols)) {
      std::vector<Eigen::Vector2d> corners;
      for (const std::uint64_t k : chain) {
        const double r = double(k / (l.cols + 1)), col = double(k % (l.cols + 1));
        corners.push_back({(col - 0.5) * l.dx, -(r - 0.5) * l.dy});
      }
      if (corners.size() < 2) continue;
      std::vector<Eigen::Vector3d> pts;
      double top = -std::numeric_limits<double>::infinity();
      for (const Eigen::Vector2d& p : resampled(corners, std::min(l.dx, l.dy))) {
        const double z = crest_z(l, p);
        if (!std::isfinite(z)) continue;
        pts.push_back({p.x(), p.y(), z});
        top = std::max(top, z);
      }
      add_runs_above(pts, base, top, area, out);
    }
    g0 = g1;
  }
  return out;
}

}  // namespace drainage
