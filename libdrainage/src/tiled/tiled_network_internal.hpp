#pragma once
// The tiled network's parts shared by its two passes (tiled_network.cpp: each tile alone and
// the tiles completed; tiled_graph.cpp: the graph of every tile's nodes, joined and solved).
// Not installed.
#include <array>
#include <cstdint>
#include <vector>

#include "drainage/d8.hpp"
#include "drainage/tiled.hpp"
#include "terrain/big_vector.hpp"
#include "tiled_internal.hpp"

namespace drainage::tiled {

// A Strahler order o needs 2^(o-1) points, and a tiled grid has fewer than 2^32: orders
// are at most 32, and one more inflow makes 33. (The table was 64 entries: a third of a
// graph node's bytes, and rank 0 holds every tile's nodes at once.)
constexpr int kMaxOrder = 33;
using OrderTable = std::array<std::uint8_t, kMaxOrder + 1>;  // f(o), o = 1..kMaxOrder

// Strahler order from the largest order m of the inflows and how many (k) carry it.
inline std::uint8_t strahler(std::uint8_t m, int k) {
  return k == 0 ? 1 : std::uint8_t(m + (k >= 2 ? 1 : 0));
}
inline void add_inflow(std::uint8_t& m, std::uint8_t& k, std::uint8_t o) {
  if (o > m)
    m = o, k = 1;
  else if (o == m)
    ++k;
}
// The order of a point with local inflows (m, k) and one more inflow of order o.
inline std::uint8_t with_inflow(std::uint8_t m, std::uint8_t k, std::uint8_t o) {
  add_inflow(m, k, o);
  return strahler(m, k);
}

inline OrderTable identity_table() {
  OrderTable t{};
  for (int o = 0; o <= kMaxOrder; ++o) t[std::size_t(o)] = std::uint8_t(o);
  return t;
}

// What one tile knows alone (both passes compute it the same way).
struct LocalNetwork {
  terrain::RasterWindow w;
  std::size_t nr = 0, nc = 0;
  D8Codes dirs;
  terrain::BigVector<std::uint8_t> cut, leaves, entry, influenced, node, m, k, order, pit;
  terrain::BigVector<std::uint32_t> down,
      acc;                          // acc: 1 + inflows not influenced (final where not influenced)
  std::vector<std::uint32_t> topo;  // upstream before downstream
  std::vector<std::uint64_t>
      target;  // of each leaving cell, in cell order: global index downstream
  std::array<std::uint64_t, 4> classes{};  // NetworkTotals::classes of the tile (pass 2 only)
};

// The tile's cells with their local accumulation and order, walked within the tile alone
// (with `count_classes`, its NetworkTotals::classes too).
LocalNetwork local_network(const TileGrid& tiles, std::size_t t, const CodeReader& read,
                           bool count_classes = false);

struct Node {                   // 72 bytes: the wide fields first
  std::uint64_t cell = 0;       // global index
  std::uint64_t pit_id = 0;     // pit nodes: the basin id (after pass 1)
  std::uint32_t acc_local = 0;  // 1 + inflows from outside the graph
  std::uint32_t next = kNone;   // the node it drains into
  std::uint32_t add = 0;        // accumulation added on the way to next
  std::uint8_t m = 0, k = 0;    // their largest order and its count
  bool pit = false;
  OrderTable table{};  // order arriving at next, by this node's order
};

// Pass 1 of tiled_network for one tile: its graph nodes (`next` counted from the tile's
// first node), its pits per row and its leaving nodes with the cell each flows into.
struct TileNodes {
  std::vector<Node> nodes;
  std::vector<std::uint32_t> pits_in_row;   // by row of the tile
  std::vector<std::uint32_t> leave_node;    // tile node index
  std::vector<std::uint64_t> leave_target;  // global cell
};

// What one rank's tiles need from the solved graph.
struct TileSolution {
  std::vector<std::uint32_t> A, reach;  // by the tile's node index
  std::vector<std::uint8_t> O;
};
struct RankSolution {
  std::vector<TileSolution> tiles;      // by tile; filled for this rank's tiles
  std::vector<std::uint64_t> pit_base;  // as JoinedGraph's
};

// Pass 1 on every rank: each tile's graph nodes and edges, by the ranks that own them;
// rank 0 (or the only process) gets them all, in tile order.
std::vector<TileNodes> gather_tile_nodes(const TileGrid& tiles, const CodeReader& read,
                                         const TileComm& comm);
// Rank 0 joins and solves the graph and sends each rank its tiles' nodes' accumulation,
// order and basin, and the basins' numbering.
RankSolution solve_and_scatter(const TileGrid& tiles, std::vector<TileNodes>& per_tile,
                               const TileComm& comm);

}  // namespace drainage::tiled
