#include "renderer/crease.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "terrain/error.hpp"
#include "terrain/pn_surface.hpp"

namespace renderer {

CreaseGeometry build_crease_geometry(const terrain::GridMesh& mesh, const terrain::DrainageLinks& links,
                                     std::uint32_t min_accumulated) {
  using terrain::DrainageLinks;
  const auto& g = mesh.geo;
  if (links.epsg != 0 && g.epsg != 0 && links.epsg != g.epsg)
    throw terrain::Error("the drainage database (EPSG:" + std::to_string(links.epsg) + ") and the mesh (EPSG:" +
                         std::to_string(g.epsg) + ") are in different CRSs");
  const Eigen::Vector3d shift = links.origin - Eigen::Vector3d(g.origin_x, g.origin_y, g.origin_z);
  const std::size_t n = links.size();

  // Compact index of every valid point.
  std::vector<std::uint32_t> compact(n, DrainageLinks::kNone);
  CreaseGeometry out;
  for (std::size_t i = 0; i < n; ++i) {
    if (!links.valid[i]) continue;
    compact[i] = std::uint32_t(out.positions.size());
    out.positions.emplace_back((links.positions[i].cast<double>() + shift).cast<float>());
    out.flow.push_back(links.flow[i]);
  }
  const std::size_t m = out.positions.size();
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t d = links.downstream[i];
    if (compact[i] == DrainageLinks::kNone || d == DrainageLinks::kNone || d >= n || compact[d] == DrainageLinks::kNone ||
        links.accumulated[i] < min_accumulated)
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

std::string coverage_warning(const terrain::GridMesh& mesh, const terrain::DrainageLinks& h) {
  const auto& g = mesh.geo;
  // Sample extents in world coordinates: west, south, east, north.
  const double m[4] = {g.origin_x, g.origin_y - double(mesh.topo.rows - 1) * g.dy,
                       g.origin_x + double(mesh.topo.cols - 1) * g.dx, g.origin_y};
  const double d[4] = {h.origin.x(), h.origin.y() - double(h.rows - 1) * h.dy,
                       h.origin.x() + double(h.cols - 1) * h.dx, h.origin.y()};
  const double tol = std::max(h.dx, h.dy);
  for (int k = 0; k < 4; ++k)
    if (std::abs(m[k] - d[k]) > tol)
      return fmt::format("the drainage database covers x {:.1f}..{:.1f}, y {:.1f}..{:.1f}, the mesh x {:.1f}..{:.1f}, "
                         "y {:.1f}..{:.1f}: it was not made from this mesh",
                         d[0], d[2], d[1], d[3], m[0], m[2], m[1], m[3]);
  return {};
}

}  // namespace renderer
