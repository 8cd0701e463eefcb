#pragma once
// Branches of a drainage network (private to libdrainage: the templates run on all threads
// through OpenMP pragmas, which need the library's flags).
#include <cstdint>
#include <vector>

#include "drainage/d8.hpp"
#include "drainage/network.hpp"
#include "terrain/big_vector.hpp"

namespace drainage {

// The branches headed in points lo .. hi - 1 (head[i] == 1), walked down (branches_from_heads)
// into `bs` and their vertices into `vs`. In a valid network a point that heads no branch is
// reached by exactly one walk; the marks (2: listed) keep a corrupt one (a cycle, a link
// that is no neighbour) finite.
template <class Down, class Order>
void walk_band(std::size_t lo, std::size_t hi, std::size_t n,
               terrain::BigVector<std::uint8_t>& head, Down& down, Order& order,
               std::vector<Branch>& bs, terrain::BigVector<std::uint32_t>& vs) {
  const auto mark = [&](std::size_t i) {
    __atomic_store_n(&head[i], std::uint8_t(2), __ATOMIC_RELAXED);
  };
  const auto marked = [&](std::size_t i) {
    return __atomic_load_n(&head[i], __ATOMIC_RELAXED) != 0;
  };
  for (std::size_t i = lo; i < hi; ++i) {
    if (__atomic_load_n(&head[i], __ATOMIC_RELAXED) != 1) continue;
    Branch b;
    b.first = std::uint32_t(vs.size());
    b.order = order(i);
    std::uint32_t v = std::uint32_t(i);
    while (true) {
      vs.push_back(v);
      mark(v);
      const std::uint32_t d = down(v);
      if (d == kNone || d >= n || order(d) != b.order ||
          marked(d)) {  // a chain ends where the order changes
        b.drains_into = d;
        break;
      }
      v = d;
    }
    b.count = std::uint32_t(vs.size()) - b.first;
    bs.push_back(b);
  }
}

// The branches of a network whose heads are marked (head[i] = 1 at a head, 0 elsewhere,
// `points` valid points): a branch starts at each head in ascending point order and follows
// down(i) while order(i) stays the same and the next point is no head. down(i) and order(i)
// are read from several threads; emit(branch) takes each branch in turn; `vertices` receives
// the branches' vertices; `head` is used up. Bands of rows are walked on all threads and
// joined in row order, so the result does not depend on the thread count.
template <class Down, class Order, class Emit>
void branches_from_heads(std::size_t rows, std::size_t cols, std::size_t points,
                         terrain::BigVector<std::uint8_t>& head, Down&& down, Order&& order,
                         Emit&& emit, terrain::BigVector<std::uint32_t>& vertices) {
  const std::size_t n = rows * cols;
  const long R = long(rows);
  // Bands of rows, walked a wave at a time on all threads and appended in order (a wave's
  // lists are all that is held besides the result).
  constexpr long kBands = 64, kWave = 8;
  static_assert(kBands % kWave == 0);
  std::vector<std::vector<Branch>> band_branches(static_cast<std::size_t>(kWave));
  std::vector<terrain::BigVector<std::uint32_t>> band_vertices(static_cast<std::size_t>(kWave));
  vertices.clear();
  vertices.reserve(points);  // each valid point once, in a valid network
  for (long wave = 0; wave < kBands; wave += kWave) {
#pragma omp parallel for schedule(dynamic, 1)
    for (long band = wave; band < wave + kWave; ++band) {
      auto& bs = band_branches[std::size_t(band - wave)];
      auto& vs = band_vertices[std::size_t(band - wave)];
      bs.clear();
      vs.clear();
      const std::size_t lo = std::size_t(band * R / kBands) * cols,
                        hi = std::size_t((band + 1) * R / kBands) * cols;
      walk_band(lo, hi, n, head, down, order, bs, vs);
    }
    for (std::size_t k = 0; k < std::size_t(kWave); ++k) {
      const auto offset = std::uint32_t(vertices.size());
      vertices.insert(vertices.end(), band_vertices[k].begin(), band_vertices[k].end());
      for (Branch b : band_branches[k]) {
        b.first += offset;
        emit(b);
      }
    }
  }
}

// The branches of a network from its downstream links and Strahler orders (the last step
// of analyze_network; the .dv reader derives them the same way): a point heads a branch
// unless exactly one inflow has its order; heads in ascending point order. valid(i),
// down(i) (kNone: none) and order(i) read point i of a rows x cols grid (from several
// threads); then branches_from_heads.
template <class Valid, class Down, class Order, class Emit>
void network_branches(std::size_t rows, std::size_t cols, Valid&& valid, Down&& down, Order&& order,
                      Emit&& emit, terrain::BigVector<std::uint32_t>& vertices) {
  const std::size_t n = rows * cols;
  const long R = long(rows), C = long(cols);
  terrain::BigVector<std::uint8_t> head(n);
  std::size_t points = 0;
#pragma omp parallel for schedule(static) reduction(+ : points)
  for (long r = 0; r < R; ++r)
    for (long c = 0; c < C; ++c) {
      const std::size_t i = std::size_t(r * C + c);
      head[i] = 0;
      if (!valid(i)) continue;
      ++points;
      int same = 0;
      Neighbours{R, C}.inflows(
          r, c, [&](std::size_t j, int) { same += down(j) == i && order(j) == order(i); });
      head[i] = same != 1;
    }
  branches_from_heads(rows, cols, points, head, down, order, emit, vertices);
}

}  // namespace drainage
