#pragma once
// Fitted vertex normals: the normals that make the PN surface of a grid mesh reproduce the
// source DEM between the vertices (docs/dem2mesh.md, "Fitted normals").
//
// PN triangles bulge between the vertices according to the vertex normals; with normals
// from face averages the surface departs from the DEM it was made from. Here the normals
// are the unknowns of a non-linear least-squares problem (Ceres):
//   * one unit 3-vector per vertex, on Ceres' SphereManifold;
//   * one residual per source sample inside the mesh: the height of the PN surface exactly
//     above the sample (the inverse evaluation of pn_surface.hpp) minus the sample's z,
//     in metres; each sample belongs to the patch that holds it;
//   * one 3-vector residual per vertex pulling it toward its starting normal:
//     regularization * spacing * (n - n0), in metres too (a 0.1 rad turn at a 50 m
//     spacing with the default 0.05 costs like a 0.25 m height error).
// Samples are assigned to patches with the starting normals, and again after each round
// (a fitted normal moves the patch boundaries a little). Large meshes are solved in
// overlapping blocks of vertices (cores of equal size, at most `block` on a side), all
// from the round's starting normals and side by side on the threads; each block's outside
// vertices are held fixed and only its core is kept, so the result does not depend on the
// order of the blocks.
#include <array>
#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "terrain/error.hpp"
#include "terrain/grid.hpp"
#include "terrain/grid_mesh.hpp"

namespace terrain {

// Source samples in the mesh's CRS (world coordinates, metres).
struct SourceSamples {
  std::vector<double> x, y, z;
  std::size_t size() const { return x.size(); }
};

// The valid samples of `dem` whose centres lie inside the mesh's extent, in the mesh's
// CRS: as they are when the DEM is in the mesh's CRS, projected (OGR) when the DEM is
// geographic. Throws Error when the CRSs cannot be related.
SourceSamples dem_samples_for_mesh(const Grid& dem, const GridMesh& mesh);

// Only the samples inside the mesh's extent (for scattered points).
SourceSamples samples_inside_mesh(const SourceSamples& all, const GridMesh& mesh);

// The PN surface versus the samples: RMSE and max |error| of z (metres) over the samples
// the surface is above (pn_point_above); the fit's report gives it before and after.
struct SurfaceError {
  double rmse = 0, max_abs = 0;
  std::size_t samples = 0;
};

struct NormalFitOptions {
  double regularization = 0.05;   // weight of the pull toward the starting normals (see above)
  int max_iterations = 50;        // Levenberg-Marquardt iterations per round and block
  int rounds = 2;                 // patch assignment, solve; repeated
  std::size_t face_samples = 24;  // at most this many samples per face enter the problem (evenly
                                  // strided); the errors reported use all
  std::size_t block = 400;  // largest block side in vertices; meshes within one block: one problem
  std::size_t overlap = 4;  // vertices of overlap around each block's core
  int threads = 0;          // 0: all (OpenMP's count)
  bool record_costs = false;  // NormalFitReport::costs (one more evaluation per iteration)
};

struct NormalFitReport {
  SurfaceError before, after;
  std::size_t blocks = 0, iterations = 0;  // iterations summed over rounds and blocks
  // With record_costs, for a one-block problem: the cost (half the sum of squared residuals,
  // the pull included) of the iterate at the start and after every iteration, round after
  // round (each round starts from a new patch assignment).
  std::vector<double> costs;
  double seconds = 0;
};

// The fit's residuals for one face (a building block of fit_pn_normals, exposed for its
// test): for each of `samples` (local x, y, z) on the PN patch of the face's `corner`s with
// unit normals n[0..2], the patch's height above it (by the inverse evaluation, then one
// Newton step to first order) minus its z; and, for each jacobians[j] not null, d residual /
// d n_j (#samples x 3, row-major), analytic (docs/dem2mesh.md, "Fitted normals"). `start`:
// where to start each sample's inverse evaluation, (s, t) (NaN or null: the planar guess);
// `solved`: each sample's (s, t) (NaN where it did not converge), when not null.
void pn_face_residuals(const std::array<Eigen::Vector3d, 3>& corner,
                       const std::vector<Eigen::Vector3d>& samples,
                       const std::array<const double*, 3>& n, double* residuals,
                       const std::array<double*, 3>& jacobians,
                       const std::vector<Eigen::Vector2d>* start = nullptr,
                       std::vector<Eigen::Vector2d>* solved = nullptr);

// Fits mesh.normals to the samples (local = world - mesh origin is taken care of). Throws
// Error without samples inside the mesh. Sets mesh.normal_fit.
NormalFitReport fit_pn_normals(GridMesh& mesh, const SourceSamples& samples,
                               const NormalFitOptions& options = {}, const Progress& progress = {});

}  // namespace terrain
