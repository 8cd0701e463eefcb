// The mesh's levels of detail measured, and the pyramid written as the mesh's rows pass
// (MeshPyramidWriter) or from a whole mesh.
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

namespace {

// The steepest gradient (|n_xy| / n_z) of the plane through a, b, c; infinity when it
// stands vertical or turns over (counter-clockwise seen from above: n_z > 0).
double plane_slope(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d n = (b - a).cross(c - a);
  return n.z() > 0 ? n.head<2>().norm() / n.z() : std::numeric_limits<double>::infinity();
}

// Level `s`'s error and slope over a block (MeshLevelBlock::error and ::slope): the largest
// vertical distance between the block's vertices and the PN surface of its cells at step s
// (the cell's two faces as GridTopology's: NW-SW-SE and NW-SE-NE), and the steepest
// gradient of that surface: of the planes through each face's corners and through the
// surface's samples at the same parameters (each fine cell's two faces).
std::pair<float, float> level_measure(const GridMesh& mesh, const MeshLevelBlock& b,
                                      std::uint32_t s) {
  const std::size_t cols = mesh.topo.cols;
  const auto rs = level_lines(b.nr, s), cs = level_lines(b.nc, s);
  auto at = [&](std::uint32_t r, std::uint32_t c) {
    return (std::size_t(b.r0) + r) * cols + b.c0 + c;
  };
  auto p = [&](std::size_t v) { return Eigen::Vector3d(mesh.positions[v].cast<double>()); };
  auto n = [&](std::size_t v) { return Eigen::Vector3d(mesh.normals[v].cast<double>()); };
  float worst = 0;
  double steepest = 0;
  std::vector<Eigen::Vector3d> q;
  for (std::size_t i = 0; i + 1 < rs.size(); ++i)
    for (std::size_t j = 0; j + 1 < cs.size(); ++j) {
      const std::uint32_t ra = rs[i], rb = rs[i + 1], ca = cs[j], cb = cs[j + 1];
      const std::size_t nw = at(ra, ca), sw = at(rb, ca), se = at(rb, cb), ne = at(ra, cb);
      // The cubic's control points only (the surface's normals are not needed here).
      const auto lower = pn_control_points<double>(p(nw), p(sw), p(se), n(nw), n(sw), n(se));
      const auto upper = pn_control_points<double>(p(nw), p(se), p(ne), n(nw), n(se), n(ne));
      // The planes of its two faces' corners (what a patch drawn flat draws), then those
      // through the cubic's samples.
      steepest =
          std::max({steepest, plane_slope(p(nw), p(sw), p(se)), plane_slope(p(nw), p(se), p(ne))});
      const std::size_t w = cb - ca + 1;
      q.resize((rb - ra + 1) * w);
      for (std::uint32_t r = ra; r <= rb; ++r)
        for (std::uint32_t c = ca; c <= cb; ++c) {
          const double u = double(c - ca) / double(cb - ca), v = double(r - ra) / double(rb - ra);
          Eigen::Vector3d& x = q[(r - ra) * w + (c - ca)];
          x = v >= u ? pn_cubic<double>(lower, 1 - v, v - u, u)
                     : pn_cubic<double>(upper, 1 - u, v, u - v);
          worst = std::max(worst, float(std::abs(x.z() - double(mesh.positions[at(r, c)].z()))));
        }
      for (std::size_t r = 0; r + 1 < rb - ra + 1; ++r)
        for (std::size_t c = 0; c + 1 < w; ++c) {
          const Eigen::Vector3d &a = q[r * w + c], &d = q[(r + 1) * w + c],
                                &e = q[(r + 1) * w + c + 1], &f = q[r * w + c + 1];
          steepest = std::max({steepest, plane_slope(a, d, e), plane_slope(a, e, f)});
        }
    }
  return {worst, float(steepest)};
}

// Whether a vertex of block b lies outside the data (GridMesh::filled).
bool block_has_hole(const GridMesh& mesh, const MeshLevelBlock& b) {
  if (mesh.filled.size() != mesh.n_vertices()) return false;
  for (std::size_t r = b.r0; r <= std::size_t(b.r0) + b.nr; ++r)
    for (std::size_t c = b.c0; c <= std::size_t(b.c0) + b.nc; ++c)
      if (mesh.filled[r * mesh.topo.cols + c] == kOutside) return true;
  return false;
}

// A block's box and its levels' errors and slopes, from `mesh`'s vertices at the block's
// rows and columns (b.r0, b.c0, b.nr, b.nc set). A block with a hole has kHoleError above
// level 0: a coarser level would span the hole.
void measure_block(const GridMesh& mesh, MeshLevelBlock& b) {
  b.lo = Eigen::Vector3f::Constant(1e30f), b.hi = -b.lo;
  // The steepest of the vertex normals and of the mid-edge coefficients of the fine
  // patches' quadratic normals (make_pn_patch's n110, n011, n101) over every edge of its
  // cells: a fine patch's normal is a blend of these and its corners' normals with weights
  // >= 0, so none is steeper than the steepest of them.
  const auto slope = [](const Eigen::Vector3f& n) {
    return n.z() > 0 ? n.head<2>().norm() / n.z() : std::numeric_limits<float>::infinity();
  };
  auto mid_slope = [&](std::size_t i, std::size_t j) {
    const Eigen::Vector3f e = mesh.positions[j] - mesh.positions[i],
                          sum = mesh.normals[i] + mesh.normals[j];
    const float ee = e.squaredNorm();
    return slope(ee > 0 ? Eigen::Vector3f(sum - 2.0f * e.dot(sum) / ee * e) : sum);
  };
  float steepest = 0;
  for (std::uint32_t r = 0; r <= b.nr; ++r)
    for (std::uint32_t c = 0; c <= b.nc; ++c) {
      const std::size_t cols = mesh.topo.cols, v = (std::size_t(b.r0) + r) * cols + b.c0 + c;
      b.lo = b.lo.cwiseMin(mesh.positions[v]), b.hi = b.hi.cwiseMax(mesh.positions[v]);
      steepest = std::max(steepest, slope(mesh.normals[v]));
      if (c < b.nc) steepest = std::max(steepest, mid_slope(v, v + 1));
      if (r < b.nr) steepest = std::max(steepest, mid_slope(v, v + cols));
      if (r < b.nr && c < b.nc) steepest = std::max(steepest, mid_slope(v, v + cols + 1));
    }
  b.error = {0.0f};
  b.slope = {steepest};
  for (std::uint32_t s = 2; s / 2 < std::max(b.nr, b.nc); s *= 2) {
    const auto [error, level_slope] = level_measure(mesh, b, s);
    b.error.push_back(std::max(b.error.back(), error));
    b.slope.push_back(level_slope);
  }
  if (block_has_hole(mesh, b))
    for (std::size_t l = 1; l < b.error.size(); ++l) b.error[l] = kHoleError;
}

// Little-endian scalars (this project's machines are; the format says so).
struct Out {
  std::string bytes;
  template <class T>
  void put(const T& v) {
    bytes.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
};

}  // namespace

MeshLevels build_mesh_levels(const GridMesh& mesh, std::size_t block) {
  MeshLevels h;
  h.topo = mesh.topo;
  h.block = block;
  const std::size_t cells_r = mesh.topo.rows - 1, cells_c = mesh.topo.cols - 1;
  h.block_rows = (cells_r + block - 1) / block;
  h.block_cols = (cells_c + block - 1) / block;
  h.blocks.resize(h.block_rows * h.block_cols);
#pragma omp parallel for schedule(dynamic)
  for (std::ptrdiff_t k = 0; k < std::ptrdiff_t(h.blocks.size()); ++k) {
    MeshLevelBlock& b = h.blocks[std::size_t(k)];
    const std::size_t br = std::size_t(k) / h.block_cols, bc = std::size_t(k) % h.block_cols;
    b.r0 = std::uint32_t(br * block), b.c0 = std::uint32_t(bc * block);
    b.nr = std::uint32_t(std::min(block, cells_r - b.r0)),
    b.nc = std::uint32_t(std::min(block, cells_c - b.c0));
    measure_block(mesh, b);
  }
  return h;
}

struct MeshPyramidWriter::Level {
  std::size_t rows = 0, cols = 0;  // the level's grid, vertices
  std::size_t tiles_r = 0, tiles_c = 0;
  std::size_t next = 0;                   // the next level row to take
  std::size_t tile_row = 0;               // the tile row being filled
  std::vector<Eigen::Vector3f> pos, nrm;  // its rows tile_row B .. (B + 1 rows at most)
  std::vector<std::uint8_t> src;          // their sources, with MeshPyramidWriter's sources
  std::size_t held = 0;                   // rows held
  std::vector<std::uint32_t> bytes, crc;  // per tile, row-major
  std::filesystem::path file;             // levels above 0: its tiles, one after another
  TempRegistration registration;
  std::ofstream out;
};

MeshPyramidWriter::MeshPyramidWriter(const GridTopology& topo, const MeshGeoref& geo,
                                     const std::string& path, std::size_t block,
                                     const std::string& name_like, bool sources)
    : topo_(topo), geo_(geo), path_(path), block_(block), sources_(sources) {
  if (topo.rows < 2 || topo.cols < 2 || block < 2)
    throw Error("cannot write '" + path + "': no cells");
  const std::size_t cells_r = topo.rows - 1, cells_c = topo.cols - 1;
  levels_.topo = topo;
  levels_.block = block;
  levels_.block_rows = (cells_r + block - 1) / block;
  levels_.block_cols = (cells_c + block - 1) / block;
  levels_.blocks.resize(levels_.block_rows * levels_.block_cols);
  int n_levels = 1;
  for (std::size_t k = 0; k < levels_.blocks.size(); ++k) {
    MeshLevelBlock& b = levels_.blocks[k];
    b.r0 = std::uint32_t(k / levels_.block_cols * block),
    b.c0 = std::uint32_t(k % levels_.block_cols * block);
    b.nr = std::uint32_t(std::min(block, cells_r - b.r0)),
    b.nc = std::uint32_t(std::min(block, cells_c - b.c0));
    n_levels = std::max(n_levels, block_levels(b.nr, b.nc));
  }
  // The header's size is known now (finish() writes it): level 0's tiles go straight into
  // the file after it, in the index's order; the coarser levels' into temporary files,
  // appended at the end (a third of level 0's size at most).
  header_bytes_ =
      20 + 4 + 16 + 40 + 4 + 4 + geo.crs_wkt.size() + 8 + 4 + 4 + 4;  // ... digest, flags,
                                                                      // levels, CRC
  for (const MeshLevelBlock& b : levels_.blocks)
    header_bytes_ += 28 + 8 * std::uint64_t(block_levels(b.nr, b.nc));
  for (int l = 0; l < n_levels; ++l) {
    auto v = std::make_unique<Level>();
    v->rows = level_count(cells_r, l), v->cols = level_count(cells_c, l);
    v->tiles_r = (v->rows - 1 + block - 1) / block, v->tiles_c = (v->cols - 1 + block - 1) / block;
    v->pos.resize((block + 1) * v->cols), v->nrm.resize((block + 1) * v->cols);
    if (sources) v->src.resize((block + 1) * v->cols);
    header_bytes_ += 16 + 16 * std::uint64_t(v->tiles_r * v->tiles_c);
    grids_.push_back(std::move(v));
  }
  file_ = std::make_unique<AtomicFile>(path);
  out_.open(file_->temp_path(), std::ios::binary | std::ios::in | std::ios::out | std::ios::trunc);
  out_.seekp(std::streamoff(header_bytes_));
  if (!out_) throw Error("cannot write '" + path + "'");
  for (int l = 1; l < n_levels; ++l) {
    Level& v = *grids_[std::size_t(l)];
    v.file = temporary_sibling(name_like.empty() ? path : name_like);
    v.registration = TempRegistration(v.file);
    v.out.open(v.file, std::ios::binary | std::ios::trunc);
    if (!v.out) throw Error("cannot write '" + v.file.string() + "'");
  }
}

MeshPyramidWriter::~MeshPyramidWriter() {
  for (auto& v : grids_) {
    if (v->file.empty()) continue;
    v->out.close();
    std::error_code ec;
    std::filesystem::remove(v->file, ec);
  }
}

void MeshPyramidWriter::add_rows(const Eigen::Vector3f* positions, const Eigen::Vector3f* normals,
                                 std::size_t n, const std::uint8_t* sources) {
  const std::size_t cells_r = topo_.rows - 1, cells_c = topo_.cols - 1, cols = topo_.cols,
                    B = block_;
  if (sources_ != (sources != nullptr))
    throw Error("internal: a pyramid's rows given with or without their sources unlike its own");
  for (std::size_t k = 0; k < n; ++k, ++row_) {
    if (row_ >= topo_.rows) throw Error("cannot write '" + path_ + "': more rows than the grid's");
    const Eigen::Vector3f *p = positions + k * cols, *q = normals + k * cols;
    digest_.add(p, q, cols);
    for (std::size_t l = 0; l < grids_.size(); ++l) {
      Level& v = *grids_[l];
      if (v.next >= v.rows || row_ != level_index(v.next, cells_r, int(l))) continue;
      for (std::size_t c = 0; c < v.cols; ++c) {
        const std::size_t fc = level_index(c, cells_c, int(l));
        v.pos[v.held * v.cols + c] = p[fc];
        v.nrm[v.held * v.cols + c] = q[fc];
        if (sources_) v.src[v.held * v.cols + c] = sources[k * cols + fc];
      }
      ++v.held, ++v.next;
      const std::size_t r0 = v.tile_row * B, nr = std::min(B, v.rows - 1 - r0) + 1;
      if (v.held < nr) continue;
      if (l == 0) measure_block_row(v, nr);
      flush_tile_row(v, int(l), nr);
    }
  }
}

void MeshPyramidWriter::measure_block_row(const Level& v, std::size_t nr) {
  // The block row's vertices as a mesh of their own, the blocks measured there.
  GridMesh band;
  band.topo = {nr, topo_.cols};
  band.geo = geo_;
  const long n = long(nr * topo_.cols);
  band.positions.assign(v.pos.begin(), v.pos.begin() + n);
  band.normals.assign(v.nrm.begin(), v.nrm.begin() + n);
  if (sources_) band.filled.assign(v.src.begin(), v.src.begin() + n);
  const std::size_t br = block_rows_measured_++;
#pragma omp parallel for schedule(dynamic)
  for (std::ptrdiff_t bc = 0; bc < std::ptrdiff_t(levels_.block_cols); ++bc) {
    MeshLevelBlock& b = levels_.blocks[br * levels_.block_cols + std::size_t(bc)];
    MeshLevelBlock local = b;
    local.r0 = 0;
    measure_block(band, local);
    b.lo = local.lo, b.hi = local.hi, b.error = std::move(local.error),
    b.slope = std::move(local.slope);
  }
}

void MeshPyramidWriter::flush_tile_row(Level& v, int l, std::size_t nr) {
  const std::size_t B = block_, tc_n = v.tiles_c;
  std::vector<std::string> z(tc_n);
#pragma omp parallel for schedule(dynamic)
  for (std::ptrdiff_t tc = 0; tc < std::ptrdiff_t(tc_n); ++tc) {
    const std::size_t c0 = std::size_t(tc) * B, nc = std::min(B, v.cols - 1 - c0) + 1;
    // Positions, normals, then (with sources) one byte a vertex.
    const std::size_t m = nr * nc, vec = sizeof(Eigen::Vector3f);
    std::string raw(2 * m * vec + (sources_ ? m : 0), '\0');
    for (std::size_t r = 0; r < nr; ++r) {
      const std::size_t from = r * v.cols + c0;
      std::memcpy(raw.data() + r * nc * vec, v.pos.data() + from, nc * vec);
      std::memcpy(raw.data() + (m + r * nc) * vec, v.nrm.data() + from, nc * vec);
      if (sources_) std::memcpy(raw.data() + 2 * m * vec + r * nc, v.src.data() + from, nc);
    }
    std::string t(ZSTD_compressBound(raw.size()), '\0');
    const std::size_t n = ZSTD_compress(t.data(), t.size(), raw.data(), raw.size(), 3);
    if (!ZSTD_isError(n))
      t.resize(n);
    else
      t.clear();
    z[std::size_t(tc)] = std::move(t);
  }
  std::ostream& out = l == 0 ? static_cast<std::ostream&>(out_) : v.out;
  for (const std::string& t : z) {
    if (t.empty()) throw Error("cannot compress a pyramid tile");
    out.write(t.data(), std::streamsize(t.size()));
    v.bytes.push_back(std::uint32_t(t.size()));
    v.crc.push_back(crc_of(t));
  }
  if (!out) throw Error("cannot write '" + path_ + "': write failed (disk full?)");
  // The last row is the next tile row's first (border vertices are in both tiles).
  std::copy_n(v.pos.begin() + long((nr - 1) * v.cols), v.cols, v.pos.begin());
  std::copy_n(v.nrm.begin() + long((nr - 1) * v.cols), v.cols, v.nrm.begin());
  if (sources_) std::copy_n(v.src.begin() + long((nr - 1) * v.cols), v.cols, v.src.begin());
  v.held = 1;
  ++v.tile_row;
}

namespace {

// The header before the tile index: magic, version, its size (0 until known), the grid,
// the georeference, the mesh's digest, the flags and the blocks with their levels' errors
// and slopes.
void put_header_head(Out& h, const GridTopology& topo, const MeshGeoref& geo, std::size_t block,
                     std::uint64_t digest, std::uint32_t flags, const MeshLevels& levels,
                     int n_levels) {
  h.bytes.append(kMagic, 8);
  h.put(kVersion);
  h.put(std::uint64_t(0));  // the header's bytes, index included: set by finish
  h.put(std::uint32_t(block));
  h.put(std::uint64_t(topo.rows));
  h.put(std::uint64_t(topo.cols));
  for (double v : {geo.origin_x, geo.origin_y, geo.origin_z, geo.dx, geo.dy}) h.put(v);
  h.put(std::int32_t(geo.epsg));
  h.put(std::uint32_t(geo.crs_wkt.size()));
  h.bytes += geo.crs_wkt;
  h.put(digest);
  h.put(flags);
  h.put(std::uint32_t(n_levels));
  for (const MeshLevelBlock& b : levels.blocks) {
    for (int k = 0; k < 3; ++k) h.put(b.lo[k]);
    for (int k = 0; k < 3; ++k) h.put(b.hi[k]);
    h.put(std::uint32_t(b.levels()));
    for (float e : b.error) h.put(e);
    for (float e : b.slope) h.put(e);
  }
}

}  // namespace

std::uint64_t MeshPyramidWriter::finish() {
  if (row_ != topo_.rows)
    throw Error(
        fmt::format("cannot write '{}': {} of the grid's {} rows given", path_, row_, topo_.rows));
  const int n_levels = int(grids_.size());
  Out h;
  put_header_head(h, topo_, geo_, block_, digest_.value(), sources_ ? kTileSources : 0u, levels_,
                  n_levels);
  std::size_t n_tiles = 0;
  for (const auto& v : grids_) n_tiles += v->bytes.size();
  // The index: per level its tile counts, then per tile offset, bytes, CRC-32.
  const std::uint64_t index_bytes =
      std::uint64_t(n_levels) * 16 + std::uint64_t(n_tiles) * 16 + 4;  // and the CRC
  const std::uint64_t header_bytes = h.bytes.size() + index_bytes;
  if (header_bytes != header_bytes_) throw Error("internal: the pyramid header's size changed");
  std::memcpy(h.bytes.data() + 12, &header_bytes, 8);
  std::uint64_t offset = header_bytes;
  for (auto& v : grids_) {
    if (v->bytes.size() != v->tiles_r * v->tiles_c)
      throw Error("internal: a pyramid level's tiles are missing");
    h.put(std::uint64_t(v->tiles_r));
    h.put(std::uint64_t(v->tiles_c));
    for (std::size_t k = 0; k < v->bytes.size(); ++k) {
      h.put(offset);
      h.put(v->bytes[k]);
      h.put(v->crc[k]);
      offset += v->bytes[k];
    }
    if (v->file.empty()) continue;
    v->out.close();
    if (!v->out) throw Error("cannot write '" + v->file.string() + "' (disk full?)");
  }
  h.put(crc_of(h.bytes));  // of every header byte before it
  // The coarser levels after level 0, then the header before it.
  std::vector<char> buf(std::size_t(1) << 20);
  for (const auto& v : grids_) {
    if (v->file.empty()) continue;
    std::ifstream in(v->file, std::ios::binary);
    while (in) {
      in.read(buf.data(), std::streamsize(buf.size()));
      out_.write(buf.data(), in.gcount());
    }
  }
  out_.seekp(0);
  out_.write(h.bytes.data(), std::streamsize(h.bytes.size()));
  out_.close();
  if (!out_) throw Error("cannot write '" + path_ + "': write failed (disk full?)");
  file_->commit();
  return offset;
}

std::uint64_t write_mesh_pyramid(const GridMesh& mesh, const std::string& path, std::size_t block,
                                 const std::string& name_like) {
  if (mesh.positions.size() != mesh.topo.n_vertices() ||
      mesh.normals.size() != mesh.topo.n_vertices())
    throw Error("cannot write '" + path + "': positions, normals and grid size disagree");
  const bool sources = mesh.filled.size() == mesh.n_vertices();
  MeshPyramidWriter w(mesh.topo, mesh.geo, path, block, name_like, sources);
  w.add_rows(mesh.positions.data(), mesh.normals.data(), mesh.topo.rows,
             sources ? mesh.filled.data() : nullptr);
  return w.finish();
}

}  // namespace terrain
