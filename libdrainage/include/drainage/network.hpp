#pragma once
// The drainage network of a D8 direction grid: classes, basins, accumulated and
// basin-normalized flow, Strahler order and branches (O'Callaghan & Mark 1984, as used by
// Mower's Creases algorithm; docs/algorithms.md 7.5-7.7).
#include <cstdint>
#include <vector>

#include "drainage/d8.hpp"
#include "terrain/big_vector.hpp"
#include "terrain/error.hpp"

namespace drainage {

// Point classes from the D8 graph (one place; locked by tests): a pit has no downstream
// point (kNoFlow, or its flow leaves the grid: outlets count as pits); otherwise the
// number of points draining into it decides: 0 ridge, 1 channel, more junction.
enum class PointClass : std::uint8_t { Ridge = 0, Channel = 1, Junction = 2, Pit = 3, Nodata = 255 };
const char* to_string(PointClass c);

struct Branch {
  std::uint32_t first = 0;              // offset into Network::branch_vertices
  std::uint32_t count = 0;              // vertices in the branch, upstream to downstream
  std::uint32_t drains_into = 0;        // the vertex it drains into (kNone at a pit)
  std::uint8_t order = 0;               // Strahler order shared by its vertices
};

struct Network {
  std::size_t points = 0;                  // valid points
  terrain::BigVector<std::uint32_t> downstream;   // #P: downstream point or kNone
  terrain::BigVector<std::uint32_t> accumulated;  // #P: 1 + sum of the accumulated flow draining in
  terrain::BigVector<float> normalized;           // #P: accumulated / accumulated of its basin's pit
  terrain::BigVector<std::uint32_t> basin;        // #P: basin id (0..#basins-1), kNone for no-data
  terrain::BigVector<std::uint8_t> point_class;   // #P: PointClass
  terrain::BigVector<std::uint8_t> order;         // #P: Strahler order (1 at ridges), 0 for no-data
  std::vector<std::uint32_t> pits;         // #basins: the pit point of each basin, ascending
  std::vector<Branch> branches;            // heads in ascending point order
  terrain::BigVector<std::uint32_t> branch_vertices;  // #valid points, grouped by branch
};

// Everything above from D8 codes (d8.hpp) on a rows x cols grid. A direction that leaves
// the grid or points into no-data ends the flow there (the point is a pit/outlet). Flow
// is accumulated in Kahn topological order (no recursion: 100 M points are fine); a cycle
// in the directions is an Error naming how many points it traps. Basins are numbered by
// ascending pit index; a branch is a maximal downstream chain of points of one Strahler
// order (each point has at most one upstream neighbour of its own order), started at
// every point without one. Deterministic and independent of the thread count.
Network analyze_network(const D8Codes& dirs, std::size_t rows, std::size_t cols,
                        const terrain::Progress& progress = {});

// The branches of a network from its downstream links and Strahler orders (the last step
// of analyze_network; the .dv reader derives them the same way): a point heads a branch
// unless exactly one inflow has its order; heads in ascending point order. valid(i),
// down(i) (kNone: none) and order(i) read point i of a rows x cols grid; emit(branch) takes
// each branch in turn; `vertices` receives the branches' vertices.
template <class Valid, class Down, class Order, class Emit>
void network_branches(std::size_t rows, std::size_t cols, Valid&& valid, Down&& down, Order&& order, Emit&& emit,
                      terrain::BigVector<std::uint32_t>& vertices) {
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
      for (int k = 0; k < 8; ++k) {
        const long rr = r - kDRow[std::size_t(k)], cc = c - kDCol[std::size_t(k)];  // would flow in along k
        if (rr < 0 || cc < 0 || rr >= R || cc >= C) continue;
        const std::size_t j = std::size_t(rr * C + cc);
        same += down(j) == i && order(j) == order(i);
      }
      head[i] = same != 1;
    }
  vertices.clear();
  vertices.reserve(points);
  for (std::size_t i = 0; i < n; ++i) {
    if (head[i] != 1) continue;
    Branch b;
    b.first = std::uint32_t(vertices.size());
    b.order = order(i);
    std::uint32_t v = std::uint32_t(i);
    while (true) {
      vertices.push_back(v);
      head[v] = 2;  // listed
      const std::uint32_t d = down(v);
      // A chain ends where the order changes. It meets a head or a listed point only in a
      // corrupt network (a cycle, a link that is no neighbour): the guard keeps it finite.
      if (d == kNone || d >= n || order(d) != b.order || head[d]) {
        b.drains_into = d;
        break;
      }
      v = d;
    }
    b.count = std::uint32_t(vertices.size()) - b.first;
    emit(b);
  }
}

}  // namespace drainage
