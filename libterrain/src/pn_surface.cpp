#include "terrain/pn_surface.hpp"

#include <algorithm>
#include <cmath>

namespace terrain {

PnPatch face_patch(const GridMesh& mesh, std::size_t f) {
  const auto v = mesh.topo.face(f);
  return make_pn_patch(mesh.positions[v[0]].cast<double>(), mesh.positions[v[1]].cast<double>(),
                       mesh.positions[v[2]].cast<double>(), mesh.normals[v[0]].cast<double>(),
                       mesh.normals[v[1]].cast<double>(), mesh.normals[v[2]].cast<double>());
}

namespace {

constexpr std::size_t kNone = std::size_t(-1);

// The face across the edge opposite corner k of face f (grid_mesh.hpp convention), or
// kNone on the mesh boundary. Face 0 = (NW, SW, SE): opposite NW is the south edge (cell
// below, face 1), opposite SW the diagonal (face 1), opposite SE the west edge (cell to
// the west, face 1). Face 1 = (NW, SE, NE): opposite NW is the east edge (cell to the
// east, face 0), opposite SE the north edge (cell above, face 0), opposite NE the
// diagonal (face 0).
std::size_t neighbour(const GridTopology& topo, std::size_t f, int k) {
  const std::size_t cell = f / 2, r = cell / (topo.cols - 1), c = cell % (topo.cols - 1);
  const std::size_t last_r = topo.rows - 2, last_c = topo.cols - 2;
  if (f % 2 == 0) {
    if (k == 0) return r < last_r ? topo.face_of_cell(r + 1, c, 1) : kNone;
    if (k == 1) return f + 1;
    return c > 0 ? topo.face_of_cell(r, c - 1, 1) : kNone;
  }
  if (k == 0) return c < last_c ? topo.face_of_cell(r, c + 1, 0) : kNone;
  if (k == 1) return r > 0 ? topo.face_of_cell(r - 1, c, 0) : kNone;
  return f - 1;
}

}  // namespace

std::optional<SurfacePoint> pn_point_above(const GridMesh& mesh, double x, double y) {
  const GridTopology& topo = mesh.topo;
  const double dx = mesh.geo.dx, dy = mesh.geo.dy;
  const double fc = x / dx, fr = -y / dy;
  if (!(fc >= -0.5 && fr >= -0.5 && fc <= double(topo.cols) - 0.5 && fr <= double(topo.rows) - 0.5))
    return std::nullopt;
  // The flat grid triangle under (x, y).
  const std::size_t c = std::size_t(std::clamp(std::floor(fc), 0.0, double(topo.cols - 2)));
  const std::size_t r = std::size_t(std::clamp(std::floor(fr), 0.0, double(topo.rows - 2)));
  // Face 0 (NW, SW, SE) lies below the NW-SE diagonal: (fr - r) >= (fc - c).
  std::size_t f = topo.face_of_cell(r, c, (fr - double(r)) >= (fc - double(c)) ? 0 : 1);

  const double tol = 1e-9 * std::max({dx, dy, 1.0});
  std::optional<SurfacePoint> best;
  double best_min = -1e300;
  std::size_t prev = kNone;
  for (int hop = 0; hop < 8; ++hop) {
    const PnPatch patch = face_patch(mesh, f);
    const PnXySolution s = pn_solve_xy(patch, x, y, tol);
    if (!s.converged) break;
    const double bary[3] = {s.b1, s.b2, s.b3};
    const int k = int(std::min_element(bary, bary + 3) - bary);
    const std::size_t next = neighbour(topo, f, k);
    const bool inside = bary[k] >= -1e-9;
    const bool boundary = next == kNone && bary[k] >= -0.5;
    SurfacePoint here{f, s.b1, s.b2, s.b3, s.position, pn_normal(patch, s.b1, s.b2, s.b3)};
    if (inside || boundary) return here;
    if (bary[k] > best_min) {
      best_min = bary[k];
      best = here;
    }
    if (next == prev) break;  // ping-pong across one edge from rounding: take the better side
    prev = f;
    f = next;
  }
  if (best && best_min >= -1e-6) return best;
  return std::nullopt;
}

}  // namespace terrain
