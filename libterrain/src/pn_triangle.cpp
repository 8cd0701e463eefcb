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

// Mid-edge normal n110 for the edge Pi -> Pj (docs/algorithms.md 1.3).
Vector3d mid_normal(const Vector3d& pi, const Vector3d& pj, const Vector3d& ni, const Vector3d& nj,
                    const Vector3d& face_n) {
  const Vector3d e = pj - pi;
  const double ee = e.dot(e);
  const Vector3d h =
      ee > 0.0 ? Vector3d(ni + nj - 2.0 * e.dot(ni + nj) / ee * e) : Vector3d(ni + nj);
  return normalized_or(h, face_n);
}

}  // namespace

PnPatch make_pn_patch(const Vector3d& p1, const Vector3d& p2, const Vector3d& p3,
                      const Vector3d& n1, const Vector3d& n2, const Vector3d& n3) {
  PnPatch p;
  p.b = pn_control_points<double>(p1, p2, p3, n1, n2, n3);

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
  return pn_cubic<double>(p.b, b1, b2, b3);
}

Vector3d pn_normal(const PnPatch& p, double b1, double b2, double b3) {
  const auto& n = p.n;
  const Vector3d v = n[N200] * (b1 * b1) + n[N020] * (b2 * b2) + n[N002] * (b3 * b3) +
                     n[N110] * (b1 * b2) + n[N011] * (b2 * b3) + n[N101] * (b1 * b3);
  return normalized_or(v, n[N200]);
}

void pn_derivatives(const PnPatch& p, double b1, double b2, double b3, Vector3d& dpds,
                    Vector3d& dpdt) {
  const auto& b = p.b;
  // Partial derivatives of the homogeneous cubic (docs/algorithms.md 2.2).
  const Vector3d d1 =
      3.0 * (b[B300] * (b1 * b1) + b[B120] * (b2 * b2) + b[B102] * (b3 * b3) +
             2.0 * (b[B210] * (b1 * b2) + b[B201] * (b1 * b3) + b[B111] * (b2 * b3)));
  const Vector3d d2 =
      3.0 * (b[B210] * (b1 * b1) + b[B030] * (b2 * b2) + b[B012] * (b3 * b3) +
             2.0 * (b[B120] * (b1 * b2) + b[B111] * (b1 * b3) + b[B021] * (b2 * b3)));
  const Vector3d d3 =
      3.0 * (b[B201] * (b1 * b1) + b[B021] * (b2 * b2) + b[B003] * (b3 * b3) +
             2.0 * (b[B111] * (b1 * b2) + b[B102] * (b1 * b3) + b[B012] * (b2 * b3)));
  dpds = d2 - d1;
  dpdt = d3 - d1;
}

namespace {

// Monomial coefficients of the ten cubic Bernstein terms: kBasis[term][m], term in PnIndex
// order, m as in PnPolynomial. Built once by expanding 3!/(i!j!k!) (1-s-t)^i s^j t^k.
struct BasisTable {
  double m[10][10] = {};
  BasisTable() {
    const int exps[10][3] = {{3, 0, 0}, {0, 3, 0}, {0, 0, 3}, {2, 1, 0}, {1, 2, 0},
                             {0, 2, 1}, {0, 1, 2}, {1, 0, 2}, {2, 0, 1}, {1, 1, 1}};
    const int mono[10][2] = {{0, 0}, {1, 0}, {0, 1}, {2, 0}, {1, 1},
                             {0, 2}, {3, 0}, {2, 1}, {1, 2}, {0, 3}};
    const double fact[4] = {1, 1, 2, 6};
    for (int term = 0; term < 10; ++term) {
      const int i = exps[term][0], j = exps[term][1], k = exps[term][2];
      // poly[a][b]: coefficient of s^a t^b; start with (1 - s - t)^i.
      double poly[4][4] = {{1}};
      for (int e = 0; e < i; ++e) {
        double next[4][4] = {};
        for (int a = 0; a < 4; ++a)
          for (int b = 0; a + b < 4; ++b) {
            if (poly[a][b] == 0) continue;
            next[a][b] += poly[a][b];
            if (a + 1 < 4) next[a + 1][b] -= poly[a][b];
            if (b + 1 < 4) next[a][b + 1] -= poly[a][b];
          }
        std::copy(&next[0][0], &next[0][0] + 16, &poly[0][0]);
      }
      const double coef = fact[3] / (fact[i] * fact[j] * fact[k]);
      for (int mi = 0; mi < 10; ++mi) {
        const int a = mono[mi][0] - j, b = mono[mi][1] - k;  // times s^j t^k
        if (a >= 0 && b >= 0 && a + b < 4) m[term][mi] = coef * poly[a][b];
      }
    }
  }
};
const BasisTable kBasis;

}  // namespace

PnPolynomial to_polynomial(const PnPatch& p) {
  PnPolynomial out;
  for (auto& c : out.c) c.setZero();
  for (int term = 0; term < 10; ++term)
    for (int mi = 0; mi < 10; ++mi)
      if (kBasis.m[term][mi] != 0.0)
        out.c[std::size_t(mi)] += kBasis.m[term][mi] * p.b[std::size_t(term)];
  return out;
}

Vector3d PnPolynomial::at(double s, double t) const {
  return c[0] + s * (c[1] + s * (c[3] + s * c[6]) + t * (c[4] + s * c[7])) +
         t * (c[2] + t * (c[5] + t * c[9]) + s * t * c[8]);
}

PnXySolution pn_solve_xy(const PnPatch& p, double x, double y, double tolerance) {
  return pn_solve_xy(to_polynomial(p), x, y, tolerance);
}

bool pn_planar_st(const PnPolynomial& p, double x, double y, double& s, double& t) {
  const auto& c = p.c;
  const Vector3d p1 = c[0], p2 = c[0] + c[1] + c[3] + c[6], p3 = c[0] + c[2] + c[5] + c[9];
  const double ax = p2.x() - p1.x(), ay = p2.y() - p1.y();
  const double cx = p3.x() - p1.x(), cy = p3.y() - p1.y();
  const double det = ax * cy - ay * cx;
  if (det == 0.0) return false;
  s = ((x - p1.x()) * cy - (y - p1.y()) * cx) / det;
  t = (ax * (y - p1.y()) - ay * (x - p1.x())) / det;
  return true;
}

PnXySolution pn_solve_xy(const PnPolynomial& p, double x, double y, double tolerance) {
  double s, t;
  if (!pn_planar_st(p, x, y, s, t)) return {};
  return pn_solve_xy_from(p, x, y, s, t, tolerance);
}

PnXySolution pn_solve_xy_from(const PnPolynomial& p, double x, double y, double s, double t,
                              double tolerance) {
  const auto& c = p.c;
  // xy of P and its partial derivatives, from the monomial coefficients.
  auto eval = [&](double s, double t, int d, double& fx, double& fy, double& sx, double& sy,
                  double& tx, double& ty) {
    const double ss = s * s, tt = t * t, st = s * t;
    auto comp = [&](int k, double& v, double& ds, double& dt) {
      v = c[0][k] + c[1][k] * s + c[2][k] * t + c[3][k] * ss + c[4][k] * st + c[5][k] * tt +
          c[6][k] * ss * s + c[7][k] * ss * t + c[8][k] * s * tt + c[9][k] * tt * t;
      if (d) {
        ds = c[1][k] + 2 * c[3][k] * s + c[4][k] * t + 3 * c[6][k] * ss + 2 * c[7][k] * st +
             c[8][k] * tt;
        dt = c[2][k] + c[4][k] * s + 2 * c[5][k] * t + c[7][k] * ss + 2 * c[8][k] * st +
             3 * c[9][k] * tt;
      }
    };
    comp(0, fx, sx, tx);
    comp(1, fy, sy, ty);
  };
  PnXySolution sol;

  // Squared residuals throughout (hypot is costly and not needed for comparisons).
  const double tol2 = tolerance * tolerance;
  double px, py, sx, sy, tx, ty;
  eval(s, t, 1, px, py, sx, sy, tx, ty);
  double fx = px - x, fy = py - y, err2 = fx * fx + fy * fy;
  for (int it = 0; it < 30 && err2 > tol2; ++it) {
    const double dj = sx * ty - tx * sy;
    if (dj == 0.0 || !std::isfinite(dj)) break;
    const double step_s = (ty * fx - tx * fy) / dj;
    const double step_t = (-sy * fx + sx * fy) / dj;
    // Backtracking: halve the step while the residual grows.
    double lambda = 1.0;
    for (int k = 0; k < 20; ++k, lambda *= 0.5) {
      const double ns = s - lambda * step_s, nt = t - lambda * step_t;
      double nx, ny, nsx, nsy, ntx, nty;
      eval(ns, nt, 1, nx, ny, nsx, nsy, ntx, nty);
      const double ne2 = (nx - x) * (nx - x) + (ny - y) * (ny - y);
      if (ne2 < err2 || k == 19) {
        s = ns, t = nt, err2 = ne2;
        px = nx, py = ny, sx = nsx, sy = nsy, tx = ntx, ty = nty;
        fx = px - x, fy = py - y;
        break;
      }
    }
  }
  sol.b1 = 1.0 - s - t;
  sol.b2 = s;
  sol.b3 = t;
  sol.position = p.at(s, t);
  sol.converged = err2 <= tol2;
  return sol;
}

}  // namespace terrain
