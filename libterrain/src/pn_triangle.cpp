#include "terrain/pn_triangle.hpp"

#include <Eigen/Geometry>
#include <cmath>

namespace terrain {

using Eigen::Vector3d;

namespace {

Vector3d normalized_or(const Vector3d& v, const Vector3d& fallback) {
  const double len = v.norm();
  return len > 1e-12 ? Vector3d(v / len) : fallback;
}

// Mid-edge normal n110 for the edge Pi -> Pj (ALGORITHMS.md 1.3).
Vector3d mid_normal(const Vector3d& pi, const Vector3d& pj, const Vector3d& ni, const Vector3d& nj,
                    const Vector3d& face_n) {
  const Vector3d e = pj - pi;
  const double ee = e.dot(e);
  const Vector3d h = ee > 0.0 ? Vector3d(ni + nj - 2.0 * e.dot(ni + nj) / ee * e) : Vector3d(ni + nj);
  return normalized_or(h, face_n);
}

}  // namespace

PnPatch make_pn_patch(const Vector3d& p1, const Vector3d& p2, const Vector3d& p3, const Vector3d& n1,
                      const Vector3d& n2, const Vector3d& n3) {
  PnPatch p;
  auto& b = p.b;
  b[B300] = p1;
  b[B030] = p2;
  b[B003] = p3;
  // Edge point 1/3 from Pi towards Pj, projected into the tangent plane of Pi:
  // (2 Pi + Pj - w_ij Ni) / 3 with w_ij = (Pj - Pi) . Ni.
  auto edge = [](const Vector3d& pi, const Vector3d& pj, const Vector3d& ni) {
    return Vector3d((2.0 * pi + pj - (pj - pi).dot(ni) * ni) / 3.0);
  };
  b[B210] = edge(p1, p2, n1);
  b[B120] = edge(p2, p1, n2);
  b[B021] = edge(p2, p3, n2);
  b[B012] = edge(p3, p2, n3);
  b[B102] = edge(p3, p1, n3);
  b[B201] = edge(p1, p3, n1);
  const Vector3d e = (b[B210] + b[B120] + b[B021] + b[B012] + b[B102] + b[B201]) / 6.0;
  const Vector3d v = (p1 + p2 + p3) / 3.0;
  b[B111] = e + (e - v) / 2.0;

  Vector3d face_n = (p2 - p1).cross(p3 - p1);
  face_n = normalized_or(face_n, Vector3d(0, 0, 1));
  p.n[N200] = n1;
  p.n[N020] = n2;
  p.n[N002] = n3;
  p.n[N110] = mid_normal(p1, p2, n1, n2, face_n);
  p.n[N011] = mid_normal(p2, p3, n2, n3, face_n);
  p.n[N101] = mid_normal(p3, p1, n3, n1, face_n);
  return p;
}

Vector3d pn_position(const PnPatch& p, double b1, double b2, double b3) {
  const auto& b = p.b;
  return b[B300] * (b1 * b1 * b1) + b[B030] * (b2 * b2 * b2) + b[B003] * (b3 * b3 * b3) +
         3.0 * (b[B210] * (b1 * b1 * b2) + b[B120] * (b1 * b2 * b2) + b[B201] * (b1 * b1 * b3) +
                b[B102] * (b1 * b3 * b3) + b[B021] * (b2 * b2 * b3) + b[B012] * (b2 * b3 * b3)) +
         6.0 * b[B111] * (b1 * b2 * b3);
}

Vector3d pn_normal(const PnPatch& p, double b1, double b2, double b3) {
  const auto& n = p.n;
  const Vector3d v = n[N200] * (b1 * b1) + n[N020] * (b2 * b2) + n[N002] * (b3 * b3) + n[N110] * (b1 * b2) +
                     n[N011] * (b2 * b3) + n[N101] * (b1 * b3);
  return normalized_or(v, n[N200]);
}

void pn_derivatives(const PnPatch& p, double b1, double b2, double b3, Vector3d& dpds, Vector3d& dpdt) {
  const auto& b = p.b;
  // Partial derivatives of the homogeneous cubic (ALGORITHMS.md 2.2).
  const Vector3d d1 = 3.0 * (b[B300] * (b1 * b1) + b[B120] * (b2 * b2) + b[B102] * (b3 * b3) +
                             2.0 * (b[B210] * (b1 * b2) + b[B201] * (b1 * b3) + b[B111] * (b2 * b3)));
  const Vector3d d2 = 3.0 * (b[B210] * (b1 * b1) + b[B030] * (b2 * b2) + b[B012] * (b3 * b3) +
                             2.0 * (b[B120] * (b1 * b2) + b[B111] * (b1 * b3) + b[B021] * (b2 * b3)));
  const Vector3d d3 = 3.0 * (b[B201] * (b1 * b1) + b[B021] * (b2 * b2) + b[B003] * (b3 * b3) +
                             2.0 * (b[B111] * (b1 * b2) + b[B102] * (b1 * b3) + b[B012] * (b2 * b3)));
  dpds = d2 - d1;
  dpdt = d3 - d1;
}

PnXySolution pn_solve_xy(const PnPatch& p, double x, double y, double tolerance) {
  const Vector3d& p1 = p.b[B300];
  const Vector3d& p2 = p.b[B030];
  const Vector3d& p3 = p.b[B003];
  // Planar barycentrics of (x, y) in the flat triangle as the first guess.
  const double ax = p2.x() - p1.x(), ay = p2.y() - p1.y();
  const double cx = p3.x() - p1.x(), cy = p3.y() - p1.y();
  const double det = ax * cy - ay * cx;
  PnXySolution sol;
  if (det == 0.0) return sol;
  double s = ((x - p1.x()) * cy - (y - p1.y()) * cx) / det;
  double t = (ax * (y - p1.y()) - ay * (x - p1.x())) / det;

  Vector3d pos = pn_position(p, 1.0 - s - t, s, t);
  double fx = pos.x() - x, fy = pos.y() - y, err = std::hypot(fx, fy);
  for (int it = 0; it < 30 && err > tolerance; ++it) {
    Vector3d ds, dt;
    pn_derivatives(p, 1.0 - s - t, s, t, ds, dt);
    const double dj = ds.x() * dt.y() - dt.x() * ds.y();
    if (dj == 0.0 || !std::isfinite(dj)) break;
    const double step_s = (dt.y() * fx - dt.x() * fy) / dj;
    const double step_t = (-ds.y() * fx + ds.x() * fy) / dj;
    // Backtracking: halve the step while the residual grows.
    double lambda = 1.0;
    for (int k = 0; k < 20; ++k, lambda *= 0.5) {
      const double ns = s - lambda * step_s, nt = t - lambda * step_t;
      const Vector3d np = pn_position(p, 1.0 - ns - nt, ns, nt);
      const double ne = std::hypot(np.x() - x, np.y() - y);
      if (ne < err || k == 19) {
        s = ns, t = nt, pos = np, err = ne;
        fx = np.x() - x, fy = np.y() - y;
        break;
      }
    }
  }
  sol.b1 = 1.0 - s - t;
  sol.b2 = s;
  sol.b3 = t;
  sol.position = pos;
  sol.converged = err <= tolerance;
  return sol;
}

}  // namespace terrain
