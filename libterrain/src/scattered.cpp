// Scattered points to a grid: CGAL's 2D Delaunay triangulation and natural-neighbour
// coordinates (scattered.hpp). The only translation unit that includes CGAL.
#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/natural_neighbor_coordinates_2.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>

#include "terrain/error.hpp"
#include "terrain/scattered.hpp"

namespace terrain {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Triangulation_vertex_base_with_info_2<double, K>;  // info: z
using Tds = CGAL::Triangulation_data_structure_2<Vb>;
using Dt = CGAL::Delaunay_triangulation_2<K, Tds>;
using Point = K::Point_2;

// Natural-neighbour output: (z of the neighbour, its coordinate).
struct NeighbourZ {
  using argument_type = std::pair<Dt::Vertex_handle, K::FT>;
  using result_type = std::pair<double, double>;
  result_type operator()(const argument_type& a) const { return {a.first->info(), a.second}; }
};

// The points with duplicate x, y merged (mean z), ready for Dt::insert.
std::vector<std::pair<Point, double>> unique_points(const PointCloud& p, std::size_t& duplicates) {
  std::vector<std::size_t> order(p.size());
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return p.x[a] < p.x[b] || (p.x[a] == p.x[b] && p.y[a] < p.y[b]);
  });
  std::vector<std::pair<Point, double>> out;
  out.reserve(p.size());
  duplicates = 0;
  for (std::size_t k = 0; k < order.size();) {
    const std::size_t i = order[k];
    double sum = 0;
    std::size_t n = 0;
    for (; k < order.size() && p.x[order[k]] == p.x[i] && p.y[order[k]] == p.y[i]; ++k, ++n) sum += p.z[order[k]];
    duplicates += n - 1;
    out.push_back({Point(p.x[i], p.y[i]), sum / double(n)});
  }
  return out;
}

bool long_edge(const Dt::Face_handle& f, double max_edge2) {
  for (int k = 0; k < 3; ++k)
    if (CGAL::squared_distance(f->vertex(k)->point(), f->vertex((k + 1) % 3)->point()) > max_edge2) return true;
  return false;
}

// Barycentric interpolation of z in the finite face f at p.
double linear_z(const Dt::Face_handle& f, const Point& p) {
  const Point &a = f->vertex(0)->point(), &b = f->vertex(1)->point(), &c = f->vertex(2)->point();
  const double det = (b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y());
  const double wb = ((p.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (p.y() - a.y())) / det;
  const double wc = ((b.x() - a.x()) * (p.y() - a.y()) - (p.x() - a.x()) * (b.y() - a.y())) / det;
  return (1 - wb - wc) * f->vertex(0)->info() + wb * f->vertex(1)->info() + wc * f->vertex(2)->info();
}

}  // namespace

struct PointSurface::Impl {
  Dt dt;
  std::size_t duplicates = 0;
  mutable Dt::Face_handle hint;
  mutable std::vector<std::pair<double, double>> coords;
};

PointSurface::PointSurface(const PointCloud& points) : impl_(std::make_unique<Impl>()) {
  if (points.size() < 3) throw Error("a surface needs at least 3 points, got " + std::to_string(points.size()));
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
  const Dt& dt = impl_->dt;
  const Point p(x, y);
  Dt::Locate_type lt;
  int li = 0;
  const Dt::Face_handle f = dt.locate(p, lt, li, impl_->hint);
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  if (lt == Dt::OUTSIDE_CONVEX_HULL || lt == Dt::OUTSIDE_AFFINE_HULL || dt.is_infinite(f)) return nan;
  impl_->hint = f;
  if (max_edge > 0 && long_edge(f, max_edge * max_edge)) return nan;
  if (lt == Dt::VERTEX) return f->vertex(li)->info();
  if (method == PointInterpolation::Linear) return linear_z(f, p);
  auto& coords = impl_->coords;
  coords.clear();
  const auto nn = CGAL::natural_neighbor_coordinates_2(dt, p, std::back_inserter(coords), NeighbourZ(), f);
  if (!nn.third || !(nn.second > 0)) return linear_z(f, p);  // on the hull: natural reduces to linear
  double z = 0;
  for (const auto& [zn, w] : coords) z += zn * w;
  return z / nn.second;
}

PointGridResult points_to_grid(const PointCloud& points, const PointGridRequest& req, const Progress& progress) {
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
  const double r0 = std::floor(box[3] / s + 1e-9), r1 = std::ceil(box[1] / s - 1e-9);  // r0: northmost multiple
  if (c1 < c0 || r0 < r1) throw Error("the extent holds no sample at this spacing");
  const double cols = c1 - c0 + 1, rows = r0 - r1 + 1;
  if (cols * rows > 4e9) throw Error("the grid would have " + std::to_string(cols * rows) + " samples: too many");
  Georef geo;
  geo.dx = geo.dy = s;
  geo.x0 = c0 * s - 0.5 * s;
  geo.y0 = r0 * s + 0.5 * s;
  geo.crs_wkt = points.crs_wkt;
  geo.epsg = points.epsg;
  geo.crs_kind = points.crs_kind;
  res.grid = Grid(std::size_t(rows), std::size_t(cols), geo, std::numeric_limits<float>::quiet_NaN());
  Grid& g = res.grid;
  for (std::size_t r = 0; r < g.rows; ++r) {
    // Serpentine order: each sample starts its walk from the previous sample's triangle.
    for (std::size_t k = 0; k < g.cols; ++k) {
      const std::size_t c = r % 2 == 0 ? k : g.cols - 1 - k;
      g.at(r, c) = float(surface.z_at(g.geo.x_of_col(double(c)), g.geo.y_of_row(double(r)), req.interpolation,
                                      req.max_edge));
    }
    if ((r & 63) == 0) report(progress, 0.3 + 0.7 * double(r + 1) / double(g.rows));
  }
  res.nodata = g.count_nodata();
  report(progress, 1.0);
  return res;
}

}  // namespace terrain
