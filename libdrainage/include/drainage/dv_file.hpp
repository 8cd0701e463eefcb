#pragma once
// The drainage vertex database (.dv): a versioned little-endian binary file.
// Full specification: docs/dv-format.md. Version 2 (written by default) stores per point
// only what the grid does not imply - elevation, D8 code, accumulated flow, basin, Strahler
// order - in zstd-compressed blocks of block_rows x block_cols points, each with its own
// CRC-32, followed by a block index and the basins' pits; positions, downstream links,
// classes, normalized flow and branches are derived on reading. Version 1 (32 bytes per
// point, every field stored) is still read, and written on request.
#include <cstdint>
#include <string>
#include <vector>

#include "drainage/network.hpp"
#include "terrain/grid.hpp"

namespace drainage {

inline constexpr std::uint32_t kDvVersion = 2;      // the newest version, written by default
inline constexpr std::uint32_t kDvBlockSide = 256;  // default block: 256 x 256 points

enum DvFlags : std::uint32_t {
  kDvHasElevations = 1u << 0,  // z is meaningful (not a --d8-input run without a DEM)
  kDvFlatsResolved = 1u << 1,
  kDvFilled = 1u << 2,
  kDvFromPnSurface = 1u << 3,  // sampled from a mesh's PN surface (else: a raster's own grid)
  kDvBreached = 1u << 4,       // depressions breached (fill.hpp breach_depressions)
};

struct DvHeader {
  std::uint32_t version = kDvVersion;
  std::uint32_t flags = 0;
  std::uint64_t rows = 0, cols = 0, valid = 0, branches = 0, basins = 0;
  double origin_x = 0, origin_y = 0, origin_z = 0;  // world = origin + local
  double dx = 1, dy = 1;
  std::int32_t epsg = 0;
  std::string crs_wkt, provenance;
  std::uint32_t block_rows = 0, block_cols = 0;  // version 2: the block shape (0 in version 1)
};

#pragma pack(push, 1)
struct DvVertex {
  float x, y, z;
  std::uint32_t accumulated;
  float normalized;
  std::uint32_t basin;
  std::uint32_t downstream;
  std::uint8_t point_class, order, d8, reserved;
};
struct DvBranch {
  std::uint32_t first, count, drains_into;
  std::uint8_t order, pad[3];
};
#pragma pack(pop)
static_assert(sizeof(DvVertex) == 32 && sizeof(DvBranch) == 16);

struct DrainageDb {
  DvHeader header;
  terrain::BigVector<DvVertex> vertices;  // rows * cols
  std::vector<DvBranch> branches;
  terrain::BigVector<std::uint32_t> branch_vertices;
};

// The header of a network on `grid` (rows, cols, spacing, CRS, origin = sample (0,0)).
DvHeader make_dv_header(const terrain::Grid& grid, const Network& net, std::uint32_t flags,
                        const std::string& provenance);

// Writes atomically (temp + rename) in header.version (2 by default, blocks of
// header.block_rows x block_cols, kDvBlockSide when 0; or 1), streaming from the arrays
// (no copy of the database in memory). `z` gives elevations (NaN/no-data points keep
// class Nodata).
void write_dv(const std::string& path, const DvHeader& header, const terrain::Grid& z,
              const D8Codes& dirs, const Network& net);

// Version 2, block by block (the tiled build writes tiles as they finish): the stored
// fields of one block, row-major within the block, compressed and checksummed.
struct DvBlockFields {
  std::vector<float> z;           // relative to the header's origin z; 0 at no-data
  std::vector<std::uint8_t> d8;   // D8 codes (d8.hpp)
  std::vector<std::uint8_t> cut;  // 1 where d8 < 8 but the flow ends (enters no-data)
  std::vector<std::uint32_t> accumulated;
  std::vector<std::uint32_t> basin;
  std::vector<std::uint8_t> order;
};
std::vector<char> encode_dv_block(const DvBlockFields& fields);
// The same fields where they already lie (m points each; no copy): a tiled run's tile.
struct DvBlockView {
  std::size_t m = 0;
  const float* z = nullptr;
  const std::uint8_t *d8 = nullptr, *cut = nullptr;
  const std::uint32_t *accumulated = nullptr, *basin = nullptr;
  const std::uint8_t* order = nullptr;
};
std::vector<char> encode_dv_block(const DvBlockView& view);

class DvBlockWriter {
 public:
  // Writes the header (counts are patched by finish) to `out`, a seekable stream.
  DvBlockWriter(std::ostream& out, std::string path, DvHeader header);
  const DvHeader& header() const { return header_; }  // with the block shape filled in
  // Block b (row-major over the grid of blocks), once each, in any order.
  void put_block(std::size_t b, const std::vector<char>& encoded);
  // The basins' pits and their accumulated flow, the final counts; writes the trailer and
  // the header checksum.
  void finish(std::uint64_t valid, std::uint64_t branches, const std::vector<std::uint32_t>& pits,
              const std::vector<std::uint32_t>& pit_accumulated);

 private:
  struct Entry {
    std::uint64_t offset = 0;
    std::uint32_t bytes = 0, crc = 0;
  };
  std::ostream& out_;
  std::string path_;
  DvHeader header_;
  std::vector<Entry> index_;
  std::uint64_t end_ = 0;
};

// Reads and validates: wrong magic, a newer version, a grid of 2^32 points or more, a
// truncated or oversized file, a CRC mismatch, and (since a file can be made to match its
// CRC) any class, D8 code, downstream, basin, branch or branch-vertex index out of range
// are each a terrain::Error with a clear message.
DrainageDb read_dv(const std::string& path);

// Only the header (version 1 or 2), checked as read_dv checks it.
DvHeader read_dv_header(const std::string& path);

// The points of rows row0 .. row0 + rows - 1 and columns col0 .. col0 + cols - 1 (clamped to
// the grid) as a database of their own: its header's rows, cols and origin are the
// window's, x and y are relative to that origin, downstream links are window indices
// (kNone where the flow leaves the window), basins keep their global ids and classes,
// accumulated and normalized flow their global values; branches are those of the window.
// A version 2 file is read block by block: only the blocks under the window (and a
// one-point margin, for the classes) are read.
DrainageDb read_dv_window(const std::string& path, std::size_t row0, std::size_t col0,
                          std::size_t rows, std::size_t cols);

// The CRC-32 of a whole .dv file image (`size` bytes at `bytes`) with its CRC field taken
// as 0: the value the file stores at byte 16. For tools and tests that patch a file.
std::uint32_t dv_checksum(const char* bytes, std::size_t size);

// Sets every checksum of a .dv image to match its bytes: version 1 the file's CRC; version
// 2 each block's CRC in the index (where the index lies inside the image) and then the
// header's. For fuzzing and tests that patch a file; an image too short to hold a header
// is left as it is.
void dv_fix_checksums(char* bytes, std::size_t size);

// True when the file starts with the .dv magic.
bool is_dv_file(const std::string& path);

}  // namespace drainage
