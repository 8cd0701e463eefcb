// build-drainage's raster mode tile by tile (tiled.hpp): GDAL windows in, .dv blocks out.
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <unordered_map>

#include <fmt/format.h>

#include "drainage/d8.hpp"
#include "drainage/dv_file.hpp"
#include "drainage/flats.hpp"
#include "drainage/tiled_pipeline.hpp"
#include "terrain/atomic_file.hpp"
#include "terrain/dem_io.hpp"
#include "terrain/temp_files.hpp"
#include "tiled_internal.hpp"

namespace drainage {

namespace {

// A temporary raw array of rows x cols values of T (row-major) in the run's private scratch
// folder, written and read by windows and runs with pwrite / pread, so that several
// processes (the ranks of an MPI job, on a file system they share) write disjoint parts of
// it at once. Rank 0 creates it (O_EXCL: never an existing file) and removes it; the other
// ranks open it after a barrier.
template <class T>
class ScratchArray {
 public:
  ScratchArray(std::string path, std::size_t rows, std::size_t cols, const TileComm& comm)
      : path_(std::move(path)), cols_(cols), root_(comm.root()) {
    if (root_) {
      fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
      if (fd_ < 0 || ::ftruncate(fd_, off_t(rows * cols * sizeof(T))) != 0)
        fail("cannot create the temporary raster");
    }
    comm.barrier();
    if (!root_ && (fd_ = ::open(path_.c_str(), O_RDWR | O_CLOEXEC)) < 0)
      fail("cannot open the temporary raster");
  }
  ~ScratchArray() {
    if (fd_ >= 0) ::close(fd_);
    if (root_) ::unlink(path_.c_str());
  }
  ScratchArray(const ScratchArray&) = delete;
  ScratchArray& operator=(const ScratchArray&) = delete;

  void write(const terrain::RasterWindow& w, const T* values) {
    for (std::size_t r = 0; r < w.rows; ++r)
      write_run(std::uint64_t(w.row0 + r) * cols_ + w.col0, values + r * w.cols, w.cols);
  }
  void write_run(std::uint64_t cell, const T* values, std::size_t n) {
    if (::pwrite(fd_, values, n * sizeof(T), off_t(cell * sizeof(T))) != ssize_t(n * sizeof(T)))
      fail("cannot write the temporary raster (disk full?)");
  }
  void read(const terrain::RasterWindow& w, T* values) const {
    for (std::size_t r = 0; r < w.rows; ++r) {
      const std::size_t n = w.cols * sizeof(T);
      if (::pread(fd_, values + r * w.cols, n,
                  off_t((std::uint64_t(w.row0 + r) * cols_ + w.col0) * sizeof(T))) != ssize_t(n))
        fail("cannot read the temporary raster");
    }
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw terrain::Error(what + " '" + path_ + "': " + std::strerror(errno));
  }
  std::string path_;
  std::size_t cols_ = 0;
  bool root_ = false;
  int fd_ = -1;
};

using SurfaceReader = std::function<terrain::Grid(const terrain::RasterWindow&)>;

// D8 codes of window w, from the surface of w with one more sample around it (read once;
// `z`, when given, receives the surface of w itself).
D8Codes window_codes(const SurfaceReader& surface, const terrain::RasterWindow& w,
                     const TileGrid& tiles, terrain::Grid* z = nullptr) {
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

}  // namespace

double tiled_run_bytes(const terrain::DemInfo& info, std::size_t side, int threads) {
  const double cells = double(info.rows) * double(info.cols), s = double(side);
  const double edge_cells = 4.0 * cells / s;  // every tile's perimeter ring, about
  // The tiles in flight and the perimeter graphs peak in different steps (the graphs are
  // solved between the passes over the tiles).
  return double(64 << 20) +
         std::max(100.0 * double(std::max(1, threads)) * s * s, 300.0 * edge_cells);
}

std::size_t tile_size_for_memory(const terrain::DemInfo& info, double bytes, int threads) {
  if (double(info.rows) * double(info.cols) * 40.0 <= bytes) return 0;
  // The largest side that fits; if none does, the side that needs least.
  std::size_t best = 256;
  for (std::size_t side = 256; side <= 16384; side += 256) {
    if (tiled_run_bytes(info, side, threads) <= bytes)
      best = side;
    else if (tiled_run_bytes(info, best, threads) > bytes &&
             tiled_run_bytes(info, side, threads) < tiled_run_bytes(info, best, threads))
      best = side;
  }
  return best;
}

namespace {

// One tiled run's steps over its shared state: the surface (filled or as read), the D8
// codes (flats resolved or not, or a D8 raster's), then the network into the .dv.
class TiledDrainage {
 public:
  TiledDrainage(const TiledRun& run, const std::string& output_path,
                const terrain::Progress& progress, const TileComm& comm)
      : run_(run),
        output_path_(output_path),
        progress_(progress),
        comm_(comm),
        input_(run.dem.empty() ? run.d8 : run.dem),
        info_(terrain::read_dem_info(input_)),
        tiles_{info_.rows, info_.cols, run.tile} {
    summary_.rows = info_.rows, summary_.cols = info_.cols, summary_.dx = info_.geo.dx,
    summary_.dy = info_.geo.dy;
    summary_.tiles = tiles_.count();
    surface_ = [path = run.dem](const terrain::RasterWindow& w) {
      return terrain::read_dem(path, {}, w);
    };
    // Scratch rasters and rank files live in a folder private to this run (mkdtemp beside
    // the output, on the file system the ranks share): two runs on one output never share
    // a scratch file, and no scratch name can be an input's. Rank 0 makes it and tells the
    // others its name; it is removed at the end, on an error and on SIGINT/SIGTERM.
    if (comm.root()) scratch_dir_ = std::make_unique<terrain::ScratchDir>(output_path);
    scratch_ =
        comm.all_gather(comm.root() ? scratch_dir_->path().string() : std::string())[0] + "/";
    step("set-up");
  }

  TiledSummary run() {
    if (!run_.dem.empty() && run_.fill) fill();
    choose_codes();
    // This rank's blocks file (several ranks), kept until rank 0 has copied it.
    struct RemoveAtEnd {
      std::string path;
      terrain::TempRegistration on_signal{path};
      ~RemoveAtEnd() { ::unlink(path.c_str()); }
    } remove_rank_blocks{comm_.size() > 1 ? blocks_path(comm_.rank()) : std::string()};
    if (comm_.root()) {
      terrain::write_stream_atomic(run_.write_to.empty() ? output_path_ : run_.write_to,
                                   [&](std::ostream& file) {
                                     DvBlockWriter writer(file, output_path_, header());
                                     network(&writer);
                                     step("network (2 passes) and .dv blocks");
                                     const NetworkTotals& n = summary_.totals;
                                     writer.finish(n.points, n.branches, n.pits, n.pit_accumulated);
                                   });
    } else {
      network(nullptr);
    }
    comm_.barrier();  // rank 0 has read every rank's blocks
    return summary_;
  }

 private:
  void step(const char* name) {
    const auto t1 = std::chrono::steady_clock::now();
    summary_.timings.emplace_back(name, std::chrono::duration<double>(t1 - t0_).count());
    t0_ = t1;
  }

  // Priority-Flood over the tiles into a scratch raster, which becomes the surface.
  void fill() {
    filled_ = std::make_unique<ScratchArray<float>>(scratch_ + "filled.f32", info_.rows, info_.cols,
                                                    comm_);
    summary_.filled = tiled_priority_flood_fill(
        tiles_, surface_,
        [&](std::size_t t, terrain::Grid& g) {
          filled_->write(tiles_.window(t), g.z.data());
          terrain::report(progress_, 0.3 * double(t + 1) / double(tiles_.count()));
        },
        comm_, fmt::format("{}rank{}.fill", scratch_, comm_.rank()));
    comm_.barrier();  // every tile filled before any rank reads the surface
    step("fill (2 passes)");
    surface_ = [this](const terrain::RasterWindow& w) {
      terrain::Grid g(w.rows, w.cols, info_.geo.window(w.row0, w.col0));  // as read_dem gives it
      filled_->read(w, g.z.data());
      return g;
    };
    flags_ |= kDvFilled;
  }

  // The D8 codes' reader: flats resolved into a scratch raster, D8 of the surface, or a D8
  // raster's codes.
  void choose_codes() {
    if (!run_.dem.empty() && run_.resolve_flats) {
      flags_ |= kDvHasElevations | kDvFlatsResolved;
      resolved_ = std::make_unique<ScratchArray<std::uint8_t>>(scratch_ + "d8.u8", info_.rows,
                                                               info_.cols, comm_);
      tiled_resolved_codes(tiles_, surface_, *resolved_, comm_);
      step("flats (D8, flats resolved)");
      codes_ = [this](const terrain::RasterWindow& w) {
        D8Codes out(w.rows * w.cols);
        resolved_->read(w, out.data());
        return out;
      };
    } else if (!run_.dem.empty()) {
      flags_ |= kDvHasElevations;
      codes_ = [this](const terrain::RasterWindow& w) { return window_codes(surface_, w, tiles_); };
    } else {
      codes_ = [this](const terrain::RasterWindow& w) { return foreign_codes(w); };
    }
  }

  D8Codes foreign_codes(const terrain::RasterWindow& w) const {
    const terrain::Grid g = terrain::read_dem(run_.d8, {}, w);
    D8Codes out(g.size());
    for (std::size_t i = 0; i < g.size(); ++i) {
      try {
        out[i] = from_foreign_code(g.z[i], run_.encoding, std::isnan(g.z[i]));
      } catch (const terrain::Error& e) {
        throw terrain::Error(fmt::format("'{}' row {}, column {}: {}", run_.d8, w.row0 + i / g.cols,
                                         w.col0 + i % g.cols, e.what()));
      }
    }
    return out;
  }

  DvHeader header() const {
    DvHeader h;
    h.flags = flags_;
    h.rows = info_.rows, h.cols = info_.cols;
    h.origin_x = info_.geo.x_of_col(0), h.origin_y = info_.geo.y_of_row(0);
    h.dx = info_.geo.dx, h.dy = info_.geo.dy;
    h.epsg = info_.geo.epsg;
    h.crs_wkt = info_.geo.crs_wkt;
    h.provenance = run_.provenance;
    h.block_rows = h.block_cols = std::uint32_t(run_.tile);  // one block per tile
    return h;
  }

  // A tile's .dv block, encoded on the tile's thread.
  void encode(NetworkTile& tile) const {
    const std::size_t m = tile.dirs.size();
    DvBlockFields f;
    f.z.resize(m);
    if (flags_ & kDvHasElevations) {
      const terrain::Grid g = surface_(tile.window);
      for (std::size_t q = 0; q < m; ++q) f.z[q] = std::isnan(g.z[q]) ? 0.0f : g.z[q];
    }
    f.d8.assign(tile.dirs.begin(), tile.dirs.end());
    f.cut.assign(tile.cut.begin(), tile.cut.end());
    f.accumulated.assign(tile.accumulated.begin(), tile.accumulated.end());
    f.basin.assign(tile.basin.begin(), tile.basin.end());
    f.order.assign(tile.order.begin(), tile.order.end());
    tile.prepared = encode_dv_block(f);
  }

  struct BlockRef {
    std::uint64_t tile, offset, bytes;
  };
  std::string blocks_path(int rank) const { return fmt::format("{}rank{}.blocks", scratch_, rank); }

  // The network over the tiles. One process writes its blocks as they come. Several ranks
  // leave theirs in per-rank temporary files; rank 0 gathers their indexes and copies the
  // blocks into the .dv in tile order (so the file is the same byte for byte whatever the
  // number of ranks).
  void network(DvBlockWriter* writer) {
    std::ofstream blocks;
    std::vector<BlockRef> index;
    if (comm_.size() > 1) {
      blocks.open(blocks_path(comm_.rank()),
                  std::ios::binary | std::ios::trunc);  // a fresh folder: a new file
      if (!blocks)
        throw terrain::Error("cannot create the temporary file '" + blocks_path(comm_.rank()) +
                             "'");
    }
    summary_.totals = tiled_network(
        tiles_, codes_,
        [&](std::size_t t, const NetworkTile& tile) {
          const std::vector<char>& block = tile.prepared;
          if (comm_.size() == 1) {
            writer->put_block(t, block);
          } else {
            index.push_back({t, std::uint64_t(blocks.tellp()), block.size()});
            blocks.write(block.data(), std::streamsize(block.size()));
          }
          terrain::report(progress_, 0.3 + 0.7 * double(t + 1) / double(tiles_.count()));
        },
        comm_, [this](std::size_t, NetworkTile& tile) { encode(tile); });
    if (summary_.totals.points == 0)  // thrown inside the write: no output is left
      throw terrain::Error("'" + input_ + "' has no valid sample (every cell is no-data)");
    if (comm_.size() == 1) return;
    if (!blocks.flush())
      throw terrain::Error("cannot write the temporary file '" + blocks_path(comm_.rank()) +
                           "' (disk full?)");
    blocks.close();
    const std::vector<std::string> indexes = comm_.all_gather(Packer().put_vector(index).take());
    if (writer) copy_rank_blocks(indexes, *writer);
  }

  // Rank 0: every rank's blocks, in tile order, into the .dv.
  void copy_rank_blocks(const std::vector<std::string>& indexes, DvBlockWriter& writer) const {
    std::vector<std::pair<int, BlockRef>> where(tiles_.count(), {-1, {}});
    for (int r = 0; r < comm_.size(); ++r)
      for (const BlockRef& b : Unpacker(indexes[std::size_t(r)]).get_vector<BlockRef>())
        if (b.tile < tiles_.count()) where[b.tile] = {r, b};
    std::vector<std::ifstream> files(std::size_t(comm_.size()));
    for (std::size_t t = 0; t < tiles_.count(); ++t) {
      const auto& [r, b] = where[t];
      if (r < 0) throw terrain::Error("tiled run: no rank wrote tile " + std::to_string(t));
      std::ifstream& in = files[std::size_t(r)];
      if (!in.is_open()) in.open(blocks_path(r), std::ios::binary);
      std::vector<char> block(b.bytes);
      if (!in.seekg(std::streamoff(b.offset)) || !in.read(block.data(), std::streamsize(b.bytes)))
        throw terrain::Error("cannot read rank " + std::to_string(r) + "'s blocks in '" +
                             blocks_path(r) + "'");
      writer.put_block(t, block);
    }
  }

  const TiledRun& run_;
  const std::string& output_path_;
  const terrain::Progress& progress_;
  const TileComm& comm_;
  const std::string input_;
  const terrain::DemInfo info_;
  const TileGrid tiles_;
  // GDAL's block cache would grow with the windows read; a tiled run keeps its memory to
  // the tiles.
  const terrain::GdalCacheLimit cache_limit_{64};
  TiledSummary summary_;
  std::chrono::steady_clock::time_point t0_ = std::chrono::steady_clock::now();
  std::unique_ptr<terrain::ScratchDir> scratch_dir_;
  std::string scratch_;
  std::uint32_t flags_ = 0;
  std::function<terrain::Grid(const terrain::RasterWindow&)> surface_;
  CodeReader codes_;
  std::unique_ptr<ScratchArray<float>> filled_;
  std::unique_ptr<ScratchArray<std::uint8_t>> resolved_;
};

}  // namespace

TiledSummary run_tiled_drainage(const TiledRun& run, const std::string& output_path,
                                const terrain::Progress& progress, const TileComm& comm) {
  if (run.tile == 0 || run.tile > 16384)
    throw terrain::Error("--tile-size must be between 1 and 16384");
  if (run.dem.empty() == run.d8.empty())
    throw terrain::Error("tiled mode takes a DEM or a D8 raster (not both yet)");
  return TiledDrainage(run, output_path, progress, comm).run();
}

}  // namespace drainage
