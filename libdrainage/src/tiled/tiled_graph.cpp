// The tiled network's graph (tiled_network_internal.hpp): every tile's nodes, joined across
// tile edges on rank 0, solved in topological order and scattered back to the ranks.
#include <algorithm>
#include <queue>
#include <string>
#include <utility>
#include <vector>

#include "terrain/error.hpp"
#include "tiled_network_internal.hpp"

namespace drainage::tiled {

namespace {

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
  std::size_t total = 0;
  for (const TileNodes& T : per_tile) total += T.nodes.size();
  nodes.reserve(total);  // not doubled as it grows, with every tile's nodes still held
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
  {  // leaving nodes drain into the node of their target cell, in another tile: the nodes
     // by cell, sorted (16 bytes a node; a hash map took about 48)
    std::vector<std::pair<std::uint64_t, std::uint32_t>> of_cell(nodes.size());
    for (std::uint32_t v = 0; v < nodes.size(); ++v) of_cell[v] = {nodes[v].cell, v};
    std::sort(of_cell.begin(), of_cell.end());
    for (std::size_t q = 0; q < leave_node.size(); ++q) {
      const auto it = std::lower_bound(of_cell.begin(), of_cell.end(),
                                       std::make_pair(leave_target_cells[q], std::uint32_t(0)));
      if (it == of_cell.end() || it->first != leave_target_cells[q])
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

}  // namespace

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

}  // namespace drainage::tiled
