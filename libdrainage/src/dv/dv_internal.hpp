#pragma once
// The .dv format's internals, shared by its parts: dv_file.cpp (the header, checksums and
// index checks), dv_v1.cpp (version 1: 32 bytes a point), dv_v2.cpp (version 2: compressed
// blocks, encoded and decoded), dv_read.cpp (whole files and windows). Not installed.
#include <zlib.h>

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "drainage/dv_file.hpp"
#include "terrain/error.hpp"

namespace drainage::dv {

constexpr char kMagic[8] = {'T', 'R', 'N', 'D', 'R', 'A', 'I', 'N'};
constexpr std::size_t kFixedHeader = 128;
constexpr std::size_t kCrcOffset = 16;
constexpr std::uint32_t kCodecZstd = 1;
constexpr std::uint8_t kCutFlag =
    0x40;  // version 2 code byte: d8 < 8 whose flow ends (enters no-data)
constexpr std::size_t kBytesPerPoint = 14;  // version 2 block, uncompressed
constexpr std::size_t kIndexEntry = 16, kBasinEntry = 8, kEndRecord = 16;
constexpr char kEndMagic[8] = {'T', 'R', 'N', 'D',
                               'V', 'E', 'N', 'D'};  // after the file size, last

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

inline std::size_t padded(std::size_t n) { return (n + 7) / 8 * 8; }

// Header bytes (fixed part, strings, padding) with the CRC field 0.
std::vector<char> header_bytes(const DvHeader& h);

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
void check_indices(const DrainageDb& db, const std::string& path);

// "cannot read 'PATH': WHAT".
std::string cannot(const std::string& path, const std::string& what);

// An open .dv: its fixed header, checked as far as it can be alone, and its strings.
struct OpenDv {
  std::ifstream in;
  std::uint64_t size = 0;
  FixedHeader f{};
  DvHeader h;
  std::vector<char>
      header;  // every header byte as read (fixed part, strings, padding), the CRC field 0
};

// Opens `path` and reads its header, checked as far as it can be alone.
void open_dv(const std::string& path, OpenDv& d);

inline std::uint32_t crc_of(const void* p, std::size_t n, uLong crc = crc32(0L, Z_NULL, 0)) {
  return std::uint32_t(crc32_z(crc, static_cast<const Bytef*>(p), n));
}

inline std::size_t blocks_along(std::uint64_t n, std::uint32_t side) {
  return std::size_t((n + side - 1) / side);
}

// The trailer of a version 2 file: block index and basin table, checked against the header.
struct V2Trailer {
  std::vector<std::uint64_t> offset;
  std::vector<std::uint32_t> bytes, crc, pit, pit_accumulated;
};

// The trailer of an open version 2 file, checked against the header's checksum.
V2Trailer read_v2_trailer(const std::string& path, OpenDv& d);

// Decodes the points of rows [r0, r0 + nr) x columns [c0, c0 + nc) of a version 2 file into
// a database of that region (header, vertices with derived downstream links - region
// indices - and classes; no branches yet). Classes are exact where all 8 neighbours lie in
// the region.
DrainageDb decode_v2_region(const std::string& path, OpenDv& d, const V2Trailer& t, std::size_t r0,
                            std::size_t c0, std::size_t nr, std::size_t nc);

// A version 1 file, whole, checked.
DrainageDb read_dv_v1(const std::string& path, OpenDv& d);
void write_dv_v1(const std::string& path, const DvHeader& h, const terrain::Grid& z,
                 const D8Codes& dirs, const Network& net);

// Branches of a database whose vertices (downstream, order, d8) are set.
void derive_branches(DrainageDb& db);

// The window [r0, r0 + nr) x [c0, c0 + nc) of `db` (window coordinates relative to db's).
DrainageDb crop(const DrainageDb& db, std::size_t r0, std::size_t c0, std::size_t nr,
                std::size_t nc);

}  // namespace drainage::dv
