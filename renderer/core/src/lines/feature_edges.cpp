#include "renderer/core/feature_edges.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <unordered_map>

#include <Eigen/Geometry>

namespace renderer {

std::vector<MeshEdge> mesh_edges(const terrain::GridTopology& topo) {
  std::vector<MeshEdge> edges;
  edges.reserve((topo.rows - 1) * topo.cols + topo.rows * (topo.cols - 1) + topo.n_cells());
  std::unordered_map<std::uint64_t, std::size_t> seen;  // undirected edge -> its index
  seen.reserve(edges.capacity());
  for (std::size_t f = 0; f < topo.n_faces(); ++f) {
    const auto t = topo.face(f);
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = t[std::size_t(k)], b = t[std::size_t((k + 1) % 3)],
                          c = t[std::size_t((k + 2) % 3)];
      const std::uint64_t key = (std::uint64_t(std::min(a, b)) << 32) | std::max(a, b);
      const auto [it, inserted] = seen.try_emplace(key, edges.size());
      if (inserted)
        edges.push_back({a, b, c, MeshEdge::kNoVertex});
      else
        edges[it->second].v3 = c;  // the second face: its third vertex
    }
  }
  return edges;
}

std::vector<std::uint8_t> classify_edges(std::span<const MeshEdge> edges,
                                         std::span<const Eigen::Vector3f> positions,
                                         const Viewpoint& viewer, double crease_angle_deg) {
  const double cos_crease = std::cos(crease_angle_deg * std::numbers::pi / 180.0);
  std::vector<std::uint8_t> kinds(edges.size(), 0);
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const MeshEdge& e = edges[i];
    const Eigen::Vector3d p0 = positions[e.v0].cast<double>(), p1 = positions[e.v1].cast<double>();
    const Eigen::Vector3d na = (p1 - p0).cross(positions[e.v2].cast<double>() - p0).normalized();
    const Eigen::Vector3d to_eye = viewer.to_eye(p0);
    const double fa = na.dot(to_eye);
    if (e.boundary()) {
      kinds[i] = std::uint8_t(kBoundaryEdge | (fa > 0 ? kFacingEye : 0));
      continue;
    }
    const Eigen::Vector3d nb = (p0 - p1).cross(positions[e.v3].cast<double>() - p1).normalized();
    const double fb = nb.dot(to_eye);
    if (fa * fb < 0) kinds[i] |= kContourEdge;
    if (na.dot(nb) < cos_crease) kinds[i] |= kCreaseEdge;
    if (fa > 0 || fb > 0) kinds[i] |= kFacingEye;
  }
  return kinds;
}

std::vector<std::uint32_t> vertex_edges(std::span<const MeshEdge> edges, std::size_t n_vertices) {
  std::vector<std::uint32_t> slots(n_vertices * kVertexEdgeSlots, MeshEdge::kNoVertex);
  std::vector<std::uint8_t> used(n_vertices, 0);
  for (std::size_t i = 0; i < edges.size(); ++i)
    for (const std::uint32_t v : {edges[i].v0, edges[i].v1}) {
      if (used[v] == kVertexEdgeSlots) throw std::logic_error("a vertex with more than 6 edges");
      slots[v * kVertexEdgeSlots + used[v]++] = std::uint32_t(i);
    }
  return slots;
}

}  // namespace renderer
