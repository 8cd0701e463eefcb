#pragma once
// terrain-view's camera moves, GL-free: the terrain point under a pixel, orbit about it,
// pan, zoom towards it, fly, and the rule that the eye never goes below the surface. The
// camera is the renderer's own (renderer::Camera: eye, bearing and altitude of the line of
// sight, field of view), so a view moved here is a view terrain-render draws. The top
// view starts orthographic (a map); the first move makes it the perspective view from the
// same eye, which frames the same terrain (pick treats every camera as perspective).
#include <Eigen/Core>
#include <optional>

#include "renderer/core/frame_params.hpp"
#include "terrain/grid_mesh.hpp"

namespace terrain::tools {

struct ViewCamera {
  const terrain::GridMesh& mesh;
  double exaggeration;  // the frame's (given by the viewer: its settings)
  int width, height;
  // Where `mesh` is a window of the mesh (renderer::hold_views' read): the whole mesh at
  // a coarser level, the surface beyond the window.
  const terrain::GridMesh* outside = nullptr;

  // The (exaggerated) surface's height under world x, y (the window's where it holds x, y,
  // else `outside`'s); nullopt off the mesh.
  std::optional<double> surface(double x, double y) const;
  // The first point where the ray from the eye through pixel (px, py) (row 0 at the top)
  // meets the surface; nullopt when it does not within the scene.
  std::optional<Eigen::Vector3d> pick(const renderer::Camera& c, double px, double py) const;
  // Turns the camera about `pivot` by d_az degrees of bearing and d_alt of altitude: the
  // pivot stays where it was on the screen.
  void orbit(renderer::Camera& c, const Eigen::Vector3d& pivot, double d_az, double d_alt) const;
  // Moves the eye in the screen's plane by (dx, dy) pixels at the distance of `pivot`.
  void pan(renderer::Camera& c, const Eigen::Vector3d& pivot, double dx, double dy) const;
  // Moves the eye towards `target` by this share of the way (negative: away).
  void zoom(renderer::Camera& c, const Eigen::Vector3d& target, double share) const;
  // Forward (along the bearing), right and up, in metres.
  void fly(renderer::Camera& c, double forward, double right, double up) const;
  // Keeps the eye above the surface (by half a mesh spacing).
  void keep_above(renderer::Camera& c) const;
};

}  // namespace terrain::tools
