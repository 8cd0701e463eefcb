#include "view/view_camera.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "terrain/pn_surface.hpp"

namespace terrain::tools {

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

Eigen::Vector3d forward_of(const renderer::Camera& c) {
  return {std::sin(c.view_az * kDeg) * std::cos(c.view_alt * kDeg),
          std::cos(c.view_az * kDeg) * std::cos(c.view_alt * kDeg), -std::sin(c.view_alt * kDeg)};
}

// Right and up of the screen for a camera looking along f (z up; f never vertical here:
// the altitude stays within +-89 degrees).
void basis(const Eigen::Vector3d& f, Eigen::Vector3d& right, Eigen::Vector3d& up) {
  right = f.cross(Eigen::Vector3d::UnitZ()).normalized();
  up = right.cross(f);
}

// Bearing and altitude of a direction.
void angles_of(const Eigen::Vector3d& f, double& az, double& alt) {
  az = std::fmod(std::atan2(f.x(), f.y()) / kDeg + 360.0, 360.0);
  alt = std::asin(std::clamp(-f.z() / f.norm(), -1.0, 1.0)) / kDeg;
}

}  // namespace

std::optional<double> ViewCamera::surface(double x, double y) const {
  for (const terrain::GridMesh* m : {&mesh, outside}) {
    if (!m) continue;
    const auto& g = m->geo;
    if (const auto p = terrain::pn_point_above(*m, x - g.origin_x, y - g.origin_y))
      return g.origin_z + exaggeration * p->position.z();
  }
  return std::nullopt;
}

std::optional<Eigen::Vector3d> ViewCamera::pick(const renderer::Camera& c, double px,
                                                double py) const {
  if (!c.eye) return std::nullopt;
  const Eigen::Vector3d f = forward_of(c);
  Eigen::Vector3d right, up;
  basis(f, right, up);
  const double t = std::tan(c.fov * kDeg / 2), aspect = double(width) / double(height);
  const Eigen::Vector3d dir =
      (f + t * ((2 * (px + 0.5) / width - 1) * aspect * right + (1 - 2 * (py + 0.5) / height) * up))
          .normalized();
  const auto& g = mesh.geo;
  const terrain::GridMesh& whole = outside ? *outside : mesh;
  const double w = double(whole.topo.cols - 1) * whole.geo.dx,
               h = double(whole.topo.rows - 1) * whole.geo.dy;
  const double step = 0.5 * std::min(g.dx, g.dy),
               reach = 4 * std::hypot(w, h) + std::abs(c.eye->z());
  Eigen::Vector3d prev = *c.eye;
  for (double s = step; s < reach; s += step) {
    const Eigen::Vector3d p = *c.eye + s * dir;
    const auto z = surface(p.x(), p.y());
    if (z && p.z() <= *z) {  // crossed between prev and p: bisect
      Eigen::Vector3d a = prev, b = p;
      for (int k = 0; k < 20; ++k) {
        const Eigen::Vector3d m = 0.5 * (a + b);
        const auto zm = surface(m.x(), m.y());
        (zm && m.z() <= *zm ? b : a) = m;
      }
      return b;
    }
    prev = p;
  }
  return std::nullopt;
}

void ViewCamera::orbit(renderer::Camera& c, const Eigen::Vector3d& pivot, double d_az,
                       double d_alt) const {
  if (!c.eye) return;
  c.orthographic = false;
  const double alt = std::clamp(c.view_alt + d_alt, -89.0, 89.0);
  d_alt = alt - c.view_alt;
  // Bearing turns clockwise seen from above: a rotation by -d_az about z; then the
  // altitude about the screen's right axis, so the line of sight dips by d_alt.
  const Eigen::AngleAxisd yaw(-d_az * kDeg, Eigen::Vector3d::UnitZ());
  Eigen::Vector3d f = yaw * forward_of(c), right, up;
  basis(f, right, up);
  const Eigen::AngleAxisd pitch(-d_alt * kDeg, right);
  const Eigen::Matrix3d rot = (pitch * yaw).toRotationMatrix();
  c.eye = pivot + rot * (*c.eye - pivot);
  angles_of(rot * forward_of(c), c.view_az, c.view_alt);
  keep_above(c);
}

void ViewCamera::pan(renderer::Camera& c, const Eigen::Vector3d& pivot, double dx,
                     double dy) const {
  if (!c.eye) return;
  c.orthographic = false;
  const Eigen::Vector3d f = forward_of(c);
  Eigen::Vector3d right, up;
  basis(f, right, up);
  const double metres_per_px =
      2 * (pivot - *c.eye).dot(f) * std::tan(c.fov * kDeg / 2) / double(height);
  c.eye = *c.eye - metres_per_px * (dx * right - dy * up);
  keep_above(c);
}

void ViewCamera::zoom(renderer::Camera& c, const Eigen::Vector3d& target, double share) const {
  if (!c.eye) return;
  c.orthographic = false;
  c.eye = *c.eye + share * (target - *c.eye);
  keep_above(c);
}

void ViewCamera::fly(renderer::Camera& c, double forward, double right, double up) const {
  if (!c.eye) return;
  c.orthographic = false;
  const double az = c.view_az * kDeg;
  c.eye = *c.eye + forward * Eigen::Vector3d(std::sin(az), std::cos(az), 0) +
          right * Eigen::Vector3d(std::cos(az), -std::sin(az), 0) + up * Eigen::Vector3d::UnitZ();
  keep_above(c);
}

void ViewCamera::keep_above(renderer::Camera& c) const {
  if (!c.eye) return;
  const auto z = surface(c.eye->x(), c.eye->y());
  const double margin = 0.5 * std::max(mesh.geo.dx, mesh.geo.dy);
  if (z && c.eye->z() < *z + margin) c.eye->z() = *z + margin;
}

}  // namespace terrain::tools
