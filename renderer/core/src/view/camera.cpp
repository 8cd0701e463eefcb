#include "renderer/core/camera.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "camera_internal.hpp"
#include "terrain/error.hpp"
#include "terrain/pn_surface.hpp"

namespace renderer {

using detail::kDeg;
using detail::view_axes;

std::array<Eigen::Vector3d, 8> box_corners(const Box& b) {
  std::array<Eigen::Vector3d, 8> c;
  for (int i = 0; i < 8; ++i)
    c[i] = {(i & 1) ? b.hi.x() : b.lo.x(), (i & 2) ? b.hi.y() : b.lo.y(),
            (i & 4) ? b.hi.z() : b.lo.z()};
  return c;
}

Eigen::Vector3d view_direction(double az, double alt) {
  return {std::sin(az * kDeg) * std::cos(alt * kDeg), std::cos(az * kDeg) * std::cos(alt * kDeg),
          -std::sin(alt * kDeg)};
}

Eigen::Matrix4d View::view_matrix() const {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.block<1, 3>(0, 0) = right.transpose();
  m.block<1, 3>(1, 0) = up.transpose();
  m.block<1, 3>(2, 0) = -forward.transpose();
  m(0, 3) = -right.dot(eye);
  m(1, 3) = -up.dot(eye);
  m(2, 3) = forward.dot(eye);
  return m;
}

Eigen::Matrix4d View::projection() const {
  Eigen::Matrix4d p = Eigen::Matrix4d::Zero();
  if (orthographic()) {
    // Eye-space z = -d, d the distance from the eye plane. Reversed: z_ndc = 1 - d / far;
    // conventional: z_ndc = 2 d / far - 1 (window depth d / far).
    p(0, 0) = 2.0 / (map_scale * double(width));
    p(1, 1) = 2.0 / (map_scale * double(height));
    p(3, 3) = 1.0;
    p(2, 2) = reversed_z ? 1.0 / far : -2.0 / far;
    p(2, 3) = reversed_z ? 1.0 : -1.0;
    return p;
  }
  // Infinite far plane. Reversed (glClipControl ZERO_TO_ONE): z_ndc = near / distance,
  // 1 at the near plane, 0 at infinity. Conventional: z_ndc = 1 - 2 near / distance.
  const double f = 1.0 / std::tan(0.5 * fov_deg * kDeg), aspect = double(width) / double(height);
  p(0, 0) = f / aspect;
  p(1, 1) = f;
  p(3, 2) = -1.0;
  if (reversed_z) {
    p(2, 3) = near;
  } else {
    p(2, 2) = -1.0;
    p(2, 3) = -2.0 * near;
  }
  return p;
}

double View::depth_distance(double depth) const {
  if (orthographic()) return far * far_depth(reversed_z, depth);
  return near / std::max(reversed_z ? depth : 1.0 - depth, 1e-30);
}

double View::pixel_size(double distance) const {
  return orthographic() ? map_scale
                        : distance * 2.0 * std::tan(0.5 * fov_deg * kDeg) / double(height);
}

Eigen::Vector3d frame_points(const std::vector<Eigen::Vector3d>& points, double az, double alt,
                             double fov_deg, double aspect, double margin) {
  const Eigen::Vector3d f = view_direction(az, alt);
  Eigen::Vector3d right, up;
  view_axes(az, f, right, up);
  const double tv = std::tan(0.5 * fov_deg * kDeg) / margin, th = tv * aspect;
  // Eye = target - d f. A point at offset o from the target has depth d + o.f and must
  // satisfy |o.right| <= (d + o.f) th and |o.up| <= (d + o.f) tv: the smallest such d.
  // Then the target moves sideways so that the points' image is centred, and d is found
  // again (two rounds are enough in practice).
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (const auto& c : points) lo = lo.cwiseMin(c), hi = hi.cwiseMax(c);
  Eigen::Vector3d target = 0.5 * (lo + hi);
  double d = 0;
  for (int round = 0; round < 3; ++round) {
    d = 0;
    for (const auto& c : points) {
      const Eigen::Vector3d o = c - target;
      d = std::max(
          {d, std::abs(o.dot(right)) / th - o.dot(f), std::abs(o.dot(up)) / tv - o.dot(f)});
    }
    if (round == 2) break;
    double x_lo = 1e300, x_hi = -1e300, y_lo = 1e300, y_hi = -1e300;
    for (const auto& c : points) {
      const Eigen::Vector3d o = c - (target - d * f);
      const double depth = o.dot(f);
      x_lo = std::min(x_lo, o.dot(right) / depth), x_hi = std::max(x_hi, o.dot(right) / depth);
      y_lo = std::min(y_lo, o.dot(up) / depth), y_hi = std::max(y_hi, o.dot(up) / depth);
    }
    target += d * (0.5 * (x_lo + x_hi) * right + 0.5 * (y_lo + y_hi) * up);
  }
  return target - d * f;
}

Eigen::Vector3d frame_box(const Box& box, double az, double alt, double fov_deg, double aspect) {
  const auto c = box_corners(box);
  return frame_points(std::vector<Eigen::Vector3d>(c.begin(), c.end()), az, alt, fov_deg, aspect,
                      1.05);
}

View make_view(const Camera& cam, const Eigen::Vector3d& origin, const Box& box, int width,
               int height, bool reversed_z) {
  View v;
  v.width = width;
  v.height = height;
  v.fov_deg = cam.fov;
  v.reversed_z = reversed_z;
  v.forward = view_direction(cam.view_az, cam.view_alt);
  view_axes(cam.view_az, v.forward, v.right, v.up);
  const double diag = (box.hi - box.lo).norm();
  if (cam.orthographic) {
    v.eye = cam.eye ? Eigen::Vector3d(*cam.eye - origin) : Eigen::Vector3d(0.5 * (box.lo + box.hi));
    double d_lo = 1e300, d_hi = -1e300, x_lo = 1e300, x_hi = -1e300, y_lo = 1e300, y_hi = -1e300;
    for (const Eigen::Vector3d& c : box_corners(box)) {
      const Eigen::Vector3d o = c - v.eye;
      d_lo = std::min(d_lo, o.dot(v.forward)), d_hi = std::max(d_hi, o.dot(v.forward));
      x_lo = std::min(x_lo, o.dot(v.right)), x_hi = std::max(x_hi, o.dot(v.right));
      y_lo = std::min(y_lo, o.dot(v.up)), y_hi = std::max(y_hi, o.dot(v.up));
    }
    v.map_scale = cam.map_scale;
    if (!(v.map_scale > 0)) {
      v.eye += 0.5 * (x_lo + x_hi) * v.right + 0.5 * (y_lo + y_hi) * v.up;
      v.map_scale = std::max(
          {1.02 * (x_hi - x_lo) / double(width), 1.02 * (y_hi - y_lo) / double(height), 1e-9});
    }
    const double margin = std::max(0.01 * diag, 1.0);
    v.eye += (d_lo - margin) * v.forward;
    v.near = 0;
    v.far = d_hi - d_lo + 2 * margin;
    return v;
  }
  v.eye = cam.eye
              ? Eigen::Vector3d(*cam.eye - origin)
              : frame_box(box, cam.view_az, cam.view_alt, cam.fov, double(width) / double(height));
  const Eigen::Vector3d nearest = v.eye.cwiseMax(box.lo).cwiseMin(box.hi);
  v.near = std::max(0.5 * (nearest - v.eye).norm(), 1e-4 * std::max(diag, 1.0));
  return v;
}

double page_scale(const View& view, const Box& box) {
  if (view.orthographic()) return view.map_scale;
  const Eigen::Vector3d centre = 0.5 * (box.lo + box.hi),
                        nearest = view.eye.cwiseMax(box.lo).cwiseMin(box.hi);
  const double depth =
      std::max({(centre - view.eye).dot(view.forward), (nearest - view.eye).norm(), 1.0});
  return view.pixel_size(depth);
}

std::optional<std::array<double, 6>> map_geotransform(const View& view,
                                                      const Eigen::Vector3d& origin) {
  if (!view.orthographic() || (view.right - Eigen::Vector3d::UnitX()).norm() > 1e-9 ||
      (view.up - Eigen::Vector3d::UnitY()).norm() > 1e-9)
    return std::nullopt;
  const double s = view.map_scale;
  return std::array<double, 6>{origin.x() + view.eye.x() - 0.5 * double(view.width) * s,  s, 0,
                               origin.y() + view.eye.y() + 0.5 * double(view.height) * s, 0, -s};
}

Projected project(const View& view, const Eigen::Vector3d& p) {
  const Eigen::Vector4d c = view.view_projection() * Eigen::Vector4d(p.x(), p.y(), p.z(), 1.0);
  Projected r;
  r.in_front = c.w() > view.near * (1 - 1e-9);
  const double x = c.x() / c.w(), y = c.y() / c.w(), z = c.z() / c.w();
  r.u = (x * 0.5 + 0.5) * view.width;
  r.v = (1.0 - (y * 0.5 + 0.5)) * view.height;
  r.depth = view.reversed_z ? z : z * 0.5 + 0.5;
  return r;
}

Eigen::Vector3d unproject(const View& view, const Eigen::Matrix4d& inverse, double u, double v,
                          double depth) {
  const double z_ndc = view.reversed_z ? depth : 2.0 * depth - 1.0;
  const Eigen::Vector4d w =
      inverse * Eigen::Vector4d((std::floor(u) + 0.5) / view.width * 2.0 - 1.0,
                                1.0 - (std::floor(v) + 0.5) / view.height * 2.0, z_ndc, 1.0);
  return w.head<3>() / w.w();
}

void check_eye_above_terrain(const terrain::GridMesh& mesh, const Eigen::Vector3d& eye,
                             double exaggeration) {
  const auto& g = mesh.geo;
  // Far away, the terrain is a speck (and single-precision matrices lose it): an eye more
  // than kMaxEyeDistance terrain sizes from its centre is an error, not a blank frame.
  const double size =
      std::hypot(double(mesh.topo.cols - 1) * g.dx, double(mesh.topo.rows - 1) * g.dy);
  const Eigen::Vector3d centre(g.origin_x + 0.5 * double(mesh.topo.cols - 1) * g.dx,
                               g.origin_y - 0.5 * double(mesh.topo.rows - 1) * g.dy, g.origin_z);
  const double distance =
      std::hypot(std::hypot(eye.x() - centre.x(), eye.y() - centre.y()), eye.z() - centre.z());
  if (!(distance <= kMaxEyeDistance * size))
    throw terrain::Error(fmt::format(
        "the eye ({:.6g}, {:.6g}, {:.6g}) is {:.3g} km from the terrain, more than {:g} "
        "times its size ({:.3g} km): it would draw a blank frame; move it closer",
        eye.x(), eye.y(), eye.z(), distance / 1000, kMaxEyeDistance, size / 1000));
  const auto p = terrain::pn_point_above(mesh, eye.x() - g.origin_x, eye.y() - g.origin_y);
  if (!p) return;
  const double surface = g.origin_z + exaggeration * p->position.z();
  if (eye.z() < surface)
    throw terrain::Error(fmt::format(
        "the eye ({:.1f}, {:.1f}, {:.1f}) is inside the terrain: the surface is at {:.1f} "
        "m there; raise it (--eye E N Z)",
        eye.x(), eye.y(), eye.z(), surface));
}

}  // namespace renderer
