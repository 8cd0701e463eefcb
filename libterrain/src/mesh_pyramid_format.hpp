#pragma once
// The mesh pyramid's file format as its writer (mesh_pyramid_writer.cpp) and its reader
// (mesh_pyramid.cpp) share it: the magic and version, little-endian reads, the tiles'
// ranges, the CRC-32 of the header, a block's level count (docs/formats.md). Not installed.
#include <zlib.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>

#include "terrain/error.hpp"

namespace terrain::detail {

inline constexpr char kMagic[8] = {'T', 'P', 'Y', 'R', 'A', 'M', 'I', 'D'};
// 2: the blocks' slopes; 3: the mesh's digest and the header's CRC-32; 4: the header's
// flags, and with kTileSources each tile's vertex sources (GridMesh::filled) after its
// normals.
inline constexpr std::uint32_t kVersion = 4;
inline constexpr std::uint32_t kTileSources = 1;

// Little-endian scalars read back (this project's machines are; the format says so).
struct In {
  const std::string& bytes;
  const std::string& path;
  std::size_t at = 0;
  template <class T>
  T get() {
    if (at + sizeof(T) > bytes.size())
      throw Error("cannot read '" + path + "': truncated mesh pyramid");
    T v;
    std::memcpy(&v, bytes.data() + at, sizeof v);
    at += sizeof v;
    return v;
  }
};

// The level-l vertices of tile (tr, tc): rows tr B .. min(tr B + B, rows_l - 1), and so on.
struct TileRange {
  std::size_t r0, c0, nr, nc;
};
inline TileRange tile_range(std::size_t rows_l, std::size_t cols_l, std::size_t block,
                            std::size_t tr, std::size_t tc) {
  const std::size_t r0 = tr * block, c0 = tc * block;
  return {r0, c0, std::min(block, rows_l - 1 - r0) + 1, std::min(block, cols_l - 1 - c0) + 1};
}

inline std::uint32_t crc_of(const std::string& s) {
  return std::uint32_t(crc32(0L, reinterpret_cast<const Bytef*>(s.data()), uInt(s.size())));
}

// A block's level count (measure_block's): level 0, then one per step s = 2, 4, ... with
// s / 2 below its longer side.
inline int block_levels(std::uint32_t nr, std::uint32_t nc) {
  int n = 1;
  for (std::uint32_t s = 2; s / 2 < std::max(nr, nc); s *= 2) ++n;
  return n;
}

}  // namespace terrain::detail
