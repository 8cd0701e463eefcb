#pragma once
// Drainage creases (Mower's Creases algorithm, docs/algorithms.md 9.1), GL-free: the geometry
// the DM pass draws and the score that selects it. The renderer's compute shader
// (crease_score.glsl) evaluates the same formula; these functions are its test reference.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "terrain/drainage_links.hpp"
#include "renderer/frame_params.hpp"
#include "terrain/grid_mesh.hpp"

namespace renderer {

// A drainage network (terrain::DrainageLinks, e.g. from a .dv) in a mesh's local frame.
struct CreaseGeometry {
  std::vector<Eigen::Vector3f> positions;  // #C crease vertices, on the PN surface (local)
  std::vector<Eigen::Vector3f> normals;    // #C unit PN normals of the mesh's surface there
  std::vector<float> flow;                 // #C basin-normalized flow (fc), in (0, 1]
  std::vector<std::uint32_t> segments;     // 2 x #S: (vertex, its downstream vertex)
  std::size_t n_segments() const { return segments.size() / 2; }
};

// Every valid drainage point with its D8 link to its downstream point as one segment (the
// branches of a .dv are exactly these links grouped by order), for points whose
// accumulated flow is at least `min_accumulated` points (a channel-initiation threshold:
// 0 keeps every link, as the paper; hillslope links and the tiny basins along the mesh
// boundary, whose normalized flow is high, go with a small threshold). Positions are moved
// from the database's frame to the mesh's; normals are the PN normals of `mesh` above each
// vertex (pn_point_above; the vertex normal of the nearest mesh vertex where it has no
// answer). Error when the database does not overlap the mesh or their CRSs differ.
CreaseGeometry build_crease_geometry(const terrain::GridMesh& mesh, const terrain::DrainageLinks& links,
                                     std::uint32_t min_accumulated = 0);

// A warning (empty when none) when the network's sample extent differs from the mesh's
// by more than one network spacing on any side: it was made from another mesh (or a
// crop of it), so its creases will not follow this surface everywhere.
std::string coverage_warning(const terrain::GridMesh& mesh, const terrain::DrainageLinks& links);

// rs of one crease vertex (see CreaseScoreParams). `normal` and `light` are unit vectors in
// the exaggerated frame, `distance` is from the eye in that frame.
double crease_score(const Eigen::Vector3d& normal, double flow, const Eigen::Vector3d& light, double distance,
                    const CreaseScoreParams& params);

// The unit normal after scaling z by `exaggeration`: (nx, ny, nz / e) normalized.
Eigen::Vector3d exaggerate_normal(const Eigen::Vector3d& n, double exaggeration);

// Far distance used by the score when params.far_distance is 0.
double default_far_distance(const terrain::GridMesh& mesh);

// Number of segments whose two ends both score >= 0 for the eye `eye` (exaggerated local
// frame) and light direction `light`: what the DM pass draws.
std::size_t count_accepted_segments(const CreaseGeometry& g, const Eigen::Vector3d& eye, const Eigen::Vector3d& light,
                                    double exaggeration, const CreaseScoreParams& params);

}  // namespace renderer
