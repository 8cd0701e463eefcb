#pragma once
// The drainage vertex database (.dv): a versioned little-endian binary file.
// Full specification: docs/dv-format.md. In short:
//   fixed header (128 bytes): magic "TRNDRAIN", version, header size, CRC-32, flags,
//     rows, cols, valid points, branches, basins, origin x y z, dx, dy, EPSG, lengths of
//     the CRS WKT and provenance strings; then those strings, padded to 8 bytes;
//   vertex records, rows * cols x 32 bytes, vertex id = row * cols + col:
//     f32 x y z (relative to the origin), u32 accumulated flow, f32 normalized flow,
//     u32 basin, u32 downstream vertex, u8 class, u8 Strahler order, u8 D8 code, u8 0;
//   branch records, #branches x 16 bytes: u32 first, u32 count, u32 drains_into, u8 order, 3 x u8 0;
//   branch vertex list, #valid points x u32.
// The CRC-32 (zlib) covers the whole file with the CRC field set to 0.
#include <cstdint>
#include <string>
#include <vector>

#include "drainage/network.hpp"
#include "terrain/grid.hpp"

namespace drainage {

inline constexpr std::uint32_t kDvVersion = 1;

enum DvFlags : std::uint32_t {
  kDvHasElevations = 1u << 0,  // z is meaningful (not a --d8-input run without a DEM)
  kDvFlatsResolved = 1u << 1,
  kDvFilled = 1u << 2,
  kDvFromPnSurface = 1u << 3,  // sampled from a mesh's PN surface (else: a raster's own grid)
};

struct DvHeader {
  std::uint32_t version = kDvVersion;
  std::uint32_t flags = 0;
  std::uint64_t rows = 0, cols = 0, valid = 0, branches = 0, basins = 0;
  double origin_x = 0, origin_y = 0, origin_z = 0;  // world = origin + local
  double dx = 1, dy = 1;
  std::int32_t epsg = 0;
  std::string crs_wkt, provenance;
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
  terrain::BigVector<DvVertex> vertices;     // rows * cols
  std::vector<DvBranch> branches;
  terrain::BigVector<std::uint32_t> branch_vertices;
};

// The header of a network on `grid` (rows, cols, spacing, CRS, origin = sample (0,0)).
DvHeader make_dv_header(const terrain::Grid& grid, const Network& net, std::uint32_t flags,
                        const std::string& provenance);

// Writes atomically (temp + rename), streaming the records from the arrays (no copy of
// the database in memory). `z` gives elevations (NaN/no-data points keep class Nodata).
void write_dv(const std::string& path, const DvHeader& header, const terrain::Grid& z,
              const D8Codes& dirs, const Network& net);

// Reads and validates: wrong magic, a newer version, a grid of 2^32 points or more, a
// truncated or oversized file, a CRC mismatch, and (since a file can be made to match its
// CRC) any class, D8 code, downstream, basin, branch or branch-vertex index out of range
// are each a terrain::Error with a clear message.
DrainageDb read_dv(const std::string& path);

// The CRC-32 of a whole .dv file image (`size` bytes at `bytes`) with its CRC field taken
// as 0: the value the file stores at byte 16. For tools and tests that patch a file.
std::uint32_t dv_checksum(const char* bytes, std::size_t size);

// True when the file starts with the .dv magic.
bool is_dv_file(const std::string& path);

}  // namespace drainage
