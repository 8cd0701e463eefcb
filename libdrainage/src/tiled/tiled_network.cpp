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
#include "tiled_network_internal.hpp"

namespace drainage {

using namespace tiled;

namespace tiled {

namespace {

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

void allocate(LocalNetwork& L, std::size_t n) {
  L.dirs.resize(n);
  L.cut.assign(n, 0), L.leaves.assign(n, 0), L.entry.assign(n, 0), L.influenced.assign(n, 0),
      L.node.assign(n, 0);
  L.m.assign(n, 0), L.k.assign(n, 0), L.order.assign(n, 0), L.pit.assign(n, 0);
  L.down.assign(n, kNone), L.acc.assign(n, 0);
}

// The tile walked (walk_tile; a cycle is an error) and its graph nodes marked: the cells
// that leave the tile, and the influenced cells where an entry, a pit or two influenced
// inflows are.
void walk_and_mark_nodes(LocalNetwork& L, std::vector<std::uint8_t>& indeg, std::size_t t) {
  const std::size_t n = L.dirs.size();
  std::vector<std::uint8_t> inflows_influenced(n, 0);
  walk_tile(L, indeg, inflows_influenced);
  if (L.topo.size() != std::size_t(std::count_if(L.dirs.begin(), L.dirs.end(),
                                                 [](std::uint8_t d) { return d != kNodata; })))
    throw terrain::Error("the D8 directions contain a cycle (in tile " + std::to_string(t) + ")");
  for (std::size_t i = 0; i < n; ++i)
    L.node[i] = L.dirs[i] != kNodata &&
                (L.leaves[i] ||
                 (L.influenced[i] && (L.entry[i] || L.pit[i] || inflows_influenced[i] >= 2)));
}

// The classes, as the .dv's reader derives them (classify): a pit where the flow ends,
// else by the codes entering the cell, in the tile (`indeg`) and, on its edge, from the
// halo `h` (the tile at row dr, column dc of it).
void count_tile_classes(LocalNetwork& L, const D8Codes& halo, const terrain::RasterWindow& h,
                        long dr, long dc, const std::vector<std::uint8_t>& indeg) {
  const long nr = long(L.nr), nc = long(L.nc), HC = long(h.cols);
  const Neighbours around{long(h.rows), HC};
  for (long r = 0; r < nr; ++r)
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
}

}  // namespace

LocalNetwork local_network(const TileGrid& tiles, std::size_t t, const CodeReader& read,
                           bool count_classes) {
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
  allocate(L, n);
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
  if (count_classes) count_tile_classes(L, halo, h, dr, dc, indeg);
  walk_and_mark_nodes(L, indeg, t);
  return L;
}

}  // namespace tiled

namespace {

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
  NetworkTile& out = d.out;
  {  // the walk's arrays (about 26 bytes a cell) freed before `prepare` makes the .dv block
    LocalNetwork L = local_network(tiles, t, read, true);
    const std::size_t n = L.nr * L.nc;
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
  }
  if (prepare) {  // then only what it made waits for `done`
    prepare(t, out);
    out.dirs = {}, out.cut = {}, out.accumulated = {}, out.basin = {}, out.order = {};
  }
  return d;
}

// The heads among the tiles' ring cells: their inflows across tile edges counted first.
std::uint64_t ring_heads(const TileGrid& tiles, std::vector<std::vector<RingCell>>& rings) {
  const std::size_t ntc = tiles.tile_cols();
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
  std::uint64_t heads = 0;
  for (const auto& ring : rings)
    for (const RingCell& x : ring) heads += x.valid && x.same != 1;
  return heads;
}

// Rank 0 gets every rank's counts, basins and rings and finishes the totals (the heads of
// ring cells, whose inflows cross tile edges); every rank gets the counts.
NetworkTotals finish_totals(const TileGrid& tiles, const TileComm& comm, std::uint64_t n_pits,
                            NetworkTotals mine, std::vector<PitEntry>& my_pits,
                            std::vector<std::vector<RingCell>>& rings) {
  const std::size_t nt = tiles.count();
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
  totals.branches += ring_heads(tiles, rings);
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
