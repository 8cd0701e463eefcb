#pragma once
// Camera matrices and projection (GL-free; the renderer uploads these and tests project
// with them). Coordinates are the mesh's local frame (world = origin + local) with z
// multiplied by the vertical exaggeration; x east, y north, z up.
#include <array>

#include <Eigen/Core>

#include "renderer/frame_params.hpp"
#include "terrain/grid_mesh.hpp"

namespace renderer {

struct Box {
  Eigen::Vector3d lo, hi;
};

// The view of one frame: eye, orthonormal axes, projection and image size.
struct View {
  Eigen::Vector3d eye, forward, right, up;  // local frame
  double fov_deg = 35, near = 1;
  int width = 1, height = 1;
  bool reversed_z = true;                   // depth 1 at `near`, 0 at infinity (glClipControl)
  Eigen::Matrix4d view_matrix() const;      // local -> eye space (camera looks down -z)
  Eigen::Matrix4d projection() const;       // infinite far plane
  Eigen::Matrix4d view_projection() const { return projection() * view_matrix(); }
};

// Unit line-of-sight vector for a bearing and an angle below the horizon (degrees).
Eigen::Vector3d view_direction(double view_az_deg, double view_alt_deg);

// The eye position (local frame) that frames `box` entirely, looking along
// view_direction(view_az, view_alt), with a vertical field of view `fov` and aspect
// width/height: the nearest eye for which every box corner lies inside the view (5%
// margin), moved sideways so that the box's image is centred.
Eigen::Vector3d frame_box(const Box& box, double view_az, double view_alt, double fov_deg, double aspect);

// The default view of a terrain (terrain-render with no camera options;
// docs/terrain-render.md, "The default view"). On the grid coarsened to at most 95 cells a
// side, each cell's local relief is the max - min height over a window a sixth of the
// shorter side. The subject is the cells of at least 3/4 of the largest local relief (the
// walls of a crater, the front of a range) near the one of largest relief: its centre is
// their relief-weighted mean within half the shorter side, iterated until it stays (mean
// shift), its half-width 1.5 times their weighted standard deviation (at least the relief
// window, at most a quarter of the shorter side). It is seen from its open side: the
// bearing, in 15 degree steps, along which the mean height from a quarter to one and a
// quarter half-widths from the centre is least (outside the grid counts as the subject's
// lowest height), so the view looks into a breached crater or up a valley. From view_alt
// above the horizon, the eye looks at the centre from 1.5 times the distance that frames
// the subject's box. The light comes from the right of the line of sight (bearing + 90),
// 35 degrees high, side-lighting the slopes that face the eye.
struct ReliefView {
  Camera camera;             // eye set, world coordinates
  Light light;
  Eigen::Vector2d centre;    // of the subject, world x y
  double relief = 0;         // the max - min height within its box, metres
};
ReliefView relief_view(const terrain::GridMesh& mesh, double exaggeration, double fov_deg, double aspect,
                       double view_alt = 30.0);

// The view of `camera` over a scene whose local frame has world origin `origin` and whose
// (exaggerated) bounding box is `box`: the eye is camera.eye - origin, or framed on `box`
// (frame_box) when camera.eye is unset. `near` is half the distance from the eye to the
// box, at least 1e-4 of the box diagonal.
View make_view(const Camera& camera, const Eigen::Vector3d& origin, const Box& box, int width, int height,
               bool reversed_z = true);

// Throws terrain::Error when `eye` (world coordinates) lies below the PN surface of `mesh`
// (heights scaled by `exaggeration` about the mesh origin, as the renderer draws them):
// the view from inside the terrain is blank. An eye outside the mesh's extent is fine.
void check_eye_above_terrain(const terrain::GridMesh& mesh, const Eigen::Vector3d& eye, double exaggeration);

struct Projected {
  double u = 0, v = 0;   // pixel coordinates: u right, v down, pixel centres at +0.5
  double depth = 0;      // window depth as the GL depth buffer stores it
  bool in_front = false; // in front of the near plane
};
Projected project(const View& view, const Eigen::Vector3d& p_local);

}  // namespace renderer
