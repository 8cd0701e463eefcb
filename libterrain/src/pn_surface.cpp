#include "terrain/pn_surface.hpp"

#include <fmt/format.h>

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace terrain {

PnPatch face_patch(const GridMesh& mesh, std::size_t f) {
  const auto v = mesh.topo.face(f);
  return make_pn_patch(mesh.positions[v[0]].cast<double>(), mesh.positions[v[1]].cast<double>(),
                       mesh.positions[v[2]].cast<double>(), mesh.normals[v[0]].cast<double>(),
                       mesh.normals[v[1]].cast<double>(), mesh.normals[v[2]].cast<double>());
}

namespace {

constexpr std::size_t kNoFace = GridTopology::kNoFace;

// The face of the flat grid under local (x, y), or kNoFace outside the grid's extent
// (with half a cell of slack).
std::size_t flat_face(const GridMesh& mesh, double x, double y) {
  const GridTopology& topo = mesh.topo;
  const double fc = x / mesh.geo.dx, fr = -y / mesh.geo.dy;
  if (!(fc >= -0.5 && fr >= -0.5 && fc <= double(topo.cols) - 0.5 && fr <= double(topo.rows) - 0.5))
    return kNoFace;
  const std::size_t c = std::size_t(std::clamp(std::floor(fc), 0.0, double(topo.cols - 2)));
  const std::size_t r = std::size_t(std::clamp(std::floor(fr), 0.0, double(topo.rows - 2)));
  // Face 0 (NW, SW, SE) lies below the NW-SE diagonal: (fr - r) >= (fc - c).
  return topo.face_of_cell(r, c, (fr - double(r)) >= (fc - double(c)) ? 0 : 1);
}

struct WalkResult {
  std::size_t face = kNoFace;
  PnXySolution solution;
};

// The Newton correction (solution minus planar guess) of the last solved point, a
// better start for the next point in the same face (samples along a row).
struct Hint {
  std::size_t face = kNoFace;
  double ds = 0, dt = 0;
};

// The patch walk of pn_point_above over polynomials from `poly(face)`.
template <class PolyOf>
WalkResult walk(const GridMesh& mesh, double x, double y, PolyOf&& poly, Hint& hint) {
  std::size_t f = flat_face(mesh, x, y);
  if (f == kNoFace) return {};
  const double tol = 5e-7;  // metres: half the 1e-6 m the inverse evaluation promises
  WalkResult best;
  double best_min = -1e300;
  std::size_t prev = kNoFace;
  for (int hop = 0; hop < 8; ++hop) {
    const PnPolynomial& pf = poly(f);
    double s0, t0;
    if (!pn_planar_st(pf, x, y, s0, t0)) break;
    const double ps = s0, pt = t0;
    if (hint.face == f) s0 += hint.ds, t0 += hint.dt;
    const PnXySolution s = pn_solve_xy_from(pf, x, y, s0, t0, tol);
    if (!s.converged) break;
    hint = {f, s.b2 - ps, s.b3 - pt};
    const double bary[3] = {s.b1, s.b2, s.b3};
    const int k = int(std::min_element(bary, bary + 3) - bary);
    const std::size_t next = mesh.topo.face_across(f, k);
    if (bary[k] >= -1e-9 || (next == kNoFace && bary[k] >= -0.5)) return {f, s};
    if (bary[k] > best_min) {
      best_min = bary[k];
      best = {f, s};
    }
    if (next == kNoFace) break;  // far outside the mesh's edge (a fold of a rough surface's patch)
    if (next == prev) break;     // ping-pong across one edge from rounding: take the better side
    prev = f;
    f = next;
  }
  return best_min >= -1e-6 ? best : WalkResult{};
}

}  // namespace

std::optional<SurfacePoint> pn_point_above(const GridMesh& mesh, double x, double y) {
  PnPolynomial scratch;
  Hint hint;
  const WalkResult w = walk(
      mesh, x, y,
      [&](std::size_t f) -> const PnPolynomial& {
        scratch = to_polynomial(face_patch(mesh, f));
        return scratch;
      },
      hint);
  if (w.face == kNoFace) return std::nullopt;
  const PnXySolution& s = w.solution;
  return SurfacePoint{w.face, s.b1,       s.b2,
                      s.b3,   s.position, pn_normal(face_patch(mesh, w.face), s.b1, s.b2, s.b3)};
}

std::pair<std::size_t, std::size_t> sampled_size(const GridMesh& mesh, double spacing) {
  const double width = double(mesh.topo.cols - 1) * mesh.geo.dx,
               height = double(mesh.topo.rows - 1) * mesh.geo.dy;
  return {std::size_t(std::floor(width / spacing + 1e-9)) + 1,
          std::size_t(std::floor(height / spacing + 1e-9)) + 1};
}

namespace {

// No-data at every sample in a mesh cell with a filled corner (GridMesh::filled): a
// sample on a cell's shared edge or corner belongs to each cell it touches.
void drop_filled_cells(const GridMesh& mesh, Grid& grid) {
  const std::size_t cols = mesh.topo.cols, rows = mesh.topo.rows;
  const double s = grid.geo.dx;
#pragma omp parallel for schedule(static)
  for (long j = 0; j < long(grid.rows); ++j) {
    const double v = double(j) * s / mesh.geo.dy;  // cell rows from the top
    const std::size_t r0 = std::size_t(std::max(0.0, std::ceil(v) - 1)),
                      r1 = std::min(rows - 2, std::size_t(v));
    for (std::size_t i = 0; i < grid.cols; ++i) {
      const double u = double(i) * s / mesh.geo.dx;
      const std::size_t c0 = std::size_t(std::max(0.0, std::ceil(u) - 1)),
                        c1 = std::min(cols - 2, std::size_t(u));
      bool filled = false;
      for (std::size_t r = r0; r <= r1 + 1 && !filled; ++r)
        for (std::size_t c = c0; c <= c1 + 1 && !filled; ++c)
          filled = !drained(mesh.filled[r * cols + c]);
      if (filled) grid.z[std::size_t(j) * grid.cols + i] = std::numeric_limits<float>::quiet_NaN();
    }
  }
}

// The sampled grid's georeference: samples at the spacing from the mesh's first vertex.
Georef sampled_georef(const GridMesh& mesh, double spacing) {
  Georef geo;
  geo.dx = geo.dy = spacing;
  geo.x0 = mesh.geo.origin_x - spacing / 2;
  geo.y0 = mesh.geo.origin_y + spacing / 2;
  geo.crs_wkt = mesh.geo.crs_wkt;
  geo.epsg = mesh.geo.epsg;
  geo.crs_kind = mesh.geo.crs_wkt.empty() ? CrsKind::None : CrsKind::Projected;
  return geo;
}

// The height at (x, y) of the flat triangle under it (where the PN surface folds over).
double flat_height(const GridMesh& mesh, double x, double y) {
  const auto v = mesh.topo.face(flat_face(mesh, x, y));
  const Eigen::Vector3d a = mesh.positions[v[0]].cast<double>(),
                        b = mesh.positions[v[1]].cast<double>(),
                        c = mesh.positions[v[2]].cast<double>();
  const Eigen::Vector3d n = face_normal(a, b, c);  // equal normals: the patch is the flat triangle
  return pn_solve_xy(to_polynomial(make_pn_patch(a, b, c, n, n, n)), x, y).position.z();
}

// Polynomials of three cell rows (`face_row` faces each), slot = cell row % 3, built on
// first use; consecutive samples share faces.
class PolynomialCache {
 public:
  PolynomialCache(const GridMesh& mesh, std::size_t face_row) : mesh_(mesh), face_row_(face_row) {}
  const PnPolynomial& at(std::size_t f) {
    if (f == last_face_) return *last_poly_;
    const std::size_t row = f / face_row_;
    Slot& slot = slots_[row % 3];
    if (slot.row != row) {
      slot.polys.resize(face_row_);
      for (std::size_t k = 0; k < face_row_; ++k)
        slot.polys[k] = to_polynomial(face_patch(mesh_, row * face_row_ + k));
      slot.row = row;
    }
    last_face_ = f;
    last_poly_ = &slot.polys[f - row * face_row_];
    return *last_poly_;
  }

 private:
  struct Slot {
    std::size_t row = std::size_t(-1);
    std::vector<PnPolynomial> polys;
  };
  const GridMesh& mesh_;
  std::size_t face_row_;
  Slot slots_[3];
  std::size_t last_face_ = kNoFace;
  const PnPolynomial* last_poly_ = nullptr;
};

}  // namespace

SampledSurface sample_pn_surface(const GridMesh& mesh, double spacing, const Progress& progress) {
  if (!(spacing > 0.0 && std::isfinite(spacing)))
    throw Error("the sampling spacing must be a positive number of metres");
  const double width = double(mesh.topo.cols - 1) * mesh.geo.dx,
               height = double(mesh.topo.rows - 1) * mesh.geo.dy;
  // Named variables, not a structured binding: clang 14 cannot use a binding inside the OpenMP
  // region below.
  const auto size = sampled_size(mesh, spacing);
  const std::size_t nx = size.first, ny = size.second;
  if (nx < 2 || ny < 2)
    throw Error(fmt::format(
        "sampling at {:g} m gives {} x {} points: the sampled surface needs at least 2 x 2; give a "
        "spacing at most the mesh's extent ({:g} x {:g} m)",
        spacing, nx, ny, width, height));
  if (double(nx) * double(ny) >= double(std::numeric_limits<std::uint32_t>::max()))
    throw Error("sampling at " + std::to_string(spacing) +
                " m would give more than 2^32 - 1 points");
  SampledSurface out;
  out.grid = Grid(ny, nx, sampled_georef(mesh, spacing));
  const std::size_t face_row = 2 * (mesh.topo.cols - 1);
  // Blocks of rows between progress reports; each block rebuilds the per-thread caches.
  const long rows = long(ny), block = std::max(256L, rows / 20);
  std::size_t fallbacks = 0;
  for (long jb = 0; jb < rows; jb += block) {
    const long je = std::min(rows, jb + block);
#pragma omp parallel reduction(+ : fallbacks)
    {
      PolynomialCache cache{mesh, face_row};
      auto poly = [&](std::size_t f) -> const PnPolynomial& { return cache.at(f); };
#pragma omp for schedule(static)
      for (long j = jb; j < je; ++j) {
        const double y = -double(j) * spacing;
        Hint hint;  // per row: the result does not depend on how rows are shared out
        for (std::size_t i = 0; i < nx; ++i) {
          const double x = double(i) * spacing;
          const WalkResult w = walk(mesh, x, y, poly, hint);
          double z;
          if (w.face != kNoFace) {
            z = w.solution.position.z();
          } else {  // fold-over: the flat triangle under the point
            ++fallbacks;
            z = flat_height(mesh, x, y);
          }
          out.grid.z[std::size_t(j) * nx + i] = float(z + mesh.geo.origin_z);
        }
      }
    }
    report(progress, double(je) / double(rows));
  }
  out.fallbacks = fallbacks;
  if (mesh.filled.size() == mesh.n_vertices()) drop_filled_cells(mesh, out.grid);
  return out;
}

}  // namespace terrain
