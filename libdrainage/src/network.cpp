#include "drainage/network.hpp"

#include <string>

#include "drainage/d8.hpp"

namespace drainage {

namespace {

// v = n copies of `value`, written by all threads: a fresh array's pages are zeroed by the
// kernel on first touch, and a serial fill would leave that (a quarter of the run) to one core.
template <class T, class V>
void parallel_assign(terrain::BigVector<T>& v, std::size_t n, V value) {
  v.clear();
  v.resize(n);  // default-initialized: not touched
#pragma omp parallel for schedule(static)
  for (long i = 0; i < long(n); ++i) v[std::size_t(i)] = T(value);
}

}  // namespace

const char* to_string(PointClass c) {
  switch (c) {
    case PointClass::Ridge: return "ridge";
    case PointClass::Channel: return "channel";
    case PointClass::Junction: return "junction";
    case PointClass::Pit: return "pit";
    case PointClass::Nodata: return "nodata";
  }
  return "?";
}

Network analyze_network(const D8Codes& dirs, std::size_t rows, std::size_t cols,
                        const terrain::Progress& progress) {
  const std::size_t n = rows * cols;
  if (dirs.size() != n) throw terrain::Error("analyze_network: direction grid does not match rows x cols");
  if (n >= std::size_t(kNone)) throw terrain::Error("analyze_network: more than 2^32 - 1 points");
  Network net;
  const long R = long(rows), C = long(cols);

  // Downstream links: in-grid, valid targets only.
  parallel_assign(net.downstream, n, kNone);
#pragma omp parallel for schedule(static)
  for (long r = 0; r < R; ++r)
    for (long c = 0; c < C; ++c) {
      const std::size_t i = std::size_t(r * C + c);
      const std::uint8_t d = dirs[i];
      if (d >= 8) continue;
      const long rr = r + kDRow[d], cc = c + kDCol[d];
      if (rr < 0 || cc < 0 || rr >= R || cc >= C) continue;
      const std::size_t j = std::size_t(rr * C + cc);
      if (dirs[j] != kNodata) net.downstream[i] = std::uint32_t(j);
    }
  terrain::report(progress, 0.1);

  // In-degrees (gathered per point: no write conflicts) and classes.
  terrain::BigVector<std::uint8_t> indeg;
  parallel_assign(indeg, n, 0);
  parallel_assign(net.point_class, n, std::uint8_t(PointClass::Nodata));
  std::size_t points = 0;
#pragma omp parallel for schedule(static) reduction(+ : points)
  for (long r = 0; r < R; ++r)
    for (long c = 0; c < C; ++c) {
      const std::size_t i = std::size_t(r * C + c);
      if (dirs[i] == kNodata) continue;
      ++points;
      std::uint8_t in = 0;
      for (int k = 0; k < 8; ++k) {
        const long rr = r - kDRow[k], cc = c - kDCol[k];  // the neighbour that would flow in along k
        if (rr < 0 || cc < 0 || rr >= R || cc >= C) continue;
        const std::size_t j = std::size_t(rr * C + cc);
        if (net.downstream[j] == i) ++in;
      }
      indeg[i] = in;
      const PointClass cls = net.downstream[i] == kNone ? PointClass::Pit
                             : in == 0                  ? PointClass::Ridge
                             : in == 1                  ? PointClass::Channel
                                                        : PointClass::Junction;
      net.point_class[i] = std::uint8_t(cls);
    }
  net.points = points;
  terrain::report(progress, 0.2);

  // Kahn's topological order, walked chain by chain: from each source (in index order)
  // follow the flow downstream for as long as the next point has received all its
  // inflows. Accumulate flow and Strahler order on the way.
  parallel_assign(net.accumulated, n, 0);
  parallel_assign(net.order, n, 0);
  terrain::BigVector<std::uint8_t> max_count;  // inflows carrying the maximum order so far
  parallel_assign(max_count, n, 0);
  terrain::BigVector<std::uint32_t> topo;
  topo.reserve(net.points);
  for (std::size_t src = 0; src < n; ++src) {
    if (dirs[src] == kNodata || indeg[src] != 0) continue;
    std::uint32_t i = std::uint32_t(src);
    while (true) {
      topo.push_back(i);
      indeg[i] = 0xFF;  // done: not a source for the outer loop any more
      net.accumulated[i] += 1;
      // order[i] holds the largest incoming order so far (0: none).
      const std::uint8_t ord = net.order[i] == 0 ? 1 : std::uint8_t(net.order[i] + (max_count[i] >= 2 ? 1 : 0));
      net.order[i] = ord;
      const std::uint32_t d = net.downstream[i];
      if (d == kNone) break;
      net.accumulated[d] += net.accumulated[i];
      if (ord > net.order[d]) {
        net.order[d] = ord;
        max_count[d] = 1;
      } else if (ord == net.order[d]) {
        ++max_count[d];
      }
      if (--indeg[d] != 0) break;
      i = d;
    }
  }
  if (topo.size() != net.points)
    throw terrain::Error("the D8 directions contain a cycle: " + std::to_string(net.points - topo.size()) +
                         " points never reach a pit or outlet");
  terrain::BigVector<std::uint8_t>().swap(indeg);
  terrain::report(progress, 0.5);

  // Basins, numbered by ascending pit index, and normalized flow: pits first, then one
  // pass in reverse topological order (each point after the point it drains into).
  parallel_assign(net.basin, n, kNone);
  parallel_assign(net.normalized, n, 0.0f);
  for (std::size_t i = 0; i < n; ++i) {
    if (dirs[i] == kNodata) {
      net.basin[i] = kNone;
      net.normalized[i] = 0.0f;
    } else if (net.downstream[i] == kNone) {
      net.basin[i] = std::uint32_t(net.pits.size());
      net.normalized[i] = 1.0f;
      net.pits.push_back(std::uint32_t(i));
    }
  }
  for (auto it = topo.rbegin(); it != topo.rend(); ++it) {
    const std::uint32_t i = *it, d = net.downstream[i];
    if (d == kNone) continue;
    const std::uint32_t b = net.basin[d];
    net.basin[i] = b;
    net.normalized[i] = float(double(net.accumulated[i]) / double(net.accumulated[net.pits[b]]));
  }
  terrain::report(progress, 0.7);

  topo.clear();
  net.branch_vertices.swap(topo);  // reuse the buffer
  network_branches(
      rows, cols, [&](std::size_t i) { return dirs[i] != kNodata; }, [&](std::size_t i) { return net.downstream[i]; },
      [&](std::size_t i) { return net.order[i]; }, [&](const Branch& b) { net.branches.push_back(b); },
      net.branch_vertices);
  terrain::report(progress, 1.0);
  return net;
}

}  // namespace drainage
