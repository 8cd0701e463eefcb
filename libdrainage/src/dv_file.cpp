#include "drainage/dv_file.hpp"

#include <zlib.h>
#include <zstd.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>

#include "branches.hpp"
#include "drainage/d8.hpp"
#include "terrain/atomic_file.hpp"
#include "terrain/error.hpp"

namespace drainage {

static_assert(std::endian::native == std::endian::little, "the .dv writer assumes a little-endian machine");

namespace {

constexpr char kMagic[8] = {'T', 'R', 'N', 'D', 'R', 'A', 'I', 'N'};
constexpr std::size_t kFixedHeader = 128;
constexpr std::size_t kCrcOffset = 16;
constexpr std::uint32_t kCodecZstd = 1;
constexpr std::uint8_t kCutFlag = 0x40;   // version 2 code byte: d8 < 8 whose flow ends (enters no-data)
constexpr std::size_t kBytesPerPoint = 14;  // version 2 block, uncompressed
constexpr std::size_t kIndexEntry = 16, kBasinEntry = 8, kEndRecord = 16;
constexpr char kEndMagic[8] = {'T', 'R', 'N', 'D', 'V', 'E', 'N', 'D'};  // after the file size, last

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
  std::uint32_t block_rows, block_cols, codec;  // version 2 (0 in version 1)
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
  if (h.version >= 2) f.block_rows = h.block_rows, f.block_cols = h.block_cols, f.codec = kCodecZstd;
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

namespace {

void write_dv_v1(const std::string& path, const DvHeader& h, const terrain::Grid& z,
              const D8Codes& dirs, const Network& net) {
  const std::size_t n = std::size_t(h.rows * h.cols);
  if (z.size() != n || dirs.size() != n || net.downstream.size() != n)
    throw terrain::Error("write_dv: grid, directions and network sizes disagree");
  if (net.normalized.size() != n || net.branches.size() != net.branch_count)
    throw terrain::Error("write_dv: version 1 stores the whole network (NetworkDetail::Full)");
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

}  // namespace

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

namespace {

std::string cannot(const std::string& path, const std::string& what) { return "cannot read '" + path + "': " + what; }

// An open .dv: its fixed header, checked as far as it can be alone, and its strings.
struct OpenDv {
  std::ifstream in;
  std::uint64_t size = 0;
  FixedHeader f{};
  DvHeader h;
  std::vector<char> header;  // every header byte as read (fixed part, strings, padding), the CRC field 0
};

void open_dv(const std::string& path, OpenDv& d) {
  d.in.open(path, std::ios::binary);
  if (!d.in) throw terrain::Error(cannot(path, "no such file or not readable"));
  d.size = std::filesystem::file_size(path);
  FixedHeader& f = d.f;
  d.in.read(reinterpret_cast<char*>(&f), sizeof f);
  if (!d.in || std::memcmp(f.magic, kMagic, 8) != 0)
    throw terrain::Error(cannot(path, "not a drainage database (.dv): wrong magic"));
  if (f.version > kDvVersion || f.version == 0)
    throw terrain::Error(cannot(path, ".dv version " + std::to_string(f.version) + " is newer than this tool's (" +
                                          std::to_string(kDvVersion) + ")"));
  // Vertex ids are u32 with kNone reserved: rows x cols < 2^32 (checked without overflow).
  if (f.rows == 0 || f.cols == 0 || f.rows >= kNone || f.cols >= kNone || f.rows > (kNone - 1) / f.cols)
    throw terrain::Error(cannot(path, "corrupt .dv header (grid " + std::to_string(f.cols) + " x " +
                                          std::to_string(f.rows) + ")"));
  if (!(f.dx > 0) || !(f.dy > 0) || !std::isfinite(f.dx) || !std::isfinite(f.dy) || !std::isfinite(f.origin_x) ||
      !std::isfinite(f.origin_y) || !std::isfinite(f.origin_z) || f.basins > f.rows * f.cols)
    throw terrain::Error(cannot(path, "corrupt .dv header (spacing, origin or basin count)"));
  const std::uint64_t n = f.rows * f.cols;
  if (f.header_bytes != kFixedHeader + padded(std::size_t(f.wkt_bytes) + f.provenance_bytes) || f.valid > n ||
      f.branches > n || f.header_bytes > d.size)
    throw terrain::Error(cannot(path, "corrupt .dv header"));
  if (f.version >= 2 ? (f.block_rows == 0 || f.block_cols == 0 || f.block_rows > (1u << 14) ||
                        f.block_cols > (1u << 14) || f.codec != kCodecZstd)
                     : (f.block_rows != 0 || f.block_cols != 0 || f.codec != 0))
    throw terrain::Error(cannot(path, "corrupt .dv header (block shape or codec)"));
  DvHeader& h = d.h;
  h.version = f.version, h.flags = f.flags, h.rows = f.rows, h.cols = f.cols, h.valid = f.valid;
  h.branches = f.branches, h.basins = f.basins;
  h.origin_x = f.origin_x, h.origin_y = f.origin_y, h.origin_z = f.origin_z, h.dx = f.dx, h.dy = f.dy;
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
}

DrainageDb read_dv_v1(const std::string& path, OpenDv& d) {
  const FixedHeader& f = d.f;
  const std::uint64_t n = f.rows * f.cols;
  const std::uint64_t expected = std::uint64_t(f.header_bytes) + n * sizeof(DvVertex) + f.branches * sizeof(DvBranch) +
                                 f.valid * sizeof(std::uint32_t);
  if (d.size < expected)
    throw terrain::Error(cannot(path, "truncated (" + std::to_string(d.size) + " bytes, expected " +
                                          std::to_string(expected) + ")"));
  if (d.size > expected)
    throw terrain::Error(cannot(path, std::to_string(d.size - expected) + " unexpected trailing bytes"));
  DrainageDb db;
  db.header = d.h;
  db.vertices.resize(n);
  db.branches.resize(f.branches);
  db.branch_vertices.resize(f.valid);
  d.in.read(reinterpret_cast<char*>(db.vertices.data()), std::streamsize(n * sizeof(DvVertex)));
  d.in.read(reinterpret_cast<char*>(db.branches.data()), std::streamsize(f.branches * sizeof(DvBranch)));
  d.in.read(reinterpret_cast<char*>(db.branch_vertices.data()), std::streamsize(f.valid * sizeof(std::uint32_t)));
  if (!d.in) throw terrain::Error(cannot(path, "read failed"));

  // CRC over the whole file with the CRC field zeroed: every header byte as read.
  const std::vector<char>& head = d.header;
  uLong crc = crc32(0L, Z_NULL, 0);
  crc = crc32_z(crc, reinterpret_cast<const Bytef*>(head.data()), head.size());
  crc = crc32_z(crc, reinterpret_cast<const Bytef*>(db.vertices.data()), db.vertices.size() * sizeof(DvVertex));
  crc = crc32_z(crc, reinterpret_cast<const Bytef*>(db.branches.data()), db.branches.size() * sizeof(DvBranch));
  crc = crc32_z(crc, reinterpret_cast<const Bytef*>(db.branch_vertices.data()),
                db.branch_vertices.size() * sizeof(std::uint32_t));
  if (std::uint32_t(crc) != f.crc32) throw terrain::Error(cannot(path, "checksum mismatch (corrupt file)"));
  check_indices(db, path);
  return db;
}

// ---- version 2 ----

std::uint32_t crc_of(const void* p, std::size_t n, uLong crc = crc32(0L, Z_NULL, 0)) {
  return std::uint32_t(crc32_z(crc, static_cast<const Bytef*>(p), n));
}

std::size_t blocks_along(std::uint64_t n, std::uint32_t side) { return std::size_t((n + side - 1) / side); }

// The trailer of a version 2 file: block index and basin table, checked against the header.
struct V2Trailer {
  std::vector<std::uint64_t> offset;
  std::vector<std::uint32_t> bytes, crc, pit, pit_accumulated;
};

V2Trailer read_v2_trailer(const std::string& path, OpenDv& d) {
  const FixedHeader& f = d.f;
  const std::size_t nb = blocks_along(f.rows, f.block_rows) * blocks_along(f.cols, f.block_cols);
  // The end record (file size, end magic) tells a truncated file from a corrupt one.
  char end[kEndRecord] = {};
  if (d.size >= f.header_bytes + kEndRecord) {
    d.in.seekg(std::streamoff(d.size - kEndRecord));
    d.in.read(end, kEndRecord);
  }
  std::uint64_t recorded = 0;
  std::memcpy(&recorded, end, 8);
  if (!d.in || std::memcmp(end + 8, kEndMagic, 8) != 0 || recorded < d.size)
    throw terrain::Error(cannot(path, "truncated or damaged (" + std::to_string(d.size) + " bytes, no end record at the end)"));
  if (recorded > d.size)
    throw terrain::Error(cannot(path, "truncated (" + std::to_string(d.size) + " bytes, expected " +
                                          std::to_string(recorded) + ")"));
  const std::uint64_t trailer = nb * kIndexEntry + f.basins * kBasinEntry + kEndRecord;
  if (d.size < f.header_bytes + trailer)
    throw terrain::Error(cannot(path, "truncated (" + std::to_string(d.size) + " bytes, the header and index alone need " +
                                          std::to_string(f.header_bytes + trailer) + ")"));
  std::vector<char> raw(trailer);
  d.in.seekg(std::streamoff(d.size - trailer));
  d.in.read(raw.data(), std::streamsize(raw.size()));
  if (!d.in) throw terrain::Error(cannot(path, "read failed"));
  const std::vector<char>& head = d.header;  // every header byte as read
  if (crc_of(raw.data(), raw.size(), crc_of(head.data(), head.size())) != f.crc32)
    throw terrain::Error(cannot(path, "checksum mismatch in the header or block index (corrupt file)"));
  V2Trailer t;
  t.offset.resize(nb), t.bytes.resize(nb), t.crc.resize(nb);
  const std::uint64_t data_end = d.size - trailer;
  for (std::size_t b = 0; b < nb; ++b) {
    std::memcpy(&t.offset[b], raw.data() + b * kIndexEntry, 8);
    std::memcpy(&t.bytes[b], raw.data() + b * kIndexEntry + 8, 4);
    std::memcpy(&t.crc[b], raw.data() + b * kIndexEntry + 12, 4);
    if (t.offset[b] < f.header_bytes || t.offset[b] > data_end || t.bytes[b] > data_end - t.offset[b])
      throw terrain::Error(cannot(path, "corrupt .dv (block " + std::to_string(b) + " lies outside the data)"));
  }
  t.pit.resize(f.basins), t.pit_accumulated.resize(f.basins);
  const char* basins = raw.data() + nb * kIndexEntry;
  for (std::size_t k = 0; k < f.basins; ++k) {
    std::memcpy(&t.pit[k], basins + k * kBasinEntry, 4);
    std::memcpy(&t.pit_accumulated[k], basins + k * kBasinEntry + 4, 4);
    if (t.pit[k] >= f.rows * f.cols || t.pit_accumulated[k] == 0 || (k > 0 && t.pit[k] <= t.pit[k - 1]))
      throw terrain::Error(cannot(path, "corrupt .dv (basin " + std::to_string(k) + ")"));
  }
  return t;
}

// Decodes the points of rows [r0, r0 + nr) x columns [c0, c0 + nc) of a version 2 file into
// a database of that region (header, vertices with derived downstream links - region
// indices - and classes; no branches yet). Classes are exact where all 8 neighbours lie in
// the region.
DrainageDb decode_v2_region(const std::string& path, OpenDv& d, const V2Trailer& t, std::size_t r0, std::size_t c0,
                            std::size_t nr, std::size_t nc) {
  const FixedHeader& f = d.f;
  const std::size_t R = std::size_t(f.rows), C = std::size_t(f.cols), BR = f.block_rows, BC = f.block_cols;
  const std::size_t nbc = blocks_along(C, f.block_cols);
  DrainageDb db;
  db.header = d.h;
  DvHeader& h = db.header;
  h.rows = nr, h.cols = nc;
  h.origin_x = d.h.origin_x + double(c0) * d.h.dx;
  h.origin_y = d.h.origin_y - double(r0) * d.h.dy;
  db.vertices.resize(nr * nc);
  // Each vertex's reserved byte holds its cut flag until the classes are known, then 0.
  auto cut = [&](std::size_t i) { return db.vertices[i].reserved != 0; };

  // The blocks under the region, read in file order, decoded in parallel.
  std::vector<std::size_t> blocks;
  for (std::size_t br = r0 / BR; br * BR < r0 + nr; ++br)
    for (std::size_t bc = c0 / BC; bc * BC < c0 + nc; ++bc) blocks.push_back(br * nbc + bc);
  std::vector<std::vector<char>> packed(blocks.size());
  for (std::size_t k = 0; k < blocks.size(); ++k) {
    const std::size_t b = blocks[k];
    packed[k].resize(t.bytes[b]);
    d.in.seekg(std::streamoff(t.offset[b]));
    d.in.read(packed[k].data(), std::streamsize(t.bytes[b]));
    if (!d.in) throw terrain::Error(cannot(path, "read failed"));
  }
  std::string error;
#pragma omp parallel for schedule(dynamic)
  for (long k = 0; k < long(blocks.size()); ++k) {
    const std::size_t b = blocks[std::size_t(k)], br = b / nbc, bc = b % nbc;
    const std::size_t rows_b = std::min(BR, R - br * BR), cols_b = std::min(BC, C - bc * BC), m = rows_b * cols_b;
    auto fail = [&](const std::string& what) {
#pragma omp critical(dv_error)
      if (error.empty()) error = cannot(path, what);
    };
    const std::vector<char>& in = packed[std::size_t(k)];
    if (crc_of(in.data(), in.size()) != t.crc[b]) {
      fail("checksum mismatch in block " + std::to_string(b) + " (corrupt file)");
      continue;
    }
    // Per-thread buffers and context: a fresh one per block would cost the kernel's
    // zeroing of new pages for every block.
    thread_local std::vector<std::uint8_t> raw;
    thread_local std::unique_ptr<ZSTD_DCtx, std::size_t (*)(ZSTD_DCtx*)> ctx(ZSTD_createDCtx(), ZSTD_freeDCtx);
    if (raw.size() < kBytesPerPoint * m) raw.resize(kBytesPerPoint * m);
    const std::size_t got = ZSTD_decompressDCtx(ctx.get(), raw.data(), kBytesPerPoint * m, in.data(), in.size());
    if (ZSTD_isError(got) || got != kBytesPerPoint * m) {
      fail("corrupt .dv (block " + std::to_string(b) + " does not decompress to its size)");
      continue;
    }
    const std::uint8_t* planes = raw.data();
    auto u32 = [&](std::size_t at, std::size_t q) {  // byte-shuffled planes: byte k of value q at at + k m + q
      return std::uint32_t(planes[at + q]) | std::uint32_t(planes[at + m + q]) << 8 |
             std::uint32_t(planes[at + 2 * m + q]) << 16 | std::uint32_t(planes[at + 3 * m + q]) << 24;
    };
    const std::uint8_t* code = planes + 4 * m;
    const std::uint8_t* order = planes + 13 * m;
    std::uint32_t zprev = 0, bprev = 0;
    for (std::size_t q = 0; q < m; ++q) {
      zprev += u32(0, q), bprev += u32(9 * m, q);  // deltas
      const std::size_t gr = br * BR + q / cols_b, gc = bc * BC + q % cols_b;
      if (gr < r0 || gr >= r0 + nr || gc < c0 || gc >= c0 + nc) continue;
      const std::size_t i = (gr - r0) * nc + (gc - c0);
      DvVertex& v = db.vertices[i];
      const std::uint8_t c = code[q];
      const bool is_cut = (c & 0xF8) == kCutFlag;
      v.d8 = is_cut ? std::uint8_t(c & 7) : c;
      v.x = float(double(gc - c0) * h.dx);
      v.y = float(-double(gr - r0) * h.dy);
      v.z = std::bit_cast<float>(zprev);
      v.accumulated = u32(5 * m, q);
      v.basin = bprev;
      v.order = order[q];
      v.reserved = is_cut;
      v.downstream = kNone;
      const bool nodata = v.d8 == kNodata;
      if (!(v.d8 <= kOutlet || nodata) || !std::isfinite(v.z)) {
        fail("corrupt .dv (D8 code or elevation of vertex " + std::to_string(gr * C + gc) + ")");
        break;
      }
      if (nodata ? (v.basin != kNone || v.accumulated != 0) : (v.basin >= f.basins || v.accumulated == 0)) {
        fail("corrupt .dv (basin of vertex " + std::to_string(gr * C + gc) + ")");
        break;
      }
      v.normalized = nodata ? 0.0f : float(double(v.accumulated) / double(t.pit_accumulated[v.basin]));
      v.point_class = std::uint8_t(nodata ? PointClass::Nodata : PointClass::Pit);  // refined below
    }
  }
  if (!error.empty()) throw terrain::Error(error);

  // Downstream links (region indices) and classes from the codes.
  const long NR = long(nr), NC = long(nc);
  std::uint64_t valid = 0;
#pragma omp parallel for schedule(static) reduction(+ : valid)
  for (long r = 0; r < NR; ++r)
    for (long c = 0; c < NC; ++c) {
      const std::size_t i = std::size_t(r * NC + c);
      DvVertex& v = db.vertices[i];
      if (v.d8 == kNodata) continue;
      ++valid;
      if (v.d8 >= 8 || cut(i)) continue;
      const long rr = r + kDRow[v.d8], cc = c + kDCol[v.d8];
      const long gr = long(r0) + rr, gc = long(c0) + cc;
      if (gr < 0 || gc < 0 || gr >= long(R) || gc >= long(C)) {
#pragma omp critical(dv_error)
        if (error.empty()) error = cannot(path, "corrupt .dv (D8 code of vertex " + std::to_string((r0 + std::size_t(r)) * C + c0 + std::size_t(c)) + " leaves the grid)");
        continue;
      }
      if (rr < 0 || cc < 0 || rr >= NR || cc >= NC) continue;  // outside the region
      const std::size_t j = std::size_t(rr * NC + cc);
      if (db.vertices[j].d8 == kNodata) {
#pragma omp critical(dv_error)
        if (error.empty()) error = cannot(path, "corrupt .dv (downstream of vertex " + std::to_string((r0 + std::size_t(r)) * C + c0 + std::size_t(c)) + " is no-data)");
        continue;
      }
      v.downstream = std::uint32_t(j);
    }
  if (!error.empty()) throw terrain::Error(error);
  h.valid = valid;
#pragma omp parallel for schedule(static)
  for (long r = 0; r < NR; ++r)
    for (long c = 0; c < NC; ++c) {
      const std::size_t i = std::size_t(r * NC + c);
      DvVertex& v = db.vertices[i];
      if (v.d8 == kNodata || v.d8 >= 8 || cut(i)) continue;  // no-data or a pit (outlets included)
      int in = 0;
      for (int k = 0; k < 8; ++k) {
        const long rr = r - kDRow[k], cc = c - kDCol[k];
        if (rr < 0 || cc < 0 || rr >= NR || cc >= NC) continue;
        const DvVertex& u = db.vertices[std::size_t(rr * NC + cc)];
        in += u.d8 == std::uint8_t(k) && !cut(std::size_t(rr * NC + cc));
      }
      v.point_class = std::uint8_t(in == 0 ? PointClass::Ridge : in == 1 ? PointClass::Channel : PointClass::Junction);
    }
#pragma omp parallel for schedule(static)
  for (long i = 0; i < NR * NC; ++i) db.vertices[std::size_t(i)].reserved = 0;
  return db;
}

// Branches of a database whose vertices (downstream, order, d8) are set.
void derive_branches(DrainageDb& db) {
  const auto& v = db.vertices;
  db.branches.clear();
  network_branches(
      std::size_t(db.header.rows), std::size_t(db.header.cols), [&](std::size_t i) { return v[i].d8 != kNodata; },
      [&](std::size_t i) { return v[i].downstream; }, [&](std::size_t i) { return v[i].order; },
      [&](const Branch& b) { db.branches.push_back(DvBranch{b.first, b.count, b.drains_into, b.order, {0, 0, 0}}); },
      db.branch_vertices);
  db.header.branches = db.branches.size();
}

// The window [r0, r0 + nr) x [c0, c0 + nc) of `db` (window coordinates relative to db's).
DrainageDb crop(const DrainageDb& db, std::size_t r0, std::size_t c0, std::size_t nr, std::size_t nc) {
  const std::size_t C = std::size_t(db.header.cols);
  DrainageDb out;
  out.header = db.header;
  DvHeader& h = out.header;
  h.rows = nr, h.cols = nc;
  h.origin_x = db.header.origin_x + double(c0) * h.dx;
  h.origin_y = db.header.origin_y - double(r0) * h.dy;
  out.vertices.resize(nr * nc);
  std::uint64_t valid = 0;
  for (std::size_t r = 0; r < nr; ++r)
    for (std::size_t c = 0; c < nc; ++c) {
      DvVertex v = db.vertices[(r0 + r) * C + c0 + c];
      v.x = float(double(c) * h.dx);
      v.y = float(-double(r) * h.dy);
      if (v.downstream != kNone) {
        const std::size_t dr = v.downstream / C, dc = v.downstream % C;
        v.downstream = dr >= r0 && dr < r0 + nr && dc >= c0 && dc < c0 + nc
                           ? std::uint32_t((dr - r0) * nc + (dc - c0))
                           : kNone;
      }
      valid += v.point_class != std::uint8_t(PointClass::Nodata);
      out.vertices[r * nc + c] = v;
    }
  h.valid = valid;
  derive_branches(out);
  return out;
}

}  // namespace

void dv_fix_checksums(char* bytes, std::size_t size) {
  FixedHeader f{};
  if (size < sizeof f) return;
  std::memcpy(&f, bytes, sizeof f);
  std::uint32_t crc = 0;
  if (f.version < 2) {
    crc = dv_checksum(bytes, size);
  } else {
    if (f.block_rows == 0 || f.block_cols == 0 || f.header_bytes > size) return;
    const std::uint64_t nb = std::uint64_t(blocks_along(f.rows, f.block_rows)) * blocks_along(f.cols, f.block_cols);
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

DvHeader read_dv_header(const std::string& path) {
  OpenDv d;
  open_dv(path, d);
  if (d.f.version >= 2) (void)read_v2_trailer(path, d);  // checks the header's checksum
  return d.h;
}

namespace {

// What a whole version 2 grid, decoded, must agree with in its header and basin table: the
// valid points, the branches and each basin's pit. read_dv and read_dv_window (when its
// window is the whole grid) check the same.
void check_whole_v2(DrainageDb& db, const OpenDv& d, const V2Trailer& t, const std::string& path) {
  if (db.header.valid != d.f.valid)
    throw terrain::Error(cannot(path, "corrupt .dv (" + std::to_string(db.header.valid) + " valid points, the header says " +
                                          std::to_string(d.f.valid) + ")"));
  derive_branches(db);
  if (db.header.branches != d.f.branches)
    throw terrain::Error(cannot(path, "corrupt .dv (" + std::to_string(db.header.branches) +
                                          " branches derived, the header says " + std::to_string(d.f.branches) + ")"));
  for (std::size_t k = 0; k < t.pit.size(); ++k) {
    const DvVertex& v = db.vertices[t.pit[k]];
    if (v.point_class != std::uint8_t(PointClass::Pit) || v.basin != k || v.accumulated != t.pit_accumulated[k])
      throw terrain::Error(cannot(path, "corrupt .dv (pit of basin " + std::to_string(k) + ")"));
  }
}

}  // namespace

DrainageDb read_dv(const std::string& path) {
  OpenDv d;
  open_dv(path, d);
  if (d.f.version == 1) return read_dv_v1(path, d);
  const V2Trailer t = read_v2_trailer(path, d);
  DrainageDb db = decode_v2_region(path, d, t, 0, 0, std::size_t(d.f.rows), std::size_t(d.f.cols));
  check_whole_v2(db, d, t, path);
  check_indices(db, path);
  return db;
}

DrainageDb read_dv_window(const std::string& path, std::size_t row0, std::size_t col0, std::size_t rows,
                          std::size_t cols) {
  OpenDv d;
  open_dv(path, d);
  const std::size_t R = std::size_t(d.f.rows), C = std::size_t(d.f.cols);
  row0 = std::min(row0, R), col0 = std::min(col0, C);
  rows = std::min(rows, R - row0), cols = std::min(cols, C - col0);
  if (rows == 0 || cols == 0) throw terrain::Error(cannot(path, "the window lies outside the grid"));
  if (d.f.version == 1) return crop(read_dv_v1(path, d), row0, col0, rows, cols);
  const V2Trailer t = read_v2_trailer(path, d);
  if (rows == R && cols == C) {  // the whole grid: checked as read_dv checks it
    DrainageDb db = decode_v2_region(path, d, t, 0, 0, R, C);
    check_whole_v2(db, d, t, path);
    check_indices(db, path);
    return db;
  }
  // One point of margin, so that the window's classes see all their inflows.
  const std::size_t er0 = row0 > 0 ? row0 - 1 : 0, ec0 = col0 > 0 ? col0 - 1 : 0;
  const std::size_t er1 = std::min(R, row0 + rows + 1), ec1 = std::min(C, col0 + cols + 1);
  const DrainageDb region = decode_v2_region(path, d, t, er0, ec0, er1 - er0, ec1 - ec0);
  DrainageDb db = crop(region, row0 - er0, col0 - ec0, rows, cols);
  check_indices(db, path);
  return db;
}

// ---- writing ----

std::vector<char> encode_dv_block(const DvBlockFields& f) {
  const std::size_t m = f.z.size();
  if (f.d8.size() != m || f.cut.size() != m || f.accumulated.size() != m || f.basin.size() != m || f.order.size() != m)
    throw terrain::Error("encode_dv_block: fields of different sizes");
  thread_local std::vector<std::uint8_t> raw;  // reused: see the reader
  thread_local std::unique_ptr<ZSTD_CCtx, std::size_t (*)(ZSTD_CCtx*)> ctx(ZSTD_createCCtx(), ZSTD_freeCCtx);
  raw.resize(kBytesPerPoint * m);
  // Plain pointers (restrict): byte stores could alias the vectors' own pointers, which
  // the compiler would then reload on every store.
  std::uint8_t* __restrict const o = raw.data();
  const float* __restrict const zs = f.z.data();
  const std::uint8_t* __restrict const d8 = f.d8.data();
  const std::uint8_t* __restrict const cut = f.cut.data();
  const std::uint32_t* __restrict const acc = f.accumulated.data();
  const std::uint32_t* __restrict const basin = f.basin.data();
  const std::uint8_t* __restrict const order = f.order.data();
  // Deltas first (neighbours share high bits), then each byte plane in its own loop: one
  // output stream per loop vectorizes; fourteen interleaved streams per point did not
  // (the shuffle took three times zstd's time).
  thread_local std::vector<std::uint32_t> dzs, dbs;
  dzs.resize(m), dbs.resize(m);
  std::uint32_t* __restrict const dz = dzs.data();
  std::uint32_t* __restrict const db = dbs.data();
  for (std::size_t q = 0; q < m; ++q) {
    const std::uint32_t zb = std::bit_cast<std::uint32_t>(zs[q]);
    dz[q] = zb - (q ? std::bit_cast<std::uint32_t>(zs[q - 1]) : 0u);
    db[q] = basin[q] - (q ? basin[q - 1] : 0u);
  }
  for (std::size_t k = 0; k < 4; ++k) {
    const unsigned shift = unsigned(8 * k);
    std::uint8_t* __restrict const pz = o + k * m;
    std::uint8_t* __restrict const pa = o + (5 + k) * m;
    std::uint8_t* __restrict const pb = o + (9 + k) * m;
    for (std::size_t q = 0; q < m; ++q) pz[q] = std::uint8_t(dz[q] >> shift);
    for (std::size_t q = 0; q < m; ++q) pa[q] = std::uint8_t(acc[q] >> shift);
    for (std::size_t q = 0; q < m; ++q) pb[q] = std::uint8_t(db[q] >> shift);
  }
  std::uint8_t* __restrict const pd = o + 4 * m;
  std::uint8_t* __restrict const po = o + 13 * m;
  for (std::size_t q = 0; q < m; ++q) pd[q] = cut[q] && d8[q] < 8 ? std::uint8_t(kCutFlag | d8[q]) : d8[q];
  for (std::size_t q = 0; q < m; ++q) po[q] = order[q];
  std::vector<char> out(ZSTD_compressBound(raw.size()));
  const std::size_t n = ZSTD_compressCCtx(ctx.get(), out.data(), out.size(), raw.data(), raw.size(), 1);
  if (ZSTD_isError(n)) throw terrain::Error(std::string("zstd: ") + ZSTD_getErrorName(n));
  out.resize(n);
  return out;
}

DvBlockWriter::DvBlockWriter(std::ostream& out, std::string path, DvHeader header)
    : out_(out), path_(std::move(path)), header_(std::move(header)) {
  header_.version = 2;
  if (header_.block_rows == 0) header_.block_rows = kDvBlockSide;
  if (header_.block_cols == 0) header_.block_cols = kDvBlockSide;
  index_.resize(blocks_along(header_.rows, header_.block_rows) * blocks_along(header_.cols, header_.block_cols));
  const std::vector<char> head = header_bytes(header_);
  out_.write(head.data(), std::streamsize(head.size()));
  end_ = head.size();
  if (!out_) throw terrain::Error("cannot write '" + path_ + "': write failed (disk full?)");
}

void DvBlockWriter::put_block(std::size_t b, const std::vector<char>& encoded) {
  if (b >= index_.size() || index_[b].bytes != 0) throw terrain::Error("DvBlockWriter: block written twice or out of range");
  index_[b] = Entry{end_, std::uint32_t(encoded.size()), crc_of(encoded.data(), encoded.size())};
  out_.write(encoded.data(), std::streamsize(encoded.size()));
  end_ += encoded.size();
  if (!out_) throw terrain::Error("cannot write '" + path_ + "': write failed (disk full?)");
}

void DvBlockWriter::finish(std::uint64_t valid, std::uint64_t branches, const std::vector<std::uint32_t>& pits,
                           const std::vector<std::uint32_t>& pit_accumulated) {
  for (std::size_t b = 0; b < index_.size(); ++b)
    if (index_[b].bytes == 0) throw terrain::Error("DvBlockWriter: block " + std::to_string(b) + " was not written");
  header_.valid = valid, header_.branches = branches, header_.basins = pits.size();
  std::vector<char> trailer(index_.size() * kIndexEntry + pits.size() * kBasinEntry + kEndRecord);
  for (std::size_t b = 0; b < index_.size(); ++b) {
    std::memcpy(trailer.data() + b * kIndexEntry, &index_[b].offset, 8);
    std::memcpy(trailer.data() + b * kIndexEntry + 8, &index_[b].bytes, 4);
    std::memcpy(trailer.data() + b * kIndexEntry + 12, &index_[b].crc, 4);
  }
  char* basins = trailer.data() + index_.size() * kIndexEntry;
  for (std::size_t k = 0; k < pits.size(); ++k) {
    std::memcpy(basins + k * kBasinEntry, &pits[k], 4);
    std::memcpy(basins + k * kBasinEntry + 4, &pit_accumulated[k], 4);
  }
  const std::uint64_t total = end_ + trailer.size();
  std::memcpy(trailer.data() + trailer.size() - kEndRecord, &total, 8);
  std::memcpy(trailer.data() + trailer.size() - 8, kEndMagic, 8);
  out_.write(trailer.data(), std::streamsize(trailer.size()));
  std::vector<char> head = header_bytes(header_);
  const std::uint32_t crc = crc_of(trailer.data(), trailer.size(), crc_of(head.data(), head.size()));
  std::memcpy(head.data() + kCrcOffset, &crc, 4);
  out_.seekp(0);
  out_.write(head.data(), std::streamsize(head.size()));
  out_.seekp(0, std::ios::end);
  if (!out_) throw terrain::Error("cannot write '" + path_ + "': write failed (disk full?)");
}

void write_dv(const std::string& path, const DvHeader& h, const terrain::Grid& z, const D8Codes& dirs,
              const Network& net) {
  if (h.version == 1) return write_dv_v1(path, h, z, dirs, net);
  const std::size_t n = std::size_t(h.rows * h.cols);
  if (z.size() != n || dirs.size() != n || net.downstream.size() != n)
    throw terrain::Error("write_dv: grid, directions and network sizes disagree");
  terrain::write_stream_atomic(path, [&](std::ostream& file) {
    DvBlockWriter w(file, path, h);
    const DvHeader& wh = w.header();
    const std::size_t BR = wh.block_rows, BC = wh.block_cols, R = std::size_t(h.rows), C = std::size_t(h.cols);
    const std::size_t nbc = blocks_along(C, wh.block_cols);
    std::vector<std::vector<char>> band(nbc);
    for (std::size_t br = 0; br * BR < R; ++br) {
#pragma omp parallel for schedule(dynamic)
      for (long bc = 0; bc < long(nbc); ++bc) {
        const std::size_t r0 = br * BR, c0 = std::size_t(bc) * BC;
        const std::size_t rows_b = std::min(BR, R - r0), cols_b = std::min(BC, C - c0), m = rows_b * cols_b;
        thread_local DvBlockFields fields;  // reused: fresh buffers per block cost the kernel's page zeroing
        DvBlockFields& f = fields;          // one thread-local lookup, not one per access
        f.z.resize(m), f.d8.resize(m), f.cut.resize(m), f.accumulated.resize(m), f.basin.resize(m), f.order.resize(m);
        for (std::size_t r = 0, q = 0; r < rows_b; ++r)
          for (std::size_t c = 0, i = (r0 + r) * C + c0; c < cols_b; ++c, ++q, ++i) {
            f.z[q] = std::isnan(z.z[i]) ? 0.0f : float(double(z.z[i]) - h.origin_z);
            f.d8[q] = dirs[i];
            f.cut[q] = dirs[i] < 8 && net.downstream[i] == kNone;
            f.accumulated[q] = net.accumulated[i];
            f.basin[q] = net.basin[i];
            f.order[q] = net.order[i];
          }
        band[std::size_t(bc)] = encode_dv_block(f);
      }
      for (std::size_t bc = 0; bc < nbc; ++bc) w.put_block(br * nbc + bc, band[bc]);
    }
    std::vector<std::uint32_t> pit_acc(net.pits.size());
    for (std::size_t k = 0; k < pit_acc.size(); ++k) pit_acc[k] = net.accumulated[net.pits[k]];
    w.finish(net.points, net.branch_count, net.pits, pit_acc);
  });
}

}  // namespace drainage
