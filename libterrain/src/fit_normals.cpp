// Fitted vertex normals (fit_normals.hpp): Ceres over the PN patches' inverse evaluation.
#include "terrain/fit_normals.hpp"

#include <ceres/ceres.h>
#include <ceres/manifold.h>
#include <ogr_spatialref.h>
#include <omp.h>

#include <Eigen/LU>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <memory>

#include "terrain/pn_surface.hpp"
#include "terrain/pn_triangle.hpp"

namespace terrain {

namespace {

using Eigen::Vector3d;

// The residuals of the samples of one face, as pn_face_residuals computes them, each
// sample's inverse evaluation started from its solution at the last accepted iterate (at
// first, under the starting normals `n`). Not from the last evaluation's, whatever it was:
// the residual would then depend on the trial steps (two roots where a patch folds), and
// the logged cost rose between iterations.
class FaceCost : public ceres::CostFunction {
 public:
  FaceCost(const std::array<Vector3d, 3>& corner, std::vector<Vector3d> samples,
           const std::array<const double*, 3>& n)
      : corner_(corner), samples_(std::move(samples)) {
    set_num_residuals(int(samples_.size()));
    *mutable_parameter_block_sizes() = {3, 3, 3};
    std::vector<double> r(samples_.size());
    pn_face_residuals(corner_, samples_, n, r.data(), {nullptr, nullptr, nullptr}, nullptr,
                      &start_);
  }
  bool Evaluate(double const* const* n, double* residuals, double** jacobians) const override {
    std::array<double*, 3> jac{nullptr, nullptr, nullptr};
    if (jacobians) jac = {jacobians[0], jacobians[1], jacobians[2]};
    // The Jacobian is evaluated at accepted iterates only: their solutions start the
    // trial steps from there.
    const bool accepted = jac[0] || jac[1] || jac[2];
    pn_face_residuals(corner_, samples_, {n[0], n[1], n[2]}, residuals, jac, &start_,
                      accepted ? &solved_ : nullptr);
    if (accepted) start_.swap(solved_);
    return true;
  }

 private:
  std::array<Vector3d, 3> corner_;
  std::vector<Vector3d> samples_;
  mutable std::vector<Eigen::Vector2d> start_, solved_;
};

// weight * (n - n0): the pull toward the starting normal.
struct PullCost {
  Vector3d n0;
  double weight;
  template <class T>
  bool operator()(const T* n, T* residuals) const {
    for (int k = 0; k < 3; ++k) residuals[k] = weight * (n[k] - n0[k]);
    return true;
  }
};

// The cost of the current iterate after every iteration. Ceres' own IterationSummary::cost
// is not that (it can be a trial's cost, or differ from the state after an accepted step),
// so the problem is evaluated at the state (update_state_every_iteration).
struct CostLog : ceres::IterationCallback {
  std::vector<double>* costs = nullptr;
  ceres::Problem* problem = nullptr;
  int threads = 1;
  ceres::CallbackReturnType operator()(const ceres::IterationSummary&) override {
    double cost = 0;
    ceres::Problem::EvaluateOptions eo;
    eo.num_threads = threads;
    problem->Evaluate(eo, &cost, nullptr, nullptr, nullptr);
    costs->push_back(cost);
    return ceres::SOLVER_CONTINUE;
  }
};

// The samples on the PN surface under the current normals, in one pass: the surface's error
// at them and the face each lies in, as lists per face (samples with no point above: none).
struct Assignment {
  std::vector<std::size_t> offset;  // #F + 1
  std::vector<std::uint32_t> sample;
};

SurfaceError locate(const GridMesh& mesh, const std::vector<Vector3d>& local, Assignment* a) {
  constexpr std::uint32_t kNone = std::uint32_t(-1);
  std::vector<std::uint32_t> face(a ? local.size() : 0, kNone);
  double se = 0, mx = 0;
  std::size_t n = 0;
#pragma omp parallel for schedule(dynamic, 1024) reduction(+ : se, n) reduction(max : mx)
  for (std::ptrdiff_t i = 0; i < std::ptrdiff_t(local.size()); ++i) {
    const Vector3d& q = local[std::size_t(i)];
    const auto p = pn_point_above(mesh, q.x(), q.y());
    if (!p) continue;
    if (a) face[std::size_t(i)] = std::uint32_t(p->face);
    const double e = p->position.z() - q.z();
    se += e * e;
    mx = std::max(mx, std::abs(e));
    ++n;
  }
  if (a) {
    a->offset.assign(mesh.n_faces() + 1, 0);
    for (const std::uint32_t f : face)
      if (f != kNone) ++a->offset[f + 1];
    for (std::size_t f = 0; f < mesh.n_faces(); ++f) a->offset[f + 1] += a->offset[f];
    a->sample.resize(a->offset.back());
    std::vector<std::size_t> fill(a->offset.begin(), a->offset.end() - 1);
    for (std::size_t i = 0; i < face.size(); ++i)
      if (face[i] != kNone) a->sample[fill[face[i]]++] = std::uint32_t(i);
  }
  return {n ? std::sqrt(se / double(n)) : 0.0, mx, n};
}

std::vector<Vector3d> to_local(const GridMesh& mesh, const SourceSamples& s) {
  std::vector<Vector3d> out(s.size());
  for (std::size_t i = 0; i < s.size(); ++i)
    out[i] = Vector3d(s.x[i] - mesh.geo.origin_x, s.y[i] - mesh.geo.origin_y,
                      s.z[i] - mesh.geo.origin_z);
  return out;
}

bool inside(const GridMesh& mesh, double wx, double wy) {
  const double x = wx - mesh.geo.origin_x, y = wy - mesh.geo.origin_y;
  return x >= 0 && x <= double(mesh.topo.cols - 1) * mesh.geo.dx && y <= 0 &&
         y >= -double(mesh.topo.rows - 1) * mesh.geo.dy;
}

// The face's PN polynomial for the corner normals `n`; with `m`, each control point's
// derivatives by the normals too (the control points in dual numbers, once per face).
PnPolynomial face_polynomial(const std::array<Eigen::Vector3d, 3>& corner,
                             const std::array<const double*, 3>& n,
                             std::array<Eigen::Matrix<double, 3, 9>, 10>* m) {
  PnPatch pd;
  if (m) {
    using J = ceres::Jet<double, 9>;
    Vec3<J> nj[3];
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) nj[j][k] = J(n[std::size_t(j)][k], 3 * j + k);
    const auto b = pn_control_points<J>(corner[0].cast<J>(), corner[1].cast<J>(),
                                        corner[2].cast<J>(), nj[0], nj[1], nj[2]);
    for (std::size_t k = 0; k < 10; ++k)
      for (int r = 0; r < 3; ++r) {
        pd.b[k][r] = b[k][r].a;
        (*m)[k].row(r) = b[k][r].v.transpose();
      }
  } else {
    const auto b = pn_control_points<double>(
        corner[0], corner[1], corner[2], Eigen::Map<const Vector3d>(n[0]),
        Eigen::Map<const Vector3d>(n[1]), Eigen::Map<const Vector3d>(n[2]));
    for (std::size_t k = 0; k < 10; ++k) pd.b[k] = b[k];
  }
  return to_polynomial(pd);
}

// Sample i's row of each corner normal's Jacobian (those asked for), at its solution
// (s0, t0), with g the height's gradient there and m the control points' derivatives.
void sample_jacobians(double s0, double t0, const Eigen::RowVector2d& g,
                      const std::array<Eigen::Matrix<double, 3, 9>, 10>& m,
                      const std::array<double*, 3>& jacobians, std::size_t i) {
  const Eigen::RowVector3d w(-g.x(), -g.y(), 1.0);
  const double u = 1.0 - s0 - t0, v = s0, x = t0;  // Bernstein weights in PnPatch::b order
  // The corners do not move with the normals; each edge point moves with its own corner's
  // normal only (B210 and B201 with n1, B120 and B021 with n2, B012 and B102 with n3); the
  // centre B111 = 1.5 mean(edge points) - 0.5 mean(corners) moves with a quarter of each.
  const double b9 = 1.5 * u * v * x;  // 6 u v x / 4
  const double bw[10] = {0,
                         0,
                         0,
                         3 * u * u * v + b9,
                         3 * u * v * v + b9,
                         3 * v * v * x + b9,
                         3 * v * x * x + b9,
                         3 * u * x * x + b9,
                         3 * u * u * x + b9,
                         0};
  constexpr std::size_t kEdge[3][2] = {{B210, B201}, {B120, B021}, {B012, B102}};
  for (std::size_t j = 0; j < 3; ++j) {
    if (!jacobians[j]) continue;
    const auto d = (bw[kEdge[j][0]] * m[kEdge[j][0]].middleCols<3>(long(3 * j)) +
                    bw[kEdge[j][1]] * m[kEdge[j][1]].middleCols<3>(long(3 * j)))
                       .eval();
    const Eigen::RowVector3d r = w * d;
    for (std::size_t k = 0; k < 3; ++k) jacobians[j][3 * i + k] = r[long(k)];
  }
}

}  // namespace

void pn_face_residuals(const std::array<Eigen::Vector3d, 3>& corner,
                       const std::vector<Eigen::Vector3d>& samples,
                       const std::array<const double*, 3>& n, double* residuals,
                       const std::array<double*, 3>& jacobians,
                       const std::vector<Eigen::Vector2d>* start,
                       std::vector<Eigen::Vector2d>* solved) {
  if (solved) solved->resize(samples.size());
  using Derivatives = std::array<Eigen::Matrix<double, 3, 9>, 10>;
  Derivatives m;  // d b_k / d(n1, n2, n3)
  const bool jac = jacobians[0] || jacobians[1] || jacobians[2];
  const PnPolynomial poly = face_polynomial(corner, n, jac ? &m : nullptr);
  const auto& c = poly.c;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const Vector3d& q = samples[i];
    // Newton from the caller's start if it has one (FaceCost: the solutions at the last
    // accepted iterate, a step or two away), else from the planar guess.
    PnXySolution sol;
    if (start && std::isfinite((*start)[i].x()))
      sol = pn_solve_xy_from(poly, q.x(), q.y(), (*start)[i].x(), (*start)[i].y(), 1e-7);
    if (!sol.converged) sol = pn_solve_xy(poly, q.x(), q.y(), 1e-7);
    double s0 = sol.b2, t0 = sol.b3;
    if (!sol.converged && !pn_planar_st(poly, q.x(), q.y(), s0, t0)) s0 = t0 = 1.0 / 3.0;
    if (solved) (*solved)[i] = sol.converged ? Eigen::Vector2d(s0, t0) : Eigen::Vector2d(NAN, NAN);
    const Vector3d p0 = sol.converged ? sol.position : poly.at(s0, t0);
    // dP/ds, dP/dt from the monomial form (PnPolynomial's order).
    const double ss = s0 * s0, st = s0 * t0, tt = t0 * t0;
    const Vector3d dpds =
        c[1] + 2 * s0 * c[3] + t0 * c[4] + 3 * ss * c[6] + 2 * st * c[7] + tt * c[8];
    const Vector3d dpdt =
        c[2] + s0 * c[4] + 2 * t0 * c[5] + ss * c[7] + 2 * st * c[8] + 3 * tt * c[9];
    Eigen::Matrix2d jm;
    jm << dpds.x(), dpdt.x(), dpds.y(), dpdt.y();
    const Eigen::RowVector2d g = Eigen::RowVector2d(dpds.z(), dpdt.z()) * jm.inverse();
    // The height after one Newton step from (s0, t0), to first order: z - g F.
    residuals[i] = p0.z() - (g.x() * (p0.x() - q.x()) + g.y() * (p0.y() - q.y())) - q.z();
    if (!jac) continue;
    sample_jacobians(s0, t0, g, m, jacobians, i);
  }
}

SourceSamples dem_samples_for_mesh(const Grid& dem, const GridMesh& mesh) {
  std::unique_ptr<OGRCoordinateTransformation> ct;
  if (dem.geo.crs_kind == CrsKind::Geographic) {
    if (mesh.geo.crs_wkt.empty())
      throw Error("the DEM is geographic but the mesh has no CRS: cannot relate them");
    OGRSpatialReference src, dst;
    if (src.importFromWkt(dem.geo.crs_wkt.c_str()) != OGRERR_NONE ||
        dst.importFromWkt(mesh.geo.crs_wkt.c_str()) != OGRERR_NONE)
      throw Error("cannot read the DEM's or the mesh's CRS");
    src.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    dst.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    ct.reset(OGRCreateCoordinateTransformation(&src, &dst));
    if (!ct) throw Error("no transformation from the DEM's CRS to the mesh's");
  }
  SourceSamples out;
  std::vector<double> xs(dem.cols), ys(dem.cols);
  for (std::size_t r = 0; r < dem.rows; ++r) {
    for (std::size_t c = 0; c < dem.cols; ++c) {
      xs[c] = dem.geo.x_of_col(double(c));
      ys[c] = dem.geo.y_of_row(double(r));
    }
    if (ct && !ct->Transform(dem.cols, xs.data(), ys.data()))
      throw Error("cannot project the DEM's samples");
    for (std::size_t c = 0; c < dem.cols; ++c) {
      const float z = dem.at(r, c);
      if (std::isnan(z) || !inside(mesh, xs[c], ys[c])) continue;
      out.x.push_back(xs[c]);
      out.y.push_back(ys[c]);
      out.z.push_back(double(z));
    }
  }
  return out;
}

SourceSamples samples_inside_mesh(const SourceSamples& all, const GridMesh& mesh) {
  SourceSamples out;
  for (std::size_t i = 0; i < all.size(); ++i)
    if (inside(mesh, all.x[i], all.y[i])) {
      out.x.push_back(all.x[i]);
      out.y.push_back(all.y[i]);
      out.z.push_back(all.z[i]);
    }
  return out;
}

// What every block of a round shares (fit_pn_normals): the mesh, the samples and their
// faces, the options, the round's starting normals and the first round's, the pull, the
// blocks' cores, the threads a block gets; and the normals the blocks' cores are kept in.
struct BlockRound {
  const GridMesh& mesh;
  const Assignment& a;
  const std::vector<Vector3d>& local;
  const NormalFitOptions& opt;
  const std::vector<Vector3d>& snapshot;
  const std::vector<Vector3d>& start;
  double pull;
  std::size_t brows, bcols, nbc;
  int per_block;
  ceres::SphereManifold<3>& sphere;
  NormalFitReport& rep;
  std::vector<Vector3d>& normal;
};

// The cost of every face of cells fr0 .. fr1 - 1, fc0 .. fc1 - 1 that has samples, over the
// block's normals `nb` (a face's corners outside the block are held fixed by the caller).
void add_face_costs(ceres::Problem& problem, const BlockRound& k, std::vector<Vector3d>& nb,
                    std::size_t fr0, std::size_t fc0, std::size_t fr1, std::size_t fc1) {
  const GridMesh& mesh = k.mesh;
  const GridTopology& topo = mesh.topo;
  const Assignment& a = k.a;
  for (std::size_t r = fr0; r < fr1; ++r)
    for (std::size_t c = fc0; c < fc1; ++c)
      for (int half = 0; half < 2; ++half) {
        const std::size_t f = topo.face_of_cell(r, c, half);
        if (a.offset[f] == a.offset[f + 1]) continue;
        const auto fv = topo.face(f);
        std::array<Vector3d, 3> corner;
        for (int j = 0; j < 3; ++j)
          corner[std::size_t(j)] = mesh.positions[fv[std::size_t(j)]].cast<double>();
        const std::size_t count = a.offset[f + 1] - a.offset[f];
        const std::size_t take = k.opt.face_samples ? std::min(count, k.opt.face_samples) : count;
        std::vector<Vector3d> picked;
        for (std::size_t j = 0; j < take; ++j)  // evenly strided over the face's samples
          picked.push_back(k.local[a.sample[a.offset[f] + j * count / take]]);
        problem.AddResidualBlock(
            new FaceCost(corner, std::move(picked),
                         {nb[fv[0]].data(), nb[fv[1]].data(), nb[fv[2]].data()}),
            nullptr, nb[fv[0]].data(), nb[fv[1]].data(), nb[fv[2]].data());
      }
}

// The block's problem solved by Levenberg-Marquardt; returns its iterations.
std::size_t solve_problem(ceres::Problem& problem, const BlockRound& k) {
  ceres::Solver::Options so;
  // Conjugate gradients on the normal equations (Jacobi preconditioner): the blocks are
  // grids of up to 400 x 400 vertices, on which the sparse Cholesky factorization took
  // two thirds of the time (docs/performance.md, "--fit-normals").
  so.linear_solver_type = ceres::CGNR;
  so.function_tolerance = 1e-5;
  so.max_num_iterations = k.opt.max_iterations;
  so.num_threads = k.per_block;
  so.logging_type = ceres::SILENT;
  CostLog log;
  if (k.opt.record_costs && k.rep.blocks == 1) {
    log.costs = &k.rep.costs;
    log.problem = &problem;
    log.threads = k.per_block;
    so.update_state_every_iteration = true;
    so.callbacks.push_back(&log);
  }
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  return summary.iterations.size() > 0 ? summary.iterations.size() - 1 : 0;
}

// One block: its problem on a copy of the round's starting normals, its core kept.
// Returns its Levenberg-Marquardt iterations.
std::size_t solve_block(const BlockRound& k, std::size_t b) {
  const GridMesh& mesh = k.mesh;
  const GridTopology& topo = mesh.topo;
  const NormalFitOptions& opt = k.opt;
  const std::size_t brows = k.brows, bcols = k.bcols, nbc = k.nbc;
  std::vector<Vector3d> nb = k.snapshot;
  const std::size_t r0 = (b / nbc) * brows, c0 = (b % nbc) * bcols;
  const std::size_t r1 = std::min(topo.rows, r0 + brows), c1 = std::min(topo.cols, c0 + bcols);
  const std::size_t er0 = r0 > opt.overlap ? r0 - opt.overlap : 0,
                    ec0 = c0 > opt.overlap ? c0 - opt.overlap : 0;
  const std::size_t er1 = std::min(topo.rows, r1 + opt.overlap),
                    ec1 = std::min(topo.cols, c1 + opt.overlap);
  const auto in_ext = [&](std::size_t v) {
    const std::size_t r = v / topo.cols, c = v % topo.cols;
    return r >= er0 && r < er1 && c >= ec0 && c < ec1;
  };
  ceres::Problem::Options po;
  po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  // Faces with a corner in the extended block; their other corners are held fixed.
  const std::size_t fr0 = er0 > 0 ? er0 - 1 : 0, fc0 = ec0 > 0 ? ec0 - 1 : 0;
  const std::size_t fr1 = std::min(topo.rows - 1, er1), fc1 = std::min(topo.cols - 1, ec1);
  add_face_costs(problem, k, nb, fr0, fc0, fr1, fc1);
  for (std::size_t r = er0; r < er1; ++r)
    for (std::size_t c = ec0; c < ec1; ++c) {
      const std::size_t v = r * topo.cols + c;
      if (k.pull > 0)
        problem.AddResidualBlock(
            new ceres::AutoDiffCostFunction<PullCost, 3, 3>(new PullCost{k.start[v], k.pull}),
            nullptr, nb[v].data());
    }
  std::vector<double*> blocks;
  problem.GetParameterBlocks(&blocks);
  for (double* p : blocks) {
    const std::size_t v = std::size_t((reinterpret_cast<Vector3d*>(p)) - nb.data());
    if (in_ext(v))
      problem.SetManifold(p, &k.sphere);
    else
      problem.SetParameterBlockConstant(p);
  }
  const std::size_t iterations = solve_problem(problem, k);
  // Keep the core; the overlap is solved by the block whose core it is.
  for (std::size_t r = r0; r < r1; ++r)
    for (std::size_t c = c0; c < c1; ++c) k.normal[r * topo.cols + c] = nb[r * topo.cols + c];
  return iterations;
}

// The blocks of round `round`, `side_by_side` at once; the iterations counted and the
// progress reported as they finish; the first failure thrown after.
void solve_round(const BlockRound& k, int round, int side_by_side, const Progress& progress) {
  NormalFitReport& rep = k.rep;
  const int rounds = k.opt.rounds;
  std::exception_ptr error;
  std::size_t blocks_done = 0;
#pragma omp parallel for schedule(dynamic) num_threads(side_by_side)
  for (std::size_t b = 0; b < rep.blocks; ++b) {
    try {
      const std::size_t iterations = solve_block(k, b);
#pragma omp critical(fit_normals_block)
      {
        rep.iterations += iterations;
        ++blocks_done;
        report(progress,
               (double(round) + double(blocks_done) / double(rep.blocks)) / double(rounds));
      }
    } catch (...) {
#pragma omp critical(fit_normals_block)
      if (!error) error = std::current_exception();
    }
  }
  if (error) std::rethrow_exception(error);
}

NormalFitReport fit_pn_normals(GridMesh& mesh, const SourceSamples& samples,
                               const NormalFitOptions& opt, const Progress& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  if (!(opt.regularization >= 0) || opt.max_iterations < 1 || opt.rounds < 1 || opt.block < 2)
    throw Error(
        "fit_pn_normals: regularization >= 0, iterations, rounds >= 1 and a block of >= 2 "
        "vertices");
  NormalFitReport rep;
  const std::vector<Vector3d> local = to_local(mesh, samples);
  Assignment a;
  rep.before = locate(mesh, local, &a);  // and the first round's assignment
  if (rep.before.samples == 0)
    throw Error("no source sample lies under the mesh: nothing to fit the normals to");
  const GridTopology& topo = mesh.topo;
  const std::size_t nv = mesh.n_vertices();
  std::vector<Vector3d> normal(nv), start(nv);
  for (std::size_t v = 0; v < nv; ++v)
    normal[v] = start[v] = mesh.normals[v].cast<double>().normalized();
  const double pull = opt.regularization * mesh.geo.dx;

  // Blocks of vertices: cores tile the grid.
  const std::size_t block = opt.block;
  const std::size_t nbr = (topo.rows + block - 1) / block, nbc = (topo.cols + block - 1) / block;
  // Cores of equal size (at most `block`), so that blocks solved side by side take as long.
  const std::size_t brows = (topo.rows + nbr - 1) / nbr, bcols = (topo.cols + nbc - 1) / nbc;
  rep.blocks = nbr * nbc;
  ceres::SphereManifold<3> sphere;
  const int threads = opt.threads > 0 ? opt.threads : omp_get_max_threads();
  for (int round = 0; round < opt.rounds; ++round) {
    if (round > 0) (void)locate(mesh, local, &a);
    // The blocks of a round are solved at once, each from the round's starting normals
    // (a copy of its own: its overlap with the others is theirs to change) and each
    // keeping its core: the result does not depend on the order or the threads. Ceres
    // runs its conjugate gradients on one thread, so blocks side by side use the cores.
    const std::vector<Vector3d> snapshot = normal;
    const int side_by_side = int(std::min<std::size_t>(rep.blocks, std::size_t(threads)));
    const int per_block = std::max(1, threads / side_by_side);
    const BlockRound k{mesh,  a,     local, opt,       snapshot, start, pull,
                       brows, bcols, nbc,   per_block, sphere,   rep,   normal};
    solve_round(k, round, side_by_side, progress);
    for (std::size_t v = 0; v < nv; ++v) mesh.normals[v] = normal[v].normalized().cast<float>();
  }
  rep.after = locate(mesh, local, nullptr);
  mesh.normal_fit = {true,           rep.before.rmse,   rep.before.max_abs,
                     rep.after.rmse, rep.after.max_abs, rep.after.samples};
  rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return rep;
}

}  // namespace terrain
