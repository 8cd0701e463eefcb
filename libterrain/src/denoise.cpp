#include "terrain/denoise.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>

namespace terrain {

using Eigen::Vector3d;
using Eigen::Vector3f;

namespace {

struct FaceGeom {
  Vector3d centroid;
  double area;
};

FaceGeom face_geom(const GridMesh& m, std::size_t f) {
  const auto t = m.topo.face(f);
  const Vector3d a = m.positions[t[0]].cast<double>(), b = m.positions[t[1]].cast<double>(),
                 c = m.positions[t[2]].cast<double>();
  return {(a + b + c) / 3.0, 0.5 * (b - a).cross(c - a).norm()};
}

// Faces sharing at least one vertex with f (f excluded); returns the count (<= 12 on a grid)
// and marks in `shared` how many vertices each shares.
int face_neighbours(const GridTopology& topo, std::size_t f, std::array<std::uint32_t, 18>& out,
                    std::array<int, 18>& shared) {
  int n = 0;
  for (const std::uint32_t v : topo.face(f)) {
    std::array<std::uint32_t, 6> faces;
    std::array<std::uint8_t, 6> corners;
    const int k = topo.vertex_faces(v, faces, corners);
    for (int i = 0; i < k; ++i) {
      const std::uint32_t g = faces[std::size_t(i)];
      if (g == f) continue;
      int j = 0;
      while (j < n && out[std::size_t(j)] != g) ++j;
      if (j == n) out[std::size_t(n)] = g, shared[std::size_t(n++)] = 0;
      ++shared[std::size_t(j)];
    }
  }
  return n;
}

// Angle between two vectors; atan2 keeps small angles exact (acos of a dot product of
// float unit vectors reads 0.03 degrees for identical ones).
double angle_deg(const Vector3f& a, const Vector3f& b) {
  const Vector3d x = a.cast<double>(), y = b.cast<double>();
  return std::atan2(x.cross(y).norm(), x.dot(y)) * 180.0 / std::numbers::pi;
}

}  // namespace

BigVector<Vector3f> face_normals(const GridMesh& m) {
  BigVector<Vector3f> n(m.n_faces());
#pragma omp parallel for schedule(static)
  for (std::size_t f = 0; f < m.n_faces(); ++f) {
    const auto t = m.topo.face(f);
    const Vector3d fn =
        face_normal(m.positions[t[0]].cast<double>(), m.positions[t[1]].cast<double>(),
                    m.positions[t[2]].cast<double>());
    n[f] = fn.squaredNorm() > 0 ? fn.cast<float>() : Vector3f(0, 0, 1);
  }
  return n;
}

BigVector<Vector3f> bilateral_filter_normals(const GridMesh& m, const BigVector<Vector3f>& normals,
                                             const DenoiseOptions& o, double& sigma_s_used,
                                             const Progress& progress) {
  const std::size_t nf = m.n_faces();
  if (normals.size() != nf) throw Error("bilateral_filter_normals: one normal per face expected");
  std::vector<FaceGeom> geom(nf);
#pragma omp parallel for schedule(static)
  for (std::size_t f = 0; f < nf; ++f) geom[f] = face_geom(m, f);

  double sigma_s = o.sigma_s;
  if (!(sigma_s > 0)) {  // mean centroid distance of edge-adjacent pairs
    double sum = 0;
    std::size_t count = 0;
#pragma omp parallel for schedule(static) reduction(+ : sum, count)
    for (std::size_t f = 0; f < nf; ++f) {
      std::array<std::uint32_t, 18> nb;
      std::array<int, 18> shared;
      const int k = face_neighbours(m.topo, f, nb, shared);
      for (int i = 0; i < k; ++i)
        if (shared[std::size_t(i)] == 2)
          sum += (geom[f].centroid - geom[nb[std::size_t(i)]].centroid).norm(), ++count;
    }
    sigma_s = count ? sum / double(count) : 1.0;
  }
  sigma_s_used = sigma_s;
  const double ks = 1.0 / (2 * sigma_s * sigma_s);
  const double kr = o.sigma_r > 0 ? 1.0 / (2 * o.sigma_r * o.sigma_r) : 0.0;

  BigVector<Vector3f> cur = normals, next(nf);
  for (int it = 0; it < o.iterations; ++it) {
#pragma omp parallel for schedule(static)
    for (std::size_t f = 0; f < nf; ++f) {
      std::array<std::uint32_t, 18> nb;
      std::array<int, 18> shared;
      const int k = face_neighbours(m.topo, f, nb, shared);
      const Vector3d ni = cur[f].cast<double>();
      Vector3d sum = Vector3d::Zero();
      for (int i = 0; i < k; ++i) {
        const std::size_t j = nb[std::size_t(i)];
        const Vector3d nj = cur[j].cast<double>();
        const double dc = (geom[f].centroid - geom[j].centroid).squaredNorm();
        const double dn = (ni - nj).squaredNorm();
        sum += geom[j].area * std::exp(-dc * ks - dn * kr) * nj;
      }
      const double len = sum.norm();
      next[f] = len > 0 ? Vector3f((sum / len).cast<float>()) : cur[f];
    }
    std::swap(cur, next);
    report(progress, double(it + 1) / double(std::max(o.iterations, 1)));
  }
  return cur;
}

// Vertex updating (Zheng et al. 2011): `iterations` rounds moving each interior vertex's
// height towards the planes of its faces' filtered normals; x, y and the boundary fixed.
static void update_vertices(GridMesh& m, const BigVector<Vector3f>& filtered, int iterations) {
  const std::size_t nv = m.n_vertices(), rows = m.topo.rows, cols = m.topo.cols;
  BigVector<Vector3f> next = m.positions;  // only interior z values change
  std::vector<Vector3d> centroid(m.n_faces());
  for (int it = 0; it < iterations; ++it) {
#pragma omp parallel for schedule(static)
    for (std::size_t f = 0; f < centroid.size(); ++f) centroid[f] = face_geom(m, f).centroid;
#pragma omp parallel for schedule(static)
    for (std::size_t v = 0; v < nv; ++v) {
      const std::size_t r = v / cols, c = v % cols;
      if (r == 0 || c == 0 || r + 1 == rows || c + 1 == cols) continue;  // boundary fixed
      std::array<std::uint32_t, 6> faces;
      std::array<std::uint8_t, 6> corners;
      const int k = m.topo.vertex_faces(v, faces, corners);
      const Vector3d x = m.positions[v].cast<double>();
      Vector3d step = Vector3d::Zero();
      for (int i = 0; i < k; ++i) {
        const std::size_t f = faces[std::size_t(i)];
        const Vector3d n = filtered[f].cast<double>();
        step += n * n.dot(centroid[f] - x);
      }
      next[v].z() = float(x.z() + step.z() / double(k));
    }
    std::swap(m.positions, next);  // both hold the same x, y and boundary z
  }
}

DenoiseStats denoise_normals(GridMesh& m, const DenoiseOptions& o, const Progress& progress) {
  if (o.iterations < 0 || o.vertex_iterations < 0) throw Error("iterations must be >= 0");
  if (!(o.sigma_s >= 0) || !std::isfinite(o.sigma_s))
    throw Error("sigma_s must be a finite width in metres > 0 (or 0 for the default), not " +
                std::to_string(o.sigma_s));
  if (!(o.sigma_r >= 0) || !std::isfinite(o.sigma_r))
    throw Error("sigma_r must be a finite width >= 0, not " + std::to_string(o.sigma_r));
  DenoiseStats stats;
  // The change is measured between vertex normals built by the same rule (area-weighted
  // face normals) before and after filtering, so it shows the filter alone, not a change
  // of weighting (dem2mesh's default is uniform weights).
  const BigVector<Vector3f> before =
      o.iterations > 0 ? vertex_normals(m.positions, m.topo, NormalWeighting::Area) : m.normals;
  const BigVector<Vector3f> filtered = bilateral_filter_normals(
      m, face_normals(m), o, stats.sigma_s, sub_progress(progress, 0, 0.8));
  const std::size_t nv = m.n_vertices();
  if (o.update_vertices && o.iterations > 0) {
    const BigVector<Vector3f> original = m.positions;
    update_vertices(m, filtered, o.vertex_iterations);
    for (std::size_t v = 0; v < nv; ++v)
      stats.max_vertex_shift =
          std::max(stats.max_vertex_shift, double((m.positions[v] - original[v]).norm()));
    m.normals = vertex_normals(m.positions, m.topo, NormalWeighting::Area);
  } else if (o.iterations > 0) {
#pragma omp parallel for schedule(static)
    for (std::size_t v = 0; v < nv; ++v) {
      std::array<std::uint32_t, 6> faces;
      std::array<std::uint8_t, 6> corners;
      const int k = m.topo.vertex_faces(v, faces, corners);
      Vector3d sum = Vector3d::Zero();
      for (int i = 0; i < k; ++i)
        sum += face_geom(m, faces[std::size_t(i)]).area *
               filtered[faces[std::size_t(i)]].cast<double>();
      if (sum.norm() > 0) m.normals[v] = sum.normalized().cast<float>();
    }
  }
  m.normal_change.resize(nv);
  m.normal_fit = {};  // the normals are no longer the fitted ones
  double total = 0;
  for (std::size_t v = 0; v < nv; ++v) {
    const double a = angle_deg(before[v], m.normals[v]);
    m.normal_change[v] = float(a);
    total += a;
    stats.max_change_deg = std::max(stats.max_change_deg, a);
  }
  stats.mean_change_deg = nv ? total / double(nv) : 0;
  report(progress, 1.0);
  return stats;
}

}  // namespace terrain
