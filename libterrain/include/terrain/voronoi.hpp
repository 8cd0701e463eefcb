#pragma once
// Mixed Voronoi areas (Meyer, Desbrun, Schroeder & Barr 2001/2003; docs/algorithms.md 4) and
// vertex tangent frames: the per-vertex weights photic extremum lines need to move face
// gradients to vertices (docs/algorithms.md 5.3).
#include <Eigen/Core>

#include "terrain/grid_mesh.hpp"

namespace terrain {

// Mixed Voronoi area of each corner of the triangle (p0, p1, p2), in that order:
//   no obtuse angle: A_P = (|P-R|^2 cot Q + |P-Q|^2 cot R) / 8 (the Voronoi region);
//   obtuse at P: area / 2; obtuse elsewhere: area / 4.
// The three sum to the triangle's area; each is >= 0; a degenerate triangle gives 0s.
// Tested: docs/algorithms.md 4.2 worked examples (acute, right, obtuse).
Eigen::Vector3d mixed_voronoi_corners(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                                      const Eigen::Vector3d& p2);

// Corner areas of every face (#F x 3, face(f) order), vertex totals (#V) and tangents
// (#V: t1 = normalize(e x n) for the edge e to the east neighbour, or the west one on the
// last column, projected off n; t2 = n x t1) of a grid mesh, from its positions and
// vertex normals. Computed in double, stored as float. Tested: vertex areas sum to the
// mesh area (real and jittered meshes with obtuse triangles), an interior vertex of a
// regular planar grid gets one cell's area, corners are >= 0.
VoronoiWeights voronoi_weights(const GridMesh& mesh);

// The same sums in double precision, for checks: {sum of vertex areas, sum of face areas}.
std::pair<double, double> voronoi_area_sums(const GridMesh& mesh);

}  // namespace terrain
