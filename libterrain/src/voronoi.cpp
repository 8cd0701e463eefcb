#include "terrain/voronoi.hpp"

#include <Eigen/Geometry>
#include <cmath>

namespace terrain {

using Eigen::Vector3d;

Vector3d mixed_voronoi_corners(const Vector3d& p0, const Vector3d& p1, const Vector3d& p2) {
  const Vector3d e0 = p2 - p1, e1 = p0 - p2, e2 = p1 - p0;  // e_i opposite corner i
  const double area = 0.5 * e2.cross(-e1).norm();
  if (!(area > 0)) return Vector3d::Zero();
  // Angle at corner i is obtuse when the dot product of its two edges is negative.
  const double d0 = e2.dot(-e1), d1 = e0.dot(-e2), d2 = e1.dot(-e0);
  if (d0 < 0) return {area / 2, area / 4, area / 4};
  if (d1 < 0) return {area / 4, area / 2, area / 4};
  if (d2 < 0) return {area / 4, area / 4, area / 2};
  // cot of the angle at corner i = d_i / (2 area).
  const double c0 = d0 / (2 * area), c1 = d1 / (2 * area), c2 = d2 / (2 * area);
  const double l0 = e0.squaredNorm(), l1 = e1.squaredNorm(), l2 = e2.squaredNorm();
  return {(l1 * c1 + l2 * c2) / 8, (l2 * c2 + l0 * c0) / 8, (l0 * c0 + l1 * c1) / 8};
}

namespace {
Vector3d corners_of(const GridMesh& m, std::size_t f) {
  const auto t = m.topo.face(f);
  return mixed_voronoi_corners(m.positions[t[0]].cast<double>(), m.positions[t[1]].cast<double>(),
                               m.positions[t[2]].cast<double>());
}
}  // namespace

VoronoiWeights voronoi_weights(const GridMesh& m) {
  VoronoiWeights w;
  const std::size_t nf = m.n_faces(), nv = m.n_vertices();
  w.corner_areas.resize(nf);
#pragma omp parallel for schedule(static)
  for (std::size_t f = 0; f < nf; ++f) w.corner_areas[f] = corners_of(m, f).cast<float>();
  w.vertex_areas.resize(nv);
  w.tangents.resize(nv);
  const std::size_t cols = m.topo.cols;
#pragma omp parallel for schedule(static)
  for (std::size_t v = 0; v < nv; ++v) {
    std::array<std::uint32_t, 6> faces;
    std::array<std::uint8_t, 6> corners;
    const int k = m.topo.vertex_faces(v, faces, corners);
    double a = 0;
    for (int i = 0; i < k; ++i)
      a += double(w.corner_areas[faces[std::size_t(i)]][corners[std::size_t(i)]]);
    w.vertex_areas[v] = float(a);
    const Vector3d n = m.normals[v].cast<double>();
    const std::size_t c = v % cols;
    const Vector3d e = c + 1 < cols
                           ? Vector3d((m.positions[v + 1] - m.positions[v]).cast<double>())
                           : Vector3d((m.positions[v] - m.positions[v - 1]).cast<double>());
    Vector3d t = e - e.dot(n) * n;  // the edge projected into the tangent plane: t1 points east
    if (t.norm() < 1e-12) t = Vector3d::UnitX() - n.x() * n;
    w.tangents[v] = t.normalized().cast<float>();
  }
  return w;
}

std::pair<double, double> voronoi_area_sums(const GridMesh& m) {
  double vertex_sum = 0, face_sum = 0;
  for (std::size_t v = 0; v < m.n_vertices(); ++v) {
    std::array<std::uint32_t, 6> faces;
    std::array<std::uint8_t, 6> corners;
    const int k = m.topo.vertex_faces(v, faces, corners);
    for (int i = 0; i < k; ++i)
      vertex_sum += corners_of(m, faces[std::size_t(i)])[corners[std::size_t(i)]];
  }
  for (std::size_t f = 0; f < m.n_faces(); ++f) {
    const auto t = m.topo.face(f);
    const Vector3d a = m.positions[t[0]].cast<double>(), b = m.positions[t[1]].cast<double>(),
                   c = m.positions[t[2]].cast<double>();
    face_sum += 0.5 * (b - a).cross(c - a).norm();
  }
  return {vertex_sum, face_sum};
}

}  // namespace terrain
