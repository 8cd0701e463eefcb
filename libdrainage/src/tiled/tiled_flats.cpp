// Flats resolved tile by tile (tiled_codes.hpp): a flat inside a tile with its tile, a flat
// that crosses tile edges joined across the tiles and resolved in a window of its box.
#include <algorithm>
#include <numeric>
#include <unordered_map>
#include <vector>

#include <fmt/format.h>

#include "drainage/flats.hpp"
#include "tiled_codes.hpp"
#include "tiled_internal.hpp"

namespace drainage::tiled {

D8Codes window_codes(const SurfaceReader& surface, const terrain::RasterWindow& w,
                     const TileGrid& tiles, terrain::Grid* z) {
  const terrain::RasterWindow h = tiles.halo(w);
  const terrain::Grid zh = surface(h);
  const D8Codes all = d8_directions(zh);
  const std::size_t dr = w.row0 - h.row0, dc = w.col0 - h.col0;
  D8Codes out(w.rows * w.cols);
  for (std::size_t r = 0; r < w.rows; ++r)
    for (std::size_t c = 0; c < w.cols; ++c) out[r * w.cols + c] = all[(r + dr) * h.cols + c + dc];
  if (z) {
    *z = terrain::Grid(w.rows, w.cols, zh.geo.window(dr, dc));
    for (std::size_t r = 0; r < w.rows; ++r)
      for (std::size_t c = 0; c < w.cols; ++c) z->at(r, c) = zh.at(r + dr, c + dc);
  }
  return out;
}

namespace {

// The flats of a window as resolve_flats sees them: no-flow cells and their equal-elevation
// neighbours with a direction (low edges), joined into components through equal
// elevations (8-connected). Returns each cell's component (kNone outside flats).
std::vector<std::uint32_t> flat_components(const terrain::Grid& z, const D8Codes& raw,
                                           std::uint32_t& count) {
  const long C = long(z.cols);
  const Neighbours nb{long(z.rows), C};
  const std::size_t n = z.size();
  auto involved = [&](long r, long c) {
    const std::size_t i = std::size_t(r * C + c);
    if (raw[i] == kNoFlow) return true;
    if (raw[i] == kNodata) return false;
    bool beside = false;  // beside a no-flow cell of its elevation
    nb.each(r, c, [&](std::size_t j, int) {
      beside = beside || (raw[j] == kNoFlow && z.z[j] == z.z[i]);
    });
    return beside;
  };
  std::vector<std::uint32_t> label(n, kNone);
  std::vector<std::uint32_t> stack;
  count = 0;
  for (std::size_t s = 0; s < n; ++s) {
    // Every component, also one of low edges only: in a window it may be a piece of a flat
    // whose no-flow cells lie outside the window.
    if (label[s] != kNone || !involved(long(s) / C, long(s) % C)) continue;
    label[s] = count;
    stack.assign(1, std::uint32_t(s));
    while (!stack.empty()) {
      const std::uint32_t i = stack.back();
      stack.pop_back();
      nb.each(std::size_t(i), [&](std::size_t j, int) {
        if (label[j] != kNone || z.z[j] != z.z[i] || !involved(long(j) / C, long(j) % C)) return;
        label[j] = count;
        stack.push_back(std::uint32_t(j));
      });
    }
    ++count;
  }
  return label;
}

// The flats of window w: D8 codes before and after resolve_flats on the window alone, and
// the flat components (flat_components).
struct WindowFlats {
  D8Codes raw, resolved;
  std::vector<std::uint32_t> comp;
  std::uint32_t count = 0;
};
WindowFlats window_flats(const SurfaceReader& surface, const terrain::RasterWindow& w,
                         const TileGrid& tiles) {
  WindowFlats f;
  terrain::Grid z;
  f.raw = window_codes(surface, w, tiles, &z);
  f.resolved = f.raw;
  resolve_flats(z, f.resolved);
  f.comp = flat_components(z, f.raw, f.count);
  return f;
}

struct Box {
  std::size_t r0 = ~std::size_t(0), c0 = ~std::size_t(0), r1 = 0, c1 = 0;  // inclusive
  void add(std::size_t r, std::size_t c) {
    r0 = std::min(r0, r), c0 = std::min(c0, c), r1 = std::max(r1, r), c1 = std::max(c1, c);
  }
  void add(const Box& b) { add(b.r0, b.c0), add(b.r1, b.c1); }
};

// A cell of a crossing flat and the flat's piece (index into the pieces' boxes).
struct CellPiece {
  std::uint64_t cell;
  std::uint32_t piece;
};

// One tile's codes and its crossing flats, pieces numbered from 0.
struct TilePieces {
  D8Codes codes;
  std::vector<Box> boxes;
  std::vector<std::uint64_t> seeds;
  std::vector<CellPiece> ring, contacts;
};

// Tile t's codes (flats inside it resolved) and the pieces of the flats that cross its edge:
// their boxes, a member each, their members on the tile's ring and just outside it.
TilePieces tile_pieces(const TileGrid& tiles, const SurfaceReader& surface, std::size_t t) {
  const std::size_t C = tiles.cols;
  // Two samples of halo: whether a cell one sample outside the tile is a low edge
  // depends on its own neighbours.
  const terrain::RasterWindow w = tiles.window(t), h = tiles.halo(tiles.halo(w));
  const WindowFlats f = window_flats(surface, h, tiles);
  TilePieces p;
  std::vector<std::uint32_t> crossing(f.count, kNone);
  auto inside = [&](std::size_t gr, std::size_t gc) {
    return gr >= w.row0 && gr < w.row0 + w.rows && gc >= w.col0 && gc < w.col0 + w.cols;
  };
  std::vector<std::uint8_t> where(f.count, 0);  // bit 1: a member inside the tile, bit 2: outside
  for (std::size_t i = 0; i < f.comp.size(); ++i)
    if (f.comp[i] != kNone)
      where[f.comp[i]] |= inside(h.row0 + i / h.cols, h.col0 + i % h.cols) ? 1 : 2;
  for (std::uint32_t k = 0; k < f.count; ++k)
    if (where[k] == 3) {
      crossing[k] = std::uint32_t(p.boxes.size());
      p.boxes.emplace_back();
      p.seeds.push_back(~std::uint64_t(0));
    }
  p.codes.resize(w.rows * w.cols);
  for (std::size_t r = 0; r < h.rows; ++r)
    for (std::size_t c = 0; c < h.cols; ++c) {
      const std::size_t i = r * h.cols + c, gr = h.row0 + r, gc = h.col0 + c;
      const std::uint64_t cell = std::uint64_t(gr) * C + gc;
      const std::uint32_t k = f.comp[i];
      const bool in = inside(gr, gc);
      if (in)
        p.codes[(gr - w.row0) * w.cols + gc - w.col0] =
            k != kNone && crossing[k] == kNone ? f.resolved[i] : f.raw[i];
      if (k == kNone || crossing[k] == kNone) continue;
      const std::uint32_t x = crossing[k];
      if (!in) {  // a member in a neighbouring tile, on its ring: the same flat there
        if (gr + 1 >= w.row0 && gr <= w.row0 + w.rows && gc + 1 >= w.col0 && gc <= w.col0 + w.cols)
          p.contacts.push_back({cell, x});
        continue;
      }
      p.boxes[x].add(gr, gc);
      if (p.seeds[x] == ~std::uint64_t(0)) p.seeds[x] = cell;
      if (on_tile_edge(gr - w.row0, gc - w.col0, w.rows, w.cols)) p.ring.push_back({cell, x});
    }
  return p;
}

// The crossing flats' pieces joined (union-find over the contacts with the ring), each
// root's box grown to the flat's. Returns each piece's root.
std::vector<std::uint32_t> join_pieces(std::vector<Box>& boxes, const std::vector<CellPiece>& ring,
                                       const std::vector<CellPiece>& contacts, std::size_t C) {
  std::unordered_map<std::uint64_t, std::uint32_t> ring_piece;
  for (const CellPiece& x : ring) ring_piece.emplace(x.cell, x.piece);
  std::vector<std::uint32_t> parent(boxes.size());
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const auto& [cell, x] : contacts) {
    const auto it = ring_piece.find(cell);
    if (it == ring_piece.end() || x >= boxes.size() || it->second >= boxes.size())
      throw terrain::Error(fmt::format(
          "tiled flats: a flat crosses into a tile that does not see it (row {}, column {})",
          cell / C, cell % C));
    const std::uint32_t a = find(x), b = find(it->second);
    if (a != b) parent[a] = b;
  }
  for (std::uint32_t x = 0; x < boxes.size(); ++x)
    if (find(x) != x) boxes[find(x)].add(boxes[x]);
  for (std::uint32_t x = 0; x < boxes.size(); ++x) parent[x] = find(x);
  return parent;
}

// Each joined flat resolved in a window of its bounding box (and a halo), shared out among
// the ranks; its no-flow cells written, row run by row run.
void resolve_joined(const TileGrid& tiles, const SurfaceReader& surface,
                    const std::vector<Box>& boxes, const std::vector<std::uint64_t>& seeds,
                    const std::vector<std::uint32_t>& root, ScratchArray<std::uint8_t>& out,
                    const TileComm& comm) {
  const std::size_t C = tiles.cols;
  std::size_t joined = 0;
  for (std::uint32_t x = 0; x < boxes.size(); ++x) {
    if (root[x] != x || !comm.owns(joined++)) continue;
    const terrain::RasterWindow box{boxes[x].r0, boxes[x].c0, boxes[x].r1 - boxes[x].r0 + 1,
                                    boxes[x].c1 - boxes[x].c0 + 1};
    const terrain::RasterWindow W = tiles.halo(box);
    const WindowFlats f = window_flats(surface, W, tiles);
    const std::uint64_t seed = seeds[x];
    const std::uint32_t mine = f.comp[(seed / C - W.row0) * W.cols + seed % C - W.col0];
    auto fixed = [&](std::size_t i) { return f.comp[i] == mine && f.raw[i] == kNoFlow; };
    for (std::size_t r = 0; r < W.rows; ++r)
      for (std::size_t c = 0; c < W.cols;) {
        if (!fixed(r * W.cols + c)) {
          ++c;
          continue;
        }
        std::size_t e = c;
        while (e < W.cols && fixed(r * W.cols + e)) ++e;
        out.write_run(std::uint64_t(W.row0 + r) * C + W.col0 + c,
                      f.resolved.data() + r * W.cols + c, e - c);
        c = e;
      }
  }
}

}  // namespace

// Codes with flats resolved, tile by tile, into `out`: a flat inside one tile is resolved
// with its tile (and a halo); a flat that crosses tile edges is joined across tiles and
// resolved in a window of its bounding box. Each flat's directions depend on that flat
// alone, so both equal resolve_flats on the whole grid. With several ranks each rank does
// its own tiles, every rank joins the crossing pieces, and the joined flats are shared out
// among the ranks, which write only the cells of their flats.
void tiled_resolved_codes(const TileGrid& tiles, const SurfaceReader& surface,
                          ScratchArray<std::uint8_t>& out, const TileComm& comm) {
  std::vector<Box> boxes;            // crossing flats, one per (tile, component)
  std::vector<std::uint64_t> seeds;  // a member of each
  std::vector<CellPiece> ring;       // members on their tile's ring
  std::vector<CellPiece> contacts;   // members outside the tile
  const std::size_t C = tiles.cols;
  auto pieces = [&](std::size_t t) { return tile_pieces(tiles, surface, t); };
  tiled::for_each_tile(comm, tiles.count(), pieces, [&](std::size_t t, TilePieces&& p) {
    const auto base = std::uint32_t(boxes.size());  // numbered tile after tile
    boxes.insert(boxes.end(), p.boxes.begin(), p.boxes.end());
    seeds.insert(seeds.end(), p.seeds.begin(), p.seeds.end());
    for (const CellPiece& x : p.ring) ring.push_back({x.cell, x.piece + base});
    for (const CellPiece& x : p.contacts) contacts.push_back({x.cell, x.piece + base});
    out.write(tiles.window(t), p.codes.data());
  });
  if (comm.size() > 1) {  // every rank gets every rank's pieces, numbered rank after rank
    Packer mine;
    mine.put_vector(boxes).put_vector(seeds).put_vector(ring).put_vector(contacts);
    boxes.clear(), seeds.clear(), ring.clear(), contacts.clear();
    for (const std::string& bytes : comm.all_gather(mine.take())) {
      Unpacker in(bytes);
      const auto base = std::uint32_t(boxes.size());
      for (const Box& b : in.get_vector<Box>()) boxes.push_back(b);
      for (const std::uint64_t c : in.get_vector<std::uint64_t>()) seeds.push_back(c);
      for (CellPiece x : in.get_vector<CellPiece>()) ring.push_back({x.cell, x.piece + base});
      for (CellPiece x : in.get_vector<CellPiece>()) contacts.push_back({x.cell, x.piece + base});
      if (seeds.size() != boxes.size())
        throw terrain::Error("tiled flats: a rank sent a wrong message");
    }
  }
  const std::vector<std::uint32_t> root = join_pieces(boxes, ring, contacts, C);
  resolve_joined(tiles, surface, boxes, seeds, root, out, comm);
  comm.barrier();  // every flat written before any rank reads the codes
}

}  // namespace drainage::tiled
