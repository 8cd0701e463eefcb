#pragma once
// Curved point-normal (PN) triangles, Vlachos, Peters, Boyd & Mitchell 2001
// (docs/algorithms.md 1 and 2). This CPU code is the reference the renderer's shaders are
// tested against.
//
// Barycentric convention (one place): (b1, b2, b3) are the weights of corners P1, P2, P3;
// b1 + b2 + b3 = 1. Control point b_ijk carries b1^i b2^j b3^k. (s, t) = (b2, b3).
#include <Eigen/Core>
#include <array>

namespace terrain {

struct PnPatch {
  // Cubic geometry control points, in this order:
  //   b300 b030 b003 b210 b120 b021 b012 b102 b201 b111
  std::array<Eigen::Vector3d, 10> b;
  // Quadratic normal coefficients: n200 n020 n002 n110 n011 n101
  std::array<Eigen::Vector3d, 6> n;
};

enum PnIndex { B300, B030, B003, B210, B120, B021, B012, B102, B201, B111 };
enum PnNormalIndex { N200, N020, N002, N110, N011, N101 };

// The ten geometry control points (PnPatch::b order) from corner positions P1..P3 and UNIT
// vertex normals N1..N3, for any scalar type (double; Ceres' Jet when fitting normals):
// edge points (2 Pi + Pj - ((Pj - Pi) . Ni) Ni) / 3, centre E + (E - V) / 2.
template <class T>
using Vec3 = Eigen::Matrix<T, 3, 1>;
template <class T>
std::array<Vec3<T>, 10> pn_control_points(const Vec3<T>& p1, const Vec3<T>& p2, const Vec3<T>& p3,
                                          const Vec3<T>& n1, const Vec3<T>& n2, const Vec3<T>& n3) {
  const auto edge = [](const Vec3<T>& pi, const Vec3<T>& pj, const Vec3<T>& ni) -> Vec3<T> {
    return (T(2.0) * pi + pj - (pj - pi).dot(ni) * ni) / T(3.0);
  };
  std::array<Vec3<T>, 10> b;
  b[0] = p1;                // B300
  b[1] = p2;                // B030
  b[2] = p3;                // B003
  b[3] = edge(p1, p2, n1);  // B210
  b[4] = edge(p2, p1, n2);  // B120
  b[5] = edge(p2, p3, n2);  // B021
  b[6] = edge(p3, p2, n3);  // B012
  b[7] = edge(p3, p1, n3);  // B102
  b[8] = edge(p1, p3, n1);  // B201
  const Vec3<T> e = (b[3] + b[4] + b[5] + b[6] + b[7] + b[8]) / T(6.0);
  const Vec3<T> v = (p1 + p2 + p3) / T(3.0);
  b[9] = e + (e - v) / T(2.0);  // B111
  return b;
}

// The cubic P(b1, b2, b3) of control points b (PnPatch::b order), for any scalar type.
template <class T>
Vec3<T> pn_cubic(const std::array<Vec3<T>, 10>& b, const T& b1, const T& b2, const T& b3) {
  return b[0] * (b1 * b1 * b1) + b[1] * (b2 * b2 * b2) + b[2] * (b3 * b3 * b3) +
         T(3.0) * (b[3] * (b1 * b1 * b2) + b[4] * (b1 * b2 * b2) + b[8] * (b1 * b1 * b3) +
                   b[7] * (b1 * b3 * b3) + b[5] * (b2 * b2 * b3) + b[6] * (b2 * b3 * b3)) +
         T(6.0) * b[9] * (b1 * b2 * b3);
}

// Control points from corner positions P1..P3 and UNIT vertex normals N1..N3 (in this
// order, counter-clockwise): pn_control_points, and the quadratic normal field.
// Degenerate edges and cancelling normals fall back to the face normal (docs/algorithms.md 1.5).
PnPatch make_pn_patch(const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
                      const Eigen::Vector3d& p3, const Eigen::Vector3d& n1,
                      const Eigen::Vector3d& n2, const Eigen::Vector3d& n3);

// Cubic position P(b1, b2, b3).
Eigen::Vector3d pn_position(const PnPatch& p, double b1, double b2, double b3);

// Quadratic shading normal, the paper's form (no factor 2 on the mixed terms), normalized.
Eigen::Vector3d pn_normal(const PnPatch& p, double b1, double b2, double b3);

// dP/ds and dP/dt at (b1, b2, b3), with s = b2, t = b3, b1 = 1 - s - t.
void pn_derivatives(const PnPatch& p, double b1, double b2, double b3, Eigen::Vector3d& dpds,
                    Eigen::Vector3d& dpdt);

// The cubic position of a patch in monomial form over (s, t) = (b2, b3):
//   P(s, t) = sum c[m] s^a t^b, m = 0..9 for (a, b) = (0,0) (1,0) (0,1) (2,0) (1,1) (0,2)
//             (3,0) (2,1) (1,2) (0,3).
// The same polynomial as pn_position (tested to 1e-12), cheaper to evaluate with its
// derivatives: the inverse evaluation runs on it.
struct PnPolynomial {
  std::array<Eigen::Vector3d, 10> c;
  Eigen::Vector3d at(double s, double t) const;
};
PnPolynomial to_polynomial(const PnPatch& p);

struct PnXySolution {
  double b1 = 0, b2 = 0, b3 = 0;  // may be outside [0,1] when the point is not on this patch
  Eigen::Vector3d position;       // P(b1, b2, b3)
  bool converged = false;         // |P.xy - (x, y)| <= tolerance
};

// Solves P.xy(b1, b2, b3) = (x, y) by Newton's method on (s, t) from the planar
// barycentrics, with backtracking (docs/algorithms.md 2.3). `tolerance` is in the units of
// the positions. Tested: worked example 2.5, planar patches, random terrain patches.
PnXySolution pn_solve_xy(const PnPatch& p, double x, double y, double tolerance = 1e-9);
PnXySolution pn_solve_xy(const PnPolynomial& p, double x, double y, double tolerance = 1e-9);

// The planar barycentrics (s, t) = (b2, b3) of (x, y) in the flat triangle of the patch's
// corners; false when the triangle is degenerate in xy.
bool pn_planar_st(const PnPolynomial& p, double x, double y, double& s, double& t);
// Newton from the start (s0, t0) instead of the planar guess (for callers that know a
// better one, such as a neighbouring sample's solution).
PnXySolution pn_solve_xy_from(const PnPolynomial& p, double x, double y, double s0, double t0,
                              double tolerance = 1e-9);

}  // namespace terrain
