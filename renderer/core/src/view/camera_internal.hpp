#pragma once
// What camera.cpp and auto_views.cpp share. Not installed.
#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

namespace renderer::detail {

inline constexpr double kDeg = std::numbers::pi / 180.0;

// Right and up axes of a line of sight at bearing `az`: right is horizontal, so the image
// is never rolled, also when looking straight down.
inline void view_axes(double az_deg, const Eigen::Vector3d& f, Eigen::Vector3d& right,
                      Eigen::Vector3d& up) {
  right = Eigen::Vector3d(std::cos(az_deg * kDeg), -std::sin(az_deg * kDeg), 0.0);
  up = right.cross(f).normalized();
}

}  // namespace renderer::detail
