#include "terrain/grid_mesh.hpp"

#include <Eigen/Geometry>
#include <cmath>

#include "terrain/error.hpp"

namespace terrain {

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

// The faces around vertex (r, c): the cell offset (dr, dc) relative to the vertex, the
// face k in that cell, and the position of the vertex among the face's corners.
struct Incidence {
  int dr, dc, k, corner;
};
// Cell (r-1,c-1): vertex is SE, in both faces (corner 2 of (NW,SW,SE), corner 1 of
// (NW,SE,NE)); cell (r-1,c): vertex is SW, face 0 corner 1; cell (r,c-1): vertex is NE,
// face 1 corner 2; cell (r,c): vertex is NW, corner 0 of both faces.
constexpr Incidence kIncidences[6] = {{-1, -1, 0, 2}, {-1, -1, 1, 1}, {-1, 0, 0, 1},
                                      {0, -1, 1, 2},  {0, 0, 0, 0},   {0, 0, 1, 0}};

}  // namespace

std::vector<Eigen::Vector3f> vertex_normals(const std::vector<Eigen::Vector3f>& positions,
                                            const GridTopology& topo, NormalWeighting weighting) {
  if (positions.size() != topo.n_vertices())
    throw Error("vertex_normals: positions do not match the grid topology");
  std::vector<Eigen::Vector3f> normals(positions.size());
  const long rows = long(topo.rows), cols = long(topo.cols);
#pragma omp parallel for schedule(static)
  for (long r = 0; r < rows; ++r) {
    for (long c = 0; c < cols; ++c) {
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for (const Incidence& inc : kIncidences) {
        const long cr = r + inc.dr, cc = c + inc.dc;
        if (cr < 0 || cc < 0 || cr >= rows - 1 || cc >= cols - 1) continue;
        const auto f = topo.face(topo.face_of_cell(std::size_t(cr), std::size_t(cc), inc.k));
        // Corners (v, q, s) counter-clockwise starting at this vertex.
        const Eigen::Vector3d v = positions[f[inc.corner]].cast<double>();
        const Eigen::Vector3d q = positions[f[(inc.corner + 1) % 3]].cast<double>();
        const Eigen::Vector3d s = positions[f[(inc.corner + 2) % 3]].cast<double>();
        const Eigen::Vector3d e1 = q - v, e2 = s - v, cross = e1.cross(e2);
        const double len = cross.norm();
        if (!(len > 0.0)) continue;
        switch (weighting) {
          case NormalWeighting::Uniform: sum += cross / len; break;
          case NormalWeighting::Area: sum += cross; break;
          case NormalWeighting::Angle: sum += cross / len * std::atan2(len, e1.dot(e2)); break;
        }
      }
      const double len = sum.norm();
      normals[std::size_t(r * cols + c)] =
          len > 0.0 ? Eigen::Vector3f((sum / len).cast<float>()) : Eigen::Vector3f(0, 0, 1);
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
      m.positions[std::size_t(r * cols + c)] = Eigen::Vector3f(
          float(double(c) * grid.geo.dx), float(-double(r) * grid.geo.dy), grid.at(std::size_t(r), std::size_t(c)));
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
