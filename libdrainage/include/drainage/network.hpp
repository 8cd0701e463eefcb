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
enum class PointClass : std::uint8_t {
  Ridge = 0,
  Channel = 1,
  Junction = 2,
  Pit = 3,
  Nodata = 255
};
const char* to_string(PointClass c);

struct Branch {
  std::uint32_t first = 0;        // offset into Network::branch_vertices
  std::uint32_t count = 0;        // vertices in the branch, upstream to downstream
  std::uint32_t drains_into = 0;  // the vertex it drains into (kNone at a pit)
  std::uint8_t order = 0;         // Strahler order shared by its vertices
};

struct Network {
  std::size_t points = 0;                         // valid points
  terrain::BigVector<std::uint32_t> downstream;   // #P: downstream point or kNone
  terrain::BigVector<std::uint32_t> accumulated;  // #P: 1 + sum of the accumulated flow draining in
  terrain::BigVector<float> normalized;          // #P: accumulated / accumulated of its basin's pit
  terrain::BigVector<std::uint32_t> basin;       // #P: basin id (0..#basins-1), kNone for no-data
  terrain::BigVector<std::uint8_t> point_class;  // #P: PointClass
  terrain::BigVector<std::uint8_t> order;        // #P: Strahler order (1 at ridges), 0 for no-data
  std::vector<std::uint32_t> pits;               // #basins: the pit point of each basin, ascending
  std::vector<Branch> branches;                  // heads in ascending point order
  terrain::BigVector<std::uint32_t> branch_vertices;  // #valid points, grouped by branch
  std::size_t branch_count = 0;  // branches.size(), also when they are not listed
};

// How much analyze_network lists. Lean leaves out what a version-2 .dv does not store (its
// readers derive it): Network::normalized, branches and branch_vertices stay empty, and
// branch_count still counts the branches. On Logan at 5 m (57.6 M points) that was half of
// the step's time (1.56 of 2.95 s) and 8 of its 24 bytes per point.
enum class NetworkDetail { Full, Lean };

// Everything above from D8 codes (d8.hpp) on a rows x cols grid. A direction that leaves
// the grid or points into no-data ends the flow there (the point is a pit/outlet). Flow
// is accumulated in Kahn topological order (no recursion: 100 M points are fine); a cycle
// in the directions is an Error naming how many points it traps. Basins are numbered by
// ascending pit index; a branch is a maximal downstream chain of points of one Strahler
// order (each point has at most one upstream neighbour of its own order), started at
// every point without one. Deterministic and independent of the thread count.
Network analyze_network(const D8Codes& dirs, std::size_t rows, std::size_t cols,
                        const terrain::Progress& progress = {},
                        NetworkDetail detail = NetworkDetail::Full);

}  // namespace drainage
