#include "renderer/core/camera.hpp"
#include "terrain/error.hpp"
#include "terrain/pn_surface.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace renderer {

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kAcrossWeight = 0.15, kUphillWeight = 0.02;  // auto_view's score (camera.hpp)
constexpr double kMaxAutoAlt = 55, kAutoCoverage = 0.6;

// Right and up axes of a line of sight at bearing `az`: right is horizontal, so the image
// is never rolled, also when looking straight down.
void axes(double az_deg, const Eigen::Vector3d& f, Eigen::Vector3d& right, Eigen::Vector3d& up) {
  right = Eigen::Vector3d(std::cos(az_deg * kDeg), -std::sin(az_deg * kDeg), 0.0);
  up = right.cross(f).normalized();
}
}  // namespace

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
  axes(az, f, right, up);
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

namespace {

// Vertex i of `mesh` as drawn: local frame, height times the exaggeration e.
Eigen::Vector3d drawn_vertex(const terrain::GridMesh& mesh, std::size_t i, double e) {
  const Eigen::Vector3f& p = mesh.positions[i];
  return {p.x(), p.y(), double(p.z()) * e};
}

// 0, step, 2 step, ... and n - 1.
std::vector<std::size_t> grid_samples(std::size_t n, std::size_t step) {
  std::vector<std::size_t> v;
  for (std::size_t i = 0; i < n; i += step) v.push_back(i);
  if (v.back() != n - 1) v.push_back(n - 1);
  return v;
}

// The points a default view frames: every vertex, or every s-th in rows and columns (and the
// last row and column) on a large mesh, at most ~256 k; no-data vertices left out.
std::vector<Eigen::Vector3d> framing_points(const terrain::GridMesh& mesh, double e) {
  const std::size_t rows = mesh.topo.rows, cols = mesh.topo.cols;
  const std::size_t s =
      std::max<std::size_t>(1, std::size_t(std::ceil(std::sqrt(double(rows * cols) / 262144.0))));
  std::vector<Eigen::Vector3d> points;
  for (const std::size_t r : grid_samples(rows, s))
    for (const std::size_t c : grid_samples(cols, s))
      if (const Eigen::Vector3d p = drawn_vertex(mesh, r * cols + c, e); p.allFinite())
        points.push_back(p);
  if (points.size() < 3) throw terrain::Error("the mesh has no faces");
  return points;
}

}  // namespace

// The main relief over the coarse grid's cells (rows rk x columns ck of `at`): the
// principal axis of the height gradients (the structure tensor J = sum g g^T), as a
// bearing, its anisotropy (1 - l2 / l1), and the mean plane's uphill direction.
struct ReliefAxis {
  double axis = 0, anisotropy = 0;
  Eigen::Vector2d uphill{0, 0};
};
template <class At>
ReliefAxis relief_axis(const At& at, const std::vector<std::size_t>& rk,
                       const std::vector<std::size_t>& ck) {
  double jxx = 0, jxy = 0, jyy = 0, gx_sum = 0, gy_sum = 0;
  for (std::size_t i = 0; i + 1 < rk.size(); ++i)
    for (std::size_t j = 0; j + 1 < ck.size(); ++j) {
      const Eigen::Vector3d a = at(rk[i], ck[j]), b = at(rk[i], ck[j + 1]),
                            c = at(rk[i + 1], ck[j]);
      if (!a.allFinite() || !b.allFinite() || !c.allFinite()) continue;
      const double gx = (b.z() - a.z()) / (b.x() - a.x()), gy = (c.z() - a.z()) / (c.y() - a.y());
      jxx += gx * gx, jxy += gx * gy, jyy += gy * gy, gx_sum += gx, gy_sum += gy;
    }
  const double tr = jxx + jyy, det = jxx * jyy - jxy * jxy,
               disc = std::sqrt(std::max(0.0, 0.25 * tr * tr - det));
  const double l1 = 0.5 * tr + disc, l2 = 0.5 * tr - disc;
  ReliefAxis r;
  // The eigenvector of l1, (l1 - jyy, jxy) in (east, north), as a bearing.
  r.axis = jxy == 0 ? (jxx >= jyy ? 90.0 : 0.0) : std::atan2(l1 - jyy, jxy) / kDeg;
  r.anisotropy = l1 > 0 ? 1.0 - l2 / l1 : 0.0;
  r.uphill = Eigen::Vector2d(gx_sum, gy_sum);
  return r;
}

// The share of a v.width x v.height frame the coarse grid's triangles cover.
template <class At>
double frame_coverage(const View& v, const At& at, const std::vector<std::size_t>& rk,
                      const std::vector<std::size_t>& ck) {
  const int mw = v.width, mh = v.height;
  std::vector<std::uint8_t> mask(std::size_t(mw * mh), 0);
  auto fill = [&](const Projected& p0, const Projected& p1, const Projected& p2) {
    const double x0 = std::min({p0.u, p1.u, p2.u}), x1 = std::max({p0.u, p1.u, p2.u});
    const double y0 = std::min({p0.v, p1.v, p2.v}), y1 = std::max({p0.v, p1.v, p2.v});
    const double area = (p1.u - p0.u) * (p2.v - p0.v) - (p2.u - p0.u) * (p1.v - p0.v);
    if (area == 0) return;
    for (int y = std::max(0, int(std::floor(y0))); y < std::min(mh, int(std::ceil(y1))); ++y)
      for (int x = std::max(0, int(std::floor(x0))); x < std::min(mw, int(std::ceil(x1))); ++x) {
        const double px = x + 0.5, py = y + 0.5;
        const double w0 = ((p1.u - px) * (p2.v - py) - (p2.u - px) * (p1.v - py)) / area;
        const double w1 = ((p2.u - px) * (p0.v - py) - (p0.u - px) * (p2.v - py)) / area;
        if (w0 >= 0 && w1 >= 0 && w0 + w1 <= 1) mask[std::size_t(y * mw + x)] = 1;
      }
  };
  for (std::size_t i = 0; i + 1 < rk.size(); ++i)
    for (std::size_t j = 0; j + 1 < ck.size(); ++j) {
      const Eigen::Vector3d q[4] = {at(rk[i], ck[j]), at(rk[i], ck[j + 1]), at(rk[i + 1], ck[j]),
                                    at(rk[i + 1], ck[j + 1])};
      if (!q[0].allFinite() || !q[1].allFinite() || !q[2].allFinite() || !q[3].allFinite())
        continue;
      const Projected p[4] = {project(v, q[0]), project(v, q[1]), project(v, q[2]),
                              project(v, q[3])};
      fill(p[0], p[1], p[2]);
      fill(p[1], p[3], p[2]);
    }
  return double(std::count(mask.begin(), mask.end(), 1)) / double(mask.size());
}

AutoView auto_view(const terrain::GridMesh& mesh, double e, double fov_deg, double aspect,
                   double view_alt, bool search_alt) {
  const std::size_t rows = mesh.topo.rows, cols = mesh.topo.cols;
  if (rows < 2 || cols < 2) throw terrain::Error("the mesh has no faces");
  auto at = [&](std::size_t r, std::size_t c) { return drawn_vertex(mesh, r * cols + c, e); };
  const std::vector<Eigen::Vector3d> points = framing_points(mesh, e);
  // The coarse grid (at most 64 cells a side) for the coverage and the relief's axis.
  const std::size_t k = std::max<std::size_t>(1, (std::max(rows, cols) + 63) / 64);
  const auto rk = grid_samples(rows, k), ck = grid_samples(cols, k);
  const ReliefAxis relief = relief_axis(at, rk, ck);
  const double axis = relief.axis, anisotropy = relief.anisotropy;
  const Eigen::Vector2d& uphill = relief.uphill;
  AutoView best;
  double best_score = -1e300;
  const int mw = 160, mh = std::max(1, int(std::lround(160.0 / aspect)));
  std::vector<double> alts{view_alt};
  if (search_alt)
    for (double a = view_alt + 5; a <= kMaxAutoAlt + 1e-9; a += 5) alts.push_back(a);
  for (int step = 0; step < 24 * int(alts.size()); ++step) {
    const double az = 15.0 * (step % 24), view_alt = alts[std::size_t(step / 24)];
    Camera cam;
    cam.view_az = az;
    cam.view_alt = view_alt;
    cam.fov = fov_deg;
    View v;
    v.width = mw;
    v.height = mh;
    v.fov_deg = fov_deg;
    v.forward = view_direction(az, view_alt);
    axes(az, v.forward, v.right, v.up);
    v.eye = frame_points(points, az, view_alt, fov_deg, double(mw) / double(mh), 1.02);
    v.near = 1e-3;
    const double coverage = frame_coverage(v, at, rk, ck);
    const double across = std::pow(std::cos((az - axis) * kDeg), 2.0);
    const Eigen::Vector2d dir(std::sin(az * kDeg), std::cos(az * kDeg));
    const double score = coverage + kAcrossWeight * anisotropy * across +
                         (dir.dot(uphill) > 0 ? kUphillWeight : 0.0);
    if (score > best_score) {
      best_score = score;
      best.camera = cam;
      best.camera.eye =
          v.eye + Eigen::Vector3d(mesh.geo.origin_x, mesh.geo.origin_y, mesh.geo.origin_z);
      best.coverage = coverage;
    }
    // The least steep altitude at which the best bearing fills enough of the frame.
    if (step % 24 == 23 && best.coverage >= kAutoCoverage) break;
  }
  best.light.azimuth =
      std::fmod(best.camera.view_az + 315.0, 360.0);  // from the upper left of the image
  best.light.altitude = 45;
  best.relief_axis = std::fmod(axis + 360.0, 180.0);
  best.anisotropy = anisotropy;
  return best;
}

// The local relief of every coarse cell (f x f mesh cells, their corner vertices
// included): max - min over the h x h cells centred on it (h about a sixth of the shorter
// side, `hh` its half); `top` the largest.
struct LocalRelief {
  std::size_t f = 1, R = 0, C = 0;
  long hh = 0;
  std::vector<double> relief;
  double top = 0;
};
LocalRelief local_relief(const terrain::GridMesh& mesh) {
  const std::size_t rows = mesh.topo.rows, cols = mesh.topo.cols;
  const auto z = [&](std::size_t r, std::size_t c) {
    return double(mesh.positions[r * cols + c].z());
  };
  LocalRelief out;
  // Coarse cells of f x f mesh cells (their corner vertices included): their lowest and
  // highest heights.
  const std::size_t f = (std::max(rows, cols) + 94) / 95, R = (rows - 2) / f + 1,
                    C = (cols - 2) / f + 1;
  out.f = f, out.R = R, out.C = C;
  std::vector<double> lo(R * C, 1e300), hi(R * C, -1e300);
  for (std::size_t i = 0; i < R; ++i)
    for (std::size_t j = 0; j < C; ++j)
      for (std::size_t r = i * f; r <= std::min((i + 1) * f, rows - 1); ++r)
        for (std::size_t c = j * f; c <= std::min((j + 1) * f, cols - 1); ++c) {
          lo[i * C + j] = std::min(lo[i * C + j], z(r, c));
          hi[i * C + j] = std::max(hi[i * C + j], z(r, c));
        }
  // Local relief of every coarse cell: max - min over the h x h cells centred on it (h
  // about a sixth of the shorter side).
  const long hh = std::max<long>(1, long(std::min(R, C)) / 6) / 2;
  out.hh = hh;
  std::vector<double>& relief = out.relief;
  relief.assign(R * C, 0.0);
  double& top = out.top;
  for (long i = 0; i < long(R); ++i)
    for (long j = 0; j < long(C); ++j) {
      double a = 1e300, b = -1e300;
      for (long u = std::max(0L, i - hh); u <= std::min(long(R) - 1, i + hh); ++u)
        for (long v = std::max(0L, j - hh); v <= std::min(long(C) - 1, j + hh); ++v)
          a = std::min(a, lo[std::size_t(u) * C + std::size_t(v)]),
          b = std::max(b, hi[std::size_t(u) * C + std::size_t(v)]);
      relief[std::size_t(i) * C + std::size_t(j)] = b - a;
      top = std::max(top, b - a);
    }
  return out;
}

// The open side of a subject at `centre` (local) of half-width w: the bearing (every 15
// degrees) from which the heights between the eye and the subject are lowest.
double open_side(const terrain::GridMesh& mesh, const Eigen::Vector2d& centre, double w,
                 double wlo) {
  const std::size_t rows = mesh.topo.rows, cols = mesh.topo.cols;
  const auto z = [&](std::size_t r, std::size_t c) {
    return double(mesh.positions[r * cols + c].z());
  };
  const auto& g = mesh.geo;
  // The eye's bearing from the centre is the view's bearing + 180.
  double view_az = 225, lowest = 1e300;
  for (int a = 0; a < 360; a += 15) {
    const Eigen::Vector2d towards_eye = -Eigen::Vector2d(std::sin(a * kDeg), std::cos(a * kDeg));
    double sum = 0;
    for (int s = 0; s <= 8; ++s) {
      const Eigen::Vector2d p = centre + w * (0.25 + 0.125 * s) * towards_eye;
      const double c = std::round(p.x() / g.dx), r = std::round(-p.y() / g.dy);
      sum += (c >= 0 && r >= 0 && c < double(cols) && r < double(rows))
                 ? z(std::size_t(r), std::size_t(c))
                 : wlo;
    }
    if (sum < lowest - 1e-9 * std::abs(lowest)) lowest = sum, view_az = a;
  }
  return view_az;
}

ReliefView relief_view(const terrain::GridMesh& mesh, double e, double fov_deg, double aspect,
                       double view_alt) {
  const std::size_t rows = mesh.topo.rows, cols = mesh.topo.cols;
  if (rows < 2 || cols < 2) throw terrain::Error("the mesh has no faces");
  const auto z = [&](std::size_t r, std::size_t c) {
    return double(mesh.positions[r * cols + c].z());
  };
  const LocalRelief lr = local_relief(mesh);
  const std::size_t f = lr.f, R = lr.R, C = lr.C;
  const long hh = lr.hh;
  const std::vector<double>& relief = lr.relief;
  const double top = lr.top;
  // The subject: the cells of at least 3/4 of the largest local relief (the walls of a
  // crater, the front of a range) around the one of largest relief: its centre is their
  // relief-weighted mean within half the grid's shorter side, moved there until it stays
  // (mean shift). Its half-width is 1.5 times their weighted standard deviation, at least
  // the local-relief window and at most a quarter of the shorter side.
  const double reach = 0.5 * double(std::min(R, C)), big = 0.75 * top;
  std::size_t peak = 0;
  for (std::size_t k = 0; k < R * C; ++k)
    if (relief[k] > relief[peak]) peak = k;
  double ci = double(peak / C), cj = double(peak % C), si2 = 0, sj2 = 0;
  for (int it = 0; it < 50; ++it) {
    double si = 0, sj = 0, sw = 0;
    si2 = 0, sj2 = 0;
    for (std::size_t i = 0; i < R; ++i)
      for (std::size_t j = 0; j < C; ++j) {
        const double r = relief[i * C + j], di = double(i) - ci, dj = double(j) - cj;
        if (r < big || di * di + dj * dj > reach * reach) continue;
        si += r * double(i), sj += r * double(j), sw += r, si2 += r * di * di, sj2 += r * dj * dj;
      }
    si2 /= sw, sj2 /= sw;
    const double ni = si / sw, nj = sj / sw, moved = std::hypot(ni - ci, nj - cj);
    ci = ni, cj = nj;
    if (moved < 0.25) break;
  }
  const double least = double(hh) + 0.5, most = std::max(least, 0.25 * double(std::min(R, C)));
  const double spread = std::clamp(1.5 * std::sqrt(std::max(si2, sj2)), least, most);
  const auto& g = mesh.geo;
  const double fdx = double(f) * g.dx, fdy = double(f) * g.dy;
  const Eigen::Vector2d centre((cj + 0.5) * fdx, -(ci + 0.5) * fdy);  // local
  const Eigen::Vector2d half(spread * fdx, spread * fdy);
  // Heights within the subject's extent.
  const auto clamp_c = [&](double x) {
    return std::size_t(std::clamp(std::round(x / g.dx), 0.0, double(cols - 1)));
  };
  const auto clamp_r = [&](double y) {
    return std::size_t(std::clamp(std::round(-y / g.dy), 0.0, double(rows - 1)));
  };
  const std::size_t c0 = clamp_c(centre.x() - half.x()), c1 = clamp_c(centre.x() + half.x());
  const std::size_t r0 = clamp_r(centre.y() + half.y()), r1 = clamp_r(centre.y() - half.y());
  double wlo = 1e300, whi = -1e300, mean = 0;
  for (std::size_t r = r0; r <= r1; ++r)
    for (std::size_t c = c0; c <= c1; ++c)
      wlo = std::min(wlo, z(r, c)), whi = std::max(whi, z(r, c)), mean += z(r, c);
  mean /= double((r1 - r0 + 1) * (c1 - c0 + 1));
  const double w = std::max(half.x(), half.y());
  const double view_az = open_side(mesh, centre, w, wlo);
  // The eye looks at the subject's centre at its mean height, from 1.5 times the distance
  // that frames its box: the subject fills about the middle two thirds of the frame.
  const Box box{{centre.x() - half.x(), centre.y() - half.y(), wlo * e},
                {centre.x() + half.x(), centre.y() + half.y(), whi * e}};
  const double framed =
      (0.5 * (box.lo + box.hi) - frame_box(box, view_az, view_alt, fov_deg, aspect)).norm();
  const Eigen::Vector3d target(centre.x(), centre.y(), mean * e);
  ReliefView rv;
  rv.camera.view_az = view_az;
  rv.camera.view_alt = view_alt;
  rv.camera.fov = fov_deg;
  const Eigen::Vector3d origin(g.origin_x, g.origin_y, g.origin_z);
  rv.camera.eye = origin + target - 1.5 * framed * view_direction(view_az, view_alt);
  rv.light.azimuth = std::fmod(view_az + 90.0, 360.0);
  rv.light.altitude = 35;
  rv.centre = centre + origin.head<2>();
  rv.relief = whi - wlo;
  return rv;
}

double auto_exaggeration(const terrain::GridMesh& mesh) {
  const std::size_t n = mesh.n_vertices();
  if (n == 0) return 1.0;
  std::vector<float> z(n);
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::max()), hi = -lo;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3f& p = mesh.positions[i];
    z[i] = p.z();
    lo = lo.cwiseMin(Eigen::Vector2d(p.x(), p.y())),
    hi = hi.cwiseMax(Eigen::Vector2d(p.x(), p.y()));
  }
  auto percentile = [&](double q) {
    const auto at = z.begin() + std::ptrdiff_t(q * double(n - 1));
    std::nth_element(z.begin(), at, z.end());
    return double(*at);
  };
  const double p1 = percentile(0.01), p99 = percentile(0.99), relief = p99 - p1;
  const double extent = std::sqrt((hi.x() - lo.x()) * (hi.y() - lo.y()));
  if (!(relief > 0) || !(extent > 0)) return 1.0;
  const double e = std::clamp(kReliefRatio * extent / relief, 1.0, kMaxAutoExaggeration);
  return std::round(2.0 * e) / 2.0;
}

DefaultView default_view(const terrain::GridMesh& mesh, ViewMode mode, double e, double fov_deg,
                         double aspect, std::optional<double> given_alt) {
  const double view_alt = given_alt.value_or(30.0);
  DefaultView d;
  if (mode == ViewMode::Relief) {
    const ReliefView rv = relief_view(mesh, e, fov_deg, aspect, view_alt);
    d.camera = rv.camera;
    d.light = rv.light;
    d.description = fmt::format(
        "relief view: the relief around {:.0f} {:.0f} ({:.0f} m), seen from bearing {:.0f}",
        rv.centre.x(), rv.centre.y(), rv.relief, std::fmod(rv.camera.view_az + 180, 360.0));
    return d;
  }
  if (mode == ViewMode::Top) {
    d.camera.view_az = 0;
    d.camera.view_alt = 90;
    d.camera.fov = fov_deg;
    if (mesh.topo.rows < 2 || mesh.topo.cols < 2) throw terrain::Error("the mesh has no faces");
    // Orthographic; the eye, centred over the terrain's extent, at the height that frames
    // it in perspective (the viewer's view once it moves).
    const std::vector<Eigen::Vector3d> points = framing_points(mesh, e);
    Eigen::Vector2d lo(1e300, 1e300), hi = -lo;
    for (const Eigen::Vector3d& p : points)
      lo = lo.cwiseMin(p.head<2>()), hi = hi.cwiseMax(p.head<2>());
    Eigen::Vector3d eye = frame_points(points, 0, 90, fov_deg, aspect, 1.02);
    eye.head<2>() = 0.5 * (lo + hi);
    d.camera.eye = eye + Eigen::Vector3d(mesh.geo.origin_x, mesh.geo.origin_y, mesh.geo.origin_z);
    d.camera.orthographic = true;
    d.light = {315, 45};
    d.description = "top view: orthographic, straight down, north up";
    return d;
  }
  const AutoView av = auto_view(mesh, e, fov_deg, aspect, view_alt, !given_alt);
  d.camera = av.camera;
  d.light = av.light;
  d.description = fmt::format(
      "automatic view: the whole terrain from bearing {:.0f}, {:.0f} degrees down, covering "
      "{:.0f} % of the frame (relief axis {:.0f}, anisotropy {:.2f}); light from {:.0f}",
      av.camera.view_az, av.camera.view_alt, 100 * av.coverage, av.relief_axis, av.anisotropy,
      av.light.azimuth);
  return d;
}

View make_view(const Camera& cam, const Eigen::Vector3d& origin, const Box& box, int width,
               int height, bool reversed_z) {
  View v;
  v.width = width;
  v.height = height;
  v.fov_deg = cam.fov;
  v.reversed_z = reversed_z;
  v.forward = view_direction(cam.view_az, cam.view_alt);
  axes(cam.view_az, v.forward, v.right, v.up);
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
