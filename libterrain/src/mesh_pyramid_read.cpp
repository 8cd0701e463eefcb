// A terrain mesh read from its pyramid (mesh_pyramid.hpp) when the pyramid beside the PLY
// was made from it: the level and window a view needs, checked as the PLY's vertices are.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include "mesh_io_internal.hpp"
#include "terrain/mesh_io.hpp"
#include "terrain/mesh_pyramid.hpp"

namespace terrain {

using namespace detail;

namespace {

// The PLY's data that its pyramid does not keep: empty when it has none. A pyramid with
// its vertices' sources keeps 'filled' (and the faces follow from it).
std::string unkept_data(const PlyHeader& header, bool sources) {
  for (const PlyElement& e : header.elements)
    for (const PlyProperty& p : e.properties)
      if (!(e.name == "vertex" &&
            (p.name == "x" || p.name == "y" || p.name == "z" || p.name == "nx" || p.name == "ny" ||
             p.name == "nz" || (sources && p.name == "filled"))) &&
          !(e.name == "face" && p.name == "vertex_indices"))
        return "the mesh has data its pyramid does not keep (" + e.name + " property '" + p.name +
               "')";
  return {};
}

bool header_has_filled(const PlyHeader& header) {
  const PlyElement* v = header.find("vertex");
  return v && v->find("filled");
}

// Why the pyramid at `pyr` was not made from the mesh `m` (its PLY's `header`): empty when
// it was. The pair is one when the pyramid was made from the vertices the PLY holds: both
// carry the digest of those vertices (dem2mesh writes it into both).
std::string other_mesh(const MeshPyramid& pyramid, const PlyHeader& header, const GridMesh& m,
                       const std::string& pyr) {
  const std::optional<std::uint64_t> digest = header_digest(header);
  if (!pyramid.digest())
    return fmt::format(
        "'{}' (version {}) does not say which mesh it was made from; dem2mesh --pyramid makes one "
        "that does",
        pyr, pyramid.version());
  if (!digest || *digest != *pyramid.digest())
    return "'" + pyr +
           "' was made from another mesh than this one (their digests differ; dem2mesh --pyramid "
           "again)";
  const MeshGeoref& g = pyramid.georef();
  auto same = [](double a, double b) {
    return std::abs(a - b) <= 1e-9 * std::max(1.0, std::abs(a));
  };
  if (pyramid.topology().rows != m.topo.rows || pyramid.topology().cols != m.topo.cols ||
      !same(g.origin_x, m.geo.origin_x) || !same(g.origin_y, m.geo.origin_y) ||
      !same(g.origin_z, m.geo.origin_z) || !same(g.dx, m.geo.dx) || !same(g.dy, m.geo.dy) ||
      g.epsg != m.geo.epsg)
    return "'" + pyr + "' describes another grid than the mesh's";
  return {};
}

// A window read (level-0 cells from row R0, column C0; blocks br0 .. br1 - 1, bc0 .. bc1 - 1
// of `all`) moved into its own frame, its first vertex at the origin, with its blocks and
// where it lies in the whole mesh (MeshLevels::window); `fine` the same.
void to_window_frame(PyramidMesh& out, GridMesh& fine, const MeshLevels& all, std::size_t R0,
                     std::size_t C0, std::size_t br0, std::size_t br1, std::size_t bc0,
                     std::size_t bc1) {
  GridMesh& m = out.mesh;
  const Eigen::Vector3f shift(float(double(C0) * fine.geo.dx), float(-double(R0) * fine.geo.dy),
                              0.0f);
  MeshLevels::Window w{R0, C0, all.topo, fine.geo, {}, {}};
  for (std::size_t i = 0; i < m.n_vertices(); ++i) m.positions[i] -= shift;
  m.geo.origin_x += double(C0) * fine.geo.dx;
  m.geo.origin_y -= double(R0) * fine.geo.dy;
  fine.geo.origin_x = m.geo.origin_x, fine.geo.origin_y = m.geo.origin_y;
  w.lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max());
  w.hi = -w.lo;
  for (const MeshLevelBlock& b : all.blocks)
    w.lo = w.lo.cwiseMin(b.lo - shift), w.hi = w.hi.cwiseMax(b.hi - shift);
  out.levels.topo = fine.topo;
  out.levels.block_rows = br1 - br0, out.levels.block_cols = bc1 - bc0;
  out.levels.blocks.clear();
  for (std::size_t br = br0; br < br1; ++br)
    for (std::size_t bc = bc0; bc < bc1; ++bc) {
      MeshLevelBlock b = all.blocks[br * all.block_cols + bc];
      b.r0 -= std::uint32_t(R0), b.c0 -= std::uint32_t(C0);
      b.lo -= shift, b.hi -= shift;
      out.levels.blocks.push_back(std::move(b));
    }
  out.levels.window = w;
}

}  // namespace

std::optional<PyramidMesh> read_mesh_via_pyramid(
    const std::string& ply_path, std::string& why,
    const std::function<PyramidPart(const MeshPyramid&)>& part) {
  namespace fs = std::filesystem;
  why.clear();
  const std::string pyr = pyramid_path_of(ply_path);
  std::error_code ec;
  if (pyr == ply_path || !fs::is_regular_file(pyr, ec) || !is_mesh_pyramid(pyr))
    return std::nullopt;
  PlyHeader header;
  std::ifstream in;
  PyramidMesh out{read_terrain_header(ply_path, header, in), {}, 0};
  in.close();
  GridMesh& m = out.mesh;
  MeshPyramid pyramid(pyr);
  if (why = unkept_data(header, pyramid.has_sources()); !why.empty()) return std::nullopt;
  if (why = other_mesh(pyramid, header, m, pyr); !why.empty()) return std::nullopt;
  out.digest = *pyramid.digest();
  const PyramidPart want = part ? part(pyramid) : PyramidPart{};
  const int l = std::clamp(want.level, 0, pyramid.level_count() - 1);
  const MeshLevels& all = pyramid.levels();
  const std::size_t B = all.block, rows0 = m.topo.rows - 1, cols0 = m.topo.cols - 1;
  // The window's blocks, and its level-0 cells: whole blocks, so level l's lines (B is a
  // multiple of 2^l; a level too coarse for that reads the whole level).
  const std::size_t br0 = std::min(want.br0, all.block_rows - 1),
                    br1 = std::clamp(want.br1, br0 + 1, all.block_rows);
  const std::size_t bc0 = std::min(want.bc0, all.block_cols - 1),
                    bc1 = std::clamp(want.bc1, bc0 + 1, all.block_cols);
  const bool window = (br0 > 0 || bc0 > 0 || br1 < all.block_rows || bc1 < all.block_cols) &&
                      B % (std::size_t(1) << l) == 0;
  const std::size_t R0 = window ? br0 * B : 0, C0 = window ? bc0 * B : 0;
  const std::size_t R1 = window ? std::min(br1 * B, rows0) : rows0,
                    C1 = window ? std::min(bc1 * B, cols0) : cols0;
  GridMesh fine;  // the grid held at level 0, what its vertices are checked against
  fine.topo = GridTopology{R1 - R0 + 1, C1 - C0 + 1}, fine.geo = m.geo;
  const std::size_t r0 = R0 >> l, c0 = C0 >> l;  // level l's first row and column of the window
  const std::size_t rows = (R1 == rows0 ? pyramid.rows(l) - 1 : R1 >> l) - r0 + 1;
  const std::size_t cols = (C1 == cols0 ? pyramid.cols(l) - 1 : C1 >> l) - c0 + 1;
  // The whole level's spacing: its extent over its cells.
  m.geo.dx *= double(cols0) / double(pyramid.cols(l) - 1);
  m.geo.dy *= double(rows0) / double(pyramid.rows(l) - 1);
  m.topo = GridTopology{rows, cols};
  m.positions.resize(m.topo.n_vertices());
  m.normals.resize(m.topo.n_vertices());
  // Sources only where the PLY has them: a pyramid's of a mesh without are all data.
  if (pyramid.has_sources() && header_has_filled(header)) m.filled.resize(m.topo.n_vertices());
  pyramid.read_window(l, r0, c0, rows, cols, m.positions.data(), m.normals.data(),
                      m.filled.empty() ? nullptr : m.filled.data());
  out.levels = all;
  out.levels.base = l;
  if (window) to_window_frame(out, fine, all, R0, C0, br0, br1, bc0, bc1);
  check_vertices(m, pyr, l, &fine);
  return out;
}

}  // namespace terrain
