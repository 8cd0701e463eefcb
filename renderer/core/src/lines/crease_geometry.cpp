// Crease geometry: the flow each drainage point carries, which links become segments, and
// the lines smoothed along the flow.
#include "renderer/core/crease.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "crease_internal.hpp"
#include "renderer/core/camera.hpp"
#include "renderer/core/line_stats.hpp"
#include "terrain/error.hpp"
#include "terrain/pn_surface.hpp"

namespace renderer {

using detail::vertex_segments;
using detail::VertexSegments;

namespace {

// crease_flow on both scales from one walk to the pits: the linear share a / T
// (CreaseGeometry::share) and fc on the scale asked for (log_fc on the log scale; on the
// linear one fc is the share and log_fc is empty: one array a point, not two).
struct BasinFlow {
  std::vector<float> share, log_fc;
  float fc(std::size_t i) const { return log_fc.empty() ? share[i] : log_fc[i]; }
};
BasinFlow basin_flow(const terrain::DrainageLinks& links, double edge_basin_min_share,
                     bool log_flow) {
  using terrain::DrainageLinks;
  const std::size_t n = links.size();
  const bool edge_rule = edge_basin_min_share > 0;
  if (!edge_rule && !log_flow) return {links.flow, {}};
  // The pit each point drains to (memoized walks downstream).
  std::vector<std::uint32_t> pit(n, DrainageLinks::kNone), path;
  for (std::size_t s = 0; s < n; ++s) {
    if (!links.valid[s] || pit[s] != DrainageLinks::kNone) continue;
    std::uint32_t i = std::uint32_t(s);
    path.clear();
    while (pit[i] == DrainageLinks::kNone) {
      path.push_back(i);
      const std::uint32_t d = links.downstream[i];
      if (d == DrainageLinks::kNone || d >= n || !links.valid[d] || path.size() > n) {
        pit[i] = i;
        break;
      }
      i = d;
    }
    for (const std::uint32_t j : path) pit[j] = pit[i];
  }
  // Basins that drain off the grid: their pit on the grid's edge or beside no-data.
  const long R = long(links.rows), C = long(links.cols);
  auto drains_off = [&](std::uint32_t p) {
    const long r = long(p) / C, c = long(p) % C;
    if (r == 0 || c == 0 || r == R - 1 || c == C - 1) return true;
    for (long dr = -1; dr <= 1; ++dr)
      for (long dc = -1; dc <= 1; ++dc)
        if (!links.valid[std::size_t((r + dr) * C + c + dc)]) return true;
    return false;
  };
  double points = 0;
  for (std::size_t i = 0; i < n; ++i) points += links.valid[i];
  BasinFlow out{std::vector<float>(n, 0.0f), std::vector<float>(log_flow ? n : 0, 0.0f)};
  for (std::size_t i = 0; i < n; ++i) {
    if (!links.valid[i]) continue;
    const std::uint32_t p = pit[i];
    double total = std::max(1.0, double(links.accumulated[p]));
    if (edge_rule && drains_off(p)) total = std::max(total, edge_basin_min_share * points);
    const double a = std::clamp(double(links.accumulated[i]), 1.0, total);
    out.share[i] = float(a / total);
    if (log_flow) out.log_fc[i] = float(total > 1 ? std::log(a) / std::log(total) : 1.0);
  }
  return out;
}

}  // namespace

std::vector<float> crease_flow(const terrain::DrainageLinks& links, double edge_basin_min_share,
                               bool log_flow) {
  BasinFlow f = basin_flow(links, edge_basin_min_share, log_flow);
  return log_flow ? std::move(f.log_fc) : std::move(f.share);
}

// In topological order (Kahn): each point passes its longest path down.
std::vector<float> contributing_width(const terrain::DrainageLinks& links) {
  using terrain::DrainageLinks;
  const std::size_t n = links.size();
  // Inflows of a valid point: at most its 8 neighbours (a byte each; 255 marks a point
  // already passed on, and a corrupt database's point of more, which then stops the walks).
  std::vector<std::uint8_t> inflows(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t d = links.downstream[i];
    if (links.valid[i] && d != DrainageLinks::kNone && d < n && inflows[d] < 254) ++inflows[d];
  }
  // From each head down while the point below has had all its inflows: each point is
  // passed on once, after every point above it (no queue of the points held).
  std::vector<float> length(n, 0.0f);
  for (std::size_t s = 0; s < n; ++s) {
    if (!links.valid[s] || inflows[s] != 0) continue;
    for (std::uint32_t i = std::uint32_t(s);;) {
      const std::uint32_t d = links.downstream[i];
      if (d == DrainageLinks::kNone || d >= n) break;
      const float step = (links.position(d) - links.position(i)).head<2>().norm();
      length[d] = std::max(length[d], length[i] + step);
      if (--inflows[d] != 0) break;
      inflows[d] = 255;  // passed on now: no head for the loop over s
      i = d;
    }
  }
  const float cell = float(std::sqrt(links.dx * links.dy));
  const double area = links.dx * links.dy;
  for (std::size_t i = 0; i < n; ++i)  // the width in the lengths' place
    length[i] = float(double(links.accumulated[i]) * area / double(length[i] + cell));
  return length;
}

std::vector<std::uint8_t> off_main_flat_path(const terrain::DrainageLinks& links) {
  using terrain::DrainageLinks;
  const std::size_t n = links.size();
  auto flat = [&](std::size_t i) {  // a link that does not descend
    const std::uint32_t d = links.downstream[i];
    return links.valid[i] && d != DrainageLinks::kNone && d < n && links.valid[d] &&
           links.z[d] >= links.z[i];
  };
  // Flat inflows of every point (compressed rows).
  std::vector<std::uint32_t> first(n + 1, 0), from;
  for (std::size_t i = 0; i < n; ++i)
    if (flat(i)) ++first[links.downstream[i] + 1];
  for (std::size_t i = 0; i < n; ++i) first[i + 1] += first[i];
  from.resize(first[n]);
  // Filled from the back, each row's start moving down to its place (no second array).
  for (std::size_t i = n; i-- > 0;)
    if (flat(i)) from[--first[links.downstream[i] + 1]] = std::uint32_t(i);
  for (std::size_t v = 0; v < n; ++v) first[v] = first[v + 1];
  first[n] = std::uint32_t(from.size());
  std::vector<std::uint8_t> off(n, 0);
  for (std::size_t i = 0; i < n; ++i) off[i] = flat(i);
  // From each point where flow leaves a flat, upstream along the largest flat inflow.
  for (std::size_t v = 0; v < n; ++v) {
    if (first[v] == first[v + 1] || flat(v)) continue;
    std::uint32_t cur = std::uint32_t(v);
    while (first[cur] != first[cur + 1]) {
      std::uint32_t best = from[first[cur]];
      for (std::uint32_t k = first[cur] + 1; k < first[cur + 1]; ++k)
        if (links.accumulated[from[k]] > links.accumulated[best]) best = from[k];
      off[best] = 0;
      cur = best;
    }
  }
  return off;
}

namespace {

// Marks every link downstream of a marked one, along the D8 links, while `may(d)` holds:
// each walk stops at the first link already marked, so every link is marked once.
template <class May>
void mark_downstream(const terrain::DrainageLinks& links, std::vector<std::uint8_t>& mark,
                     May may) {
  const std::size_t n = mark.size();
  for (std::size_t s = 0; s < n; ++s) {
    if (!mark[s]) continue;
    for (std::uint32_t d = links.downstream[s]; d < n && !mark[d] && may(d);
         d = links.downstream[d])
      mark[d] = 1;
  }
}

// Branches of the kept links (from a channel head or a junction down to the next junction
// or outlet) whose mean concavity across the flow (CreaseRules::valley_branches) is at most
// rules.valley_curvature and that drain less than rules.river_share of their basin are left
// out, unless a kept branch drains into them.
void drop_branches_off_valleys(const terrain::GridMesh& mesh, const terrain::DrainageLinks& links,
                               const Eigen::Vector3d& shift, const std::vector<float>& share,
                               const CreaseRules& rules, std::vector<std::uint8_t>& keep) {
  const std::size_t n = links.size();
  const double w = std::max({rules.valley_width, mesh.geo.dx, mesh.geo.dy});
  // (z(+w) + z(-w) - 2 z) / w^2 across link i -> d, at its midpoint (mesh heights, bilinear).
  auto concavity = [&](std::uint32_t i, std::uint32_t d) {
    const Eigen::Vector3d a = links.position(i).cast<double>() + shift,
                          b = links.position(d).cast<double>() + shift;
    const Eigen::Vector2d mid = 0.5 * (a + b).head<2>(), along = (b - a).head<2>().normalized();
    const Eigen::Vector2d side(-along.y() * w, along.x() * w);
    auto z = [&](const Eigen::Vector2d& p) {
      return vertex_value_at(
          mesh, [&](std::size_t v) { return mesh.positions[v].z(); }, p.x(), p.y());
    };
    return (z(mid + side) + z(mid - side) - 2 * z(mid)) / (w * w);
  };
  std::vector<std::uint8_t> inflows(n, 0);
  for (std::size_t i = 0; i < n; ++i)
    if (keep[i])
      inflows[links.downstream[i]] = std::uint8_t(std::min(2, inflows[links.downstream[i]] + 1));
  std::vector<std::uint32_t> branch;
  std::vector<std::uint8_t> dropped(n, 0);
  for (std::size_t s = 0; s < n; ++s) {
    if (!keep[s] || inflows[s] == 1) continue;  // a branch starts at a head or a junction
    branch.clear();
    double sum = 0, top_share = 0;
    for (std::uint32_t i = std::uint32_t(s);;) {
      branch.push_back(i);
      const std::uint32_t d = links.downstream[i];
      sum += concavity(i, d);
      top_share = std::max(top_share, double(share[i]));
      if (!keep[d] || inflows[d] != 1) break;
      i = d;
    }
    if (sum / double(branch.size()) <= rules.valley_curvature && top_share < rules.river_share)
      for (const std::uint32_t i : branch) dropped[i] = 1;
  }
  // A dropped branch fed by a kept one is the stream's way on to the river it joins, across
  // the valley floor or a fan (planar, so the rule dropped it): kept, or the tributary
  // would stop short of its stem as a dash. Only branches that start the flow - tracks
  // down planes from their heads - stay out.
  for (std::size_t i = 0; i < n; ++i)
    if (dropped[i]) keep[i] = 0;
  mark_downstream(links, keep, [&](std::uint32_t d) { return dropped[d] != 0; });
}

}  // namespace

namespace {

// Which points' links to their downstream point become crease segments: valid ends, the
// area, the flat rule, runs along the grid's edge, the contributing width, the valleys.
std::vector<std::uint8_t> kept_links(const terrain::GridMesh& mesh,
                                     const terrain::DrainageLinks& links, const CreaseRules& rules,
                                     const std::vector<std::uint8_t>& off_flat,
                                     const Eigen::Vector3d& shift,
                                     const std::vector<float>& share) {
  using terrain::DrainageLinks;
  const std::size_t n = links.size();
  // Links that may be drawn at all: both ends valid, draining at least min_area, and not a
  // run along the grid's edge (within 2 samples of it).
  std::vector<std::uint8_t> eligible(n, 0);
  const double cell_area = links.dx * links.dy;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t d = links.downstream[i];
    eligible[i] = links.valid[i] && d != DrainageLinks::kNone && d < n && links.valid[d] &&
                  double(links.accumulated[i]) * cell_area >= rules.min_area;
  }
  if (rules.off_edge_runs) {
    const long R = long(links.rows), C = long(links.cols), m = 2;
    auto edge_row = [&](long r) { return r < m || r >= R - m; };
    auto edge_col = [&](long c) { return c < m || c >= C - m; };
    for (std::size_t i = 0; i < n; ++i) {
      if (!eligible[i]) continue;
      const long d = long(links.downstream[i]), ri = long(i) / C, ci = long(i) % C, rd = d / C,
                 cd = d % C;
      if ((ri == rd && edge_row(ri)) || (ci == cd && edge_col(ci))) eligible[i] = 0;
    }
  }
  std::vector<std::uint8_t> keep(n, 0);
  for (std::size_t i = 0; i < n; ++i) keep[i] = eligible[i] && !off_flat[i];
  if (rules.min_width > 0) {
    const double least = std::max(rules.min_width, 2 * std::sqrt(cell_area));
    const std::vector<float> w = contributing_width(links);
    for (std::size_t i = 0; i < n; ++i)
      if (keep[i] && double(w[i]) < least) keep[i] = 0;
  }
  // A channel, once begun, goes on downstream to where it joins another or leaves the
  // terrain (connected creases): the width and flat rules choose where channels
  // begin, not where they stop. A contributing width can fall below the threshold further
  // down (the longest flow path grows faster than the area), and a tributary that reaches
  // a flat joins the flat's main path along the flat's resolved D8 path; left out, both
  // made dangling pieces (Logan: 16 % of the creases' length with every segment drawn).
  mark_downstream(links, keep, [&](std::uint32_t d) { return eligible[d] != 0; });
  if (rules.valley_branches) drop_branches_off_valleys(mesh, links, shift, share, rules, keep);
  return keep;
}

// The PN shading normal above each crease vertex (the nearest vertex's normal off the
// mesh); throws when none lies on the mesh.
void pn_normals_above(CreaseGeometry& out, const terrain::GridMesh& mesh) {
  const auto& g = mesh.geo;
  const std::size_t m = out.positions.size();
  out.normals.resize(m);
  std::size_t inside = 0;
#pragma omp parallel for schedule(dynamic, 4096) reduction(+ : inside)
  for (std::size_t i = 0; i < m; ++i) {
    const Eigen::Vector3f& p = out.positions[i];
    if (const auto sp = terrain::pn_point_above(mesh, p.x(), p.y())) {
      out.normals[i] = sp->normal.cast<float>();
      ++inside;
    } else {
      const double c = std::clamp(std::round(p.x() / g.dx), 0.0, double(mesh.topo.cols - 1));
      const double r = std::clamp(std::round(-p.y() / g.dy), 0.0, double(mesh.topo.rows - 1));
      out.normals[i] = mesh.normals[std::size_t(r) * mesh.topo.cols + std::size_t(c)];
    }
  }
  if (m > 0 && inside == 0)
    throw terrain::Error(
        "the drainage database does not overlap the mesh (no drainage vertex lies on it)");
}

// The median |z - PN z| over the network's valid points above the mesh (every point, or
// every (n >> 16)-th: 65,536 to 131,071 of them), 0 when none lies on it. Over all points,
// not the crease vertices: conditioning (--breach, --fill) moves the channels' points,
// which on land of closed depressions are most of the creases' (Minnesota's: a median
// 2.6 m off, breached), but leaves the hillsides on the surface.
double median_surface_offset(const terrain::GridMesh& mesh, const terrain::DrainageLinks& links,
                             const Eigen::Vector3d& shift) {
  const std::size_t n = links.size(), stride = std::max<std::size_t>(1, n >> 16);
  std::vector<float> offset;
  for (std::size_t i = 0; i < n; i += stride) {
    if (!links.valid[i]) continue;
    const Eigen::Vector3d p = links.position(i).cast<double>() + shift;
    if (const auto sp = terrain::pn_point_above(mesh, p.x(), p.y()))
      offset.push_back(float(std::abs(p.z() - sp->position.z())));
  }
  if (offset.empty()) return 0;
  const auto mid = offset.begin() + long(offset.size() / 2);
  std::nth_element(offset.begin(), mid, offset.end());
  return *mid;
}

}  // namespace

CreaseGeometry build_crease_geometry(const terrain::GridMesh& mesh,
                                     const terrain::DrainageLinks& links,
                                     const CreaseRules& rules) {
  using terrain::DrainageLinks;
  const auto& g = mesh.geo;
  if (links.epsg != 0 && g.epsg != 0 && links.epsg != g.epsg)
    throw terrain::Error("the drainage database (EPSG:" + std::to_string(links.epsg) +
                         ") and the mesh (EPSG:" + std::to_string(g.epsg) +
                         ") are in different CRSs");
  const Eigen::Vector3d shift = links.origin - Eigen::Vector3d(g.origin_x, g.origin_y, g.origin_z);
  const std::size_t n = links.size();
  const BasinFlow flow = basin_flow(links, rules.edge_basin_min_share, rules.log_flow);
  const std::vector<std::uint8_t> off_flat =
      rules.one_line_per_flat ? off_main_flat_path(links) : std::vector<std::uint8_t>(n, 0);

  std::vector<std::uint8_t> keep = kept_links(mesh, links, rules, off_flat, shift, flow.share);
  // Only the vertices of kept segments, in the points' order: the DM pass scores every
  // vertex each frame, and most points of a network are on no crease (the paper's scene:
  // 355,216 points, 13,882 segments; Logan at 10 m: 14.3 M points, 0.54 M kept). Their
  // PN normals are looked up for them alone.
  // A kept segment's ends, marked in `keep` (bit 1); a vertex's index is found in `source`,
  // the points' order (no index array over all points).
  std::vector<std::uint8_t>& ends = keep;
  for (std::size_t i = 0; i < n; ++i)
    if (ends[i] & 1) ends[i] |= 2, ends[links.downstream[i]] |= 2;
  CreaseGeometry out;
  for (std::size_t i = 0; i < n; ++i) {
    if (!(ends[i] & 2)) continue;
    out.positions.emplace_back((links.position(i).cast<double>() + shift).cast<float>());
    out.source.push_back(std::uint32_t(i));
    out.flow.push_back(flow.fc(i));
    out.share.push_back(flow.share[i]);
    out.area.push_back(float(double(links.accumulated[i]) * links.dx * links.dy));
  }
  auto compact = [&](std::uint32_t point) {
    return std::uint32_t(std::lower_bound(out.source.begin(), out.source.end(), point) -
                         out.source.begin());
  };
  for (std::size_t i = 0; i < n; ++i) {
    if (!(keep[i] & 1)) continue;
    out.segments.push_back(compact(std::uint32_t(i)));
    out.segments.push_back(compact(links.downstream[i]));
  }

  pn_normals_above(out, mesh);
  out.median_surface_offset = median_surface_offset(mesh, links, shift);
  if (rules.smooth_spacings > 0 && std::min(links.dx, links.dy) > 0)
    smooth_crease_lines(
        out, mesh,
        std::max(rules.smooth_spacings * std::min(g.dx, g.dy) / std::min(links.dx, links.dy),
                 rules.smooth_min_samples));
  return out;
}

void smooth_crease_lines(CreaseGeometry& g, const terrain::GridMesh& mesh, double sigma_samples) {
  if (!(sigma_samples > 0)) return;
  sigma_samples = std::min(sigma_samples, double(kMaxSmoothSigma));
  const std::size_t m = g.positions.size();
  constexpr std::uint32_t kNone = kNoSegment;
  // Along each line: the vertex downstream, and upstream the one of largest flow.
  const VertexSegments links = vertex_segments(g);
  std::vector<std::uint32_t> down(m, kNone), up(m, kNone);
  for (std::size_t i = 0; i < m; ++i) {
    if (links.leaving[i] != kNone) down[i] = g.segments[2 * links.leaving[i] + 1];
    if (links.entering[i] != kNone) up[i] = g.segments[2 * links.entering[i]];
  }
  const int reach = int(std::ceil(2 * sigma_samples));  // <= 2 kMaxSmoothSigma
  std::vector<double> weight(std::size_t(reach) + 1);
  for (int k = 0; k <= reach; ++k)
    weight[std::size_t(k)] = std::exp(-0.5 * k * k / (sigma_samples * sigma_samples));
  std::vector<Eigen::Vector3f> positions = g.positions, normals = g.normals;
#pragma omp parallel for schedule(dynamic, 1024)
  for (std::size_t i = 0; i < m; ++i) {
    if (down[i] == kNone && up[i] == kNone) continue;
    std::uint32_t ups[2 * kMaxSmoothSigma], downs[2 * kMaxSmoothSigma];
    int nu = 0, nd = 0;
    for (std::uint32_t v = up[i]; v != kNone && nu < reach; v = up[v]) ups[nu++] = v;
    for (std::uint32_t v = down[i]; v != kNone && nd < reach; v = down[v]) downs[nd++] = v;
    const int r = std::min(nu, nd);
    if (r == 0) continue;
    Eigen::Vector2d sum = weight[0] * g.positions[i].head<2>().cast<double>();
    double total = weight[0];
    for (int k = 1; k <= r; ++k) {
      const double w = weight[std::size_t(k)];
      sum += w * (g.positions[ups[k - 1]].head<2>().cast<double>() +
                  g.positions[downs[k - 1]].head<2>().cast<double>());
      total += 2 * w;
    }
    const Eigen::Vector2d xy = sum / total;
    const Eigen::Vector3f& p = g.positions[i];
    if ((xy - p.head<2>().cast<double>()).norm() < 1e-6) continue;
    const auto before = terrain::pn_point_above(mesh, p.x(), p.y());
    const auto after = terrain::pn_point_above(mesh, xy.x(), xy.y());
    if (!before || !after) continue;
    positions[i] =
        Eigen::Vector3f(float(xy.x()), float(xy.y()),
                        float(double(p.z()) + after->position.z() - before->position.z()));
    normals[i] = after->normal.cast<float>();
  }
  g.positions = std::move(positions);
  g.normals = std::move(normals);
}

namespace detail {

// Per vertex, the segment leaving it and the one entering it from the largest flow (ties:
// the lower index), kNoSegment where none; only segments with drawn[s] > 0 when `drawn`
// is given. The rule strokes follow (segment_chains) and lines are smoothed along.
VertexSegments vertex_segments(const CreaseGeometry& g, const std::vector<float>& drawn) {
  VertexSegments v{std::vector<std::uint32_t>(g.positions.size(), kNoSegment),
                   std::vector<std::uint32_t>(g.positions.size(), kNoSegment)};
  for (std::uint32_t s = 0; s < g.n_segments(); ++s) {
    if (!drawn.empty() && !(drawn[s] > 0)) continue;
    v.leaving[g.segments[2 * s]] = s;
    std::uint32_t& m = v.entering[g.segments[2 * s + 1]];
    if (m == kNoSegment || g.flow[g.segments[2 * s]] > g.flow[g.segments[2 * m]]) m = s;
  }
  return v;
}

}  // namespace detail

}  // namespace renderer
