#include "terrain/grid_mesh.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <omp.h>

#include "terrain/error.hpp"

namespace terrain {

bool georef_in_range(const GridTopology& topo, const MeshGeoref& geo) {
  return geo.dx >= 1e-3 && geo.dy >= 1e-3 && geo.dx <= 1e6 && geo.dy <= 1e6 &&
         double(topo.cols - 1) * geo.dx <= 1e8 && double(topo.rows - 1) * geo.dy <= 1e8 &&
         std::abs(geo.origin_x) <= 1e8 && std::abs(geo.origin_y) <= 1e8 && std::abs(geo.origin_z) <= 1e8;
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
    case NormalWeighting::Uniform: return "uniform";
    case NormalWeighting::Angle: return "angle";
    case NormalWeighting::Area: return "area";
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
      case NormalWeighting::Uniform: return unit;
      case NormalWeighting::Area: return cross;
      case NormalWeighting::Angle: return unit * angle[k];
    }
    return unit;
  }
};

// Terms of both faces of every cell of cell row `cr`: out[2*c + k].
void cell_row_terms(const BigVector<Eigen::Vector3f>& positions, const GridTopology& topo, std::size_t cr,
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

}  // namespace

BigVector<Eigen::Vector3f> vertex_normals(const BigVector<Eigen::Vector3f>& positions,
                                            const GridTopology& topo, NormalWeighting weighting) {
  if (positions.size() != topo.n_vertices() || topo.rows < 2 || topo.cols < 2)
    throw Error("vertex_normals: positions do not match the grid topology");
  BigVector<Eigen::Vector3f> normals(positions.size());
  const std::size_t rows = topo.rows, cols = topo.cols;
  // Each thread takes a contiguous band of vertex rows and slides a window of two cell
  // rows (above and below the vertex row) over it, so every face is evaluated about once.
#pragma omp parallel
  {
    const std::size_t nt = std::size_t(omp_get_num_threads()), t = std::size_t(omp_get_thread_num());
    const std::size_t r_begin = rows * t / nt, r_end = rows * (t + 1) / nt;
    std::vector<FaceTerms> above, below;
    if (r_begin < r_end && r_begin > 0) cell_row_terms(positions, topo, r_begin - 1, weighting, above);
    for (std::size_t r = r_begin; r < r_end; ++r) {
      if (r + 1 < rows) cell_row_terms(positions, topo, r, weighting, below);
      for (std::size_t c = 0; c < cols; ++c) {
        // Faces around vertex (r, c) and the vertex's corner in each (grid_mesh.hpp):
        // cell (r-1,c-1): SE of both faces (corner 2 of face 0, corner 1 of face 1);
        // cell (r-1,c): SW, face 0 corner 1; cell (r,c-1): NE, face 1 corner 2;
        // cell (r,c): NW, corner 0 of both faces.
        Eigen::Vector3d sum = Eigen::Vector3d::Zero();
        if (r > 0 && c > 0)
          sum += above[2 * (c - 1)].at_corner(2, weighting) + above[2 * (c - 1) + 1].at_corner(1, weighting);
        if (r > 0 && c + 1 < cols) sum += above[2 * c].at_corner(1, weighting);
        if (r + 1 < rows && c > 0) sum += below[2 * (c - 1) + 1].at_corner(2, weighting);
        if (r + 1 < rows && c + 1 < cols)
          sum += below[2 * c].at_corner(0, weighting) + below[2 * c + 1].at_corner(0, weighting);
        const double len = sum.norm();
        normals[r * cols + c] = len > 0.0 ? Eigen::Vector3f((sum / len).cast<float>()) : Eigen::Vector3f(0, 0, 1);
      }
      std::swap(above, below);
    }
  }
  return normals;
}

GridMesh make_grid_mesh(const Grid& grid, NormalWeighting weighting) {
  if (grid.rows < 2 || grid.cols < 2) throw Error("a mesh needs at least 2 x 2 samples");
  if (const std::size_t nd = grid.count_nodata(); nd > 0)
    throw Error("cannot mesh a grid with " + std::to_string(nd) + " no-data samples");
  GridMesh m;
  m.topo = {grid.rows, grid.cols};
  m.geo.crs_wkt = grid.geo.crs_wkt;
  m.geo.epsg = grid.geo.epsg;
  m.geo.origin_x = grid.geo.x_of_col(0);
  m.geo.origin_y = grid.geo.y_of_row(0);
  m.geo.origin_z = 0.0;
  m.geo.dx = grid.geo.dx;
  m.geo.dy = grid.geo.dy;
  m.positions.resize(grid.size());
  const long rows = long(grid.rows), cols = long(grid.cols);
#pragma omp parallel for schedule(static)
  for (long r = 0; r < rows; ++r)
    for (long c = 0; c < cols; ++c)
      m.positions[std::size_t(r * cols + c)] = grid_vertex(std::size_t(r), std::size_t(c), grid.geo.dx, grid.geo.dy,
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
