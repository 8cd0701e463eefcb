#include "drainage/network.hpp"

#include <algorithm>
#include <cstddef>
#include <string>

#include "drainage/d8.hpp"
#include "network/branches.hpp"

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
    case PointClass::Ridge:
      return "ridge";
    case PointClass::Channel:
      return "channel";
    case PointClass::Junction:
      return "junction";
    case PointClass::Pit:
      return "pit";
    case PointClass::Nodata:
      return "nodata";
  }
  return "?";
}

namespace {

// Downstream links: in-grid, valid targets only.
void link_downstream(const D8Codes& dirs, long R, long C, Network& net) {
  const std::size_t n = std::size_t(R * C);
  parallel_assign(net.downstream, n, kNone);
#pragma omp parallel for schedule(static)
  for (long r = 0; r < R; ++r)
    for (long c = 0; c < C; ++c) {
      const std::size_t i = std::size_t(r * C + c);
      const std::size_t j = flows_into(dirs, std::size_t(R), std::size_t(C), i);
      if (j != kNone) net.downstream[i] = std::uint32_t(j);
    }
}

// Inflow masks (bit k: the neighbour at (r - kDRow[k], c - kDCol[k]) drains in; gathered
// per point, so no write conflicts), in-degrees still pending, classes and the pits.
void classify_points(const D8Codes& dirs, long R, long C, Network& net,
                     terrain::BigVector<std::uint8_t>& inflow,
                     terrain::BigVector<std::uint8_t>& pending) {
  const std::size_t n = std::size_t(R * C);
  const Neighbours nb{R, C};
  parallel_assign(inflow, n, 0);
  parallel_assign(pending, n, 0);
  parallel_assign(net.point_class, n, std::uint8_t(PointClass::Nodata));
  std::size_t points = 0;
#pragma omp parallel reduction(+ : points)
  {
    std::vector<std::uint32_t> pits;  // this thread's, ascending
#pragma omp for schedule(static) nowait
    for (long r = 0; r < R; ++r)
      for (long c = 0; c < C; ++c) {
        const std::size_t i = std::size_t(r * C + c);
        if (dirs[i] == kNodata) continue;
        ++points;
        std::uint8_t mask = 0, in = 0;
        nb.inflows(r, c, [&](std::size_t j, int k) {
          if (net.downstream[j] == i) mask |= std::uint8_t(1u << k), ++in;
        });
        inflow[i] = mask;
        pending[i] = in;
        const PointClass cls = net.downstream[i] == kNone ? PointClass::Pit
                               : in == 0                  ? PointClass::Ridge
                               : in == 1                  ? PointClass::Channel
                                                          : PointClass::Junction;
        net.point_class[i] = std::uint8_t(cls);
        if (cls == PointClass::Pit) pits.push_back(std::uint32_t(i));
      }
#pragma omp critical
    net.pits.insert(net.pits.end(), pits.begin(), pits.end());
  }
  std::sort(net.pits.begin(), net.pits.end());
  net.points = points;
}

// Flow and Strahler order in topological order, on all threads: from each source walk
// downstream; a point is computed from its inflows (1 + their flow; their largest order,
// plus one where two or more carry it) by the walk that delivers its last inflow (the
// acquire-release count makes the other walks' results visible). Sums and maxima do not
// depend on the order of arrival, so neither do the results.
// `pending` ends holding the branch heads' marks.
void flow_and_order(const D8Codes& dirs, long R, long C, Network& net,
                    terrain::BigVector<std::uint8_t>& inflow,
                    terrain::BigVector<std::uint8_t>& pending) {
  const std::size_t n = std::size_t(R * C);
  std::ptrdiff_t offset[8];
  for (int k = 0; k < 8; ++k) offset[k] = -(kDRow[k] * C + kDCol[k]);
  parallel_assign(net.accumulated, n, 0);
  parallel_assign(net.order, n, 0);
  std::size_t done = 0, heads = 0;
#pragma omp parallel for schedule(dynamic, 16) reduction(+ : done, heads)
  for (long r = 0; r < R; ++r)
    for (long c = 0; c < C; ++c) {
      std::size_t i = std::size_t(r * C + c);
      if (dirs[i] == kNodata || inflow[i] != 0) continue;
      while (true) {
        std::uint32_t acc = 1;
        std::uint8_t top = 0, count = 0;
        for (unsigned mask = inflow[i]; mask != 0; mask &= mask - 1) {
          const std::size_t j = std::size_t(std::ptrdiff_t(i) + offset[__builtin_ctz(mask)]);
          acc += net.accumulated[j];
          const std::uint8_t o = net.order[j];
          if (o > top)
            top = o, count = 1;
          else if (o == top)
            ++count;
        }
        net.accumulated[i] = acc;
        net.order[i] = top == 0 ? 1 : std::uint8_t(top + (count >= 2 ? 1 : 0));
        // A branch head unless exactly one inflow has its order (network_branches, in
        // branches.hpp). All of i's inflows have arrived: its pending count can hold the mark.
        pending[i] = top == 0 || count != 1;
        heads += pending[i];
        ++done;
        const std::uint32_t d = net.downstream[i];
        if (d == kNone) break;
        // A point with one inflow is this walk's to compute; others wait for their last.
        if ((inflow[d] & (inflow[d] - 1)) != 0 &&
            __atomic_sub_fetch(&pending[d], std::uint8_t(1), __ATOMIC_ACQ_REL) != 0)
          break;
        i = d;
      }
    }
  if (done != net.points)
    throw terrain::Error("the D8 directions contain a cycle: " + std::to_string(net.points - done) +
                         " points never reach a pit or outlet");
  terrain::BigVector<std::uint8_t>().swap(inflow);
  net.branch_count = heads;
}

// Basins, numbered by ascending pit index. Every other point takes its pit's basin: walk
// downstream to a point whose basin is known and give it to the points on the way (two
// threads may write the same value to a point: relaxed atomics).
void assign_basins(const D8Codes& dirs, long R, long C, Network& net) {
  const std::size_t n = std::size_t(R * C);
  parallel_assign(net.basin, n, kNone);
#pragma omp parallel for schedule(static)
  for (long k = 0; k < long(net.pits.size()); ++k)
    net.basin[net.pits[std::size_t(k)]] = std::uint32_t(k);
#pragma omp parallel
  {
    std::vector<std::uint32_t> path;
#pragma omp for schedule(dynamic, 16)
    for (long r = 0; r < R; ++r)
      for (long c = 0; c < C; ++c) {
        const std::size_t i = std::size_t(r * C + c);
        if (dirs[i] == kNodata || __atomic_load_n(&net.basin[i], __ATOMIC_RELAXED) != kNone)
          continue;
        path.clear();
        std::uint32_t v = std::uint32_t(i), b;
        while ((b = __atomic_load_n(&net.basin[v], __ATOMIC_RELAXED)) == kNone) {
          path.push_back(v);
          v = net.downstream[v];
        }
        for (const std::uint32_t p : path) __atomic_store_n(&net.basin[p], b, __ATOMIC_RELAXED);
      }
  }
}

}  // namespace

Network analyze_network(const D8Codes& dirs, std::size_t rows, std::size_t cols,
                        const terrain::Progress& progress, NetworkDetail detail) {
  const std::size_t n = rows * cols;
  if (dirs.size() != n)
    throw terrain::Error("analyze_network: direction grid does not match rows x cols");
  if (n >= std::size_t(kNone)) throw terrain::Error("analyze_network: more than 2^32 - 1 points");
  Network net;
  const long R = long(rows), C = long(cols);

  link_downstream(dirs, R, C, net);
  terrain::report(progress, 0.1);

  terrain::BigVector<std::uint8_t> inflow, pending;
  classify_points(dirs, R, C, net, inflow, pending);
  terrain::report(progress, 0.2);

  flow_and_order(dirs, R, C, net, inflow, pending);
  terrain::report(progress, 0.5);

  assign_basins(dirs, R, C, net);
  if (detail == NetworkDetail::Lean) {
    terrain::report(progress, 1.0);
    return net;
  }
  // Normalized flow: each point's flow over its pit's (1 at the pits).
  parallel_assign(net.normalized, n, 0.0f);
#pragma omp parallel for schedule(static)
  for (long i = 0; i < long(n); ++i) {
    const std::uint32_t b = net.basin[std::size_t(i)];
    if (b != kNone)
      net.normalized[std::size_t(i)] =
          float(double(net.accumulated[std::size_t(i)]) / double(net.accumulated[net.pits[b]]));
  }
  terrain::report(progress, 0.7);

  terrain::BigVector<std::uint8_t>& head = pending;  // marked by the flow walk
  branches_from_heads(
      rows, cols, net.points, head, [&](std::size_t i) { return net.downstream[i]; },
      [&](std::size_t i) { return net.order[i]; },
      [&](const Branch& b) { net.branches.push_back(b); }, net.branch_vertices);
  terrain::report(progress, 1.0);
  return net;
}

}  // namespace drainage
