#include "renderer/core/hachures.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "terrain/error.hpp"
#include "terrain/least_by_key.hpp"
#include "terrain/pn_surface.hpp"

namespace renderer {

namespace {

using Eigen::Vector2f;

// A field of w x h pixels without terrain.
HachureField empty_field(int w, int h) {
  HachureField f;
  f.width = w, f.height = h;
  const std::size_t n = std::size_t(w) * std::size_t(h);
  f.fall.assign(n, Vector2f::Zero());
  f.slope.assign(n, std::numeric_limits<float>::quiet_NaN());
  f.tone.assign(n, 0.0f);
  f.elevation.assign(n, 0.0f);
  return f;
}

// The slope (as drawn: heights exaggerated by e) and the tone of pixel i from the unit
// normal `nrm` of the true surface.
void set_slope_and_tone(HachureField& f, std::size_t i, const Eigen::Vector3d& nrm, double e,
                        const Eigen::Vector3d* light) {
  const double g = nrm.head<2>().norm() / std::max(nrm.z(), 1e-6), drawn = g * e;
  f.slope[i] = float(std::atan(drawn));
  if (light) {  // the shadow, 1 - n.l on the drawn (exaggerated) surface, less half the flat's
    const Eigen::Vector3d ne = Eigen::Vector3d(nrm.x(), nrm.y(), nrm.z() / e).normalized();
    f.tone[i] = float(std::clamp(1.0 - ne.dot(*light) - kFlatShare * (1.0 - light->z()), 0.0, 1.0));
  } else {  // Lehmann: 0 flat .. 1 at 45 degrees
    f.tone[i] = float(std::clamp(drawn, 0.0, 1.0));
  }
}

}  // namespace

double row_interval_for(double scale, double spacing, double slope) {
  const double raw = 4.0 * spacing * scale * std::tan(std::clamp(slope, 0.01, 1.4));
  const double decade = std::pow(10.0, std::floor(std::log10(raw)));
  for (const double m : {1.0, 2.0, 5.0})
    if (raw <= m * decade * 1.5) return m * decade;
  return 10.0 * decade;
}

void stretch_tone(HachureField& f, double min_slope) {
  std::vector<float> t;
  for (std::size_t i = 0; i < f.tone.size(); ++i)
    if (f.slope[i] >= min_slope) t.push_back(f.tone[i]);  // NaN (no terrain) compares false
  if (t.size() < 2) return;
  const auto at = [&](std::size_t k) {
    std::nth_element(t.begin(), t.begin() + std::ptrdiff_t(k), t.end());
    return double(t[k]);
  };
  const double lo = at(t.size() * 2 / 100), hi = at(t.size() * 98 / 100);
  if (!(hi > lo + 1e-6)) return;
  for (float& x : f.tone) x = float(std::clamp((double(x) - lo) / (hi - lo), 0.0, 1.0));
}

double median_slope(const HachureField& f, double min_slope) {
  std::vector<float> s;
  for (const float x : f.slope)
    if (x >= min_slope) s.push_back(x);
  if (s.empty()) return 0;
  std::nth_element(s.begin(), s.begin() + std::ptrdiff_t(s.size() / 2), s.end());
  return s[s.size() / 2];
}

double slope_percentile(const HachureField& f, double q) {
  std::vector<float> s;
  for (const float x : f.slope)
    if (!std::isnan(x)) s.push_back(x);
  if (s.empty()) return 0;
  const std::size_t k =
      std::min(s.size() - 1, std::size_t(std::clamp(q, 0.0, 1.0) * double(s.size())));
  std::nth_element(s.begin(), s.begin() + std::ptrdiff_t(k), s.end());
  return s[k];
}

PlanView plan_view(const terrain::GridMesh& mesh, double scale) {
  if (!(scale > 0)) throw terrain::Error("the map's scale must be positive metres a pixel");
  const double w = double(mesh.topo.cols - 1) * mesh.geo.dx,
               h = double(mesh.topo.rows - 1) * mesh.geo.dy;
  PlanView p;
  p.scale = scale;
  const double pw = std::ceil(w / scale), ph = std::ceil(h / scale);
  if (pw * ph > double(std::numeric_limits<int>::max()) || pw < 1 || ph < 1)
    throw terrain::Error(fmt::format(
        "a map of {:.0f} x {:.0f} pixels at {:g} m a pixel is too large", pw, ph, scale));
  if (std::max(pw, ph) < kMinPlanSide)
    throw terrain::Error(
        fmt::format("a map of {:.0f} x {:.0f} pixels at {:g} m a pixel is too small to show the "
                    "terrain: give a --scale of at most {:.3g}",
                    pw, ph, scale, std::max(w, h) / kMinPlanSide));
  p.width = int(pw), p.height = int(ph);
  p.x0 = 0.5 * (w - pw * scale), p.y0 = -0.5 * (h - ph * scale);  // centred on the mesh
  return p;
}

HachureField plan_hachure_field(const terrain::GridMesh& mesh, const PlanView& plan,
                                const Eigen::Vector3d* light) {
  HachureField f = empty_field(plan.width, plan.height);
#pragma omp parallel for schedule(dynamic, 4)
  for (int v = 0; v < f.height; ++v)
    for (int u = 0; u < f.width; ++u) {
      const std::size_t i = std::size_t(v) * std::size_t(f.width) + std::size_t(u);
      const Eigen::Vector2d q = plan_to_local(plan, Vector2f(float(u) + 0.5f, float(v) + 0.5f));
      const auto sp = terrain::pn_point_above(mesh, q.x(), q.y());
      if (!sp || !mesh.face_kept(sp->face)) continue;  // outside the data: no terrain
      const Eigen::Vector3d& nrm = sp->normal;
      f.elevation[i] = float(sp->position.z());
      set_slope_and_tone(f, i, nrm, 1.0, light);
      const Eigen::Vector2d down(nrm.x(), -nrm.y());  // -gradient, v down = south
      if (down.norm() > 1e-12) f.fall[i] = (down / down.norm()).cast<float>();
    }
  return f;
}

std::optional<Eigen::Vector3d> surface_point(const View& view, const Eigen::Matrix4d& inverse,
                                             const std::vector<float>& depth_buf, double u,
                                             double v) {
  if (u < 0 || v < 0 || u >= view.width || v >= view.height) return std::nullopt;
  const double depth = depth_buf[std::size_t(v) * std::size_t(view.width) + std::size_t(u)];
  if (far_depth(view.reversed_z, depth) >= 1.0) return std::nullopt;
  return unproject(view, inverse, u, v, depth);
}

Coherence hachure_coherence(const std::vector<Eigen::Vector3f>& previous, const View& next,
                            const std::vector<float>& next_depth,
                            const std::vector<std::uint8_t>& next_ink, int radius) {
  Coherence c;
  const int w = next.width, h = next.height;
  const Eigen::Matrix4d inverse = next.view_projection().inverse();
  for (const Eigen::Vector3f& p : previous) {
    const Projected q = project(next, p.cast<double>());
    if (!q.in_front) continue;
    const auto s = surface_point(next, inverse, next_depth, q.u, q.v);
    if (!s || (*s - p.cast<double>()).norm() > 0.01 * std::abs(next.viewpoint().distance(*s)))
      continue;  // hidden, or off the surface
    ++c.counted;
    bool hit = false;
    const int x = int(q.u), y = int(q.v);
    for (int yy = std::max(0, y - radius); yy <= std::min(h - 1, y + radius) && !hit; ++yy)
      for (int xx = std::max(0, x - radius); xx <= std::min(w - 1, x + radius) && !hit; ++xx)
        hit = next_ink[std::size_t(yy) * std::size_t(w) + std::size_t(xx)] != 0;
    c.near += hit;
  }
  return c;
}

std::vector<Eigen::Vector2f> surface_seeds(const View& view, const std::vector<float>& depth,
                                           double spacing, double cell,
                                           const Eigen::Vector2d& anchor) {
  // Each cell's candidate nearest its centre (the first of equals): some thousands of
  // cells, a hundred times as many candidates.
  struct Best {
    Vector2f seed;
    float d2;
  };
  struct Nearer {
    bool operator()(const Best& a, const Best& b) const { return a.d2 < b.d2; }
  };
  terrain::LeastByKey<Best, Nearer> best;
  const double step = std::max(1.0, spacing / 3.0);
  const Eigen::Matrix4d inverse = view.view_projection().inverse();
  // The candidates' ground points, unprojected in parallel (NaN off the terrain), then
  // taken in the grid's order.
  std::vector<double> us, vs;
  for (double v = 0.5 * step; v < view.height; v += step) vs.push_back(v);
  for (double u = 0.5 * step; u < view.width; u += step) us.push_back(u);
  std::vector<Eigen::Vector2f> ground(us.size() * vs.size());
#pragma omp parallel for schedule(static)
  for (long iv = 0; iv < long(vs.size()); ++iv)
    for (std::size_t iu = 0; iu < us.size(); ++iu) {
      const auto q = surface_point(view, inverse, depth, us[iu], vs[std::size_t(iv)]);
      ground[std::size_t(iv) * us.size() + iu] =
          q ? Eigen::Vector2f(q->head<2>().cast<float>())
            : Eigen::Vector2f::Constant(std::numeric_limits<float>::quiet_NaN());
    }
  for (std::size_t iv = 0; iv < vs.size(); ++iv)
    for (std::size_t iu = 0; iu < us.size(); ++iu) {
      const double u = us[iu], v = vs[iv];
      const Eigen::Vector2f& q = ground[iv * us.size() + iu];
      if (std::isnan(q.x())) continue;
      const Eigen::Vector2d g = q.cast<double>() + anchor;
      const double cx = std::floor(g.x() / cell), cy = std::floor(g.y() / cell);
      const float d2 = float((g - cell * Eigen::Vector2d(cx + 0.5, cy + 0.5)).squaredNorm());
      const std::uint64_t key =
          (std::uint64_t(std::int64_t(cx)) << 32) ^ std::uint64_t(std::uint32_t(std::int64_t(cy)));
      best.offer(key, {Vector2f(float(u), float(v)), d2});
    }
  std::vector<std::pair<std::uint64_t, Vector2f>> order;
  order.reserve(best.size());
  best.for_each([&](std::uint64_t key, const Best& b) {
    std::uint64_t z = key + 0x9e3779b97f4a7c15ull;  // splitmix64: a fixed shuffle of the cells
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    order.emplace_back(z ^ (z >> 31), b.seed);
  });
  std::sort(order.begin(), order.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<Vector2f> out;
  out.reserve(order.size());
  for (const auto& o : order) out.push_back(o.second);
  return out;
}

HachureField hachure_field(const terrain::GridMesh& mesh, const View& view, double e,
                           const std::vector<float>& toward_depth, const Eigen::Vector3d* light) {
  HachureField f = empty_field(view.width, view.height);
  const Eigen::Matrix4d inverse = view.view_projection().inverse();
#pragma omp parallel for schedule(dynamic, 4)
  for (int v = 0; v < f.height; ++v)
    for (int u = 0; u < f.width; ++u) {
      const std::size_t i = std::size_t(v) * std::size_t(f.width) + std::size_t(u);
      const auto q = surface_point(view, inverse, toward_depth, u, v);
      if (!q) continue;               // no surface here
      const Eigen::Vector3d& p = *q;  // exaggerated local frame
      const auto sp = terrain::pn_point_above(mesh, p.x(), p.y());
      if (!sp) continue;
      const Eigen::Vector3d nrm = sp->normal;
      f.elevation[i] = float(sp->position.z());
      const Eigen::Vector2d grad =
          -nrm.head<2>() / std::max(nrm.z(), 1e-6);  // dz/dx, dz/dy (metres a metre)
      const double g = grad.norm();
      set_slope_and_tone(f, i, nrm, e, light);
      if (g < 1e-9) continue;
      // A step of 1 m down the fall line on the drawn (exaggerated) surface.
      const Eigen::Vector3d down(-grad.x() / g, -grad.y() / g, -g * e);
      const Projected a = project(view, p), b = project(view, p + down);
      const Eigen::Vector2d d(b.u - a.u, b.v - a.v);
      if (d.norm() > 0) f.fall[i] = (d / d.norm()).cast<float>();
    }
  return f;
}

}  // namespace renderer
