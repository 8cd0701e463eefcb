#include "renderer/core/hachures.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include <fmt/format.h>

#include "terrain/error.hpp"
#include "terrain/pn_surface.hpp"

namespace renderer {

namespace {

using Eigen::Vector2f;

// The points of the accepted hachures, by cells of the occupancy grid.
class Occupancy {
 public:
  Occupancy(int width, int height, double cell)
      : cell_(cell),
        cols_(long(std::ceil(width / cell)) + 1),
        rows_(long(std::ceil(height / cell)) + 1),
        cells_(std::size_t(cols_ * rows_)) {}
  // Whether a point q of another hachure than `self`, of row `row` (-1: any row), lies
  // closer to p than `share` times the smaller of the two points' local spacings (p's is
  // `spacing`): the test is the same seen from either hachure.
  bool near(const Vector2f& p, double share, double spacing, long self, long row = -1) const {
    const double d = share * spacing;
    const long reach = long(std::ceil(d / cell_)), cu = long(p.x() / cell_),
               cv = long(p.y() / cell_);
    for (long v = std::max(0L, cv - reach); v <= std::min(rows_ - 1, cv + reach); ++v)
      for (long u = std::max(0L, cu - reach); u <= std::min(cols_ - 1, cu + reach); ++u)
        for (const Entry& e : cells_[std::size_t(v * cols_ + u)]) {
          const double dq = share * std::min(spacing, double(e.spacing));
          if (e.id != self && (row < 0 || e.row == row) && (e.p - p).squaredNorm() < dq * dq)
            return true;
        }
    return false;
  }
  // Whether a point of another hachure than `self` lies closer than `d` to p.
  bool within(const Vector2f& p, double d, long self) const {
    const long reach = long(std::ceil(d / cell_)), cu = long(p.x() / cell_),
               cv = long(p.y() / cell_);
    for (long v = std::max(0L, cv - reach); v <= std::min(rows_ - 1, cv + reach); ++v)
      for (long u = std::max(0L, cu - reach); u <= std::min(cols_ - 1, cu + reach); ++u)
        for (const Entry& e : cells_[std::size_t(v * cols_ + u)])
          if (e.id != self && (e.p - p).squaredNorm() < d * d) return true;
    return false;
  }
  void add(const Vector2f& p, double spacing, long id, long row) {
    const long u = std::clamp(long(p.x() / cell_), 0L, cols_ - 1),
               v = std::clamp(long(p.y() / cell_), 0L, rows_ - 1);
    cells_[std::size_t(v * cols_ + u)].push_back({p, float(spacing), id, row});
  }

 private:
  struct Entry {
    Vector2f p;
    float spacing;
    long id, row;
  };
  double cell_;
  long cols_, rows_;
  std::vector<std::vector<Entry>> cells_;
};

// The half-pixel cells a trace passed, each with the index of its last point there: an
// open-addressing table kept from trace to trace (a generation stamp clears it), as a
// trace's few hundred steps each look one up (an unordered_map's node per step cost more
// than the step).
class Visited {
 public:
  void clear() {
    if (++generation_ == 0) std::fill(stamp_.begin(), stamp_.end(), 0u), generation_ = 1;
    size_ = 0;
  }
  // The slot of `key`: its index (fresh: false), or a new slot holding `index` (fresh: true).
  std::pair<std::uint32_t*, bool> try_emplace(std::uint64_t key, std::uint32_t index) {
    if (2 * (size_ + 1) > stamp_.size()) grow();
    const std::size_t mask = stamp_.size() - 1;
    for (std::size_t s = hash(key) & mask;; s = (s + 1) & mask) {
      if (stamp_[s] != generation_) {
        stamp_[s] = generation_, key_[s] = key, value_[s] = index, ++size_;
        return {&value_[s], true};
      }
      if (key_[s] == key) return {&value_[s], false};
    }
  }

 private:
  static std::size_t hash(std::uint64_t k) {
    k ^= k >> 33, k *= 0xff51afd7ed558ccdull, k ^= k >> 33;
    return std::size_t(k);
  }
  void grow() {
    std::vector<std::uint64_t> keys;
    std::vector<std::uint32_t> values;
    for (std::size_t s = 0; s < stamp_.size(); ++s)
      if (stamp_[s] == generation_) keys.push_back(key_[s]), values.push_back(value_[s]);
    const std::size_t n = std::max<std::size_t>(1024, 2 * stamp_.size());
    key_.assign(n, 0), value_.assign(n, 0), stamp_.assign(n, 0), generation_ = 1, size_ = 0;
    for (std::size_t k = 0; k < keys.size(); ++k) try_emplace(keys[k], values[k]);
  }
  std::vector<std::uint64_t> key_;
  std::vector<std::uint32_t> value_, stamp_;
  std::uint32_t generation_ = 1;
  std::size_t size_ = 0;
};

// The fall line at p, bilinear between the four nearest pixel centres (pixels without
// terrain add nothing), normalized; zero where none has a direction.
Vector2f fall_at(const HachureField& f, const Vector2f& p) {
  const float x = p.x() - 0.5f, y = p.y() - 0.5f;
  const long u0 = long(std::floor(x)), v0 = long(std::floor(y));
  const float a = x - float(u0), b = y - float(v0);
  Vector2f sum = Vector2f::Zero();
  for (int dv = 0; dv < 2; ++dv)
    for (int du = 0; du < 2; ++du) {
      const long u = std::clamp(u0 + du, 0L, long(f.width) - 1),
                 v = std::clamp(v0 + dv, 0L, long(f.height) - 1);
      sum += (du ? a : 1 - a) * (dv ? b : 1 - b) *
             f.fall[std::size_t(v) * std::size_t(f.width) + std::size_t(u)];
    }
  const float n = sum.norm();
  return n > 1e-6f ? Vector2f(sum / n) : Vector2f::Zero();
}

// The spacing hachures keep at pixel i: the rule's spacing over the tone (kMinTone .. 1).
double local_spacing(const HachureField& f, const HachureRule& rule, std::size_t i) {
  return rule.spacing / std::clamp(double(f.tone[i]), kMinTone, 1.0);
}

struct Tracer {
  const HachureField& f;
  const HachureRule& rule;
  const Occupancy& occupied;

  std::size_t at(const Vector2f& p) const {
    return std::size_t(long(p.y())) * std::size_t(f.width) + std::size_t(long(p.x()));
  }
  bool usable(const Vector2f& p) const {
    if (!f.terrain(long(p.x()), long(p.y())) || p.x() < 0 || p.y() < 0) return false;
    const std::size_t i = at(p);
    return f.slope[i] >= rule.min_slope && (f.blocked.empty() || !f.blocked[i]) &&
           f.fall[i].squaredNorm() > 0.5f;
  }
  double spacing(const Vector2f& p) const { return local_spacing(f, rule, at(p)); }
  // The row of a point: the band between two form lines (-1: no rows).
  long row(const Vector2f& p) const {
    return rule.row_interval > 0 ? long(std::floor(double(f.elevation[at(p)]) / rule.row_interval))
                                 : -1;
  }
  bool free(const Vector2f& p, long self, long r) const {
    return !occupied.near(p, rule.test_share, spacing(p), self, r);
  }

  // From `seed` along the fall line (sign +1 downhill, -1 uphill), the points after it. A
  // trace ends within twice the frame's diagonal, and where it comes back to where it was
  // (a fall line that loops, on a surface steeper than the field resolves).
  std::vector<Vector2f> run(const Vector2f& seed, float sign, long self, double length) const {
    constexpr float kStep = 0.5f;
    constexpr std::size_t kLoopSteps = 4;  // a point this many steps back is not its neighbour
    std::vector<Vector2f> out;
    Vector2f p = seed, last = sign * fall_at(f, seed);
    const long r = row(seed);
    const double longest =
        std::min(rule.max_length, 2.0 * std::hypot(double(f.width), double(f.height)));
    static thread_local Visited visited;  // half-pixel cell -> its last point
    visited.clear();
    const auto cell = [](const Vector2f& q) {
      return (std::uint64_t(std::uint32_t(long(2 * q.x()))) << 32) | std::uint32_t(long(2 * q.y()));
    };
    visited.try_emplace(cell(seed), 0);
    while (length < longest) {
      const Vector2f d1 = sign * fall_at(f, p);
      const Vector2f mid = p + 0.5f * kStep * d1;
      if (!usable(mid)) break;
      const Vector2f d2 = sign * fall_at(f, mid);
      if (d2.dot(last) <= 0.0f)
        break;  // the fall line turns back (a valley or a ridge), or has none
      const Vector2f next = p + kStep * d2;
      if (!usable(next) || !free(next, self, r)) break;
      if (row(next) != r) {  // a form line: end half a pixel before it (the seam)
        if (!out.empty()) out.pop_back();
        break;
      }
      const auto [last_here, fresh] =
          visited.try_emplace(cell(next), std::uint32_t(out.size() + 1));
      if (!fresh && out.size() + 1 - *last_here > kLoopSteps) break;  // back where it was
      *last_here = std::uint32_t(out.size() + 1);
      out.push_back(next);
      p = next, last = d2, length += kStep;
    }
    return out;
  }
};

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

HachureStats hachure_stats(const HachureField& f, const std::vector<Hachure>& hs,
                           const HachureRule& rule) {
  HachureStats st;
  st.hachures = hs.size();
  st.ink.assign(std::size_t(f.width) * std::size_t(f.height), 0);
  const auto at = [&](const Vector2f& p) {
    return std::size_t(std::clamp(long(p.y()), 0L, long(f.height) - 1)) * std::size_t(f.width) +
           std::size_t(std::clamp(long(p.x()), 0L, long(f.width) - 1));
  };
  const auto local = [&](const Vector2f& p) { return local_spacing(f, rule, at(p)); };
  Occupancy grid(f.width, f.height, std::max(1.0, rule.spacing));
  for (std::size_t h = 0; h < hs.size(); ++h)
    for (const Vector2f& p : hs[h].points) grid.add(p, local(p), long(h), -1), st.ink[at(p)] = 1;
  std::size_t steps = 0, along = 0, spaced = 0;
  const float cos10 = float(std::cos(10.0 * std::acos(-1.0) / 180.0));
  for (std::size_t h = 0; h < hs.size(); ++h) {
    const auto& pts = hs[h].points;
    for (std::size_t k = 0; k < pts.size(); ++k) {
      ++st.points;
      if (k) {
        const Vector2f step = pts[k] - pts[k - 1], mid = 0.5f * (pts[k] + pts[k - 1]);
        st.length_px += double(step.norm());
        ++steps;
        along += step.norm() > 0 && step.normalized().dot(fall_at(f, mid)) >= cos10;
      }
      const double s_p = local(pts[k]);
      // Nearer than half the pair's spacing (the smaller local one), or no other hachure
      // within 2 of p's own.
      const bool close = grid.near(pts[k], 0.5 * (1 - 1e-3), s_p, long(h));
      const bool far = !grid.within(pts[k], 2.0 * s_p, long(h));
      spaced += !close && !far;
      st.close_share += close, st.far_share += far;
    }
  }
  st.along_share = steps ? double(along) / double(steps) : 1.0;
  st.spacing_share = st.points ? double(spaced) / double(st.points) : 1.0;
  st.close_share /= double(std::max<std::size_t>(st.points, 1)),
      st.far_share /= double(std::max<std::size_t>(st.points, 1));
  return st;
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
      if (!sp) continue;
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
  struct Best {
    Vector2f seed;
    float d2;
  };
  std::unordered_map<std::uint64_t, Best> best;
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
      const auto [it, fresh] = best.try_emplace(key, Best{Vector2f(float(u), float(v)), d2});
      if (!fresh && d2 < it->second.d2) it->second = {Vector2f(float(u), float(v)), d2};
    }
  std::vector<std::pair<std::uint64_t, Vector2f>> order;
  order.reserve(best.size());
  for (const auto& [key, b] : best) {
    std::uint64_t z = key + 0x9e3779b97f4a7c15ull;  // splitmix64: a fixed shuffle of the cells
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    order.emplace_back(z ^ (z >> 31), b.seed);
  }
  std::sort(order.begin(), order.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<Vector2f> out;
  out.reserve(order.size());
  for (const auto& o : order) out.push_back(o.second);
  return out;
}

std::vector<Hachure> trace_hachures(const HachureField& f, const HachureRule& rule,
                                    const std::vector<Eigen::Vector2f>& first) {
  std::vector<Hachure> out;
  if (f.width <= 0 || f.height <= 0 || !(rule.spacing > 0)) return out;
  if (rule.row_interval > 0 && f.elevation.size() != f.slope.size())
    throw terrain::Error("hachure rows need the field's heights");
  Occupancy occupied(f.width, f.height, std::max(1.0, rule.spacing));
  const Tracer tracer{f, rule, occupied};
  // A seed is traced where the field is usable there and no hachure lies within its spacing.
  const auto trace_from = [&](const Vector2f& seed) {
    const long id = long(out.size());
    const long row = tracer.row(seed);
    if (occupied.near(seed, 1.0, tracer.spacing(seed), -1, row)) return;
    const std::vector<Vector2f> up = tracer.run(seed, -1.0f, id, 0.0);
    const std::vector<Vector2f> down = tracer.run(seed, 1.0f, id, 0.5 * double(up.size()));
    if (0.5 * double(up.size() + down.size()) < rule.min_length) return;
    Hachure h;
    h.row = row;
    h.points.assign(up.rbegin(), up.rend());
    h.points.push_back(seed);
    h.points.insert(h.points.end(), down.begin(), down.end());
    for (const Vector2f& p : h.points) {
      h.tone.push_back(f.tone[tracer.at(p)]);
      h.slope.push_back(f.slope[tracer.at(p)]);
      occupied.add(p, tracer.spacing(p), id, row);
    }
    out.push_back(std::move(h));
  };
  for (const Vector2f& seed : first)
    if (seed.x() >= 0 && seed.y() >= 0 && seed.x() < float(f.width) && seed.y() < float(f.height) &&
        tracer.usable(seed))
      trace_from(seed);
  // Then seeds on a grid a third of the spacing apart; where the tone asks for k times the
  // spacing, only every k-th seed of the grid each way (a seed there must keep k spacings
  // from every hachure: the others would be tested in vain).
  const double seed_step = std::max(1.0, rule.spacing / 3.0);
  long iv = 0;
  for (double v = 0.5 * seed_step; v < f.height; v += seed_step, ++iv) {
    long iu = 0;
    for (double u = 0.5 * seed_step; u < f.width; u += seed_step, ++iu) {
      const Vector2f seed{float(u), float(v)};
      if (!tracer.usable(seed)) continue;
      const long k = long(tracer.spacing(seed) / rule.spacing + 1e-6);
      if (iu % k || iv % k) continue;
      trace_from(seed);
    }
  }
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
