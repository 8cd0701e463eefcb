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
// docs/terrain-render.md, "The default view"). The part of highest relief: on the grid
// coarsened to at most 95 cells a side, among the square windows a third of its shorter
// side whose relief (max - min height) is within 0.5 % of the largest, the most rugged one
// (whose cells' reliefs sum highest). It is seen from the side where the terrain
// around it is lowest: the bearing, in 15 degree steps, along which the mean height
// between a half and one and a half windows beyond its centre is least (outside the grid
// counts as the window's lowest height), so the view looks into the open side of a crater
// or up a valley. From view_alt above the horizon, the eye frames the window and a window
// of terrain around it on every side (the window fills about the middle third of the
// image). The light comes from the left of the line of sight (bearing - 90), 35 degrees
// high, so that the slopes facing the eye are side-lit.
struct ReliefView {
  Camera camera;             // eye set, world coordinates
  Light light;
  Eigen::Vector2d centre;    // of the relief window, world x y
  double relief = 0;         // its max - min height, metres
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
