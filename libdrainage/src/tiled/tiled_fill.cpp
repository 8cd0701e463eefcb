// Priority-Flood filling tile by tile (tiled.hpp; Barnes, Lehman & Mulla 2016).
#include "drainage/tiled.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <queue>
#include <unordered_map>
#include <vector>

#include "drainage/d8.hpp"
#include "drainage/fill.hpp"
#include "spill_edges.hpp"
#include "terrain/error.hpp"
#include "terrain/temp_files.hpp"
#include "tiled_internal.hpp"

namespace drainage {

using namespace tiled;

terrain::RasterWindow TileGrid::window(std::size_t t) const {
  const std::size_t tr = t / tile_cols(), tc = t % tile_cols();
  terrain::RasterWindow w;
  w.row0 = tr * side;
  w.col0 = tc * side;
  w.rows = std::min(side, rows - w.row0);
  w.cols = std::min(side, cols - w.col0);
  return w;
}

terrain::RasterWindow TileGrid::halo(const terrain::RasterWindow& w) const {
  terrain::RasterWindow h = w;
  if (h.row0 > 0) --h.row0, ++h.rows;
  if (h.col0 > 0) --h.col0, ++h.cols;
  h.rows = std::min(h.rows + 1, rows - h.row0);
  h.cols = std::min(h.cols + 1, cols - h.col0);
  return h;
}

namespace {

// One tile, with the halo that tells which of its cells are the grid's own seeds.
struct TileFlood {
  std::size_t nr = 0, nc = 0;
  std::vector<float> z;              // the tile's elevations, flooded from its perimeter
  std::vector<float> original;       // as read
  std::vector<std::uint32_t> label;  // kNone at no-data
  terrain::Georef geo;               // the tile's
};

// Floods tile t: seeds are the grid's seeds (label kOutside) and the tile's perimeter
// cells (label first_label + ring position). `edge(a, b, w)` gets each touching pair of
// labels with the elevation at which they meet.
template <class Edge>
TileFlood flood_tile(const TileGrid& tiles, std::size_t t, const WindowReader& read,
                     std::uint32_t first_label, Edge&& edge) {
  const terrain::RasterWindow w = tiles.window(t);
  const terrain::RasterWindow h = tiles.halo(w);
  const terrain::Grid halo = read(h);
  if (halo.rows != h.rows || halo.cols != h.cols)
    throw terrain::Error("tiled fill: the reader returned a wrong window");
  const std::size_t dr = w.row0 - h.row0, dc = w.col0 - h.col0;

  TileFlood f;
  f.nr = w.rows, f.nc = w.cols;
  f.geo = halo.geo.window(dr, dc);
  const long nr = long(f.nr), nc = long(f.nc);
  f.z.resize(f.nr * f.nc);
  for (std::size_t r = 0; r < f.nr; ++r)
    for (std::size_t c = 0; c < f.nc; ++c) f.z[r * f.nc + c] = halo.at(r + dr, c + dc);
  f.original = f.z;
  f.label.assign(f.z.size(), kNone);

  std::vector<std::uint32_t> seeds;
  const Neighbours around{long(h.rows), long(h.cols)};
  const bool voids =
      std::any_of(halo.z.begin(), halo.z.end(), [](float v) { return std::isnan(v); });
  for (long r = 0; r < nr; ++r)
    for (long c = 0; c < nc; ++c) {
      const std::size_t i = std::size_t(r * nc + c);
      if (std::isnan(f.z[i])) continue;
      const std::size_t gr = w.row0 + std::size_t(r), gc = w.col0 + std::size_t(c);
      bool seed = gr == 0 || gc == 0 || gr + 1 == tiles.rows || gc + 1 == tiles.cols;
      if (!seed && voids)  // an interior cell beside no-data (its neighbours all in the halo)
        around.each(r + long(dr), c + long(dc),
                    [&](std::size_t j, int) { seed = seed || std::isnan(halo.z[j]); });
      if (seed) {
        f.label[i] = kOutside;
      } else if (on_tile_edge(std::size_t(r), std::size_t(c), f.nr, f.nc)) {
        f.label[i] =
            first_label + std::uint32_t(ring_position(std::size_t(r), std::size_t(c), f.nr, f.nc));
      } else {
        continue;
      }
      seeds.push_back(std::uint32_t(i));
    }
  priority_flood(f.z, nr, nc, seeds, [&](std::uint32_t i, std::uint32_t j) {
    if (std::isnan(f.z[j])) return false;
    if (f.label[j] != kNone) {  // taken: where two labels meet, record the elevation
      if (f.label[j] != f.label[i]) edge(f.label[i], f.label[j], std::max(f.z[i], f.z[j]));
      return false;
    }
    f.label[j] = f.label[i];
    return true;
  });
  return f;
}

// Pass 1's tiles on disk for pass 2: each tile's flooded elevations, labels and original
// elevations (those only where the flood raised a cell; else they are the flooded ones),
// appended in the order put, found by offset. No file when the path is empty.
class TileCache {
 public:
  explicit TileCache(const std::string& path) : path_(path) {
    if (path.empty()) return;
    registration_ = terrain::TempRegistration(path);
    file_.open(path, std::ios::in | std::ios::out | std::ios::trunc | std::ios::binary);
    if (!file_) throw terrain::Error("cannot create the temporary file '" + path + "'");
  }
  ~TileCache() {
    if (path_.empty()) return;
    file_.close();
    std::error_code ec;
    std::filesystem::remove(path_, ec);
  }
  explicit operator bool() const { return !path_.empty(); }
  void put(std::size_t t, const TileFlood& f) {
    if (path_.empty()) return;
    Entry& e = entries_[t];
    e.offset = end_, e.nr = f.nr, e.nc = f.nc, e.geo = f.geo;
    std::vector<std::uint32_t> raised;  // cells the flood raised, with their elevation as read
    std::vector<float> before;
    for (std::size_t i = 0; i < f.z.size(); ++i)
      if (f.z[i] != f.original[i] && !std::isnan(f.z[i]))
        raised.push_back(std::uint32_t(i)), before.push_back(f.original[i]);
    e.raised = raised.size();
    write(f.z.data(), f.z.size() * sizeof(float));
    write(f.label.data(), f.label.size() * sizeof(std::uint32_t));
    write(raised.data(), raised.size() * sizeof(std::uint32_t));
    write(before.data(), before.size() * sizeof(float));
  }
  TileFlood get(std::size_t t) {
    const Entry& e = entries_.at(t);
    TileFlood f;
    f.nr = e.nr, f.nc = e.nc, f.geo = e.geo;
    const std::size_t n = e.nr * e.nc;
    f.z.resize(n), f.label.resize(n);
    std::vector<std::uint32_t> raised(e.raised);
    std::vector<float> before(e.raised);
    file_.seekg(std::streamoff(e.offset));
    read(f.z.data(), n * sizeof(float));
    read(f.label.data(), n * sizeof(std::uint32_t));
    read(raised.data(), raised.size() * sizeof(std::uint32_t));
    read(before.data(), before.size() * sizeof(float));
    f.original = f.z;
    for (std::size_t k = 0; k < raised.size(); ++k) f.original[raised[k]] = before[k];
    return f;
  }

 private:
  struct Entry {
    std::uint64_t offset = 0;
    std::size_t nr = 0, nc = 0, raised = 0;
    terrain::Georef geo;
  };
  void write(const void* p, std::size_t n) {
    file_.write(static_cast<const char*>(p), std::streamsize(n));
    if (!file_)
      throw terrain::Error("cannot write the temporary file '" + path_ + "' (disk full?)");
    end_ += n;
  }
  void read(void* p, std::size_t n) {
    file_.read(static_cast<char*>(p), std::streamsize(n));
    if (!file_) throw terrain::Error("cannot read the temporary file '" + path_ + "'");
  }
  std::string path_;
  terrain::TempRegistration registration_;
  std::fstream file_;
  std::unordered_map<std::size_t, Entry> entries_;
  std::uint64_t end_ = 0;
};

// A tile's perimeter: each ring position's label and elevation as read.
struct Ring {
  std::vector<std::uint32_t> label;
  std::vector<float> z;
};

Ring perimeter(const TileFlood& f) {
  Ring ring;
  ring.label.assign(ring_size(f.nr, f.nc), kNone);
  ring.z.assign(ring.label.size(), NAN);
  for (std::size_t r = 0; r < f.nr; ++r)
    for (std::size_t c = 0; c < f.nc; ++c)
      if (on_tile_edge(r, c, f.nr, f.nc)) {
        const std::size_t p = ring_position(r, c, f.nr, f.nc);
        ring.label[p] = f.label[r * f.nc + c];
        ring.z[p] = f.original[r * f.nc + c];  // perimeter cells are seeds: never raised
      }
  return ring;
}

// Pass 1: labels and spill elevations inside this rank's tiles (into `edges`, and the
// tiles into `cache`); rank 0 (or the only process) gets every tile's ring and every
// rank's edges.
std::vector<Ring> flood_pass(const TileGrid& tiles, const WindowReader& read, const TileComm& comm,
                             const std::vector<std::uint32_t>& first, TileCache& cache,
                             SpillEdges& edges) {
  const std::size_t nt = tiles.count();
  std::vector<Ring> rings(nt);
  Packer mine;  // this rank's tiles: their rings
  struct Flooded {
    TileFlood f;
    std::vector<SpillEdges::Entry> edges;  // the tile's own, each pair once
  };
  for_each_tile(
      comm, nt,
      [&](std::size_t t) {  // on the tile's thread: the edges into a map of its own
        TileEdges own;
        Flooded x;
        x.f = flood_tile(tiles, t, read, first[t],
                         [&](std::uint32_t a, std::uint32_t b, float z) { own.add(a, b, z); });
        x.edges = own.entries();
        return x;
      },
      [&](std::size_t t, Flooded&& x) {
        for (const SpillEdges::Entry& e : x.edges) edges.add(e);
        cache.put(t, x.f);
        rings[t] = perimeter(x.f);
        if (comm.size() > 1)
          mine.put(std::uint64_t(t)).put_vector(rings[t].label).put_vector(rings[t].z);
      });
  if (comm.size() == 1) return rings;
  mine.put(~std::uint64_t(0)).put_vector(edges.entries());
  if (!comm.root()) edges.clear(), std::vector<Ring>(nt).swap(rings);
  for (const std::string& bytes : comm.gather(mine.take())) {
    Unpacker in(bytes);
    for (auto t = in.get<std::uint64_t>(); t != ~std::uint64_t(0); t = in.get<std::uint64_t>()) {
      if (t >= nt) throw terrain::Error("tiled fill: a rank sent a tile out of range");
      rings[t].label = in.get_vector<std::uint32_t>();
      rings[t].z = in.get_vector<float>();
    }
    for (const SpillEdges::Entry& e : in.get_vector<SpillEdges::Entry>()) edges.add(e);
  }
  return rings;
}

// Edges across tile edges: each perimeter cell with its 8 neighbours in other tiles.
void cross_tile_edges(const TileGrid& tiles, const std::vector<Ring>& rings, SpillEdges& edges) {
  const Neighbours grid{long(tiles.rows), long(tiles.cols)};
  for (std::size_t t = 0; t < tiles.count(); ++t) {
    const terrain::RasterWindow w = tiles.window(t);
    const Ring& ring = rings[t];
    for (std::size_t r = 0; r < w.rows; ++r)
      for (std::size_t c = 0; c < w.cols; ++c) {
        if (!on_tile_edge(r, c, w.rows, w.cols)) continue;
        const std::size_t p = ring_position(r, c, w.rows, w.cols);
        if (ring.label[p] == kNone) continue;
        grid.each(long(w.row0 + r), long(w.col0 + c), [&](std::size_t j, int) {
          const std::size_t gr = j / tiles.cols, gc = j % tiles.cols;
          const std::size_t u = gr / tiles.side * tiles.tile_cols() + gc / tiles.side;
          if (u == t) return;
          const terrain::RasterWindow wu = tiles.window(u);
          const Ring& other = rings[u];
          const std::size_t q = ring_position(gr - wu.row0, gc - wu.col0, wu.rows, wu.cols);
          if (other.label[q] == kNone || other.label[q] == ring.label[p]) return;
          edges.add(ring.label[p], other.label[q], std::max(ring.z[p], other.z[q]));
        });
      }
  }
}

// The spill elevation of every label: minimax paths from the outside (Dijkstra with max).
std::vector<float> spill_elevations(std::uint64_t labels, SpillEdges& edges) {
  // The graph in compressed rows: label a's neighbours are adjacent[start[a] .. start[a + 1]).
  std::vector<std::pair<std::uint32_t, float>> adjacent;
  std::vector<std::size_t> start(labels + 1, 0);
  {
    const std::vector<SpillEdges::Entry>& list = edges.entries();
    for (const SpillEdges::Entry& e : list)
      ++start[(e.key >> 32) + 1], ++start[std::uint32_t(e.key) + 1];
    for (std::size_t a = 0; a < labels; ++a) start[a + 1] += start[a];
    adjacent.resize(start[labels]);
    std::vector<std::size_t> at(start.begin(), start.end() - 1);
    for (const SpillEdges::Entry& e : list) {
      const auto a = std::uint32_t(e.key >> 32), b = std::uint32_t(e.key);
      adjacent[at[a]++] = {b, e.z};
      adjacent[at[b]++] = {a, e.z};
    }
  }
  edges.clear();
  std::vector<float> spill(labels, std::numeric_limits<float>::infinity());
  std::vector<std::uint8_t> settled(labels, 0);
  using Entry = std::pair<float, std::uint32_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  spill[kOutside] = -std::numeric_limits<float>::infinity();
  queue.push({spill[kOutside], kOutside});
  while (!queue.empty()) {
    const auto [z, a] = queue.top();
    queue.pop();
    if (settled[a]) continue;
    settled[a] = 1;
    for (std::size_t i = start[a]; i < start[a + 1]; ++i) {
      const auto [b, w] = adjacent[i];
      const float s = std::max(z, w);
      if (s < spill[b]) {
        spill[b] = s;
        queue.push({s, b});
      }
    }
  }
  return spill;
}

// Rank 0 solves the spill graph; each rank gets the spills of its tiles' labels, by ring
// position.
std::vector<std::vector<float>> scatter_spills(const TileGrid& tiles, const TileComm& comm,
                                               const std::vector<std::uint32_t>& first,
                                               std::uint64_t labels, std::vector<Ring>& rings,
                                               SpillEdges& edges) {
  const std::size_t nt = tiles.count();
  std::vector<std::string> per_rank;
  if (comm.root()) {
    cross_tile_edges(tiles, rings, edges);
    std::vector<Ring>().swap(rings);
    const std::vector<float> spill = spill_elevations(labels, edges);
    std::vector<Packer> packs(std::size_t(comm.size()));
    for (std::size_t t = 0; t < nt; ++t) {
      const terrain::RasterWindow w = tiles.window(t);
      const auto s0 = spill.begin() + std::ptrdiff_t(first[t]);
      packs[t % std::size_t(comm.size())]
          .put(std::uint64_t(t))
          .put_vector(std::vector<float>(s0, s0 + std::ptrdiff_t(ring_size(w.rows, w.cols))));
    }
    for (Packer& pk : packs) per_rank.push_back(pk.take());
  }
  std::vector<std::vector<float>> tile_spill(nt);
  const std::string bytes = comm.scatter(std::move(per_rank));
  Unpacker in(bytes);
  while (!in.done()) {
    const auto t = in.get<std::uint64_t>();
    if (t >= nt || !comm.owns(t))
      throw terrain::Error("tiled fill: rank 0 sent a tile out of range");
    tile_spill[t] = in.get_vector<float>();
  }
  return tile_spill;
}

// Pass 2 for one tile: flooded again (or from the cache) and raised to its labels' spill
// elevations; the tile's elevations and how many cells were raised.
std::pair<terrain::Grid, std::size_t> raise_tile(const TileGrid& tiles, std::size_t t,
                                                 const WindowReader& read,
                                                 std::uint32_t first_label,
                                                 const std::vector<float>& spill,
                                                 TileCache& cache) {
  TileFlood f;
  if (cache) {
#pragma omp critical(tiled_fill_cache)
    f = cache.get(t);
  } else {
    f = flood_tile(tiles, t, read, first_label, [](std::uint32_t, std::uint32_t, float) {});
  }
  const terrain::RasterWindow w = tiles.window(t);
  std::pair<terrain::Grid, std::size_t> out{terrain::Grid(w.rows, w.cols, f.geo, NAN), 0};
  for (std::size_t i = 0; i < f.z.size(); ++i) {
    if (f.label[i] == kNone) continue;
    const float s = f.label[i] == kOutside ? -std::numeric_limits<float>::infinity()
                                           : spill.at(f.label[i] - first_label);
    const float z = std::isfinite(s) ? std::max(f.z[i], s) : f.z[i];
    out.second += z > f.original[i];
    out.first.z[i] = z;
  }
  return out;
}

}  // namespace

std::size_t tiled_priority_flood_fill(const TileGrid& tiles, const WindowReader& read,
                                      const std::function<void(std::size_t, terrain::Grid&)>& done,
                                      const TileComm& comm, const std::string& cache_path) {
  if (tiles.side == 0 || tiles.rows == 0 || tiles.cols == 0)
    throw terrain::Error("tiled fill: empty grid or tile size 0");
  const std::size_t nt = tiles.count();
  // Labels: 0 = outside, then each tile's ring positions.
  std::vector<std::uint32_t> first(nt);
  std::uint64_t labels = 1;
  for (std::size_t t = 0; t < nt; ++t) {
    const terrain::RasterWindow w = tiles.window(t);
    first[t] = std::uint32_t(labels);
    labels += ring_size(w.rows, w.cols);
    if (labels >= kNone)
      throw terrain::Error("tiled fill: too many tiles (use a larger tile size)");
  }
  SpillEdges edges;
  TileCache cache(cache_path);
  std::vector<Ring> rings = flood_pass(tiles, read, comm, first, cache, edges);
  const std::vector<std::vector<float>> tile_spill =
      scatter_spills(tiles, comm, first, labels, rings, edges);
  std::size_t raised = 0;
  using Filled = std::pair<terrain::Grid, std::size_t>;  // a tile's elevations, how many raised
  for_each_tile(
      comm, nt,
      [&](std::size_t t) { return raise_tile(tiles, t, read, first[t], tile_spill[t], cache); },
      [&](std::size_t t, Filled&& out) {
        raised += out.second;
        done(t, out.first);
      });
  return sum_over_ranks(comm, raised);
}

}  // namespace drainage
