#pragma once
// Camera matrices and projection (GL-free; the renderer uploads these and tests project
// with them). Coordinates are the mesh's local frame (world = origin + local) with z
// multiplied by the vertical exaggeration; x east, y north, z up.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "renderer/core/frame_params.hpp"
#include "renderer/core/viewpoint.hpp"
#include "terrain/grid_mesh.hpp"

namespace renderer {

struct Box {
  Eigen::Vector3d lo, hi;
};
std::array<Eigen::Vector3d, 8> box_corners(const Box& b);

// Window depth to "distance order": larger is farther, 1 where nothing was drawn. The one
// far test of the CPU references, as common.glsl's far_of on the GPU (the same arithmetic,
// in float for float depths).
inline double far_depth(bool reversed_z, double depth) { return reversed_z ? 1.0 - depth : depth; }
inline float far_depth(bool reversed_z, float depth) { return reversed_z ? 1.0f - depth : depth; }

// The view of one frame: eye, orthonormal axes, projection and image size. Perspective,
// or orthographic when map_scale > 0 (the top view: the eye is then on a plane before the
// whole scene, near 0, and depth runs linearly from the eye plane to `far`).
struct View {
  Eigen::Vector3d eye, forward, right, up;  // local frame
  double fov_deg = Camera{}.fov, near = 1;
  double map_scale = 0, far = 0;  // orthographic: metres a pixel, the far plane's distance
  int width = 1, height = 1;
  bool reversed_z = true;               // depth 1 at `near`, 0 at infinity or `far` (glClipControl)
  Eigen::Matrix4d view_matrix() const;  // local -> eye space (camera looks down -z)
  Eigen::Matrix4d projection() const;   // perspective: infinite far plane
  Eigen::Matrix4d view_projection() const { return projection() * view_matrix(); }
  bool orthographic() const { return map_scale > 0; }
  Viewpoint viewpoint() const { return orthographic() ? Viewpoint(eye, forward) : Viewpoint(eye); }
  // The distance along the line of sight of a window depth (as the depth buffer stores it).
  double depth_distance(double depth) const;
  // The metres one pixel spans at `distance` along the line of sight (orthographic: map_scale).
  double pixel_size(double distance) const;
};

// Unit line-of-sight vector for a bearing and an angle below the horizon (degrees).
Eigen::Vector3d view_direction(double view_az_deg, double view_alt_deg);

// The eye position (local frame) that frames `box` entirely, looking along
// view_direction(view_az, view_alt), with a vertical field of view `fov` and aspect
// width/height: the nearest eye for which every box corner lies inside the view (5%
// margin), moved sideways so that the box's image is centred.
Eigen::Vector3d frame_box(const Box& box, double view_az, double view_alt, double fov_deg,
                          double aspect);

// The eye (local frame) that frames every point of `points` (the nearest eye for which
// all lie inside the view, the field of view narrowed by `margin`), moved sideways so that
// their image is centred, looking along view_direction(view_az, view_alt).
Eigen::Vector3d frame_points(const std::vector<Eigen::Vector3d>& points, double view_az,
                             double view_alt, double fov_deg, double aspect, double margin);

// The automatic view (terrain-render with no camera option, the viewer's Home;
// docs/terrain-render.md, "The automatic view"): the whole terrain from `view_alt` above
// the horizon, framed tightly (every vertex inside the view, a 2 % margin; a large mesh
// sampled at most ~256 k vertices), at the bearing, in 15 degree steps, of the largest
// score = coverage + 0.15 a cos^2(bearing - axis) + 0.02 [the terrain rises away from the
// eye]: coverage the share of the frame the terrain covers (its coarse grid, at most 64
// cells a side, filled into a 160-pixel-wide mask), axis the bearing of the principal axis
// of the height gradients (the structure tensor; looking along it is looking across the
// main ridges and valleys), a = 1 - l2 / l1 its anisotropy (0 on a cone, 1 on a ramp), and
// the last term the mean slope rising away from the eye. The light comes from the upper
// left of the image (bearing - 45 degrees), 45 degrees high: the cartographic convention.
struct AutoView {
  Camera camera;  // eye set, world coordinates
  Light light;
  double coverage = 0;     // share of the frame covered (the coarse estimate)
  double relief_axis = 0;  // degrees, 0..180
  double anisotropy = 0;
};
// With search_alt, the altitudes view_alt, view_alt + 5, ... 55 are tried in turn (the
// steeper, the closer the terrain's image to its plan shape and the more of the frame it
// fills), each with the 24 bearings, until the best bearing covers 60 % of the frame: the
// most oblique view that fills the frame (else the best of all).
AutoView auto_view(const terrain::GridMesh& mesh, double exaggeration, double fov_deg,
                   double aspect, double view_alt = 30.0, bool search_alt = false);

// The relief view (--view relief; the default before the automatic view;
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
  Camera camera;  // eye set, world coordinates
  Light light;
  Eigen::Vector2d centre;  // of the subject, world x y
  double relief = 0;       // the max - min height within its box, metres
};
ReliefView relief_view(const terrain::GridMesh& mesh, double exaggeration, double fov_deg,
                       double aspect, double view_alt = 30.0);

// The vertical exaggeration a frame takes when none is given: 1 where the relief is
// already strong against the terrain's extent, more where it is gentle, so that a lowland's
// valleys and divides show: e = kReliefRatio / (relief / extent) within 1 ..
// kMaxAutoExaggeration, to the nearest 0.5; relief = the 99th minus the 1st percentile of
// the vertex heights (metres), extent = sqrt(width x height) of the mesh. MSH (ratio 0.29),
// Logan (0.038) and MED (0.033): 1; the Eno DEM (0.007): 4.5.
inline constexpr double kReliefRatio = 0.03, kMaxAutoExaggeration = 5.0;
double auto_exaggeration(const terrain::GridMesh& mesh);

// The camera and light of `mode` (ViewMode) for a mesh, and a line saying what they are:
// Auto (auto_view at view_alt), Top (orthographic, straight down, north up, centred on the
// terrain's extent, which map_scale 0 fits to the image; the eye at the height that frames
// every vertex in perspective; the light from the north-west, 45 degrees high), Relief (relief_view
// at view_alt); a view_alt not given: 30 degrees, and Auto searches 30 to 55.
struct DefaultView {
  Camera camera;  // eye set, world coordinates
  Light light;
  std::string description;
};
DefaultView default_view(const terrain::GridMesh& mesh, ViewMode mode, double exaggeration,
                         double fov_deg, double aspect,
                         std::optional<double> view_alt = std::nullopt);

// The view of `camera` over a scene whose local frame has world origin `origin` and whose
// (exaggerated) bounding box is `box`: the eye is camera.eye - origin, or framed on `box`
// (frame_box) when camera.eye is unset. `near` is half the distance from the eye to the
// box, at least 1e-4 of the box diagonal. Orthographic: the eye (the box's centre when
// unset) moves along the line of sight to a plane 1 % of the box diagonal (at least 1 m)
// before the box's nearest corner, `far` as far behind its farthest; map_scale 0 fits the
// box into the image (a 2 % margin), centred.
View make_view(const Camera& camera, const Eigen::Vector3d& origin, const Box& box, int width,
               int height, bool reversed_z = true);

// The page scale of a view (docs/terrain-render.md, "Strokes"): metres
// (local frame, heights exaggerated) per pixel at the depth of the centre of `box`, the
// scene's box, along the view, that depth at least the eye's distance to the box and 1 m;
// orthographic: map_scale.
// It depends on the camera and the image, not on the mesh's spacing: what the stroke rules
// in pixels are converted to metres with.
double page_scale(const View& view, const Box& box);

// Throws terrain::Error when `eye` (world coordinates) lies below the PN surface of `mesh`
// (heights scaled by `exaggeration` about the mesh origin, as the renderer draws them):
// the view from inside the terrain is blank. An eye outside the mesh's extent is fine, up
// to kMaxEyeDistance times the terrain's size (the diagonal of its extent) from its centre.
inline constexpr double kMaxEyeDistance = 1000.0;
void check_eye_above_terrain(const terrain::GridMesh& mesh, const Eigen::Vector3d& eye,
                             double exaggeration);

// The geotransform of an orthographic north-up view (the top view), GDAL's order: x0,
// scale, 0, y0, 0, -scale, in world coordinates (the scene's local frame at `origin`): pixel
// (u, v) (u right, v down, its corner) is world (x0 + u scale, y0 - v scale). None when the
// view is perspective or turned from north up.
std::optional<std::array<double, 6>> map_geotransform(const View& view,
                                                      const Eigen::Vector3d& origin);

struct Projected {
  double u = 0, v = 0;    // pixel coordinates: u right, v down, pixel centres at +0.5
  double depth = 0;       // window depth as the GL depth buffer stores it
  bool in_front = false;  // in front of the near plane
};
Projected project(const View& view, const Eigen::Vector3d& p_local);

// project's inverse for a pixel: the local point at the centre of pixel (u, v) (u right, v
// down; the whole pixel u, v falls in) whose window depth is `depth`. `inverse` is
// view.view_projection().inverse(), computed once for many pixels.
Eigen::Vector3d unproject(const View& view, const Eigen::Matrix4d& inverse, double u, double v,
                          double depth);

}  // namespace renderer
