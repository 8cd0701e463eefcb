#include "terrain/grid_mesh.hpp"

#include <omp.h>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "terrain/error.hpp"

namespace terrain {

bool georef_in_range(const GridTopology& topo, const MeshGeoref& geo) {
  return geo.dx >= 1e-3 && geo.dy >= 1e-3 && geo.dx <= 1e6 && geo.dy <= 1e6 &&
         double(topo.cols - 1) * geo.dx <= 1e8 && double(topo.rows - 1) * geo.dy <= 1e8 &&
         std::abs(geo.origin_x) <= 1e8 && std::abs(geo.origin_y) <= 1e8 &&
         std::abs(geo.origin_z) <= 1e8;
}

Eigen::Vector3d face_normal(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                            const Eigen::Vector3d& p2) {
  const Eigen::Vector3d n = (p1 - p0).cross(p2 - p0);
  const double len = n.norm();
  return len > 0.0 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::Zero();
}

NormalWeighting parse_normal_weighting(const std::string& name) {
  if (name == "uniform" || name == "paper") return NormalWeighting::Uniform;
  if (name == "angle") return NormalWeighting::Angle;
  if (name == "area") return NormalWeighting::Area;
  throw Error("unknown normal weighting '" + name + "' (use uniform, angle or area)");
}

const char* to_string(NormalWeighting w) {
  switch (w) {
    case NormalWeighting::Uniform:
      return "uniform";
    case NormalWeighting::Angle:
      return "angle";
    case NormalWeighting::Area:
      return "area";
  }
  return "?";
}

namespace {

// What one face gives each of its corners, computed once per face.
struct FaceTerms {
  Eigen::Vector3d unit = Eigen::Vector3d::Zero();   // unit normal (zero if degenerate)
  Eigen::Vector3d cross = Eigen::Vector3d::Zero();  // (p1 - p0) x (p2 - p0): 2 * area * unit
  double angle[3] = {0, 0, 0};                      // corner angles (Angle weighting only)

  Eigen::Vector3d at_corner(int k, NormalWeighting w) const {
    switch (w) {
      case NormalWeighting::Uniform:
        return unit;
      case NormalWeighting::Area:
        return cross;
      case NormalWeighting::Angle:
        return unit * angle[k];
    }
    return unit;
  }
};

// Terms of both faces of every cell of cell row `cr`: out[2*c + k].
void cell_row_terms(const Eigen::Vector3f* positions, const GridTopology& topo, std::size_t cr,
                    NormalWeighting w, std::vector<FaceTerms>& out) {
  out.resize(2 * (topo.cols - 1));
  for (std::size_t c = 0; c + 1 < topo.cols; ++c)
    for (int k = 0; k < 2; ++k) {
      // GridTopology::face without its divisions: (NW, SW, SE), then (NW, SE, NE).
      const std::size_t nw = cr * topo.cols + c, sw = nw + topo.cols;
      const std::size_t f[3] = {nw, k == 0 ? sw : sw + 1, k == 0 ? sw + 1 : nw + 1};
      const Eigen::Vector3d p[3] = {positions[f[0]].cast<double>(), positions[f[1]].cast<double>(),
                                    positions[f[2]].cast<double>()};
      FaceTerms& t = out[2 * c + std::size_t(k)];
      t.cross = (p[1] - p[0]).cross(p[2] - p[0]);
      const double len = t.cross.norm();
      if (!(len > 0.0)) {  // degenerate or no-data: contributes nothing
        t = FaceTerms{};
        continue;
      }
      t.unit = t.cross / len;
      if (w == NormalWeighting::Angle)
        for (int i = 0; i < 3; ++i) {
          const Eigen::Vector3d e1 = p[(i + 1) % 3] - p[i], e2 = p[(i + 2) % 3] - p[i];
          t.angle[i] = std::atan2(e1.cross(e2).norm(), e1.dot(e2));
        }
    }
}

// Unit normals of both faces of every cell of cell row `cr`, lane 2*c + k: cell_row_terms'
// `unit` with the same operations in the same order (the same doubles), a face per SIMD
// lane - the Uniform rule's whole cost.
struct UnitRow {
  std::vector<double> x, y, z;
  Eigen::Vector3d at(std::size_t i) const { return {x[i], y[i], z[i]}; }
};

void cell_row_units(const Eigen::Vector3f* positions, std::size_t cols, std::size_t cr,
                    UnitRow& out) {
  const std::size_t n = 2 * (cols - 1);
  out.x.resize(n), out.y.resize(n), out.z.resize(n);
  double *ux = out.x.data(), *uy = out.y.data(), *uz = out.z.data();
  const float* p = positions[cr * cols].data();  // rows cr and cr + 1, xyz interleaved
  const std::size_t below = 3 * cols;
#pragma omp simd
  for (std::size_t i = 0; i < n; ++i) {
    // Face i of the row: cell c = i / 2, (NW, SW, SE) when i is even, else (NW, SE, NE).
    const std::size_t c = i / 2, nw = 3 * c, f1 = (i % 2 == 0) ? below + nw : below + nw + 3,
                      f2 = (i % 2 == 0) ? below + nw + 3 : nw + 3;
    const double x0 = p[nw], y0 = p[nw + 1], z0 = p[nw + 2];
    const double e1x = p[f1] - x0, e1y = p[f1 + 1] - y0, e1z = p[f1 + 2] - z0;
    const double e2x = p[f2] - x0, e2y = p[f2 + 1] - y0, e2z = p[f2 + 2] - z0;
    const double cx = e1y * e2z - e1z * e2y, cy = e1z * e2x - e1x * e2z, cz = e1x * e2y - e1y * e2x;
    const double len = std::sqrt(cx * cx + cy * cy + cz * cz);
    const bool ok = len > 0.0;  // degenerate or no-data: contributes nothing
    ux[i] = ok ? cx / len : 0.0;
    uy[i] = ok ? cy / len : 0.0;
    uz[i] = ok ? cz / len : 0.0;
  }
}

// Normals of vertex rows [r_begin, r_end) of the grid mesh `positions` into normals[r * cols + c]
// (serial). A window of two cell rows (above and below the vertex row) slides down the band,
// so every face is evaluated about once. term(row, i, k): face i's term at its corner k.
template <class Row, class Fill, class Term>
void normals_of_rows(const GridTopology& topo, std::size_t r_begin, std::size_t r_end,
                     Eigen::Vector3f* normals, const Fill& fill, const Term& term) {
  const std::size_t rows = topo.rows, cols = topo.cols;
  Row above, below;
  if (r_begin < r_end && r_begin > 0) fill(r_begin - 1, above);
  for (std::size_t r = r_begin; r < r_end; ++r) {
    if (r + 1 < rows) fill(r, below);
    for (std::size_t c = 0; c < cols; ++c) {
      // Faces around vertex (r, c) and the vertex's corner in each (grid_mesh.hpp):
      // cell (r-1,c-1): SE of both faces (corner 2 of face 0, corner 1 of face 1);
      // cell (r-1,c): SW, face 0 corner 1; cell (r,c-1): NE, face 1 corner 2;
      // cell (r,c): NW, corner 0 of both faces.
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      if (r > 0 && c > 0) sum += term(above, 2 * (c - 1), 2) + term(above, 2 * (c - 1) + 1, 1);
      if (r > 0 && c + 1 < cols) sum += term(above, 2 * c, 1);
      if (r + 1 < rows && c > 0) sum += term(below, 2 * (c - 1) + 1, 2);
      if (r + 1 < rows && c + 1 < cols) sum += term(below, 2 * c, 0) + term(below, 2 * c + 1, 0);
      const double len = sum.norm();
      normals[r * cols + c] =
          len > 0.0 ? Eigen::Vector3f((sum / len).cast<float>()) : Eigen::Vector3f(0, 0, 1);
    }
    std::swap(above, below);
  }
}

void normals_of_rows(const Eigen::Vector3f* positions, const GridTopology& topo, NormalWeighting w,
                     std::size_t r_begin, std::size_t r_end, Eigen::Vector3f* normals) {
  if (w == NormalWeighting::Uniform) {
    normals_of_rows<UnitRow>(
        topo, r_begin, r_end, normals,
        [&](std::size_t cr, UnitRow& row) { cell_row_units(positions, topo.cols, cr, row); },
        [](const UnitRow& row, std::size_t i, int) { return row.at(i); });
    return;
  }
  normals_of_rows<std::vector<FaceTerms>>(
      topo, r_begin, r_end, normals,
      [&](std::size_t cr, std::vector<FaceTerms>& row) {
        cell_row_terms(positions, topo, cr, w, row);
      },
      [w](const std::vector<FaceTerms>& row, std::size_t i, int k) {
        return row[i].at_corner(k, w);
      });
}

void check_meshable(const Grid& grid) {
  if (grid.rows < 2 || grid.cols < 2) throw Error("a mesh needs at least 2 x 2 samples");
  if (const std::size_t nd = grid.count_nodata(); nd > 0)
    throw Error("cannot mesh a grid with " + std::to_string(nd) + " no-data samples");
}

}  // namespace

BigVector<Eigen::Vector3f> vertex_normals(const BigVector<Eigen::Vector3f>& positions,
                                          const GridTopology& topo, NormalWeighting weighting) {
  if (positions.size() != topo.n_vertices() || topo.rows < 2 || topo.cols < 2)
    throw Error("vertex_normals: positions do not match the grid topology");
  BigVector<Eigen::Vector3f> normals(positions.size());
  // Each thread takes a contiguous band of vertex rows.
#pragma omp parallel
  {
    const std::size_t nt = std::size_t(omp_get_num_threads()),
                      t = std::size_t(omp_get_thread_num());
    normals_of_rows(positions.data(), topo, weighting, topo.rows * t / nt, topo.rows * (t + 1) / nt,
                    normals.data());
  }
  return normals;
}

GridMeshRows::GridMeshRows(const Grid& grid, NormalWeighting weighting)
    : grid_(grid), weighting_(weighting) {
  check_meshable(grid);
}

std::pair<const Eigen::Vector3f*, const Eigen::Vector3f*> GridMeshRows::rows(std::size_t r0,
                                                                             std::size_t r1) {
  const std::size_t cols = grid_.cols, a = r0 > 0 ? r0 - 1 : 0, b = std::min(grid_.rows, r1 + 1);
  if (r0 >= r1 || r1 > grid_.rows) throw Error("GridMeshRows: rows outside the grid");
  // The band with a row of halo on each side: its own normals equal the whole grid's on
  // every row but the halo's, as a vertex's normal needs only the cell rows beside it.
  window_.resize((b - a) * cols);
  for (std::size_t r = a; r < b; ++r)
    for (std::size_t c = 0; c < cols; ++c)
      window_[(r - a) * cols + c] = grid_vertex(r, c, grid_.geo.dx, grid_.geo.dy, grid_.at(r, c));
  window_normals_.resize(window_.size());
  normals_of_rows(window_.data(), GridTopology{b - a, cols}, weighting_, r0 - a, r1 - a,
                  window_normals_.data());
  return {window_.data() + (r0 - a) * cols, window_normals_.data() + (r0 - a) * cols};
}

void GridMeshRows::rows(std::size_t r0, std::size_t r1, Eigen::Vector3f* positions,
                        Eigen::Vector3f* normals) {
  const auto [p, n] = rows(r0, r1);
  std::copy(p, p + (r1 - r0) * grid_.cols, positions);
  std::copy(n, n + (r1 - r0) * grid_.cols, normals);
}

bool GridMesh::face_kept(std::size_t f) const {
  if (filled.size() != topo.n_vertices()) return true;
  for (const std::uint32_t v : topo.face(f))
    if (filled[v] == kOutside) return false;
  return true;
}

std::vector<std::uint32_t> GridMesh::kept_faces() const {
  std::vector<std::uint32_t> kept;
  kept.reserve(n_faces());
  for (std::size_t f = 0; f < n_faces(); ++f)
    if (face_kept(f)) kept.push_back(std::uint32_t(f));
  return kept;
}

std::vector<std::array<std::uint32_t, 2>> GridMesh::outline_edges() const {
  std::vector<std::array<std::uint32_t, 2>> edges;
  if (!has_holes()) return edges;
  for (const std::uint32_t f : kept_faces())
    for (int k = 0; k < 3; ++k) {
      const std::size_t g = topo.face_across(f, k);
      if (g == GridTopology::kNoFace || face_kept(g)) continue;
      const auto t = topo.face(f);  // the edge opposite corner k
      edges.push_back({t[std::size_t((k + 1) % 3)], t[std::size_t((k + 2) % 3)]});
    }
  return edges;
}

bool GridMesh::has_holes() const {
  return std::find(filled.begin(), filled.end(), std::uint8_t(kOutside)) != filled.end();
}

GridMesh grid_mesh_frame(const Georef& geo, std::size_t rows, std::size_t cols) {
  GridMesh m;
  m.topo = {rows, cols};
  m.geo.crs_wkt = geo.crs_wkt;
  m.geo.epsg = geo.epsg;
  m.geo.origin_x = geo.x_of_col(0);
  m.geo.origin_y = geo.y_of_row(0);
  m.geo.origin_z = 0.0;
  m.geo.dx = geo.dx;
  m.geo.dy = geo.dy;
  return m;
}

GridMesh grid_mesh_frame(const Grid& grid) {
  return grid_mesh_frame(grid.geo, grid.rows, grid.cols);
}

GridMesh make_grid_mesh(const Grid& grid, NormalWeighting weighting) {
  check_meshable(grid);
  GridMesh m = grid_mesh_frame(grid);
  m.positions.resize(grid.size());
  const long rows = long(grid.rows), cols = long(grid.cols);
#pragma omp parallel for schedule(static)
  for (long r = 0; r < rows; ++r)
    for (long c = 0; c < cols; ++c)
      m.positions[std::size_t(r * cols + c)] =
          grid_vertex(std::size_t(r), std::size_t(c), grid.geo.dx, grid.geo.dy,
                      grid.at(std::size_t(r), std::size_t(c)));
  m.normals = vertex_normals(m.positions, m.topo, weighting);
  return m;
}

Grid mesh_to_grid(const GridMesh& mesh) {
  Georef geo;
  geo.crs_wkt = mesh.geo.crs_wkt;
  geo.epsg = mesh.geo.epsg;
  geo.crs_kind = mesh.geo.crs_wkt.empty() ? CrsKind::None : CrsKind::Projected;
  geo.dx = mesh.geo.dx;
  geo.dy = mesh.geo.dy;
  geo.x0 = mesh.geo.origin_x - mesh.geo.dx / 2;
  geo.y0 = mesh.geo.origin_y + mesh.geo.dy / 2;
  Grid g(mesh.topo.rows, mesh.topo.cols, geo);
  for (std::size_t v = 0; v < mesh.positions.size(); ++v)
    g.z[v] = float(mesh.geo.origin_z + double(mesh.positions[v].z()));
  return g;
}

}  // namespace terrain
