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

#include "terrain/atomic_file.hpp"
#include "terrain/error.hpp"
#include "terrain/pn_triangle.hpp"
#include "terrain/temp_files.hpp"

namespace terrain {

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

// A block's box and its levels' errors and slopes, from `mesh`'s vertices at the block's
// rows and columns (b.r0, b.c0, b.nr, b.nc set).
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
}

// A block's level count (measure_block's): level 0, then one per step s = 2, 4, ... with
// s / 2 below its longer side.
int block_levels(std::uint32_t nr, std::uint32_t nc) {
  int n = 1;
  for (std::uint32_t s = 2; s / 2 < std::max(nr, nc); s *= 2) ++n;
  return n;
}

constexpr char kMagic[8] = {'T', 'P', 'Y', 'R', 'A', 'M', 'I', 'D'};
// 2: the blocks' slopes; 3: the mesh's digest and the header's CRC-32.
constexpr std::uint32_t kVersion = 3;

// Little-endian scalars (this project's machines are; the format says so).
struct Out {
  std::string bytes;
  template <class T>
  void put(const T& v) {
    bytes.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
};
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
TileRange tile_range(std::size_t rows_l, std::size_t cols_l, std::size_t block, std::size_t tr,
                     std::size_t tc) {
  const std::size_t r0 = tr * block, c0 = tc * block;
  return {r0, c0, std::min(block, rows_l - 1 - r0) + 1, std::min(block, cols_l - 1 - c0) + 1};
}

std::uint32_t crc_of(const std::string& s) {
  return std::uint32_t(crc32(0L, reinterpret_cast<const Bytef*>(s.data()), uInt(s.size())));
}

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
  std::size_t held = 0;                   // rows held
  std::vector<std::uint32_t> bytes, crc;  // per tile, row-major
  std::filesystem::path file;             // levels above 0: its tiles, one after another
  TempRegistration registration;
  std::ofstream out;
};

MeshPyramidWriter::MeshPyramidWriter(const GridTopology& topo, const MeshGeoref& geo,
                                     const std::string& path, std::size_t block,
                                     const std::string& name_like)
    : topo_(topo), geo_(geo), path_(path), block_(block) {
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
      20 + 4 + 16 + 40 + 4 + 4 + geo.crs_wkt.size() + 8 + 4 + 4;  // ... digest, levels, CRC
  for (const MeshLevelBlock& b : levels_.blocks)
    header_bytes_ += 28 + 8 * std::uint64_t(block_levels(b.nr, b.nc));
  for (int l = 0; l < n_levels; ++l) {
    auto v = std::make_unique<Level>();
    v->rows = level_count(cells_r, l), v->cols = level_count(cells_c, l);
    v->tiles_r = (v->rows - 1 + block - 1) / block, v->tiles_c = (v->cols - 1 + block - 1) / block;
    v->pos.resize((block + 1) * v->cols), v->nrm.resize((block + 1) * v->cols);
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
                                 std::size_t n) {
  const std::size_t cells_r = topo_.rows - 1, cells_c = topo_.cols - 1, cols = topo_.cols,
                    B = block_;
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
      }
      ++v.held, ++v.next;
      const std::size_t r0 = v.tile_row * B, nr = std::min(B, v.rows - 1 - r0) + 1;
      if (v.held < nr) continue;
      if (l == 0) measure_block_row(v.pos, v.nrm, nr);
      flush_tile_row(v, int(l), nr);
    }
  }
}

void MeshPyramidWriter::measure_block_row(const std::vector<Eigen::Vector3f>& pos,
                                          const std::vector<Eigen::Vector3f>& nrm, std::size_t nr) {
  // The block row's vertices as a mesh of their own, the blocks measured there.
  GridMesh band;
  band.topo = {nr, topo_.cols};
  band.geo = geo_;
  band.positions.assign(pos.begin(), pos.begin() + long(nr * topo_.cols));
  band.normals.assign(nrm.begin(), nrm.begin() + long(nr * topo_.cols));
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
    std::vector<Eigen::Vector3f> raw(2 * nr * nc);
    for (std::size_t r = 0; r < nr; ++r)
      for (std::size_t c = 0; c < nc; ++c) {
        raw[r * nc + c] = v.pos[r * v.cols + c0 + c];
        raw[nr * nc + r * nc + c] = v.nrm[r * v.cols + c0 + c];
      }
    std::string t(ZSTD_compressBound(raw.size() * sizeof raw[0]), '\0');
    const std::size_t n =
        ZSTD_compress(t.data(), t.size(), raw.data(), raw.size() * sizeof raw[0], 3);
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
  v.held = 1;
  ++v.tile_row;
}

std::uint64_t MeshPyramidWriter::finish() {
  if (row_ != topo_.rows)
    throw Error(
        fmt::format("cannot write '{}': {} of the grid's {} rows given", path_, row_, topo_.rows));
  const int n_levels = int(grids_.size());
  Out h;
  h.bytes.append(kMagic, 8);
  h.put(kVersion);
  h.put(std::uint64_t(0));  // the header's bytes, index included: set below
  h.put(std::uint32_t(block_));
  h.put(std::uint64_t(topo_.rows));
  h.put(std::uint64_t(topo_.cols));
  for (double v : {geo_.origin_x, geo_.origin_y, geo_.origin_z, geo_.dx, geo_.dy}) h.put(v);
  h.put(std::int32_t(geo_.epsg));
  h.put(std::uint32_t(geo_.crs_wkt.size()));
  h.bytes += geo_.crs_wkt;
  h.put(digest_.value());
  h.put(std::uint32_t(n_levels));
  for (const MeshLevelBlock& b : levels_.blocks) {
    for (int k = 0; k < 3; ++k) h.put(b.lo[k]);
    for (int k = 0; k < 3; ++k) h.put(b.hi[k]);
    h.put(std::uint32_t(b.levels()));
    for (float e : b.error) h.put(e);
    for (float e : b.slope) h.put(e);
  }
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
  MeshPyramidWriter w(mesh.topo, mesh.geo, path, block, name_like);
  w.add_rows(mesh.positions.data(), mesh.normals.data(), mesh.topo.rows);
  return w.finish();
}

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
  if (bytes.size() < 20 || version != 3 || header < 24 || header > bytes.size()) return;
  const std::uint64_t B = get(20, std::uint32_t(0)), rows = get(24, std::uint64_t(0)),
                      cols = get(32, std::uint64_t(0));
  if (B < 2 || rows < 2 || cols < 2 || rows > (1u << 30) || cols > (1u << 30)) return;
  std::uint64_t at = 84;  // after magic, version, size, B, grid, georeference, EPSG
  at += 4 + std::uint64_t(get(at, std::uint32_t(0))) + 8;  // the CRS, the digest
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

void MeshPyramid::read_header(std::uint64_t size) {
  const std::string& path = path_;
  const auto corrupt = [&](const char* what) {
    return Error(fmt::format("cannot read '{}': corrupt mesh pyramid ({})", path, what));
  };
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
  if (header_bytes < 20 || header_bytes > size)
    throw Error("cannot read '" + path + "': truncated mesh pyramid");
  bytes.resize(std::size_t(header_bytes));
  read_at(bytes.data() + 20, std::size_t(header_bytes - 20), 20);
  if (version >= 3) {  // the CRC-32 of the header before it, in its last 4 bytes
    if (header_bytes < 24) throw corrupt("its header");
    std::uint32_t crc = 0;
    std::memcpy(&crc, bytes.data() + header_bytes - 4, 4);
    if (crc_of(bytes.substr(0, std::size_t(header_bytes - 4))) != crc)
      throw corrupt("its header's checksum");
    bytes.resize(std::size_t(header_bytes - 4));
  }
  const std::size_t B = in.get<std::uint32_t>();
  const std::uint64_t rows = in.get<std::uint64_t>(), cols = in.get<std::uint64_t>();
  if (B < 2 || B > (1u << 16) || rows < 2 || cols < 2 || rows > (1u << 30) || cols > (1u << 30) ||
      rows * cols >= (std::uint64_t(1) << 32))
    throw corrupt("its grid");
  geo_.origin_x = in.get<double>(), geo_.origin_y = in.get<double>(),
  geo_.origin_z = in.get<double>();
  geo_.dx = in.get<double>(), geo_.dy = in.get<double>();
  geo_.epsg = in.get<std::int32_t>();
  if (!georef_in_range(GridTopology{std::size_t(rows), std::size_t(cols)}, geo_) || geo_.epsg < 0)
    throw corrupt("its georeference");
  const std::size_t wkt = in.get<std::uint32_t>();
  if (wkt > bytes.size() - in.at) throw Error("cannot read '" + path + "': truncated mesh pyramid");
  geo_.crs_wkt = bytes.substr(in.at, wkt);
  in.at += wkt;
  if (version >= 3) digest_ = in.get<std::uint64_t>();
  const std::uint32_t n_levels = in.get<std::uint32_t>();
  if (n_levels < 1 || n_levels > 32) throw corrupt("its levels");
  levels_.topo = GridTopology{std::size_t(rows), std::size_t(cols)};
  levels_.block = B;
  levels_.block_rows = (std::size_t(rows) - 1 + B - 1) / B;
  levels_.block_cols = (std::size_t(cols) - 1 + B - 1) / B;
  // Every count against the bytes left before anything is allocated: a block takes at
  // least 28 + 4 (version 1) or 28 + 8 bytes, a level's index 16 and a tile 16.
  const std::uint64_t n_blocks = std::uint64_t(levels_.block_rows) * levels_.block_cols;
  if (n_blocks > (bytes.size() - in.at) / 32)
    throw Error("cannot read '" + path + "': truncated mesh pyramid");
  levels_.blocks.resize(std::size_t(n_blocks));
  for (std::size_t k = 0; k < levels_.blocks.size(); ++k) {
    MeshLevelBlock& b = levels_.blocks[k];
    b.r0 = std::uint32_t(k / levels_.block_cols * B),
    b.c0 = std::uint32_t(k % levels_.block_cols * B);
    b.nr = std::uint32_t(std::min<std::uint64_t>(B, rows - 1 - b.r0));
    b.nc = std::uint32_t(std::min<std::uint64_t>(B, cols - 1 - b.c0));
    for (int j = 0; j < 3; ++j) b.lo[j] = in.get<float>();
    for (int j = 0; j < 3; ++j) b.hi[j] = in.get<float>();
    if (!b.lo.allFinite() || !b.hi.allFinite() || (b.lo.array() > b.hi.array()).any())
      throw corrupt("a block's box");
    const std::uint32_t nl = in.get<std::uint32_t>();
    if (nl < 1 || nl > n_levels || int(nl) != block_levels(b.nr, b.nc))
      throw corrupt("a block's levels");
    if (std::uint64_t(nl) * (version >= 2 ? 8 : 4) > bytes.size() - in.at)
      throw Error("cannot read '" + path + "': truncated mesh pyramid");
    b.error.resize(nl);
    for (float& e : b.error) e = in.get<float>();
    // Errors: 0 at level 0, finite and non-decreasing; slopes >= 0 (infinite where a
    // surface turns over).
    for (std::size_t j = 0; j < nl; ++j)
      if (!std::isfinite(b.error[j]) ||
          (j == 0 ? b.error[j] != 0 : !(b.error[j] >= b.error[j - 1])))
        throw corrupt("a block's errors");
    if (version >= 2) {  // version 1: not known
      b.slope.resize(nl);
      for (float& e : b.slope) e = in.get<float>();
      for (const float e : b.slope)
        if (!(e >= 0)) throw corrupt("a block's slopes");
    }
  }
  int coarsest = 1;
  for (const MeshLevelBlock& b : levels_.blocks) coarsest = std::max(coarsest, b.levels());
  if (int(n_levels) != coarsest) throw corrupt("its levels");
  tiles_.assign(n_levels, {});
  std::uint64_t end = header_bytes;  // the tiles follow the header, one after another
  for (std::uint32_t l = 0; l < n_levels; ++l) {
    LevelTiles& t = tiles_[l];
    t.tiles_r = in.get<std::uint64_t>(), t.tiles_c = in.get<std::uint64_t>();
    if (t.tiles_r != (this->rows(int(l)) - 1 + B - 1) / B ||
        t.tiles_c != (this->cols(int(l)) - 1 + B - 1) / B)
      throw corrupt("its tile counts");
    if (t.tiles_r * t.tiles_c > (bytes.size() - in.at) / 16)
      throw Error("cannot read '" + path + "': truncated mesh pyramid");
    t.tiles.resize(t.tiles_r * t.tiles_c);
    for (Tile& tile : t.tiles) {
      tile.offset = in.get<std::uint64_t>(), tile.bytes = in.get<std::uint32_t>(),
      tile.crc = in.get<std::uint32_t>();
      if (tile.offset > size || tile.bytes > size - tile.offset)
        throw Error("cannot read '" + path + "': truncated mesh pyramid");
      if (version >= 3 && tile.offset != end) throw corrupt("its tile index");
      end = tile.offset + tile.bytes;
    }
  }
  if (in.at != bytes.size()) throw corrupt("its header's size");
  if (version >= 3 && end != size)
    throw Error("cannot read '" + path + "': truncated mesh pyramid, or bytes after its tiles");
  bytes_read_ = header_bytes;
}

std::uint32_t MeshPyramid::tile_bytes(int l, std::size_t tr, std::size_t tc) const {
  const LevelTiles& t = tiles_.at(std::size_t(l));
  return t.tiles.at(tr * t.tiles_c + tc).bytes;
}

std::vector<Eigen::Vector3f> MeshPyramid::decode_tile(int l, std::size_t tr, std::size_t tc,
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
  std::vector<Eigen::Vector3f> raw(2 * t.nr * t.nc);  // positions, then normals
  const std::size_t got =
      ZSTD_decompressDCtx(ctx, raw.data(), raw.size() * sizeof raw[0], z.data(), z.size());
  if (ZSTD_isError(got) || got != raw.size() * sizeof raw[0]) throw bad("its data");
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
  return raw;
}

MeshWindow MeshPyramid::read_window(int l, std::size_t r0, std::size_t c0, std::size_t nr,
                                    std::size_t nc) {
  MeshWindow w;
  w.rows = nr, w.cols = nc;
  w.positions.resize(nr * nc);
  w.normals.resize(nr * nc);
  read_window(l, r0, c0, nr, nc, w.positions.data(), w.normals.data());
  return w;
}

void MeshPyramid::decode_tiles(
    int l, std::size_t tr0, std::size_t tc0, std::size_t tr1, std::size_t tc1,
    const std::function<void(std::size_t, std::size_t, const std::vector<Eigen::Vector3f>&)>& use) {
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
                              Eigen::Vector3f* positions, Eigen::Vector3f* normals) {
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
  decode_tiles(l, tr0, tc0, tr1 + 1, tc1 + 1,
               [&](std::size_t tr, std::size_t tc, const std::vector<Eigen::Vector3f>& raw) {
                 const TileRange t = tile_range(rows(l), cols(l), B, tr, tc);
                 const std::size_t ca = std::max(c0, t.c0), cb = std::min(c0 + nc, t.c0 + t.nc);
                 for (std::size_t r = std::max(r0, t.r0); r < std::min(r0 + nr, t.r0 + t.nr); ++r) {
                   const std::size_t to = (r - r0) * nc + (ca - c0),
                                     from = (r - t.r0) * t.nc + (ca - t.c0);
                   std::copy_n(raw.begin() + long(from), cb - ca, positions + to);
                   std::copy_n(raw.begin() + long(t.nr * t.nc + from), cb - ca, normals + to);
                 }
               });
}

std::size_t MeshPyramid::check_tiles() {
  std::size_t n = 0;
  for (int l = 0; l < level_count(); ++l) {
    const LevelTiles& lt = tiles_[std::size_t(l)];
    decode_tiles(l, 0, 0, lt.tiles_r, lt.tiles_c,
                 [](std::size_t, std::size_t, const std::vector<Eigen::Vector3f>&) {});
    n += lt.tiles.size();
  }
  return n;
}

void MeshPyramid::read_level(int l, Eigen::Vector3f* positions, Eigen::Vector3f* normals) {
  if (l < 0 || l >= level_count()) throw Error(fmt::format("'{}': no level {}", path_, l));
  read_window(l, 0, 0, rows(l), cols(l), positions, normals);
}

}  // namespace terrain
