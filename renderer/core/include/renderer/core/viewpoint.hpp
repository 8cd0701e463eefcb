#pragma once
// Where a frame is seen from, as the line rules see it (GL-free): an eye (perspective), or
// a line of sight with every ray parallel to it (orthographic: the top view). The rules ask
// two things of it: the way towards the viewer from a point (facing tests, the lift of
// lines) and how far a point is (the crease score's distance). common.glsl's to_eye and
// view_distance are the same on the GPU.
#include <Eigen/Core>

namespace renderer {

struct Viewpoint {
  Eigen::Vector3d eye =
      Eigen::Vector3d::Zero();  // local frame; orthographic: a point of the eye plane
  Eigen::Vector3d direction =
      Eigen::Vector3d::Zero();  // unit line of sight when orthographic; zero: perspective
  Viewpoint() = default;
  Viewpoint(const Eigen::Vector3d& e)
      : eye(e) {}  // NOLINT(google-explicit-constructor): a perspective eye
  Viewpoint(const Eigen::Vector3d& e, const Eigen::Vector3d& d) : eye(e), direction(d) {}

  bool orthographic() const { return direction.squaredNorm() > 0; }
  // From p towards the viewer (not normalised when perspective).
  Eigen::Vector3d to_eye(const Eigen::Vector3d& p) const {
    return orthographic() ? Eigen::Vector3d(-direction) : Eigen::Vector3d(eye - p);
  }
  // The distance of p from the eye; orthographic: from the eye plane along the line of sight.
  double distance(const Eigen::Vector3d& p) const {
    return orthographic() ? (p - eye).dot(direction) : (p - eye).norm();
  }
};

}  // namespace renderer
