// Hachures traced: seeds, steps along the fall line, the occupancy that keeps them apart,
// and the figures of what was traced (hachure_stats). The field they follow is made in
// hachures.cpp.
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

// The points of the accepted hachures, by cells of the occupancy grid. The cells' vectors
// are kept from trace to trace on the thread (emptied, not freed): a frame's hundred
// thousand points would otherwise grow and free each cell's vector every frame.
class Occupancy {
 public:
  Occupancy(int width, int height, double cell)
      : cell_(cell),
        cols_(long(std::ceil(width / cell)) + 1),
        rows_(long(std::ceil(height / cell)) + 1),
        cells_(std::move(pool())) {
    cells_.resize(std::size_t(cols_ * rows_));
    for (auto& c : cells_) c.clear();
  }
  ~Occupancy() { pool() = std::move(cells_); }
  Occupancy(const Occupancy&) = delete;
  Occupancy& operator=(const Occupancy&) = delete;
  // A point of an accepted hachure: where, its local spacing, its hachure and row.
  struct Entry {
    float x, y, spacing;
    std::int32_t id = -1, row = -1;
  };
  // Whether a point q of another hachure than `self`, of row `row` (-1: any row), lies
  // closer to p than `share` times the smaller of the two points' local spacings (p's is
  // `spacing`): the test is the same seen from either hachure. A point found near is kept
  // in `witness`, and looked at first the next time (a grid's seeds, two pixels apart, are
  // mostly refused for the same hachure).
  bool near(const Vector2f& p, double share, double spacing, long self, long row = -1,
            Entry* witness = nullptr) const {
    const auto close = [&](const Entry& e, float d2) {
      const double dq = share * std::min(spacing, double(e.spacing));
      return d2 < dq * dq;
    };
    if (witness && witness->id >= 0 && witness->id != self && (row < 0 || witness->row == row) &&
        close(*witness, distance2(*witness, p)))
      return true;
    bool found = false;
    scan(p, share * spacing, self, row, [&](const Entry& e, float d2) {
      if (!close(e, d2)) return false;
      if (witness) *witness = e;
      return found = true;
    });
    return found;
  }
  // near(), and where it is false a room that every such q keeps beyond its distance:
  // |q - p| - share min(spacing, q's) >= room for them all, those in no cell looked at
  // included (they lie beyond the cells' border).
  double room(const Vector2f& p, double share, double spacing, long self, long row,
              bool& is_near) const {
    const double d = share * spacing;
    double room = border(p, d) - d;
    is_near = false;
    scan(p, d, self, row, [&](const Entry& e, float d2) {
      const double dq = share * std::min(spacing, double(e.spacing));
      if (d2 < dq * dq) return is_near = true;
      room = std::min(room, std::sqrt(double(d2)) - dq);
      return false;
    });
    return room;
  }
  // Whether a point of another hachure than `self` lies closer than `d` to p.
  bool within(const Vector2f& p, double d, long self) const {
    bool found = false;
    scan(p, d, self, -1, [&](const Entry&, float d2) { return found = d2 < d * d; });
    return found;
  }
  void add(const Vector2f& p, double spacing, long id, long row) {
    const long u = std::clamp(long(p.x() / cell_), 0L, cols_ - 1),
               v = std::clamp(long(p.y() / cell_), 0L, rows_ - 1);
    cells_[std::size_t(v * cols_ + u)].push_back(
        {p.x(), p.y(), float(spacing), std::int32_t(id), std::int32_t(row)});
  }

 private:
  static float distance2(const Entry& e, const Vector2f& p) {
    const float dx = e.x - p.x(), dy = e.y - p.y();
    return dx * dx + dy * dy;
  }
  // The cells within d of p about p's own.
  struct Block {
    long u0, u1, v0, v1;
  };
  Block block(const Vector2f& p, double d) const {
    const long reach = long(std::ceil(d / cell_)), cu = long(p.x() / cell_),
               cv = long(p.y() / cell_);
    return {std::max(0L, cu - reach), std::min(cols_ - 1, cu + reach), std::max(0L, cv - reach),
            std::min(rows_ - 1, cv + reach)};
  }
  // How far p lies from the nearest point in no cell of its block (infinite where the block
  // reaches the grid's edge on every side).
  double border(const Vector2f& p, double d) const {
    const Block b = block(p, d);
    double m = std::numeric_limits<double>::infinity();
    if (b.u0 > 0) m = std::min(m, double(p.x()) - double(b.u0) * cell_);
    if (b.u1 < cols_ - 1) m = std::min(m, double(b.u1 + 1) * cell_ - double(p.x()));
    if (b.v0 > 0) m = std::min(m, double(p.y()) - double(b.v0) * cell_);
    if (b.v1 < rows_ - 1) m = std::min(m, double(b.v1 + 1) * cell_ - double(p.y()));
    return m;
  }
  // f(entry, squared distance) for the points of the cells within d of p, but self's and
  // those of another row than `row` (-1: any), until f says true; p's own cell first (where
  // a near point most often is).
  template <class F>
  void scan(const Vector2f& p, double d, long self, long row, F&& f) const {
    const Block b = block(p, d);
    const auto cell = [&](long u, long v) {
      for (const Entry& e : cells_[std::size_t(v * cols_ + u)])
        if (e.id != self && (row < 0 || e.row == row) && f(e, distance2(e, p))) return true;
      return false;
    };
    const long cu = std::clamp(long(p.x() / cell_), b.u0, b.u1),
               cv = std::clamp(long(p.y() / cell_), b.v0, b.v1);
    if (cell(cu, cv)) return;
    for (long v = b.v0; v <= b.v1; ++v)
      for (long u = b.u0; u <= b.u1; ++u)
        if ((u != cu || v != cv) && cell(u, v)) return;
  }
  static std::vector<std::vector<Entry>>& pool() {
    static thread_local std::vector<std::vector<Entry>> cells;
    return cells;
  }
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
  // Whether p keeps its distance from the other hachures (Occupancy::near). `room` is the
  // trace's: where the last point tested (at, spacing s) had room to spare, a point within
  // less than it of that one is free untested (the occupancy does not change while a hachure
  // is traced; Occupancy::room); else p is tested, and its room kept.
  struct Room {
    Vector2f at = Vector2f::Zero();
    double s = 0, room = -1;
  };
  bool free(const Vector2f& p, long self, long r, Room& room) const {
    constexpr double kSlack = 0.01;  // pixels, for the rounding of the distances
    const double s = spacing(p);
    if (room.room - double((p - room.at).norm()) - rule.test_share * std::max(0.0, s - room.s) >
        kSlack)
      return true;
    bool is_near = false;
    const double here = occupied.room(p, rule.test_share, s, self, r, is_near);
    if (!is_near) room = {p, s, here};
    return !is_near;
  }

  // From `seed` along the fall line (sign +1 downhill, -1 uphill), the points after it, into
  // `out` (emptied first; its memory kept from trace to trace). A trace ends within twice
  // the frame's diagonal, and where it comes back to where it was (a fall line that loops,
  // on a surface steeper than the field resolves).
  void run(const Vector2f& seed, float sign, long self, double length,
           std::vector<Vector2f>& out) const {
    constexpr float kStep = 0.5f;
    constexpr std::size_t kLoopSteps = 4;  // a point this many steps back is not its neighbour
    out.clear();
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
    Room room;
    while (length < longest) {
      const Vector2f d1 = sign * fall_at(f, p);
      const Vector2f mid = p + 0.5f * kStep * d1;
      if (!usable(mid)) break;
      const Vector2f d2 = sign * fall_at(f, mid);
      if (d2.dot(last) <= 0.0f)
        break;  // the fall line turns back (a valley or a ridge), or has none
      const Vector2f next = p + kStep * d2;
      if (!usable(next) || !free(next, self, r, room)) break;
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
  }
};

}  // namespace

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

std::vector<Hachure> trace_hachures(const HachureField& f, const HachureRule& rule,
                                    const std::vector<Eigen::Vector2f>& first) {
  std::vector<Hachure> out;
  if (f.width <= 0 || f.height <= 0 || !(rule.spacing > 0)) return out;
  if (rule.row_interval > 0 && f.elevation.size() != f.slope.size())
    throw terrain::Error("hachure rows need the field's heights");
  Occupancy occupied(f.width, f.height, std::max(1.0, rule.spacing));
  const Tracer tracer{f, rule, occupied};
  // A seed is traced where the field is usable there and no hachure lies within its spacing.
  Occupancy::Entry witness;  // the last seed's refusal
  const auto trace_from = [&](const Vector2f& seed) {
    const long id = long(out.size());
    const long row = tracer.row(seed);
    if (occupied.near(seed, 1.0, tracer.spacing(seed), -1, row, &witness)) return;
    static thread_local std::vector<Vector2f> up, down;
    tracer.run(seed, -1.0f, id, 0.0, up);
    tracer.run(seed, 1.0f, id, 0.5 * double(up.size()), down);
    if (0.5 * double(up.size() + down.size()) < rule.min_length) return;
    Hachure h;
    h.row = row;
    h.points.assign(up.rbegin(), up.rend());
    h.points.push_back(seed);
    h.points.insert(h.points.end(), down.begin(), down.end());
    h.tone.reserve(h.points.size());
    h.slope.reserve(h.points.size());
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

}  // namespace renderer
