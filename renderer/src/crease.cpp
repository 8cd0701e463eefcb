#include "renderer/crease.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "drainage/d8.hpp"
#include "terrain/error.hpp"
#include "terrain/pn_surface.hpp"

namespace renderer {

CreaseGeometry build_crease_geometry(const terrain::GridMesh& mesh, const drainage::DrainageDb& db,
                                     std::uint32_t min_accumulated) {
  const auto& h = db.header;
  const auto& g = mesh.geo;
  if (h.epsg != 0 && g.epsg != 0 && h.epsg != g.epsg)
    throw terrain::Error("the drainage database (EPSG:" + std::to_string(h.epsg) + ") and the mesh (EPSG:" +
                         std::to_string(g.epsg) + ") are in different CRSs");
  const Eigen::Vector3d shift(h.origin_x - g.origin_x, h.origin_y - g.origin_y, h.origin_z - g.origin_z);
  const std::size_t n = db.vertices.size();

  // Compact index of every valid vertex.
  std::vector<std::uint32_t> compact(n, drainage::kNone);
  CreaseGeometry out;
  for (std::size_t i = 0; i < n; ++i) {
    const auto& v = db.vertices[i];
    if (v.point_class == std::uint8_t(drainage::PointClass::Nodata)) continue;
    compact[i] = std::uint32_t(out.positions.size());
    out.positions.emplace_back((Eigen::Vector3d(v.x, v.y, v.z) + shift).cast<float>());
    out.flow.push_back(v.normalized);
  }
  const std::size_t m = out.positions.size();
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t d = db.vertices[i].downstream;
    if (compact[i] == drainage::kNone || d == drainage::kNone || d >= n || compact[d] == drainage::kNone ||
        db.vertices[i].accumulated < min_accumulated)
      continue;
    out.segments.push_back(compact[i]);
    out.segments.push_back(compact[d]);
  }

  // PN normals above each vertex.
  out.normals.resize(m);
  std::size_t inside = 0;
#pragma omp parallel for schedule(dynamic, 4096) reduction(+ : inside)
  for (std::size_t i = 0; i < m; ++i) {
    const Eigen::Vector3f& p = out.positions[i];
    const auto sp = terrain::pn_point_above(mesh, p.x(), p.y());
    if (sp) {
      out.normals[i] = sp->normal.cast<float>();
      ++inside;
    } else {
      const double c = std::clamp(std::round(p.x() / g.dx), 0.0, double(mesh.topo.cols - 1));
      const double r = std::clamp(std::round(-p.y() / g.dy), 0.0, double(mesh.topo.rows - 1));
      out.normals[i] = mesh.normals[std::size_t(r) * mesh.topo.cols + std::size_t(c)];
    }
  }
  if (m > 0 && inside == 0)
    throw terrain::Error("the drainage database does not overlap the mesh (no drainage vertex lies on it)");
  return out;
}

Eigen::Vector3d exaggerate_normal(const Eigen::Vector3d& n, double e) {
  return Eigen::Vector3d(n.x(), n.y(), n.z() / e).normalized();
}

double crease_score(const Eigen::Vector3d& n, double flow, const Eigen::Vector3d& light, double distance,
                    const CreaseScoreParams& p) {
  const double sc = 1.0 - n.z(), ic = 1.0 - n.dot(light);
  const double divisor = p.literal_divisor ? 3.0 : (p.sw + p.iw + p.fw);
  const double raw = (p.sw * sc + p.iw * ic + p.fw * flow) / divisor;
  const double rs_min =
      p.min_score + (1.0 - p.min_score) * p.falloff * std::clamp(distance / p.far_distance, 0.0, 1.0);
  return raw - rs_min;
}

double default_far_distance(const terrain::GridMesh& mesh) {
  return std::hypot(double(mesh.topo.cols - 1) * mesh.geo.dx, double(mesh.topo.rows - 1) * mesh.geo.dy);
}

std::size_t count_accepted_segments(const CreaseGeometry& g, const Eigen::Vector3d& eye, const Eigen::Vector3d& light,
                                    double e, const CreaseScoreParams& params) {
  std::vector<char> ok(g.positions.size());
  for (std::size_t i = 0; i < ok.size(); ++i) {
    const Eigen::Vector3d p = g.positions[i].cast<double>();
    const Eigen::Vector3d pe(p.x(), p.y(), p.z() * e);
    ok[i] = crease_score(exaggerate_normal(g.normals[i].cast<double>(), e), g.flow[i], light, (pe - eye).norm(),
                         params) >= 0.0;
  }
  std::size_t count = 0;
  for (std::size_t s = 0; s < g.n_segments(); ++s) count += ok[g.segments[2 * s]] && ok[g.segments[2 * s + 1]];
  return count;
}

std::string coverage_warning(const terrain::GridMesh& mesh, const drainage::DvHeader& h) {
  const auto& g = mesh.geo;
  // Sample extents in world coordinates: west, south, east, north.
  const double m[4] = {g.origin_x, g.origin_y - double(mesh.topo.rows - 1) * g.dy,
                       g.origin_x + double(mesh.topo.cols - 1) * g.dx, g.origin_y};
  const double d[4] = {h.origin_x, h.origin_y - double(h.rows - 1) * h.dy, h.origin_x + double(h.cols - 1) * h.dx,
                       h.origin_y};
  const double tol = std::max(h.dx, h.dy);
  for (int k = 0; k < 4; ++k)
    if (std::abs(m[k] - d[k]) > tol)
      return fmt::format("the drainage database covers x {:.1f}..{:.1f}, y {:.1f}..{:.1f}, the mesh x {:.1f}..{:.1f}, "
                         "y {:.1f}..{:.1f}: it was not made from this mesh",
                         d[0], d[2], d[1], d[3], m[0], m[2], m[1], m[3]);
  return {};
}

}  // namespace renderer
