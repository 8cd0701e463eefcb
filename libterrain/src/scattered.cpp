// Scattered points to a grid: CGAL's 2D Delaunay triangulation and natural-neighbour
// coordinates (scattered.hpp). The only translation unit that includes CGAL.
#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Interpolation_gradient_fitting_traits_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/interpolation_functions.h>
#include <CGAL/natural_neighbor_coordinates_2.h>
#include <CGAL/sibson_gradient_fitting.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <numeric>

#include <omp.h>

#include "terrain/error.hpp"
#include "terrain/scattered.hpp"

namespace terrain {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
// Per vertex: z, and its index into the gradients fitted for Sibson's C1 interpolant
// (kept apart: only that method pays for them).
struct VertexData {
  double z = 0;
  std::uint32_t index = 0;
};
using Vb = CGAL::Triangulation_vertex_base_with_info_2<VertexData, K>;
using Tds = CGAL::Triangulation_data_structure_2<Vb>;
using Dt = CGAL::Delaunay_triangulation_2<K, Tds>;
using Point = K::Point_2;
using GradientTraits = CGAL::Interpolation_gradient_fitting_traits_2<K>;
using Neighbour = std::pair<Dt::Vertex_handle, K::FT>;  // natural neighbour, its coordinate

// CGAL's value functor: a vertex's z (always known).
std::pair<double, bool> vertex_z(const Dt::Vertex_handle& v) { return {v->info().z, true}; }

// The points with duplicate x, y merged (mean z), ready for Dt::insert.
std::vector<std::pair<Point, VertexData>> unique_points(const PointCloud& p,
                                                        std::size_t& duplicates) {
  std::vector<std::size_t> order(p.size());
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return p.x[a] < p.x[b] || (p.x[a] == p.x[b] && p.y[a] < p.y[b]);
  });
  std::vector<std::pair<Point, VertexData>> out;
  out.reserve(p.size());
  duplicates = 0;
  for (std::size_t k = 0; k < order.size();) {
    const std::size_t i = order[k];
    double sum = 0;
    std::size_t n = 0;
    for (; k < order.size() && p.x[order[k]] == p.x[i] && p.y[order[k]] == p.y[i]; ++k, ++n)
      sum += p.z[order[k]];
    duplicates += n - 1;
    out.push_back({Point(p.x[i], p.y[i]), VertexData{sum / double(n), std::uint32_t(out.size())}});
  }
  return out;
}

bool long_edge(const Dt::Face_handle& f, double max_edge2) {
  for (int k = 0; k < 3; ++k)
    if (CGAL::squared_distance(f->vertex(k)->point(), f->vertex((k + 1) % 3)->point()) > max_edge2)
      return true;
  return false;
}

// Barycentric interpolation of z in the finite face f at p.
double linear_z(const Dt::Face_handle& f, const Point& p) {
  const Point &a = f->vertex(0)->point(), &b = f->vertex(1)->point(), &c = f->vertex(2)->point();
  const double det = (b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y());
  const double wb = ((p.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (p.y() - a.y())) / det;
  const double wc = ((b.x() - a.x()) * (p.y() - a.y()) - (p.x() - a.x()) * (b.y() - a.y())) / det;
  return (1 - wb - wc) * f->vertex(0)->info().z + wb * f->vertex(1)->info().z +
         wc * f->vertex(2)->info().z;
}

// Where a query walk starts (the last query's triangle) and its scratch space: one per
// thread.
struct Cursor {
  Dt::Face_handle hint;
  std::vector<Neighbour> coords;
};

}  // namespace

struct PointSurface::Impl {
  Dt dt;
  std::size_t duplicates = 0;
  mutable Cursor cursor;  // for z_at
  // Sibson's gradient per vertex index; none (NaN) at convex hull vertices, where CGAL
  // fits none. Empty until a Natural query.
  mutable std::vector<K::Vector_2> gradients;

  // Sibson's gradient at every vertex off the convex hull: the weighted least-squares fit
  // of the differences to its natural neighbours (what CGAL's sibson_gradient_fitting_nn_2
  // does, here on all threads: each vertex's coordinates come from a small triangulation of
  // its own, the shared one is only read).
  void fit_gradients() const {
    if (!gradients.empty()) return;
    constexpr double nan = std::numeric_limits<double>::quiet_NaN();
    std::vector<K::Vector_2> fitted(dt.number_of_vertices(), K::Vector_2(nan, nan));
    std::vector<Dt::Vertex_handle> inner;
    inner.reserve(dt.number_of_vertices());
    for (auto v = dt.finite_vertices_begin(); v != dt.finite_vertices_end(); ++v)
      if (!dt.is_edge(v, dt.infinite_vertex())) inner.push_back(v);
#pragma omp parallel
    {
      std::vector<Neighbour> coords;
#pragma omp for schedule(dynamic, 4096)
      for (std::ptrdiff_t i = 0; i < std::ptrdiff_t(inner.size()); ++i) {
        const Dt::Vertex_handle v = inner[std::size_t(i)];
        coords.clear();
        const auto nn = CGAL::natural_neighbor_coordinates_2(dt, v, std::back_inserter(coords),
                                                             CGAL::Identity<Neighbour>());
        if (!nn.third || !(nn.second > 0)) continue;
        fitted[v->info().index] =
            CGAL::sibson_gradient_fitting(coords.begin(), coords.end(), nn.second, v->point(),
                                          v->info().z, vertex_z, GradientTraits());
      }
    }
    gradients = std::move(fitted);
  }

  double z_at(const Point& p, PointInterpolation method, double max_edge, Cursor& cur) const;
};

double PointSurface::Impl::z_at(const Point& p, PointInterpolation method, double max_edge,
                                Cursor& cur) const {
  Dt::Locate_type lt;
  int li = 0;
  const Dt::Face_handle f = dt.locate(p, lt, li, cur.hint);
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  if (lt == Dt::OUTSIDE_CONVEX_HULL || lt == Dt::OUTSIDE_AFFINE_HULL || dt.is_infinite(f))
    return nan;
  cur.hint = f;
  if (max_edge > 0 && long_edge(f, max_edge * max_edge)) return nan;
  if (lt == Dt::VERTEX) return f->vertex(li)->info().z;
  if (method == PointInterpolation::Linear) return linear_z(f, p);
  auto& coords = cur.coords;
  coords.clear();
  const auto nn = CGAL::natural_neighbor_coordinates_2(dt, p, std::back_inserter(coords),
                                                       CGAL::Identity<Neighbour>(), f);
  if (!nn.third || !(nn.second > 0))
    return linear_z(f, p);  // on the hull: natural reduces to linear
  if (method == PointInterpolation::Natural) {
    const auto gradient = [this](const Dt::Vertex_handle& v) {
      const K::Vector_2& g = gradients[v->info().index];
      return std::make_pair(g, !std::isnan(g.x()));
    };
    const auto c1 = CGAL::sibson_c1_interpolation(coords.begin(), coords.end(), nn.second, p,
                                                  vertex_z, gradient, GradientTraits());
    if (c1.second) return c1.first;
    // A natural neighbour on the convex hull has no fitted gradient: Sibson's C0 below.
  }
  double z = 0;
  for (const auto& [v, w] : coords) z += v->info().z * w;
  return z / nn.second;
}

PointSurface::PointSurface(const PointCloud& points) : impl_(std::make_unique<Impl>()) {
  if (points.size() < 3)
    throw Error("a surface needs at least 3 points, got " + std::to_string(points.size()));
  if (points.size() >= std::numeric_limits<std::uint32_t>::max())
    throw Error("more than 4 billion points: split the input");
  for (std::size_t i = 0; i < points.size(); ++i)
    if (!std::isfinite(points.x[i]) || !std::isfinite(points.y[i]) || !std::isfinite(points.z[i]))
      throw Error("point " + std::to_string(i + 1) + " has a non-finite coordinate");
  const auto unique = unique_points(points, impl_->duplicates);
  impl_->dt.insert(unique.begin(), unique.end());  // spatially sorted insertion
  if (impl_->dt.dimension() < 2)
    throw Error("the points are collinear (or fewer than 3 distinct x, y): they span no surface");
}

PointSurface::~PointSurface() = default;
std::size_t PointSurface::duplicates() const { return impl_->duplicates; }
std::size_t PointSurface::vertices() const { return impl_->dt.number_of_vertices(); }

double PointSurface::z_at(double x, double y, PointInterpolation method, double max_edge) const {
  if (method == PointInterpolation::Natural) impl_->fit_gradients();
  return impl_->z_at(Point(x, y), method, max_edge, impl_->cursor);
}

void PointSurface::sample(Grid& g, PointInterpolation method, double max_edge,
                          const Progress& progress) const {
  if (method == PointInterpolation::Natural) impl_->fit_gradients();
  report(progress, 0.2);
  // A band of rows per thread, one walk each; in a band, serpentine order: each sample
  // starts its walk from the previous sample's triangle.
  // Thread 0 reports; a cancel stops every thread, and throws outside the parallel region.
  std::atomic<bool> cancelled{false};
#pragma omp parallel
  {
    const std::size_t nt = std::size_t(omp_get_num_threads()),
                      t = std::size_t(omp_get_thread_num());
    const std::size_t r_begin = g.rows * t / nt, r_end = g.rows * (t + 1) / nt;
    Cursor cur;
    for (std::size_t r = r_begin; r < r_end && !cancelled.load(std::memory_order_relaxed); ++r) {
      for (std::size_t k = 0; k < g.cols; ++k) {
        const std::size_t c = (r - r_begin) % 2 == 0 ? k : g.cols - 1 - k;
        g.at(r, c) = float(impl_->z_at(Point(g.geo.x_of_col(double(c)), g.geo.y_of_row(double(r))),
                                       method, max_edge, cur));
      }
      if (t == 0 && (r & 15) == 0 && progress &&
          !progress(0.2 + 0.8 * double(r + 1 - r_begin) / double(r_end - r_begin)))
        cancelled = true;
    }
  }
  if (cancelled) throw Cancelled();
  report(progress, 1.0);
}

PointGridResult points_to_grid(const PointCloud& points, const PointGridRequest& req,
                               const Progress& progress) {
  if (!(req.spacing > 0) || !std::isfinite(req.spacing)) throw Error("the spacing must be > 0");
  PointGridResult res;
  const PointSurface surface(points);
  res.duplicates = surface.duplicates();
  res.vertices = surface.vertices();
  report(progress, 0.3);

  // Samples on multiples of the spacing inside the extent.
  const auto [x_lo, x_hi] = std::minmax_element(points.x.begin(), points.x.end());
  const auto [y_lo, y_hi] = std::minmax_element(points.y.begin(), points.y.end());
  std::array<double, 4> box{*x_lo, *y_lo, *x_hi, *y_hi};
  if (req.bbox) box = *req.bbox;
  const double s = req.spacing;
  const double c0 = std::ceil(box[0] / s - 1e-9), c1 = std::floor(box[2] / s + 1e-9);
  const double r0 = std::floor(box[3] / s + 1e-9),
               r1 = std::ceil(box[1] / s - 1e-9);  // r0: northmost multiple
  if (c1 < c0 || r0 < r1) throw Error("the extent holds no sample at this spacing");
  const double cols = c1 - c0 + 1, rows = r0 - r1 + 1;
  if (cols * rows > 4e9)
    throw Error("the grid would have " + std::to_string(cols * rows) + " samples: too many");
  Georef geo;
  geo.dx = geo.dy = s;
  geo.x0 = c0 * s - 0.5 * s;
  geo.y0 = r0 * s + 0.5 * s;
  geo.crs_wkt = points.crs_wkt;
  geo.epsg = points.epsg;
  geo.crs_kind = points.crs_kind;
  res.grid =
      Grid(std::size_t(rows), std::size_t(cols), geo, std::numeric_limits<float>::quiet_NaN());
  surface.sample(res.grid, req.interpolation, req.max_edge, sub_progress(progress, 0.3, 1.0));
  res.nodata = res.grid.count_nodata();
  report(progress, 1.0);
  return res;
}

}  // namespace terrain
