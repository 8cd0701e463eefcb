// The automatic views: the oblique view that shows the relief best (auto_view), the relief
// view of a range's flank (relief_view), the automatic exaggeration, and the view a frame
// takes when its camera is not given (default_view).
#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "camera_internal.hpp"
#include "renderer/core/camera.hpp"
#include "terrain/error.hpp"
#include "terrain/pn_surface.hpp"

namespace renderer {

using detail::kDeg;
using detail::view_axes;

namespace {
constexpr double kAcrossWeight = 0.15, kUphillWeight = 0.02;  // auto_view's score (camera.hpp)
constexpr double kMaxAutoAlt = 55, kAutoCoverage = 0.6;
}  // namespace

namespace {

// Whether vertex i lies outside the data (no face drawn touches it).
bool outside(const terrain::GridMesh& mesh, std::size_t i) {
  return !mesh.filled.empty() && mesh.filled[i] == terrain::kOutside;
}

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
// last row and column) on a large mesh, at most ~256 k; no-data vertices and those outside
// the data left out: the view frames the data, not the grid's rectangle.
std::vector<Eigen::Vector3d> framing_points(const terrain::GridMesh& mesh, double e) {
  const std::size_t rows = mesh.topo.rows, cols = mesh.topo.cols;
  const std::size_t s =
      std::max<std::size_t>(1, std::size_t(std::ceil(std::sqrt(double(rows * cols) / 262144.0))));
  std::vector<Eigen::Vector3d> points;
  for (const std::size_t r : grid_samples(rows, s))
    for (const std::size_t c : grid_samples(cols, s))
      if (const Eigen::Vector3d p = drawn_vertex(mesh, r * cols + c, e);
          p.allFinite() && !outside(mesh, r * cols + c))
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
    view_axes(az, v.forward, v.right, v.up);
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

// The subject of a relief view, in local-relief cells: its centre row and column and its
// half-width.
struct Subject {
  double i, j, spread;
};
// The subject: the cells of at least 3/4 of the largest local relief (the walls of a
// crater, the front of a range) around the one of largest relief: its centre is their
// relief-weighted mean within half the grid's shorter side, moved there until it stays
// (mean shift). Its half-width is 1.5 times their weighted standard deviation, at least
// the local-relief window and at most a quarter of the shorter side.
static Subject subject_of(const LocalRelief& lr) {
  const std::size_t R = lr.R, C = lr.C;
  const long hh = lr.hh;
  const std::vector<double>& relief = lr.relief;
  const double top = lr.top;
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
  return {ci, cj, std::clamp(1.5 * std::sqrt(std::max(si2, sj2)), least, most)};
}

ReliefView relief_view(const terrain::GridMesh& mesh, double e, double fov_deg, double aspect,
                       double view_alt) {
  const std::size_t rows = mesh.topo.rows, cols = mesh.topo.cols;
  if (rows < 2 || cols < 2) throw terrain::Error("the mesh has no faces");
  const auto z = [&](std::size_t r, std::size_t c) {
    return double(mesh.positions[r * cols + c].z());
  };
  const LocalRelief lr = local_relief(mesh);
  const std::size_t f = lr.f;
  const Subject subject = subject_of(lr);
  const double ci = subject.i, cj = subject.j, spread = subject.spread;
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
  std::vector<float> z;  // of the data's vertices
  z.reserve(n);
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::max()), hi = -lo;
  for (std::size_t i = 0; i < n; ++i) {
    if (outside(mesh, i)) continue;
    const Eigen::Vector3f& p = mesh.positions[i];
    z.push_back(p.z());
    lo = lo.cwiseMin(Eigen::Vector2d(p.x(), p.y())),
    hi = hi.cwiseMax(Eigen::Vector2d(p.x(), p.y()));
  }
  if (z.empty()) return 1.0;
  auto percentile = [&](double q) {
    const auto at = z.begin() + std::ptrdiff_t(q * double(z.size() - 1));
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

}  // namespace renderer
