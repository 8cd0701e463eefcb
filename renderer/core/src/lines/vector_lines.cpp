#include "renderer/core/vector_lines.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <unordered_set>

#include "terrain/polyline.hpp"

namespace renderer {

namespace {

using Adjacency = std::vector<std::vector<int>>;

std::uint64_t edge_key(int a, int b) {
  return (std::uint64_t(std::uint32_t(std::min(a, b))) << 32) | std::uint32_t(std::max(a, b));
}

// Paths of an undirected simple graph: from every node of degree other than 2 along each
// unvisited edge to the next such node; then the cycles left (closed); isolated nodes as
// paths of one node.
std::vector<std::pair<std::vector<int>, bool>> trace(const Adjacency& adj) {
  std::vector<std::pair<std::vector<int>, bool>> out;
  std::unordered_set<std::uint64_t> used;
  auto walk = [&](int start, int next) {
    std::vector<int> path{start};
    int prev = start, at = next;
    used.insert(edge_key(start, next));
    while (true) {
      if (at == start) return std::make_pair(path, true);  // a loop: the start is not repeated
      path.push_back(at);
      if (adj[std::size_t(at)].size() != 2) return std::make_pair(path, false);
      const int to =
          adj[std::size_t(at)][0] == prev ? adj[std::size_t(at)][1] : adj[std::size_t(at)][0];
      if (used.count(edge_key(at, to))) return std::make_pair(path, false);
      used.insert(edge_key(at, to));
      prev = at, at = to;
    }
  };
  for (int v = 0; v < int(adj.size()); ++v) {
    if (adj[std::size_t(v)].empty()) out.push_back({{v}, false});
    if (adj[std::size_t(v)].size() == 2) continue;
    for (const int u : adj[std::size_t(v)])
      if (!used.count(edge_key(v, u))) out.push_back(walk(v, u));
  }
  for (int v = 0; v < int(adj.size()); ++v)  // cycles: every node of degree 2
    for (const int u : adj[std::size_t(v)])
      if (!used.count(edge_key(v, u))) out.push_back(walk(v, u));
  return out;
}

// Zhang-Suen thinning (1984) of a binary image, in place.
void thin(std::vector<std::uint8_t>& m, int w, int h) {
  auto at = [&](int x, int y) {
    return x >= 0 && y >= 0 && x < w && y < h && m[std::size_t(y * w + x)] != 0;
  };
  std::vector<std::size_t> drop, on;  // on: the pixels still ink (a pass looks at those alone)
  for (std::size_t i = 0; i < m.size(); ++i)
    if (m[i]) on.push_back(i);
  for (bool changed = true; changed;) {
    changed = false;
    for (int pass = 0; pass < 2; ++pass) {
      drop.clear();
      for (const std::size_t i : on) {
        const int x = int(i % std::size_t(w)), y = int(i / std::size_t(w));
        // P2..P9 clockwise from north.
        const bool p[8] = {at(x, y - 1), at(x + 1, y - 1), at(x + 1, y), at(x + 1, y + 1),
                           at(x, y + 1), at(x - 1, y + 1), at(x - 1, y), at(x - 1, y - 1)};
        int b = 0, a = 0;
        for (int k = 0; k < 8; ++k) b += p[k], a += !p[k] && p[(k + 1) % 8];
        if (b < 2 || b > 6 || a != 1) continue;
        const bool c1 = pass == 0 ? !(p[0] && p[2] && p[4]) : !(p[0] && p[2] && p[6]);
        const bool c2 = pass == 0 ? !(p[2] && p[4] && p[6]) : !(p[0] && p[4] && p[6]);
        if (c1 && c2) drop.push_back(i);
      }
      for (const std::size_t i : drop) m[i] = 0;
      std::erase_if(on, [&](std::size_t i) { return !m[i]; });
      changed = changed || !drop.empty();
    }
  }
}

}  // namespace

std::vector<Polyline> chain_mask(const std::vector<std::uint8_t>& mask, int w, int h) {
  std::vector<std::uint8_t> m(mask.begin(), mask.end());
  thin(m, w, h);
  std::vector<int> id(m.size(), -1);
  std::vector<Eigen::Vector2f> centre;
  std::vector<std::size_t> on;  // the thinned ink, in row order
  for (std::size_t i = 0; i < m.size(); ++i)
    if (m[i]) {
      id[i] = int(centre.size());
      on.push_back(i);
      centre.emplace_back(float(i % std::size_t(w)) + 0.5f, float(i / std::size_t(w)) + 0.5f);
    }
  auto ink = [&](int x, int y) {
    return x >= 0 && y >= 0 && x < w && y < h && m[std::size_t(y * w + x)] != 0;
  };
  Adjacency adj(centre.size());
  for (const std::size_t i : on) {
    const int x = int(i % std::size_t(w)), y = int(i / std::size_t(w));
    const int a = id[i];
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        if ((dx == 0 && dy == 0) || !ink(x + dx, y + dy)) continue;
        if (dx != 0 && dy != 0 && (ink(x + dx, y) || ink(x, y + dy)))
          continue;  // the staircase goes orthogonally
        adj[std::size_t(a)].push_back(id[std::size_t((y + dy) * w + x + dx)]);
      }
  }
  std::vector<Polyline> out;
  for (const auto& [path, closed] : trace(adj)) {
    Polyline p;
    p.closed = closed;
    for (const int v : path) p.points.push_back(centre[std::size_t(v)]);
    out.push_back(std::move(p));
  }
  return out;
}

std::vector<Polyline> chain_segments(const std::vector<std::array<Eigen::Vector2f, 2>>& segments,
                                     float eps) {
  std::unordered_map<std::uint64_t, int> node_of;
  std::vector<Eigen::Vector2f> pos;
  auto node = [&](const Eigen::Vector2f& p) {
    const auto qx = std::int64_t(std::llround(double(p.x()) / eps)),
               qy = std::int64_t(std::llround(double(p.y()) / eps));
    const std::uint64_t key = (std::uint64_t(qx) << 32) ^ std::uint64_t(std::uint32_t(qy));
    const auto [it, fresh] = node_of.try_emplace(key, int(pos.size()));
    if (fresh) pos.push_back(p);
    return it->second;
  };
  Adjacency adj;
  std::unordered_set<std::uint64_t> edges;
  for (const auto& s : segments) {
    const int a = node(s[0]), b = node(s[1]);
    adj.resize(pos.size());
    if (a == b || !edges.insert(edge_key(a, b)).second)
      continue;  // a point, or the same segment again
    adj[std::size_t(a)].push_back(b);
    adj[std::size_t(b)].push_back(a);
  }
  std::vector<Polyline> out;
  for (const auto& [path, closed] : trace(adj)) {
    if (path.size() < 2) continue;  // a zero-length segment's point
    Polyline p;
    p.closed = closed;
    for (const int v : path) p.points.push_back(pos[std::size_t(v)]);
    out.push_back(std::move(p));
  }
  return out;
}

std::vector<std::size_t> simplified_points(const Polyline& line, float tolerance) {
  std::vector<Eigen::Vector2f> pts = line.points;
  if (line.closed && !pts.empty())
    pts.push_back(pts.front());  // simplified as an open line from its start
  std::vector<std::size_t> out = terrain::douglas_peucker(pts, tolerance);
  if (line.closed && out.size() > 1 && out.back() == line.points.size())
    out.pop_back();  // the closing copy of the start
  return out;
}

Polyline simplify(const Polyline& line, float tolerance) {
  Polyline out;
  out.closed = line.closed;
  for (const std::size_t k : simplified_points(line, tolerance))
    out.points.push_back(line.points[k]);
  return out;
}

}  // namespace renderer
