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
#include "tiled_codes.hpp"
#include "tiled_internal.hpp"

namespace drainage {

using namespace tiled;

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

  // A tile's .dv block, encoded on the tile's thread from the tile's own arrays (copies of
  // them were 19 bytes a point more on each thread).
  void encode(NetworkTile& tile) const {
    const std::size_t m = tile.dirs.size();
    terrain::Grid g;
    if (flags_ & kDvHasElevations) {
      g = surface_(tile.window);
      for (float& z : g.z) z = std::isnan(z) ? 0.0f : z;
    } else {
      g.z.assign(m, 0.0f);
    }
    tile.prepared =
        encode_dv_block(DvBlockView{m, g.z.data(), tile.dirs.data(), tile.cut.data(),
                                    tile.accumulated.data(), tile.basin.data(), tile.order.data()});
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
