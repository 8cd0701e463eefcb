#pragma once
// Bilateral normal filtering (Zheng, Fu, Au & Tai 2011, IEEE TVCG 17(10); docs/algorithms.md 6)
// on a grid mesh: face normals are smoothed with a spatial Gaussian on face-centroid
// distance, a range Gaussian on normal difference and face-area weights, over the faces
// sharing a vertex with the face (not the face itself), all faces updated together
// (Jacobi) for `iterations` rounds. Vertex normals are then rebuilt from the filtered
// face normals; optionally the vertices first move to agree with them.
#include "terrain/error.hpp"
#include "terrain/grid_mesh.hpp"

namespace terrain {

struct DenoiseOptions {
  double sigma_s = 0;     // spatial width (metres); 0: the mean distance between the
                          // centroids of edge-adjacent faces; negative or NaN: an Error
  double sigma_r = 0.35;  // range width on |n_i - n_j| (in [0, 2]); 0: no range kernel
                          // (plain area- and distance-weighted averaging, the Laplacian-like
                          // baseline the tests compare against)
  int iterations = 20;    // normal filtering rounds
  bool update_vertices = false;
  int vertex_iterations = 10;
};

struct DenoiseStats {
  double sigma_s = 0;          // the spatial width used
  double mean_change_deg = 0;  // vertex normal change, mean and maximum (degrees)
  double max_change_deg = 0;
  double max_vertex_shift = 0;  // metres, with update_vertices
};

// Unit face normals (#F) of the mesh's positions; (0, 0, 1) for degenerate faces.
BigVector<Eigen::Vector3f> face_normals(const GridMesh& mesh);

// The filtered face normals (#F) of docs/algorithms.md 6.1, starting from `normals` (#F, unit).
// Tested: worked example 6.4 (through a three-neighbour configuration), planes with noise.
BigVector<Eigen::Vector3f> bilateral_filter_normals(const GridMesh& mesh,
                                                    const BigVector<Eigen::Vector3f>& normals,
                                                    const DenoiseOptions& options,
                                                    double& sigma_s_used,
                                                    const Progress& progress = {});

// Denoises `mesh` in place: filtered face normals; with update_vertices, the vertex update
// of docs/algorithms.md 6.2 restricted to z (x_i.z += z component of (1/|F_i|) sum_f n_f
// (n_f . (c_f - x_i)), centroids recomputed each round, boundary vertices fixed), so the
// mesh stays a regular grid that build-drainage and the renderer can use; then vertex
// normals: area-weighted from the new positions (update) or normalize(sum A_f n_f) of the
// filtered normals (no update). Fills mesh.normal_change: the angle (degrees) between the
// area-weighted vertex normals before filtering and the new ones (so a change of weighting
// rule does not count); with iterations = 0 nothing changes. Returns statistics.
DenoiseStats denoise_normals(GridMesh& mesh, const DenoiseOptions& options,
                             const Progress& progress = {});

}  // namespace terrain
