#pragma once
// The mesh's levels of detail: the blocks of cells, the error of each level of
// each block (build_mesh_levels; the renderer selects levels from them, renderer/core/lod.hpp),
// and the mesh pyramid on disk (MESH.tpyr, docs/formats.md): every level's vertices in
// tiles that a reader reads by window, so that what a view needs is read, not the mesh.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <fstream>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "terrain/atomic_file.hpp"
#include "terrain/grid_mesh.hpp"
#include "terrain/mesh_digest.hpp"

struct ZSTD_DCtx_s;
typedef struct ZSTD_DCtx_s ZSTD_DCtx;

namespace terrain {

inline constexpr std::size_t kLevelBlock = 64;  // cells a side of a block (and of a pyramid tile)

// Level l of a block keeps every 2^l-th row and column of its vertices and its last ones:
// the fine mesh's own vertices, positions and normals.
struct MeshLevelBlock {
  std::uint32_t r0 = 0, c0 = 0;  // its first vertex row and column
  std::uint32_t nr = 0, nc = 0;  // its cells down and across
  // error[l]: the largest vertical distance (metres, heights not exaggerated) between a
  // vertex of the block and the PN surface of level l over it at the same parameters;
  // non-decreasing in l, error[0] = 0. The coarsest level is the first whose step covers
  // the block.
  std::vector<float> error;
  Eigen::Vector3f lo, hi;  // its vertices' bounding box, local frame, heights not exaggerated
  // slope[l]: the steepest gradient of level l's surface over the block, heights not
  // exaggerated: at level 0 its PN patches' normals' (max |n_xy| / n_z over the vertex
  // normals and the quadratic normals' mid-edge coefficients, of which each patch's normal
  // is a blend with weights >= 0); at l > 0 its
  // patches' geometry: the planes through each patch's corners (a patch drawn flat) and
  // through its PN cubic's samples at the block's vertices' parameters (each fine cell's
  // two faces); infinity where one does not point up. Empty when not known (a pyramid of
  // version 1). What tells the renderer that no silhouette can cross the block drawn at a
  // level (renderer/core/lod.hpp).
  std::vector<float> slope;
  int levels() const { return int(error.size()); }
};

struct MeshLevels {
  GridTopology topo;
  std::size_t block = kLevelBlock, block_rows = 0, block_cols = 0;
  std::vector<MeshLevelBlock> blocks;  // row-major
  // The level whose grid the drawn mesh holds (read_mesh_via_pyramid's `level`): 0, the
  // mesh itself, unless a level of its pyramid was read in its place; no block is drawn
  // finer (renderer/core/lod.hpp).
  int base = 0;
  // Set when only a window of the mesh's blocks is held (read_mesh_via_pyramid's `part`):
  // then topo, block_rows, block_cols and blocks are the window's, in its frame (its first
  // vertex at the local origin), and this says where it lies in the whole mesh.
  struct Window {
    std::size_t r0 = 0, c0 = 0;  // its first level-0 vertex row and column in the mesh
    GridTopology whole;          // the mesh's level-0 grid
    MeshGeoref geo;              // the mesh's own (its origin and spacing, level 0's)
    Eigen::Vector3f lo, hi;  // the whole mesh's box, the window's frame, heights not exaggerated
  };
  std::optional<Window> window;
};

// The error of a coarser level of a block with a vertex outside the data: so large that no
// bound draws it (a coarse cell would span the hole; the block is drawn at level 0).
inline constexpr float kHoleError = 1e30f;

MeshLevels build_mesh_levels(const GridMesh& mesh, std::size_t block = kLevelBlock);

// The kept positions 0..n of a block side of n cells at step s: 0, s, 2s, ... below n, and n.
inline std::vector<std::uint32_t> level_lines(std::uint32_t n, std::uint32_t s) {
  std::vector<std::uint32_t> v;
  for (std::uint32_t p = 0; p < n; p += s) v.push_back(p);
  v.push_back(n);
  return v;
}

// Vertices of level l's grid along a side of n cells: every 2^l-th and the last,
// ceil(n / 2^l) + 1 of them; level_index is a level-l vertex's level-0 row (or column).
inline std::size_t level_count(std::size_t cells, int l) {
  return (cells + (std::size_t(1) << l) - 1) / (std::size_t(1) << l) + 1;
}
inline std::size_t level_index(std::size_t k, std::size_t cells, int l) {
  return std::min(k << l, cells);
}

// Writes a mesh pyramid (docs/formats.md) from the mesh's vertex rows given in order,
// holding about one tile row of each level (B + 1 of its rows) and one block row of the
// fine mesh: for meshes larger than memory (dem2mesh --tile-size). It measures each block's
// box and errors (build_mesh_levels' values) as its rows pass and compresses each level's
// tiles as their rows complete: level 0's into the file after the room for its header
// (whose size the grid fixes), the coarser levels' into temporary files beside `path`;
// finish() appends those and writes the header and index, and the file appears
// atomically (AtomicFile). The same file, byte for byte, whatever the rows' grouping into
// add_rows calls.
class MeshPyramidWriter {
 public:
  // `name_like`: the target the temporary files are named after (DIR/.STEM.tmpPID-N.tpyr,
  // temp_files.hpp), so that a later run finds any a killed run left; `path` when empty
  // (give the final name when `path` is an OutputSet's staged one).
  // `sources`: the rows come with each vertex's source (GridMesh::filled), which the tiles
  // keep and which make a block with an outside vertex drawn at level 0 (kHoleError).
  MeshPyramidWriter(const GridTopology& topo, const MeshGeoref& geo, const std::string& path,
                    std::size_t block = kLevelBlock, const std::string& name_like = {},
                    bool sources = false);
  ~MeshPyramidWriter();  // removes the temporary files
  MeshPyramidWriter(const MeshPyramidWriter&) = delete;
  MeshPyramidWriter& operator=(const MeshPyramidWriter&) = delete;
  // The next n rows of the grid: positions and normals, topo.cols each, local frame, and
  // with `sources` at construction their vertices' sources (VertexSource values).
  void add_rows(const Eigen::Vector3f* positions, const Eigen::Vector3f* normals, std::size_t n,
                const std::uint8_t* sources = nullptr);
  // After the last row: writes the file; returns its bytes.
  std::uint64_t finish();

 private:
  struct Level;
  void measure_block_row(const Level& v, std::size_t nr);
  void flush_tile_row(Level& v, int l, std::size_t nr);
  GridTopology topo_;
  MeshGeoref geo_;
  std::string path_;
  std::size_t block_;
  bool sources_ = false;
  MeshLevels levels_;
  std::vector<std::unique_ptr<Level>> grids_;
  std::size_t row_ = 0, block_rows_measured_ = 0;
  MeshDigest digest_;  // of the rows given: the mesh's (mesh_digest.hpp)
  std::uint64_t header_bytes_ = 0;
  std::unique_ptr<AtomicFile> file_;
  std::fstream out_;
};

// Writes the pyramid of `mesh` at `path` (atomically) through MeshPyramidWriter: its
// georeference, its blocks of `block` cells (boxes, errors: build_mesh_levels'), and for
// each level 0 .. (the coarsest of any block) its grid in tiles of `block` cells a side
// (their border vertices in both neighbours), each tile its positions and normals, and
// the vertices' sources when the mesh has them (GridMesh::filled), compressed with zstd.
// Returns the bytes written.
std::uint64_t write_mesh_pyramid(const GridMesh& mesh, const std::string& path,
                                 std::size_t block = kLevelBlock,
                                 const std::string& name_like = {});

// Whether the file at `path` starts as a mesh pyramid does (by content, not by name).
bool is_mesh_pyramid(const std::string& path);

// Sets every checksum of a pyramid image (version 3) to match its bytes: each tile's CRC in
// the index (where the index and the tile lie inside the image), then the header's. For
// fuzzing and tests that patch a file; an image that does not hold a version-3 header's
// fields is left as it is.
void pyramid_fix_checksums(std::string& bytes);

// The pyramid's path beside a mesh: MESH.ply -> MESH.tpyr.
std::string pyramid_path_of(const std::string& mesh_path);

struct MeshWindow {
  std::size_t rows = 0, cols = 0;                   // vertices
  std::vector<Eigen::Vector3f> positions, normals;  // row-major, local frame
  std::vector<std::uint8_t> sources;  // VertexSource values; empty when the pyramid has none
};

// A pyramid file opened for windowed reads: the header, the blocks and the tile index are
// read at once and checked (every count and size against the file's size before anything
// is allocated, the grid and georeference as a mesh's header, the boxes, errors and slopes
// as their definitions allow, and from version 3 the header's CRC-32); tiles only when a
// window needs them, and only those, each checked by its CRC-32 and against its blocks'
// boxes. Every read goes through the one descriptor opened here: a file renamed over the
// path meanwhile is not seen.
class MeshPyramid {
 public:
  explicit MeshPyramid(const std::string& path);  // terrain::Error on a bad file
  ~MeshPyramid();
  MeshPyramid(const MeshPyramid&) = delete;
  MeshPyramid& operator=(const MeshPyramid&) = delete;
  const MeshGeoref& georef() const { return geo_; }  // the mesh's
  int version() const { return version_; }
  // The digest of the mesh it was made from (mesh_digest.hpp); none before version 3.
  std::optional<std::uint64_t> digest() const { return digest_; }
  const GridTopology& topology() const { return levels_.topo; }
  // Whether its tiles keep the vertices' sources (GridMesh::filled; from version 4).
  bool has_sources() const { return sources_; }
  const MeshLevels& levels() const { return levels_; }
  int level_count() const { return int(tiles_.size()); }
  // Level l's grid, in vertices.
  std::size_t rows(int l) const { return terrain::level_count(levels_.topo.rows - 1, l); }
  std::size_t cols(int l) const { return terrain::level_count(levels_.topo.cols - 1, l); }
  // The vertices of level l's grid rows r0 .. r0 + nr - 1 and columns c0 .. c0 + nc - 1.
  MeshWindow read_window(int l, std::size_t r0, std::size_t c0, std::size_t nr, std::size_t nc);
  // The same into `positions` and `normals` (nr x nc each, row-major), and `sources` when
  // given and the pyramid has them, its tiles decoded in parallel.
  void read_window(int l, std::size_t r0, std::size_t c0, std::size_t nr, std::size_t nc,
                   Eigen::Vector3f* positions, Eigen::Vector3f* normals,
                   std::uint8_t* sources = nullptr);
  // The whole of level l's grid, rows(l) x cols(l) vertices row-major into `positions` and
  // `normals` (read_window's).
  void read_level(int l, Eigen::Vector3f* positions, Eigen::Vector3f* normals);
  // Accounting since the file was opened: bytes read (header and index included) and
  // tiles decoded.
  std::uint64_t bytes_read() const { return bytes_read_; }
  std::size_t tiles_read() const { return tiles_read_; }
  // The stored bytes of tile (tr, tc) of level l.
  std::uint32_t tile_bytes(int l, std::size_t tr, std::size_t tc) const;
  // Decodes and checks every tile of every level (terrain::Error on the first bad one);
  // returns how many.
  std::size_t check_tiles();

 private:
  struct Tile {
    std::uint64_t offset = 0;
    std::uint32_t bytes = 0, crc = 0;
  };
  struct LevelTiles {
    std::size_t tiles_r = 0, tiles_c = 0;
    std::vector<Tile> tiles;
  };
  struct TileData {
    std::vector<Eigen::Vector3f> raw;   // positions, then normals
    std::vector<std::uint8_t> sources;  // empty without
  };
  // Tile (tr, tc) of level l read and checked; its stored bytes added to `bytes`.
  TileData decode_tile(int l, std::size_t tr, std::size_t tc, ZSTD_DCtx* ctx,
                       std::uint64_t& bytes) const;
  // Tiles rows tr0 .. tr1 - 1, columns tc0 .. tc1 - 1 of level l decoded and checked in
  // parallel, each given to `use` (from any thread); the first failure thrown after.
  void decode_tiles(int l, std::size_t tr0, std::size_t tc0, std::size_t tr1, std::size_t tc1,
                    const std::function<void(std::size_t, std::size_t, const TileData&)>& use);
  // The header and tile index of a file of `size` bytes, checked; the parts of the header
  // after its head (magic, version, size, checksum), each from `bytes` at `at` onwards:
  void read_header(std::uint64_t size);
  std::uint32_t read_grid(const std::string& bytes, std::size_t& at);  // returns the levels
  void read_blocks(const std::string& bytes, std::size_t& at, std::uint32_t n_levels);
  void read_tile_index(const std::string& bytes, std::size_t& at, std::uint32_t n_levels,
                       std::uint64_t header_bytes, std::uint64_t size);
  void read_at(void* to, std::size_t n, std::uint64_t offset) const;  // n bytes at offset, or Error
  std::string path_;
  int fd_ = -1;
  int version_ = 0;
  bool sources_ = false;
  std::optional<std::uint64_t> digest_;
  MeshGeoref geo_;
  MeshLevels levels_;
  std::vector<LevelTiles> tiles_;
  std::uint64_t bytes_read_ = 0;
  std::size_t tiles_read_ = 0;
};

}  // namespace terrain
