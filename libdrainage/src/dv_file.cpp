#include "drainage/dv_file.hpp"

#include <zlib.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "drainage/d8.hpp"
#include "terrain/atomic_file.hpp"
#include "terrain/error.hpp"

namespace drainage {

static_assert(std::endian::native == std::endian::little, "the .dv writer assumes a little-endian machine");

namespace {

constexpr char kMagic[8] = {'T', 'R', 'N', 'D', 'R', 'A', 'I', 'N'};
constexpr std::size_t kFixedHeader = 128;
constexpr std::size_t kCrcOffset = 16;

#pragma pack(push, 1)
struct FixedHeader {
  char magic[8];
  std::uint32_t version;
  std::uint32_t header_bytes;  // fixed part + strings + padding
  std::uint32_t crc32;
  std::uint32_t flags;
  std::uint64_t rows, cols, valid, branches, basins;
  double origin_x, origin_y, origin_z, dx, dy;
  std::int32_t epsg;
  std::uint32_t wkt_bytes, provenance_bytes;
  std::uint8_t reserved[12];
};
#pragma pack(pop)
static_assert(sizeof(FixedHeader) == kFixedHeader);
static_assert(offsetof(FixedHeader, crc32) == kCrcOffset);

std::size_t padded(std::size_t n) { return (n + 7) / 8 * 8; }

// Header bytes (fixed part, strings, padding) with the CRC field 0.
std::vector<char> header_bytes(const DvHeader& h) {
  FixedHeader f{};
  std::memcpy(f.magic, kMagic, 8);
  f.version = h.version;
  f.flags = h.flags;
  f.rows = h.rows, f.cols = h.cols, f.valid = h.valid, f.branches = h.branches, f.basins = h.basins;
  f.origin_x = h.origin_x, f.origin_y = h.origin_y, f.origin_z = h.origin_z, f.dx = h.dx, f.dy = h.dy;
  f.epsg = h.epsg;
  f.wkt_bytes = std::uint32_t(h.crs_wkt.size());
  f.provenance_bytes = std::uint32_t(h.provenance.size());
  const std::size_t total = kFixedHeader + padded(h.crs_wkt.size() + h.provenance.size());
  f.header_bytes = std::uint32_t(total);
  std::vector<char> out(total, 0);
  std::memcpy(out.data(), &f, sizeof f);
  std::memcpy(out.data() + kFixedHeader, h.crs_wkt.data(), h.crs_wkt.size());
  std::memcpy(out.data() + kFixedHeader + h.crs_wkt.size(), h.provenance.data(), h.provenance.size());
  return out;
}

class CrcWriter {
 public:
  CrcWriter(std::ostream& out, const std::string& path) : out_(out), path_(path) {}
  void write(const void* p, std::size_t n) {
    crc_ = crc32_z(crc_, static_cast<const Bytef*>(p), n);
    out_.write(static_cast<const char*>(p), std::streamsize(n));
    if (!out_) throw terrain::Error("cannot write '" + path_ + "': write failed (disk full?)");
  }
  std::uint32_t crc() const { return std::uint32_t(crc_); }

 private:
  std::ostream& out_;
  const std::string& path_;
  uLong crc_ = crc32(0L, Z_NULL, 0);
};

// Every index and code of a database whose checksum matched (a file can be made to match):
// what the readers of a DrainageDb index with must be in range.
void check_indices(const DrainageDb& db, const std::string& path) {
  const std::uint64_t n = db.vertices.size(), basins = db.header.basins, valid = db.branch_vertices.size();
  auto bad = [&](const std::string& what, std::uint64_t i) {
    return terrain::Error("cannot read '" + path + "': corrupt .dv (" + what + " " + std::to_string(i) + ")");
  };
  for (std::uint64_t i = 0; i < n; ++i) {
    const DvVertex& v = db.vertices[i];
    const bool nodata = v.point_class == std::uint8_t(PointClass::Nodata);
    if (!(v.point_class <= std::uint8_t(PointClass::Pit) || nodata)) throw bad("class of vertex", i);
    if (!(v.d8 <= kOutlet || v.d8 == kNodata)) throw bad("D8 code of vertex", i);
    if (!(v.downstream < n || v.downstream == kNone)) throw bad("downstream index of vertex", i);
    if (!(v.basin < basins || v.basin == kNone)) throw bad("basin of vertex", i);
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z) || !std::isfinite(v.normalized))
      throw bad("coordinates or flow of vertex", i);
  }
  for (std::size_t b = 0; b < db.branches.size(); ++b) {
    const DvBranch& br = db.branches[b];
    if (br.count == 0 || std::uint64_t(br.first) + br.count > valid) throw bad("vertex range of branch", b);
    if (!(br.drains_into < n || br.drains_into == kNone)) throw bad("outlet of branch", b);
  }
  for (std::uint64_t k = 0; k < valid; ++k)
    if (db.branch_vertices[k] >= n) throw bad("branch vertex", k);
}

}  // namespace

DvHeader make_dv_header(const terrain::Grid& grid, const Network& net, std::uint32_t flags,
                        const std::string& provenance) {
  DvHeader h;
  h.flags = flags;
  h.rows = grid.rows;
  h.cols = grid.cols;
  h.valid = net.points;
  h.branches = net.branches.size();
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

void write_dv(const std::string& path, const DvHeader& h, const terrain::Grid& z,
              const D8Codes& dirs, const Network& net) {
  const std::size_t n = std::size_t(h.rows * h.cols);
  if (z.size() != n || dirs.size() != n || net.downstream.size() != n)
    throw terrain::Error("write_dv: grid, directions and network sizes disagree");
  terrain::write_stream_atomic(path, [&](std::ostream& file) {
    CrcWriter w(file, path);
    const std::vector<char> head = header_bytes(h);
    w.write(head.data(), head.size());

    std::vector<DvVertex> chunk(std::size_t(1) << 16);
    for (std::size_t start = 0; start < n; start += chunk.size()) {
      const std::size_t m = std::min(chunk.size(), n - start);
#pragma omp parallel for schedule(static)
      for (long k = 0; k < long(m); ++k) {
        const std::size_t i = start + std::size_t(k);
        const std::size_t r = i / h.cols, c = i % h.cols;
        DvVertex& v = chunk[std::size_t(k)];
        v.x = float(double(c) * h.dx);
        v.y = float(-double(r) * h.dy);
        v.z = std::isnan(z.z[i]) ? 0.0f : float(double(z.z[i]) - h.origin_z);
        v.accumulated = net.accumulated[i];
        v.normalized = net.normalized[i];
        v.basin = net.basin[i];
        v.downstream = net.downstream[i];
        v.point_class = net.point_class[i];
        v.order = net.order[i];
        v.d8 = dirs[i];
        v.reserved = 0;
      }
      w.write(chunk.data(), m * sizeof(DvVertex));
    }
    std::vector<DvBranch> branches(net.branches.size());
    for (std::size_t b = 0; b < branches.size(); ++b) {
      const Branch& s = net.branches[b];
      branches[b] = DvBranch{s.first, s.count, s.drains_into, s.order, {0, 0, 0}};
    }
    w.write(branches.data(), branches.size() * sizeof(DvBranch));
    w.write(net.branch_vertices.data(), net.branch_vertices.size() * sizeof(std::uint32_t));
    const std::uint32_t crc = w.crc();
    file.seekp(std::streamoff(kCrcOffset));
    file.write(reinterpret_cast<const char*>(&crc), sizeof crc);
  });
}

std::uint32_t dv_checksum(const char* bytes, std::size_t size) {
  uLong crc = crc32(0L, Z_NULL, 0);
  const char zero[4] = {0, 0, 0, 0};
  const std::size_t head = std::min(size, kCrcOffset);
  crc = crc32_z(crc, reinterpret_cast<const Bytef*>(bytes), head);
  if (size > kCrcOffset) crc = crc32_z(crc, reinterpret_cast<const Bytef*>(zero), std::min<std::size_t>(4, size - kCrcOffset));
  if (size > kCrcOffset + 4)
    crc = crc32_z(crc, reinterpret_cast<const Bytef*>(bytes + kCrcOffset + 4), size - kCrcOffset - 4);
  return std::uint32_t(crc);
}

bool is_dv_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[8] = {};
  in.read(magic, 8);
  return in && std::memcmp(magic, kMagic, 8) == 0;
}

DrainageDb read_dv(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw terrain::Error("cannot read '" + path + "': no such file or not readable");
  const std::uint64_t size = std::filesystem::file_size(path);
  FixedHeader f{};
  in.read(reinterpret_cast<char*>(&f), sizeof f);
  if (!in || std::memcmp(f.magic, kMagic, 8) != 0)
    throw terrain::Error("cannot read '" + path + "': not a drainage database (.dv): wrong magic");
  if (f.version > kDvVersion)
    throw terrain::Error("cannot read '" + path + "': .dv version " + std::to_string(f.version) +
                         " is newer than this tool's (" + std::to_string(kDvVersion) + ")");
  // Vertex ids are u32 with kNone reserved: rows x cols < 2^32 (checked without overflow).
  if (f.rows == 0 || f.cols == 0 || f.rows >= kNone || f.cols >= kNone || f.rows > (kNone - 1) / f.cols)
    throw terrain::Error("cannot read '" + path + "': corrupt .dv header (grid " + std::to_string(f.cols) + " x " +
                         std::to_string(f.rows) + ")");
  if (!(f.dx > 0) || !(f.dy > 0) || !std::isfinite(f.dx) || !std::isfinite(f.dy) || !std::isfinite(f.origin_x) ||
      !std::isfinite(f.origin_y) || !std::isfinite(f.origin_z) || f.basins > f.rows * f.cols)
    throw terrain::Error("cannot read '" + path + "': corrupt .dv header (spacing, origin or basin count)");
  const std::uint64_t n = f.rows * f.cols;
  const std::uint64_t expected = std::uint64_t(f.header_bytes) + n * sizeof(DvVertex) + f.branches * sizeof(DvBranch) +
                                 f.valid * sizeof(std::uint32_t);
  if (f.header_bytes != kFixedHeader + padded(std::size_t(f.wkt_bytes) + f.provenance_bytes) || f.valid > n ||
      f.branches > n)
    throw terrain::Error("cannot read '" + path + "': corrupt .dv header");
  if (size < expected)
    throw terrain::Error("cannot read '" + path + "': truncated (" + std::to_string(size) + " bytes, expected " +
                         std::to_string(expected) + ")");
  if (size > expected)
    throw terrain::Error("cannot read '" + path + "': " + std::to_string(size - expected) + " unexpected trailing bytes");

  DrainageDb db;
  DvHeader& h = db.header;
  h.version = f.version, h.flags = f.flags, h.rows = f.rows, h.cols = f.cols, h.valid = f.valid;
  h.branches = f.branches, h.basins = f.basins;
  h.origin_x = f.origin_x, h.origin_y = f.origin_y, h.origin_z = f.origin_z, h.dx = f.dx, h.dy = f.dy;
  h.epsg = f.epsg;
  std::vector<char> strings(f.header_bytes - kFixedHeader);
  in.read(strings.data(), std::streamsize(strings.size()));
  h.crs_wkt.assign(strings.data(), f.wkt_bytes);
  h.provenance.assign(strings.data() + f.wkt_bytes, f.provenance_bytes);
  db.vertices.resize(n);
  db.branches.resize(f.branches);
  db.branch_vertices.resize(f.valid);
  in.read(reinterpret_cast<char*>(db.vertices.data()), std::streamsize(n * sizeof(DvVertex)));
  in.read(reinterpret_cast<char*>(db.branches.data()), std::streamsize(f.branches * sizeof(DvBranch)));
  in.read(reinterpret_cast<char*>(db.branch_vertices.data()), std::streamsize(f.valid * sizeof(std::uint32_t)));
  if (!in) throw terrain::Error("cannot read '" + path + "': read failed");

  // CRC over the whole file with the CRC field zeroed.
  std::vector<char> head = header_bytes(h);
  uLong crc = crc32(0L, Z_NULL, 0);
  crc = crc32_z(crc, reinterpret_cast<const Bytef*>(head.data()), head.size());
  crc = crc32_z(crc, reinterpret_cast<const Bytef*>(db.vertices.data()), db.vertices.size() * sizeof(DvVertex));
  crc = crc32_z(crc, reinterpret_cast<const Bytef*>(db.branches.data()), db.branches.size() * sizeof(DvBranch));
  crc = crc32_z(crc, reinterpret_cast<const Bytef*>(db.branch_vertices.data()),
                db.branch_vertices.size() * sizeof(std::uint32_t));
  if (std::uint32_t(crc) != f.crc32) throw terrain::Error("cannot read '" + path + "': checksum mismatch (corrupt file)");
  check_indices(db, path);
  return db;
}

}  // namespace drainage
