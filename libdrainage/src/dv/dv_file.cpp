// The .dv header, its checksums and the index checks every reader runs (dv_internal.hpp).
#include "drainage/dv_file.hpp"

#include <fmt/format.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "drainage/d8.hpp"
#include "dv_internal.hpp"
#include "terrain/dem_io.hpp"

namespace drainage {

static_assert(std::endian::native == std::endian::little,
              "the .dv writer assumes a little-endian machine");

namespace dv {

std::vector<char> header_bytes(const DvHeader& h) {
  FixedHeader f{};
  std::memcpy(f.magic, kMagic, 8);
  f.version = h.version;
  f.flags = h.flags;
  f.rows = h.rows, f.cols = h.cols, f.valid = h.valid, f.branches = h.branches, f.basins = h.basins;
  f.origin_x = h.origin_x, f.origin_y = h.origin_y, f.origin_z = h.origin_z, f.dx = h.dx,
  f.dy = h.dy;
  f.epsg = h.epsg;
  f.wkt_bytes = std::uint32_t(h.crs_wkt.size());
  f.provenance_bytes = std::uint32_t(h.provenance.size());
  if (h.version >= 2)
    f.block_rows = h.block_rows, f.block_cols = h.block_cols, f.codec = kCodecZstd;
  const std::size_t total = kFixedHeader + padded(h.crs_wkt.size() + h.provenance.size());
  f.header_bytes = std::uint32_t(total);
  std::vector<char> out(total, 0);
  std::memcpy(out.data(), &f, sizeof f);
  std::memcpy(out.data() + kFixedHeader, h.crs_wkt.data(), h.crs_wkt.size());
  std::memcpy(out.data() + kFixedHeader + h.crs_wkt.size(), h.provenance.data(),
              h.provenance.size());
  return out;
}

void check_indices(const DrainageDb& db, const std::string& path) {
  const std::uint64_t n = db.vertices.size(), basins = db.header.basins,
                      valid = db.branch_vertices.size();
  auto bad = [&](const std::string& what, std::uint64_t i) {
    return terrain::Error("cannot read '" + path + "': corrupt .dv (" + what + " " +
                          std::to_string(i) + ")");
  };
  for (std::uint64_t i = 0; i < n; ++i) {
    const DvVertex& v = db.vertices[i];
    const bool nodata = v.point_class == std::uint8_t(PointClass::Nodata);
    if (!(v.point_class <= std::uint8_t(PointClass::Pit) || nodata))
      throw bad("class of vertex", i);
    if (!(v.d8 <= kOutlet || v.d8 == kNodata)) throw bad("D8 code of vertex", i);
    if (!(v.downstream < n || v.downstream == kNone)) throw bad("downstream index of vertex", i);
    if (!(v.basin < basins || v.basin == kNone)) throw bad("basin of vertex", i);
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z) ||
        !std::isfinite(v.normalized))
      throw bad("coordinates or flow of vertex", i);
  }
  for (std::size_t b = 0; b < db.branches.size(); ++b) {
    const DvBranch& br = db.branches[b];
    if (br.count == 0 || std::uint64_t(br.first) + br.count > valid)
      throw bad("vertex range of branch", b);
    if (!(br.drains_into < n || br.drains_into == kNone)) throw bad("outlet of branch", b);
  }
  for (std::uint64_t k = 0; k < valid; ++k)
    if (db.branch_vertices[k] >= n) throw bad("branch vertex", k);
}

std::string cannot(const std::string& path, const std::string& what) {
  return "cannot read '" + path + "': " + what;
}

void open_dv(const std::string& path, OpenDv& d) {
  d.in.open(path, std::ios::binary);
  if (!d.in) throw terrain::Error(cannot(path, "no such file or not readable"));
  d.size = std::filesystem::file_size(path);
  FixedHeader& f = d.f;
  d.in.read(reinterpret_cast<char*>(&f), sizeof f);
  if (!d.in || std::memcmp(f.magic, kMagic, 8) != 0)
    throw terrain::Error(cannot(path, "not a drainage database (.dv): wrong magic"));
  if (f.version > kDvVersion || f.version == 0)
    throw terrain::Error(cannot(path, ".dv version " + std::to_string(f.version) +
                                          " is newer than this tool's (" +
                                          std::to_string(kDvVersion) + ")"));
  // Vertex ids are u32 with kNone reserved: rows x cols < 2^32 (checked without overflow).
  if (f.rows == 0 || f.cols == 0 || f.rows >= kNone || f.cols >= kNone ||
      f.rows > (kNone - 1) / f.cols)
    throw terrain::Error(cannot(path, "corrupt .dv header (grid " + std::to_string(f.cols) + " x " +
                                          std::to_string(f.rows) + ")"));
  if (!(f.dx > 0) || !(f.dy > 0) || !std::isfinite(f.dx) || !std::isfinite(f.dy) ||
      !std::isfinite(f.origin_x) || !std::isfinite(f.origin_y) || !std::isfinite(f.origin_z) ||
      f.basins > f.rows * f.cols)
    throw terrain::Error(cannot(path, "corrupt .dv header (spacing, origin or basin count)"));
  // What a terrain grid can be, as the mesh reader checks it (mesh_io.cpp): an origin
  // within 1e8 (UTM coordinates are below 1e7; heights far less) and an extent within 1e8.
  if (std::abs(f.origin_x) > 1e8 || std::abs(f.origin_y) > 1e8 || std::abs(f.origin_z) > 1e8 ||
      double(f.cols - 1) * f.dx > 1e8 || double(f.rows - 1) * f.dy > 1e8)
    throw terrain::Error(
        cannot(path, fmt::format("corrupt .dv header (origin {:g} {:g} {:g}, spacing {:g} x {:g}: "
                                 "outside what a terrain grid can be)",
                                 f.origin_x, f.origin_y, f.origin_z, f.dx, f.dy)));
  const std::uint64_t n = f.rows * f.cols;
  if (f.header_bytes != kFixedHeader + padded(std::size_t(f.wkt_bytes) + f.provenance_bytes) ||
      f.valid > n || f.branches > n || f.header_bytes > d.size)
    throw terrain::Error(cannot(path, "corrupt .dv header"));
  if (f.version >= 2 ? (f.block_rows == 0 || f.block_cols == 0 || f.block_rows > (1u << 14) ||
                        f.block_cols > (1u << 14) || f.codec != kCodecZstd)
                     : (f.block_rows != 0 || f.block_cols != 0 || f.codec != 0))
    throw terrain::Error(cannot(path, "corrupt .dv header (block shape or codec)"));
  DvHeader& h = d.h;
  h.version = f.version, h.flags = f.flags, h.rows = f.rows, h.cols = f.cols, h.valid = f.valid;
  h.branches = f.branches, h.basins = f.basins;
  h.origin_x = f.origin_x, h.origin_y = f.origin_y, h.origin_z = f.origin_z, h.dx = f.dx,
  h.dy = f.dy;
  h.epsg = f.epsg;
  if (f.version >= 2) h.block_rows = f.block_rows, h.block_cols = f.block_cols;
  d.header.resize(f.header_bytes);
  std::memcpy(d.header.data(), &f, kFixedHeader);
  std::memset(d.header.data() + kCrcOffset, 0, 4);
  d.in.read(d.header.data() + kFixedHeader, std::streamsize(f.header_bytes - kFixedHeader));
  if (!d.in) throw terrain::Error(cannot(path, "truncated header"));
  const char* strings = d.header.data() + kFixedHeader;
  h.crs_wkt.assign(strings, f.wkt_bytes);
  h.provenance.assign(strings + f.wkt_bytes, f.provenance_bytes);
  if (const std::string crs = terrain::crs_fields_problem(h.crs_wkt, h.epsg); !crs.empty())
    throw terrain::Error(cannot(path, "corrupt .dv header (" + crs + ")"));
}

}  // namespace dv

using namespace dv;

DvHeader make_dv_header(const terrain::Grid& grid, const Network& net, std::uint32_t flags,
                        const std::string& provenance) {
  DvHeader h;
  h.flags = flags;
  h.rows = grid.rows;
  h.cols = grid.cols;
  h.valid = net.points;
  h.branches = net.branch_count;
  h.basins = net.pits.size();
  h.origin_x = grid.geo.x_of_col(0);
  h.origin_y = grid.geo.y_of_row(0);
  h.dx = grid.geo.dx;
  h.dy = grid.geo.dy;
  h.epsg = grid.geo.epsg;
  h.crs_wkt = grid.geo.crs_wkt;
  h.provenance = provenance;
  return h;
}

std::uint32_t dv_checksum(const char* bytes, std::size_t size) {
  uLong crc = crc32(0L, Z_NULL, 0);
  const char zero[4] = {0, 0, 0, 0};
  const std::size_t head = std::min(size, kCrcOffset);
  crc = crc32_z(crc, reinterpret_cast<const Bytef*>(bytes), head);
  if (size > kCrcOffset)
    crc = crc32_z(crc, reinterpret_cast<const Bytef*>(zero),
                  std::min<std::size_t>(4, size - kCrcOffset));
  if (size > kCrcOffset + 4)
    crc =
        crc32_z(crc, reinterpret_cast<const Bytef*>(bytes + kCrcOffset + 4), size - kCrcOffset - 4);
  return std::uint32_t(crc);
}

bool is_dv_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[8] = {};
  in.read(magic, 8);
  return in && std::memcmp(magic, kMagic, 8) == 0;
}

void dv_fix_checksums(char* bytes, std::size_t size) {
  FixedHeader f{};
  if (size < sizeof f) return;
  std::memcpy(&f, bytes, sizeof f);
  std::uint32_t crc = 0;
  if (f.version < 2) {
    crc = dv_checksum(bytes, size);
  } else {
    if (f.block_rows == 0 || f.block_cols == 0 || f.header_bytes > size) return;
    const std::uint64_t nb =
        std::uint64_t(blocks_along(f.rows, f.block_rows)) * blocks_along(f.cols, f.block_cols);
    if (nb > size || f.basins > size) return;
    const std::uint64_t trailer = nb * kIndexEntry + f.basins * kBasinEntry + kEndRecord;
    if (trailer > size - f.header_bytes) return;
    char* index = bytes + (size - trailer);
    for (std::uint64_t b = 0; b < nb; ++b) {
      std::uint64_t offset = 0;
      std::uint32_t n = 0;
      std::memcpy(&offset, index + b * kIndexEntry, 8);
      std::memcpy(&n, index + b * kIndexEntry + 8, 4);
      if (offset > size || n > size - offset) continue;
      const std::uint32_t c = crc_of(bytes + offset, n);
      std::memcpy(index + b * kIndexEntry + 12, &c, 4);
    }
    std::memset(bytes + kCrcOffset, 0, 4);
    crc = crc_of(index, trailer, crc_of(bytes, f.header_bytes));
  }
  std::memcpy(bytes + kCrcOffset, &crc, 4);
}

}  // namespace drainage
