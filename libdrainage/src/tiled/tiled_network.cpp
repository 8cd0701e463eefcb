// The network tile by tile (tiled.hpp; Barnes 2017, extended to Strahler order and basins).
#include "drainage/tiled.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <queue>
#include <unordered_map>
#include <vector>

#include "drainage/d8.hpp"
#include "drainage/fill.hpp"
#include "terrain/error.hpp"
#include "tiled_internal.hpp"

namespace drainage {

using namespace tiled;

namespace {

constexpr int kMaxOrder = 63;  // a Strahler order needs 2^(order-1) points: 33 at most here
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

OrderTable identity_table() {
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

// Kahn within the tile, chain by chain as analyze_network walks; a cell is complete when
// its walk reaches it (every inflow delivered): then whether it is influenced (downstream
// of an entry), its local accumulation and order, passed on downstream. `indeg` is spent;
// `inflows_influenced` gets each cell's influenced inflows.
void walk_tile(LocalNetwork& L, std::vector<std::uint8_t>& indeg,
               std::vector<std::uint8_t>& inflows_influenced) {
  const std::size_t n = L.dirs.size();
  L.topo.reserve(n);
  for (std::size_t src = 0; src < n; ++src) {
    if (L.dirs[src] == kNodata || indeg[src] != 0) continue;
    std::uint32_t i = std::uint32_t(src);
    while (true) {
      L.topo.push_back(i);
      indeg[i] = 0xFF;
      if (L.entry[i]) L.influenced[i] = 1;
      if (!L.influenced[i]) L.order[i] = strahler(L.m[i], L.k[i]);
      const std::uint32_t d = L.down[i];
      if (d == kNone) break;
      if (L.influenced[i]) {
        L.influenced[d] = 1;
        ++inflows_influenced[d];
      } else {
        L.acc[d] += L.acc[i];
        add_inflow(L.m[d], L.k[d], L.order[i]);
      }
      if (--indeg[d] != 0) break;
      i = d;
    }
  }
}

LocalNetwork local_network(const TileGrid& tiles, std::size_t t, const CodeReader& read,
                           bool count_classes = false) {
  LocalNetwork L;
  L.w = tiles.window(t);
  const terrain::RasterWindow& w = L.w;
  const terrain::RasterWindow h = tiles.halo(w);
  const D8Codes halo = read(h);
  if (halo.size() != h.rows * h.cols)
    throw terrain::Error("tiled network: the reader returned a wrong window");
  const long dr = long(w.row0 - h.row0), dc = long(w.col0 - h.col0), HC = long(h.cols),
             HR = long(h.rows);
  L.nr = w.rows, L.nc = w.cols;
  const long nr = long(L.nr), nc = long(L.nc);
  const std::size_t n = L.nr * L.nc;
  L.dirs.resize(n);
  L.cut.assign(n, 0), L.leaves.assign(n, 0), L.entry.assign(n, 0), L.influenced.assign(n, 0),
      L.node.assign(n, 0);
  L.m.assign(n, 0), L.k.assign(n, 0), L.order.assign(n, 0), L.pit.assign(n, 0);
  L.down.assign(n, kNone), L.acc.assign(n, 0);
  std::vector<std::uint8_t> indeg(n, 0);
  auto code_at = [&](long hr, long hc) { return halo[std::size_t(hr * HC + hc)]; };
  const Neighbours around{HR, HC};
  for (long r = 0; r < nr; ++r)
    for (long c = 0; c < nc; ++c) {
      const std::size_t i = std::size_t(r * nc + c);
      const std::uint8_t d = code_at(r + dr, c + dc);
      L.dirs[i] = d;
      if (d == kNodata) continue;
      L.acc[i] = 1;
      // Entered from outside the tile: a halo neighbour whose direction points here (only
      // cells on the tile's edge have neighbours outside it).
      const bool edge = r == 0 || c == 0 || r == nr - 1 || c == nc - 1;
      if (edge)
        around.inflows(r + dr, c + dc, [&](std::size_t j, int q) {
          const long rr = long(j) / HC - dr, cc = long(j) % HC - dc;  // in the tile's coordinates
          if ((rr < 0 || cc < 0 || rr >= nr || cc >= nc) && halo[j] == std::uint8_t(q))
            L.entry[i] = 1;
        });
      if (d >= 8) {
        L.pit[i] = 1;
        continue;
      }
      const auto [rr, cc] = step(r, c, d);  // in the tile's coordinates
      const long gr = long(w.row0) + rr, gc = long(w.col0) + cc;
      if (gr < 0 || gc < 0 || gr >= long(tiles.rows) || gc >= long(tiles.cols) ||
          code_at(rr + dr, cc + dc) == kNodata) {
        L.cut[i] = L.pit[i] = 1;
        continue;
      }
      if (rr < 0 || cc < 0 || rr >= nr || cc >= nc) {
        L.leaves[i] = 1;
        L.target.push_back(std::uint64_t(gr) * tiles.cols + std::uint64_t(gc));
      } else {
        L.down[i] = std::uint32_t(rr * nc + cc);
        ++indeg[L.down[i]];
      }
    }
  // The classes, as the .dv's reader derives them (classify): a pit where the flow ends,
  // else by the codes entering the cell, in the tile (indeg) and, on its edge, from the halo.
  for (long r = 0; count_classes && r < nr; ++r)
    for (long c = 0; c < nc; ++c) {
      const std::size_t i = std::size_t(r * nc + c);
      if (L.dirs[i] == kNodata) continue;
      if (L.pit[i]) {
        ++L.classes[0];
        continue;
      }
      int in = indeg[i];
      if (r == 0 || c == 0 || r == nr - 1 || c == nc - 1)
        around.inflows(r + dr, c + dc, [&](std::size_t j, int q) {
          const long rr = long(j) / HC - dr, cc = long(j) % HC - dc;
          in += (rr < 0 || cc < 0 || rr >= nr || cc >= nc) && halo[j] == std::uint8_t(q);
        });
      ++L.classes[in == 0 ? 1 : in == 1 ? 2 : 3];
    }
  std::vector<std::uint8_t> inflows_influenced(n, 0);
  walk_tile(L, indeg, inflows_influenced);
  if (L.topo.size() != std::size_t(std::count_if(L.dirs.begin(), L.dirs.end(),
                                                 [](std::uint8_t d) { return d != kNodata; })))
    throw terrain::Error("the D8 directions contain a cycle (in tile " + std::to_string(t) + ")");
  for (std::size_t i = 0; i < n; ++i)
    L.node[i] = L.dirs[i] != kNodata &&
                (L.leaves[i] ||
                 (L.influenced[i] && (L.entry[i] || L.pit[i] || inflows_influenced[i] >= 2)));
  return L;
}

struct Node {
  std::uint64_t cell = 0;       // global index
  std::uint32_t acc_local = 0;  // 1 + inflows from outside the graph
  std::uint8_t m = 0, k = 0;    // their largest order and its count
  bool pit = false;
  std::uint32_t next = kNone;  // the node it drains into
  std::uint32_t add = 0;       // accumulation added on the way to next
  OrderTable table{};          // order arriving at next, by this node's order
  std::uint64_t pit_id = 0;    // pit nodes: the basin id (after pass 1)
};

// Pass 1 of tiled_network for one tile: its graph nodes (`next` counted from the tile's
// first node), its pits per row and its leaving nodes with the cell each flows into.
struct TileNodes {
  std::vector<Node> nodes;
  std::vector<std::uint32_t> pits_in_row;   // by row of the tile
  std::vector<std::uint32_t> leave_node;    // tile node index
  std::vector<std::uint64_t> leave_target;  // global cell
};

TileNodes tile_nodes(const TileGrid& tiles, std::size_t t, const CodeReader& read) {
  const LocalNetwork L = local_network(tiles, t, read);
  const OrderTable identity = identity_table();
  TileNodes T;
  T.pits_in_row.assign(L.nr, 0);
  std::vector<std::uint32_t> id(L.nr * L.nc, kNone);
  std::size_t leaving = 0;
  for (std::size_t i = 0; i < id.size(); ++i) {
    const std::size_t r = i / L.nc, c = i % L.nc;
    if (L.pit[i]) ++T.pits_in_row[r];
    if (!L.node[i]) {
      leaving += L.leaves[i];
      continue;
    }
    Node v;
    v.cell = std::uint64_t(L.w.row0 + r) * tiles.cols + L.w.col0 + c;
    v.acc_local = L.acc[i], v.m = L.m[i], v.k = L.k[i], v.pit = L.pit[i];
    if (v.pit) v.pit_id = T.pits_in_row[r] - 1;  // rank in its row within the tile, for now
    id[i] = std::uint32_t(T.nodes.size());
    if (L.leaves[i]) {
      T.leave_node.push_back(id[i]);
      T.leave_target.push_back(L.target[leaving++]);
      v.table = identity;
    }
    T.nodes.push_back(v);
  }
  // In-tile edges: from each node that is neither a pit nor leaving, down its path.
  for (std::size_t i = 0; i < id.size(); ++i) {
    if (id[i] == kNone || L.pit[i] || L.leaves[i]) continue;
    Node& v = T.nodes[id[i]];
    v.table = identity;
    std::uint32_t c = L.down[i];
    std::uint64_t add = 0;
    while (!L.node[c]) {
      add += L.acc[c];
      for (int o = 1; o <= kMaxOrder; ++o)
        v.table[std::size_t(o)] = with_inflow(L.m[c], L.k[c], v.table[std::size_t(o)]);
      c = L.down[c];
    }
    v.add = std::uint32_t(add);
    v.next = id[c];
  }
  return T;
}

// Pass 1 on every rank: each tile's graph nodes and edges, by the ranks that own them;
// rank 0 (or the only process) gets them all, in tile order.
std::vector<TileNodes> gather_tile_nodes(const TileGrid& tiles, const CodeReader& read,
                                         const TileComm& comm) {
  const std::size_t nt = tiles.count();
  std::vector<TileNodes> per_tile(nt);
  Packer mine;
  for_each_tile(
      comm, nt, [&](std::size_t t) { return tile_nodes(tiles, t, read); },
      [&](std::size_t t, TileNodes&& T) {
        if (comm.size() > 1)
          mine.put(std::uint64_t(t))
              .put_vector(T.nodes)
              .put_vector(T.pits_in_row)
              .put_vector(T.leave_node)
              .put_vector(T.leave_target);
        per_tile[t] = std::move(T);
      });
  if (comm.size() == 1) return per_tile;
  if (!comm.root()) std::vector<TileNodes>(nt).swap(per_tile);
  for (const std::string& bytes : comm.gather(mine.take())) {
    Unpacker in(bytes);
    while (!in.done()) {
      const auto t = in.get<std::uint64_t>();
      if (t >= nt) throw terrain::Error("tiled network: a rank sent a tile out of range");
      TileNodes& T = per_tile[t];
      T.nodes = in.get_vector<Node>();
      T.pits_in_row = in.get_vector<std::uint32_t>();
      T.leave_node = in.get_vector<std::uint32_t>();
      T.leave_target = in.get_vector<std::uint64_t>();
      if (T.pits_in_row.size() != tiles.window(t).rows)
        throw terrain::Error("tiled network: a rank sent a wrong tile");
    }
  }
  return per_tile;
}

// Every tile's nodes as one graph (rank 0): edges across tiles joined, pits numbered.
struct JoinedGraph {
  std::vector<Node> nodes;
  std::vector<std::uint32_t> first_node;  // of each tile, and the total
  std::vector<std::uint64_t> pit_base;    // first basin id of each (global row, tile column)
};

JoinedGraph join_graph(const TileGrid& tiles, std::vector<TileNodes>& per_tile) {
  const std::size_t nt = tiles.count(), ntc = tiles.tile_cols();
  JoinedGraph g;
  std::vector<Node>& nodes = g.nodes;
  g.first_node.assign(nt + 1, 0);
  std::vector<std::uint32_t> pits_in_row(tiles.rows * ntc,
                                         0);      // pits of global row r in tile column tc
  std::vector<std::uint64_t> leave_target_cells;  // node -> target cell, for leaving nodes
  std::vector<std::uint32_t> leave_node;
  for (std::size_t t = 0; t < nt; ++t) {
    TileNodes& T = per_tile[t];
    const std::uint32_t base = std::uint32_t(nodes.size());
    if (nodes.size() + T.nodes.size() >= kNone)
      throw terrain::Error("tiled network: too many graph nodes");
    g.first_node[t] = base;
    for (Node& v : T.nodes) {
      if (v.next != kNone) v.next += base;
      nodes.push_back(v);
    }
    const terrain::RasterWindow w = tiles.window(t);
    for (std::size_t r = 0; r < w.rows; ++r)
      pits_in_row[(w.row0 + r) * ntc + t % ntc] = T.pits_in_row[r];
    for (const std::uint32_t v : T.leave_node) leave_node.push_back(base + v);
    leave_target_cells.insert(leave_target_cells.end(), T.leave_target.begin(),
                              T.leave_target.end());
    T = TileNodes();  // freed as it goes
  }
  g.first_node[nt] = std::uint32_t(nodes.size());
  {  // leaving nodes drain into the node of their target cell, in another tile
    std::unordered_map<std::uint64_t, std::uint32_t> of_cell;
    of_cell.reserve(nodes.size());
    for (std::uint32_t v = 0; v < nodes.size(); ++v) of_cell.emplace(nodes[v].cell, v);
    for (std::size_t q = 0; q < leave_node.size(); ++q) {
      const auto it = of_cell.find(leave_target_cells[q]);
      if (it == of_cell.end())
        throw terrain::Error("tiled network: a flow leaves a tile into a cell that is not entered");
      nodes[leave_node[q]].next = it->second;
    }
  }
  // Basin ids: pits numbered by ascending global index = row by row, tile column by tile column.
  g.pit_base.assign(tiles.rows * ntc + 1, 0);
  for (std::size_t q = 0; q < tiles.rows * ntc; ++q)
    g.pit_base[q + 1] = g.pit_base[q] + pits_in_row[q];
  if (g.pit_base.back() >= kNone) throw terrain::Error("tiled network: too many basins");
  for (Node& v : nodes)
    if (v.pit)
      v.pit_id += g.pit_base[(v.cell / tiles.cols) * ntc + (v.cell % tiles.cols) / tiles.side];
  return g;
}

// The joined graph solved in topological order: accumulation, order, and the basin of the
// pit each node reaches.
struct GraphSolution {
  std::vector<std::uint32_t> A;
  std::vector<std::uint8_t> O;
  std::vector<std::uint64_t> reach;
};

GraphSolution solve_graph(const std::vector<Node>& nodes) {
  const std::size_t nn = nodes.size();
  GraphSolution s;
  std::vector<std::uint32_t> indeg(nn, 0), topo;
  std::vector<std::uint8_t> M(nn), K(nn);
  s.A.resize(nn), s.O.resize(nn);
  for (const Node& v : nodes)
    if (v.next != kNone) ++indeg[v.next];
  for (std::uint32_t v = 0; v < nn; ++v)
    s.A[v] = nodes[v].acc_local, M[v] = nodes[v].m, K[v] = nodes[v].k;
  topo.reserve(nn);
  for (std::uint32_t src = 0; src < nn; ++src) {
    if (indeg[src] != 0) continue;
    std::uint32_t v = src;
    while (true) {
      topo.push_back(v);
      indeg[v] = kNone;
      s.O[v] = strahler(M[v], K[v]);
      const Node& x = nodes[v];
      if (x.next == kNone) break;
      s.A[x.next] += s.A[v] + x.add;
      add_inflow(M[x.next], K[x.next], x.table[s.O[v]]);
      if (--indeg[x.next] != 0) break;
      v = x.next;
    }
  }
  if (topo.size() != nn) throw terrain::Error("the D8 directions contain a cycle across tiles");
  s.reach.resize(nn);
  for (auto it = topo.rbegin(); it != topo.rend(); ++it)
    s.reach[*it] = nodes[*it].pit ? nodes[*it].pit_id : s.reach[nodes[*it].next];
  return s;
}

// What one rank's tiles need from the solved graph.
struct TileSolution {
  std::vector<std::uint32_t> A, reach;  // by the tile's node index
  std::vector<std::uint8_t> O;
};
struct RankSolution {
  std::vector<TileSolution> tiles;      // by tile; filled for this rank's tiles
  std::vector<std::uint64_t> pit_base;  // as JoinedGraph's
};

// Rank 0 joins and solves the graph and sends each rank its tiles' nodes' accumulation,
// order and basin, and the basins' numbering.
RankSolution solve_and_scatter(const TileGrid& tiles, std::vector<TileNodes>& per_tile,
                               const TileComm& comm) {
  const std::size_t nt = tiles.count();
  std::vector<std::string> per_rank;
  if (comm.root()) {
    const JoinedGraph g = join_graph(tiles, per_tile);
    const GraphSolution s = solve_graph(g.nodes);
    std::vector<Packer> packs(std::size_t(comm.size()));
    for (Packer& pk : packs) pk.put_vector(g.pit_base);
    for (std::size_t t = 0; t < nt; ++t) {
      const auto b0 = std::ptrdiff_t(g.first_node[t]), b1 = std::ptrdiff_t(g.first_node[t + 1]);
      std::vector<std::uint32_t> reach32(std::size_t(b1 - b0));
      for (std::size_t v = 0; v < reach32.size(); ++v)
        reach32[v] = std::uint32_t(s.reach[std::size_t(b0) + v]);
      packs[t % std::size_t(comm.size())]
          .put(std::uint64_t(t))
          .put_vector(std::vector<std::uint32_t>(s.A.begin() + b0, s.A.begin() + b1))
          .put_vector(std::vector<std::uint8_t>(s.O.begin() + b0, s.O.begin() + b1))
          .put_vector(reach32);
    }
    for (Packer& pk : packs) per_rank.push_back(pk.take());
  }
  RankSolution mine;
  mine.tiles.resize(nt);
  const std::string bytes = comm.scatter(std::move(per_rank));
  Unpacker in(bytes);
  mine.pit_base = in.get_vector<std::uint64_t>();
  if (mine.pit_base.size() != tiles.rows * tiles.tile_cols() + 1)
    throw terrain::Error("tiled network: rank 0 sent a wrong message");
  while (!in.done()) {
    const auto t = in.get<std::uint64_t>();
    if (t >= nt || !comm.owns(t))
      throw terrain::Error("tiled network: rank 0 sent a tile out of range");
    TileSolution& x = mine.tiles[t];
    x.A = in.get_vector<std::uint32_t>();
    x.O = in.get_vector<std::uint8_t>();
    x.reach = in.get_vector<std::uint32_t>();
  }
  return mine;
}

struct PitEntry {
  std::uint32_t basin, pit, accumulated;
};
struct RingCell {  // a cell on a tile's edge: its order, inflows of that order, where it leaves to
  std::uint8_t order = 0, same = 0, valid = 0;
  std::uint64_t target = ~std::uint64_t(0);  // where a leaving cell flows
};
struct DoneTile {  // one tile, complete, and what it adds to the totals
  NetworkTile out;
  std::uint64_t points = 0, branches = 0;
  std::array<std::uint64_t, 4> classes{};
  std::vector<PitEntry> pits;
  std::vector<RingCell> ring;
};

// Accumulation and order of a tile's cells: nodes from the solution, cells no entry
// influences from the tile alone, path cells from the node above them.
void tile_flow(const LocalNetwork& L, const TileSolution& sol, const std::vector<std::uint32_t>& id,
               DoneTile& d) {
  NetworkTile& out = d.out;
  for (std::size_t i = 0; i < id.size(); ++i) {
    if (L.dirs[i] == kNodata) continue;
    d.points += 1;
    if (id[i] != kNone) {
      out.accumulated[i] = sol.A.at(id[i]), out.order[i] = sol.O.at(id[i]);
    } else if (!L.influenced[i]) {
      out.accumulated[i] = L.acc[i], out.order[i] = L.order[i];
    }
  }
  for (std::size_t i = 0; i < id.size(); ++i) {
    if (id[i] == kNone || L.pit[i] || L.leaves[i]) continue;
    std::uint32_t a = out.accumulated[i];
    std::uint8_t o = out.order[i];
    for (std::uint32_t c = L.down[i]; !L.node[c]; c = L.down[c]) {
      a = out.accumulated[c] = L.acc[c] + a;
      o = out.order[c] = with_inflow(L.m[c], L.k[c], o);
    }
  }
}

// A tile's basins, downstream first: its pits numbered from pit_base, leaving cells from
// the solution.
void tile_basins(const LocalNetwork& L, const TileGrid& tiles, std::size_t t,
                 const RankSolution& sol, const std::vector<std::uint32_t>& id, DoneTile& d) {
  NetworkTile& out = d.out;
  const std::size_t tc = t % tiles.tile_cols();
  std::vector<std::uint32_t> rank_in_row(L.nr, 0);
  for (std::size_t i = 0; i < id.size(); ++i)
    if (L.pit[i]) {
      const std::size_t r = i / L.nc, gr = L.w.row0 + r;
      const std::uint64_t b = sol.pit_base[gr * tiles.tile_cols() + tc] + rank_in_row[r]++;
      out.basin[i] = std::uint32_t(b);
      d.pits.push_back({std::uint32_t(b), std::uint32_t(gr * tiles.cols + L.w.col0 + i % L.nc),
                        out.accumulated[i]});
    }
  for (auto it = L.topo.rbegin(); it != L.topo.rend(); ++it) {
    const std::uint32_t i = *it;
    if (L.pit[i]) continue;
    out.basin[i] = L.leaves[i] ? sol.tiles[t].reach.at(id[i]) : out.basin[L.down[i]];
  }
}

// Branch heads (a point heads a branch unless exactly one inflow has its order): inflows
// from inside the tile now; the tile's edge cells go to its ring, for inflows from other
// tiles.
void tile_heads(const LocalNetwork& L, DoneTile& d) {
  const NetworkTile& out = d.out;
  const std::size_t n = L.nr * L.nc;
  d.ring.assign(ring_size(L.nr, L.nc), RingCell{});
  std::size_t leaving = 0;
  std::vector<std::uint8_t> same_order(n, 0);  // inflows of a cell's own order (at most 8)
  for (std::size_t j = 0; j < n; ++j)
    if (L.down[j] != kNone && out.order[j] == out.order[L.down[j]]) ++same_order[L.down[j]];
  for (std::size_t r = 0; r < L.nr; ++r)
    for (std::size_t c = 0; c < L.nc; ++c) {
      const std::size_t i = r * L.nc + c;
      const std::uint64_t target = L.leaves[i] ? L.target[leaving++] : ~std::uint64_t(0);
      if (L.dirs[i] == kNodata) continue;
      const int same = same_order[i];
      if (on_tile_edge(r, c, L.nr, L.nc))
        d.ring[ring_position(r, c, L.nr, L.nc)] =
            RingCell{out.order[i], std::uint8_t(same), 1, target};
      else
        d.branches += same != 1;
    }
}

// Pass 2 for one tile: every cell's accumulation, order and basin, and the heads inside it.
DoneTile complete_tile(const TileGrid& tiles, std::size_t t, const CodeReader& read,
                       const RankSolution& sol,
                       const std::function<void(std::size_t, NetworkTile&)>& prepare) {
  DoneTile d;
  LocalNetwork L = local_network(tiles, t, read, true);
  const std::size_t n = L.nr * L.nc;
  NetworkTile& out = d.out;
  out.window = L.w;
  out.accumulated.assign(n, 0);
  out.basin.assign(n, kNone);
  out.order.assign(n, 0);
  std::uint32_t next_id = 0;
  std::vector<std::uint32_t> id(n, kNone);
  for (std::size_t i = 0; i < n; ++i)
    if (L.node[i]) id[i] = next_id++;
  tile_flow(L, sol.tiles[t], id, d);
  tile_basins(L, tiles, t, sol, id, d);
  tile_heads(L, d);
  out.dirs = std::move(L.dirs);
  out.cut = std::move(L.cut);
  d.classes = L.classes;
  if (prepare) {  // then only what it made waits for `done`
    prepare(t, out);
    out.dirs = {}, out.cut = {}, out.accumulated = {}, out.basin = {}, out.order = {};
  }
  return d;
}

// Rank 0 gets every rank's counts, basins and rings and finishes the totals (the heads of
// ring cells, whose inflows cross tile edges); every rank gets the counts.
NetworkTotals finish_totals(const TileGrid& tiles, const TileComm& comm, std::uint64_t n_pits,
                            NetworkTotals mine, std::vector<PitEntry>& my_pits,
                            std::vector<std::vector<RingCell>>& rings) {
  const std::size_t nt = tiles.count(), ntc = tiles.tile_cols();
  Packer pack;
  pack.put(std::uint64_t(mine.points))
      .put(std::uint64_t(mine.branches))
      .put(mine.classes)
      .put_vector(my_pits);
  for (std::size_t t = 0; t < nt; ++t)
    if (comm.owns(t)) pack.put(std::uint64_t(t)).put_vector(rings[t]);
  std::vector<PitEntry>().swap(my_pits);
  if (!comm.root()) std::vector<std::vector<RingCell>>(nt).swap(rings);
  NetworkTotals totals;
  const std::vector<std::string> from_ranks = comm.gather(pack.take());
  if (comm.root()) {
    totals.pits.assign(n_pits, kNone);
    totals.pit_accumulated.assign(n_pits, 0);
  }
  for (const std::string& bytes : from_ranks) {
    Unpacker in(bytes);
    totals.points += in.get<std::uint64_t>();
    totals.branches += in.get<std::uint64_t>();
    const auto classes = in.get<std::array<std::uint64_t, 4>>();
    for (std::size_t k = 0; k < 4; ++k) totals.classes[k] += classes[k];
    for (const PitEntry& e : in.get_vector<PitEntry>()) {
      if (e.basin >= n_pits)
        throw terrain::Error("tiled network: a rank sent a basin out of range");
      totals.pits[e.basin] = e.pit, totals.pit_accumulated[e.basin] = e.accumulated;
    }
    while (!in.done()) {
      const auto t = in.get<std::uint64_t>();
      if (t >= nt) throw terrain::Error("tiled network: a rank sent a tile out of range");
      rings[t] = in.get_vector<RingCell>();
    }
  }
  // Inflows across tile edges into ring cells, then the ring cells' heads.
  auto ring_cell = [&](std::uint64_t cell) -> RingCell& {
    const std::size_t gr = std::size_t(cell / tiles.cols), gc = std::size_t(cell % tiles.cols);
    const std::size_t u = gr / tiles.side * ntc + gc / tiles.side;
    const terrain::RasterWindow wu = tiles.window(u);
    return rings[u][ring_position(gr - wu.row0, gc - wu.col0, wu.rows, wu.cols)];
  };
  for (const auto& ring : rings)
    for (const RingCell& x : ring)
      if (x.valid && x.target != ~std::uint64_t(0)) {
        RingCell& y = ring_cell(x.target);
        y.same += x.order == y.order;
      }
  for (const auto& ring : rings)
    for (const RingCell& x : ring) totals.branches += x.valid && x.same != 1;
  if (comm.size() > 1) {  // rank 0's counts to every rank
    const std::string counts =
        comm.all_gather(comm.root() ? Packer()
                                          .put(std::uint64_t(totals.points))
                                          .put(std::uint64_t(totals.branches))
                                          .put(totals.classes)
                                          .take()
                                    : std::string())[0];
    Unpacker in(counts);
    totals.points = in.get<std::uint64_t>();
    totals.branches = in.get<std::uint64_t>();
    totals.classes = in.get<std::array<std::uint64_t, 4>>();
  }
  return totals;
}

}  // namespace

NetworkTotals tiled_network(const TileGrid& tiles, const CodeReader& read,
                            const std::function<void(std::size_t, const NetworkTile&)>& done,
                            const TileComm& comm,
                            const std::function<void(std::size_t, NetworkTile&)>& prepare) {
  if (tiles.side == 0 || tiles.rows == 0 || tiles.cols == 0)
    throw terrain::Error("tiled network: empty grid or tile size 0");
  if (tiles.rows * tiles.cols >= kNone)
    throw terrain::Error("tiled network: more than 2^32 - 1 points");
  const std::size_t nt = tiles.count();
  std::vector<TileNodes> per_tile = gather_tile_nodes(tiles, read, comm);
  const RankSolution solution = solve_and_scatter(tiles, per_tile, comm);
  std::vector<TileNodes>().swap(per_tile);
  // Pass 2: complete every tile.
  NetworkTotals mine;
  std::vector<PitEntry> my_pits;  // this rank's basins
  std::vector<std::vector<RingCell>> rings(nt);
  for_each_tile(
      comm, nt, [&](std::size_t t) { return complete_tile(tiles, t, read, solution, prepare); },
      [&](std::size_t t, DoneTile&& d) {
        mine.points += d.points, mine.branches += d.branches;
        for (std::size_t k = 0; k < 4; ++k) mine.classes[k] += d.classes[k];
        my_pits.insert(my_pits.end(), d.pits.begin(), d.pits.end());
        rings[t] = std::move(d.ring);
        done(t, d.out);
      });
  return finish_totals(tiles, comm, solution.pit_base.back(), mine, my_pits, rings);
}

}  // namespace drainage
