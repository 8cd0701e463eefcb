// The mesh pyramid read: its header checked, tiles decoded, windows and levels read.
#include "terrain/mesh_pyramid.hpp"

#include <fmt/format.h>
#include <zlib.h>
#include <zstd.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <memory>
#include <utility>

#include "mesh_pyramid_format.hpp"
#include "terrain/atomic_file.hpp"
#include "terrain/error.hpp"
#include "terrain/pn_triangle.hpp"
#include "terrain/temp_files.hpp"

namespace terrain {

using namespace detail;

bool is_mesh_pyramid(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return false;
  std::ifstream f(path, std::ios::binary);
  char m[8] = {};
  return f.read(m, 8) && std::memcmp(m, kMagic, 8) == 0;
}

void pyramid_fix_checksums(std::string& bytes) {
  const auto get = [&](std::size_t at, auto v) {
    if (at + sizeof v <= bytes.size()) std::memcpy(&v, bytes.data() + at, sizeof v);
    return v;
  };
  std::uint32_t version = get(8, std::uint32_t(0));
  const std::uint64_t header = get(12, std::uint64_t(0));
  if (bytes.size() < 20 || version < 3 || version > 4 || header < 24 || header > bytes.size())
    return;
  const std::uint64_t B = get(20, std::uint32_t(0)), rows = get(24, std::uint64_t(0)),
                      cols = get(32, std::uint64_t(0));
  if (B < 2 || rows < 2 || cols < 2 || rows > (1u << 30) || cols > (1u << 30)) return;
  std::uint64_t at = 84;  // after magic, version, size, B, grid, georeference, EPSG
  at += 4 + std::uint64_t(get(at, std::uint32_t(0))) + 8;  // the CRS, the digest
  if (version >= 4) at += 4;                               // the flags
  const std::uint32_t n_levels = get(at, std::uint32_t(0));
  at += 4;
  const std::uint64_t n_blocks = ((rows - 1 + B - 1) / B) * ((cols - 1 + B - 1) / B);
  for (std::uint64_t k = 0; k < n_blocks && at < header; ++k)
    at += 28 + 8 * std::uint64_t(get(at + 24, std::uint32_t(0)));
  for (std::uint32_t l = 0; l < n_levels && at + 16 <= header - 4; ++l) {
    const std::uint64_t tiles = get(at, std::uint64_t(0)) * get(at + 8, std::uint64_t(0));
    at += 16;
    for (std::uint64_t t = 0; t < tiles && at + 16 <= header - 4; ++t, at += 16) {
      const std::uint64_t offset = get(at, std::uint64_t(0));
      const std::uint32_t n = get(at + 8, std::uint32_t(0));
      if (offset <= bytes.size() && n <= bytes.size() - offset) {
        const std::uint32_t crc = crc_of(bytes.substr(std::size_t(offset), n));
        std::memcpy(bytes.data() + at + 12, &crc, 4);
      }
    }
  }
  const std::uint32_t crc = crc_of(bytes.substr(0, std::size_t(header - 4)));
  std::memcpy(bytes.data() + header - 4, &crc, 4);
}

std::string pyramid_path_of(const std::string& mesh_path) {
  return (mesh_path.ends_with(".ply") ? mesh_path.substr(0, mesh_path.size() - 4) : mesh_path) +
         ".tpyr";
}

MeshPyramid::MeshPyramid(const std::string& path) : path_(path) {
  fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd_ < 0) throw Error("cannot open '" + path + "': " + std::strerror(errno));
  struct stat st {};
  if (::fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd_);
    throw Error("cannot read '" + path + "': not a regular file");
  }
  const auto size = std::uint64_t(st.st_size);
  try {
    read_header(size);
  } catch (...) {
    ::close(fd_);
    throw;
  }
}

MeshPyramid::~MeshPyramid() {
  if (fd_ >= 0) ::close(fd_);
}

void MeshPyramid::read_at(void* to, std::size_t n, std::uint64_t offset) const {
  auto* at = static_cast<char*>(to);
  while (n > 0) {
    const ssize_t got = ::pread(fd_, at, n, off_t(offset));
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) throw Error("cannot read '" + path_ + "': truncated mesh pyramid");
    at += got, n -= std::size_t(got), offset += std::uint64_t(got);
  }
}

namespace {

Error corrupt_pyramid(const std::string& path, const char* what) {
  return Error(fmt::format("cannot read '{}': corrupt mesh pyramid ({})", path, what));
}
Error truncated_pyramid(const std::string& path) {
  return Error("cannot read '" + path + "': truncated mesh pyramid");
}

// One block's box, levels, errors and (version 2 on) slopes, checked; its place and size
// set before.
void read_block(In& in, MeshLevelBlock& b, std::uint32_t n_levels, int version) {
  for (int j = 0; j < 3; ++j) b.lo[j] = in.get<float>();
  for (int j = 0; j < 3; ++j) b.hi[j] = in.get<float>();
  if (!b.lo.allFinite() || !b.hi.allFinite() || (b.lo.array() > b.hi.array()).any())
    throw corrupt_pyramid(in.path, "a block's box");
  const std::uint32_t nl = in.get<std::uint32_t>();
  if (nl < 1 || nl > n_levels || int(nl) != block_levels(b.nr, b.nc))
    throw corrupt_pyramid(in.path, "a block's levels");
  if (std::uint64_t(nl) * (version >= 2 ? 8 : 4) > in.bytes.size() - in.at)
    throw truncated_pyramid(in.path);
  b.error.resize(nl);
  for (float& e : b.error) e = in.get<float>();
  // Errors: 0 at level 0, finite and non-decreasing; slopes >= 0 (infinite where a
  // surface turns over).
  for (std::size_t j = 0; j < nl; ++j)
    if (!std::isfinite(b.error[j]) || (j == 0 ? b.error[j] != 0 : !(b.error[j] >= b.error[j - 1])))
      throw corrupt_pyramid(in.path, "a block's errors");
  if (version >= 2) {  // version 1: not known
    b.slope.resize(nl);
    for (float& e : b.slope) e = in.get<float>();
    for (const float e : b.slope)
      if (!(e >= 0)) throw corrupt_pyramid(in.path, "a block's slopes");
  }
}

}  // namespace

void MeshPyramid::read_header(std::uint64_t size) {
  const std::string& path = path_;
  // The magic, the version and the header's size, then the header and index whole.
  std::string bytes(20, '\0');
  if (size < 20) throw Error("'" + path + "' is not a mesh pyramid (.tpyr)");
  read_at(bytes.data(), 20, 0);
  if (std::memcmp(bytes.data(), kMagic, 8) != 0)
    throw Error("'" + path + "' is not a mesh pyramid (.tpyr)");
  In in{bytes, path_, 8};
  const std::uint32_t version = in.get<std::uint32_t>();
  if (version > kVersion)
    throw Error(
        fmt::format("cannot read '{}': mesh pyramid version {} is newer than this tool's ({})",
                    path, version, kVersion));
  if (version < 1)
    throw Error(fmt::format("cannot read '{}': corrupt mesh pyramid (version {})", path, version));
  version_ = int(version);
  const std::uint64_t header_bytes = in.get<std::uint64_t>();
  if (header_bytes < 20 || header_bytes > size) throw truncated_pyramid(path);
  bytes.resize(std::size_t(header_bytes));
  read_at(bytes.data() + 20, std::size_t(header_bytes - 20), 20);
  if (version >= 3) {  // the CRC-32 of the header before it, in its last 4 bytes
    if (header_bytes < 24) throw corrupt_pyramid(path, "its header");
    std::uint32_t crc = 0;
    std::memcpy(&crc, bytes.data() + header_bytes - 4, 4);
    if (crc_of(bytes.substr(0, std::size_t(header_bytes - 4))) != crc)
      throw corrupt_pyramid(path, "its header's checksum");
    bytes.resize(std::size_t(header_bytes - 4));
  }
  std::size_t at = in.at;
  const std::uint32_t n_levels = read_grid(bytes, at);
  read_blocks(bytes, at, n_levels);
  read_tile_index(bytes, at, n_levels, header_bytes, size);
  bytes_read_ = header_bytes;
}

std::uint32_t MeshPyramid::read_grid(const std::string& bytes, std::size_t& at) {
  In in{bytes, path_, at};
  const std::size_t B = in.get<std::uint32_t>();
  const std::uint64_t rows = in.get<std::uint64_t>(), cols = in.get<std::uint64_t>();
  if (B < 2 || B > (1u << 16) || rows < 2 || cols < 2 || rows > (1u << 30) || cols > (1u << 30) ||
      rows * cols >= (std::uint64_t(1) << 32))
    throw corrupt_pyramid(path_, "its grid");
  geo_.origin_x = in.get<double>(), geo_.origin_y = in.get<double>(),
  geo_.origin_z = in.get<double>();
  geo_.dx = in.get<double>(), geo_.dy = in.get<double>();
  geo_.epsg = in.get<std::int32_t>();
  if (!georef_in_range(GridTopology{std::size_t(rows), std::size_t(cols)}, geo_) || geo_.epsg < 0)
    throw corrupt_pyramid(path_, "its georeference");
  const std::size_t wkt = in.get<std::uint32_t>();
  if (wkt > bytes.size() - in.at) throw truncated_pyramid(path_);
  geo_.crs_wkt = bytes.substr(in.at, wkt);
  in.at += wkt;
  if (version_ >= 3) digest_ = in.get<std::uint64_t>();
  if (version_ >= 4) {
    const std::uint32_t flags = in.get<std::uint32_t>();
    if (flags & ~kTileSources) throw corrupt_pyramid(path_, "its flags");
    sources_ = flags & kTileSources;
  }
  const std::uint32_t n_levels = in.get<std::uint32_t>();
  if (n_levels < 1 || n_levels > 32) throw corrupt_pyramid(path_, "its levels");
  levels_.topo = GridTopology{std::size_t(rows), std::size_t(cols)};
  levels_.block = B;
  levels_.block_rows = (std::size_t(rows) - 1 + B - 1) / B;
  levels_.block_cols = (std::size_t(cols) - 1 + B - 1) / B;
  at = in.at;
  return n_levels;
}

void MeshPyramid::read_blocks(const std::string& bytes, std::size_t& at, std::uint32_t n_levels) {
  In in{bytes, path_, at};
  const std::size_t B = levels_.block, rows = levels_.topo.rows, cols = levels_.topo.cols;
  // Every count against the bytes left before anything is allocated: a block takes at
  // least 28 + 4 (version 1) or 28 + 8 bytes, a level's index 16 and a tile 16.
  const std::uint64_t n_blocks = std::uint64_t(levels_.block_rows) * levels_.block_cols;
  if (n_blocks > (bytes.size() - in.at) / 32) throw truncated_pyramid(path_);
  levels_.blocks.resize(std::size_t(n_blocks));
  for (std::size_t k = 0; k < levels_.blocks.size(); ++k) {
    MeshLevelBlock& b = levels_.blocks[k];
    b.r0 = std::uint32_t(k / levels_.block_cols * B),
    b.c0 = std::uint32_t(k % levels_.block_cols * B);
    b.nr = std::uint32_t(std::min<std::uint64_t>(B, rows - 1 - b.r0));
    b.nc = std::uint32_t(std::min<std::uint64_t>(B, cols - 1 - b.c0));
    read_block(in, b, n_levels, version_);
  }
  int coarsest = 1;
  for (const MeshLevelBlock& b : levels_.blocks) coarsest = std::max(coarsest, b.levels());
  if (int(n_levels) != coarsest) throw corrupt_pyramid(path_, "its levels");
  at = in.at;
}

void MeshPyramid::read_tile_index(const std::string& bytes, std::size_t& at, std::uint32_t n_levels,
                                  std::uint64_t header_bytes, std::uint64_t size) {
  In in{bytes, path_, at};
  const std::size_t B = levels_.block;
  tiles_.assign(n_levels, {});
  std::uint64_t end = header_bytes;  // the tiles follow the header, one after another
  for (std::uint32_t l = 0; l < n_levels; ++l) {
    LevelTiles& t = tiles_[l];
    t.tiles_r = in.get<std::uint64_t>(), t.tiles_c = in.get<std::uint64_t>();
    if (t.tiles_r != (this->rows(int(l)) - 1 + B - 1) / B ||
        t.tiles_c != (this->cols(int(l)) - 1 + B - 1) / B)
      throw corrupt_pyramid(path_, "its tile counts");
    if (t.tiles_r * t.tiles_c > (bytes.size() - in.at) / 16) throw truncated_pyramid(path_);
    t.tiles.resize(t.tiles_r * t.tiles_c);
    for (Tile& tile : t.tiles) {
      tile.offset = in.get<std::uint64_t>(), tile.bytes = in.get<std::uint32_t>(),
      tile.crc = in.get<std::uint32_t>();
      if (tile.offset > size || tile.bytes > size - tile.offset) throw truncated_pyramid(path_);
      if (version_ >= 3 && tile.offset != end) throw corrupt_pyramid(path_, "its tile index");
      end = tile.offset + tile.bytes;
    }
  }
  if (in.at != bytes.size()) throw corrupt_pyramid(path_, "its header's size");
  if (version_ >= 3 && end != size)
    throw Error("cannot read '" + path_ + "': truncated mesh pyramid, or bytes after its tiles");
  at = in.at;
}

std::uint32_t MeshPyramid::tile_bytes(int l, std::size_t tr, std::size_t tc) const {
  const LevelTiles& t = tiles_.at(std::size_t(l));
  return t.tiles.at(tr * t.tiles_c + tc).bytes;
}

MeshPyramid::TileData MeshPyramid::decode_tile(int l, std::size_t tr, std::size_t tc,
                                               ZSTD_DCtx* ctx, std::uint64_t& bytes) const {
  const LevelTiles& lt = tiles_[std::size_t(l)];
  const Tile& tile = lt.tiles[tr * lt.tiles_c + tc];
  const TileRange t = tile_range(rows(l), cols(l), levels_.block, tr, tc);
  const auto bad = [&](const char* why) {
    return Error(fmt::format("cannot read '{}': tile {}, {} of level {} is corrupt ({})", path_, tr,
                             tc, l, why));
  };
  std::string z(tile.bytes, '\0');
  read_at(z.data(), z.size(), tile.offset);
  if (crc_of(z) != tile.crc) throw bad("its checksum");
  // Positions, then normals, then (with sources) one byte a vertex.
  const std::size_t m = t.nr * t.nc, vec = sizeof(Eigen::Vector3f);
  std::string plain(2 * m * vec + (sources_ ? m : 0) + 1, '\0');  // + 1: a longer tile shows
  const std::size_t got = ZSTD_decompressDCtx(ctx, plain.data(), plain.size(), z.data(), z.size());
  if (ZSTD_isError(got) || got != plain.size() - 1) throw bad("its data");
  TileData d;
  d.raw.resize(2 * m);
  std::memcpy(static_cast<void*>(d.raw.data()), plain.data(), 2 * m * vec);
  if (sources_) {
    d.sources.assign(plain.begin() + long(2 * m * vec), plain.begin() + long(2 * m * vec + m));
    for (std::uint8_t k : d.sources)
      if (k > kVoidFilled) throw bad("a vertex's source");
  }
  const std::vector<Eigen::Vector3f>& raw = d.raw;
  // Its vertices within its blocks' boxes: at level 0 a tile is one block, and its box is
  // that of these very vertices; a coarser level's vertices are some of the fine ones.
  const std::size_t s = std::size_t(1) << l;
  const std::size_t br0 = tr * s, bc0 = tc * s;
  const std::size_t br1 = std::min(levels_.block_rows, br0 + s),
                    bc1 = std::min(levels_.block_cols, bc0 + s);
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::infinity()), hi = -lo;
  for (std::size_t br = br0; br < br1; ++br)
    for (std::size_t bc = bc0; bc < bc1; ++bc) {
      const MeshLevelBlock& b = levels_.blocks[br * levels_.block_cols + bc];
      lo = lo.cwiseMin(b.lo), hi = hi.cwiseMax(b.hi);
    }
  Eigen::Vector3f tlo = raw[0], thi = raw[0];  // a tile holds at least 2 x 2 vertices
  for (std::size_t i = 1; i < t.nr * t.nc; ++i)
    tlo = tlo.cwiseMin(raw[i]), thi = thi.cwiseMax(raw[i]);
  const bool exact = l == 0;
  if (!tlo.allFinite() || !thi.allFinite() ||
      (exact ? (tlo != lo || thi != hi)
             : ((tlo.array() < lo.array()).any() || (thi.array() > hi.array()).any())))
    throw bad("its vertices are not in its block's box");
  bytes += tile.bytes;
  return d;
}

MeshWindow MeshPyramid::read_window(int l, std::size_t r0, std::size_t c0, std::size_t nr,
                                    std::size_t nc) {
  MeshWindow w;
  w.rows = nr, w.cols = nc;
  w.positions.resize(nr * nc);
  w.normals.resize(nr * nc);
  if (sources_) w.sources.resize(nr * nc);
  read_window(l, r0, c0, nr, nc, w.positions.data(), w.normals.data(),
              sources_ ? w.sources.data() : nullptr);
  return w;
}

void MeshPyramid::decode_tiles(
    int l, std::size_t tr0, std::size_t tc0, std::size_t tr1, std::size_t tc1,
    const std::function<void(std::size_t, std::size_t, const TileData&)>& use) {
  const std::size_t across = tc1 - tc0, n_tiles = (tr1 - tr0) * across;
  std::string failed;
  std::uint64_t bytes = 0;
#pragma omp parallel reduction(+ : bytes)
  {
    std::unique_ptr<ZSTD_DCtx, decltype(&ZSTD_freeDCtx)> ctx(ZSTD_createDCtx(), ZSTD_freeDCtx);
#pragma omp for schedule(dynamic, 16)
    for (std::size_t k = 0; k < n_tiles; ++k) {
      try {
        const std::size_t tr = tr0 + k / across, tc = tc0 + k % across;
        use(tr, tc, decode_tile(l, tr, tc, ctx.get(), bytes));
      } catch (const std::exception& e) {
#pragma omp critical
        if (failed.empty()) failed = e.what();
      }
    }
  }
  if (!failed.empty()) throw Error(failed);
  bytes_read_ += bytes;
  tiles_read_ += n_tiles;
}

void MeshPyramid::read_window(int l, std::size_t r0, std::size_t c0, std::size_t nr, std::size_t nc,
                              Eigen::Vector3f* positions, Eigen::Vector3f* normals,
                              std::uint8_t* sources) {
  if (l < 0 || l >= level_count() || nr == 0 || nc == 0 || r0 + nr > rows(l) || c0 + nc > cols(l))
    throw Error(
        fmt::format("'{}': no window of {} x {} at {}, {} in level {}", path_, nr, nc, r0, c0, l));
  const LevelTiles& lt = tiles_[std::size_t(l)];
  const std::size_t B = levels_.block;
  // Every tile the window touches (a vertex on a tile border is in both, the same in both).
  const std::size_t tr0 = std::min(r0 / B, lt.tiles_r - 1),
                    tr1 = std::min((r0 + nr - 1) / B, lt.tiles_r - 1);
  const std::size_t tc0 = std::min(c0 / B, lt.tiles_c - 1),
                    tc1 = std::min((c0 + nc - 1) / B, lt.tiles_c - 1);
  decode_tiles(
      l, tr0, tc0, tr1 + 1, tc1 + 1, [&](std::size_t tr, std::size_t tc, const TileData& d) {
        const std::vector<Eigen::Vector3f>& raw = d.raw;
        const TileRange t = tile_range(rows(l), cols(l), B, tr, tc);
        const std::size_t ca = std::max(c0, t.c0), cb = std::min(c0 + nc, t.c0 + t.nc);
        for (std::size_t r = std::max(r0, t.r0); r < std::min(r0 + nr, t.r0 + t.nr); ++r) {
          const std::size_t to = (r - r0) * nc + (ca - c0), from = (r - t.r0) * t.nc + (ca - t.c0);
          std::copy_n(raw.begin() + long(from), cb - ca, positions + to);
          std::copy_n(raw.begin() + long(t.nr * t.nc + from), cb - ca, normals + to);
          if (sources && !d.sources.empty())
            std::copy_n(d.sources.begin() + long(from), cb - ca, sources + to);
        }
      });
}

std::size_t MeshPyramid::check_tiles() {
  std::size_t n = 0;
  for (int l = 0; l < level_count(); ++l) {
    const LevelTiles& lt = tiles_[std::size_t(l)];
    decode_tiles(l, 0, 0, lt.tiles_r, lt.tiles_c, [](std::size_t, std::size_t, const TileData&) {});
    n += lt.tiles.size();
  }
  return n;
}

void MeshPyramid::read_level(int l, Eigen::Vector3f* positions, Eigen::Vector3f* normals) {
  if (l < 0 || l >= level_count()) throw Error(fmt::format("'{}': no level {}", path_, l));
  read_window(l, 0, 0, rows(l), cols(l), positions, normals);
}

}  // namespace terrain
