#include "renderer/core/stroke_visibility.hpp"
#include "renderer/core/camera.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

namespace renderer {

namespace {

bool bit(std::uint32_t mask, int k) { return (mask >> k) & 1u; }

// How a walk along a stroke ends: at a sample it looks for, at one that blocks it, at the
// stroke's end, or past its length limit.
enum class Stop { Found, Blocked, End, Long };
struct Walk {
  Stop stop;
  double length;  // screen length of the samples passed over
};

// From sample k of segment s, one way along the stroke (up: towards chains.prev), over the
// samples `classify` passes (0), until one it finds (1) or that blocks (2), the stroke's end
// (a segment without samples, or kStrokeReach segments on), or more than `limit` pixels.
// With `junctions_end`, past a junction downstream where the stroke does not continue (the
// next segment's prev is another), more than `limit` pixels is the stroke's end: the run
// of a tributary ends where it joins a line that goes on. crease_visibility.comp.glsl's
// stroke_walk is the same walk.
template <class Classify>
Walk walk(const std::vector<SegmentSamples>& m, const SegmentChains& chains, std::uint32_t s, int k,
          bool up, double limit, Classify classify, bool junctions_end) {
  double length = 0;
  bool joined = false;
  for (int hops = 0;;) {
    k += up ? -1 : 1;
    if (k < 0 || k >= int(m[s].n)) {
      const std::uint32_t t = up ? chains.prev[s] : chains.next[s];
      if (t == kNoSegment || m[t].n == 0 || ++hops > kStrokeReach) return {Stop::End, length};
      joined = joined || (junctions_end && !up && chains.prev[t] != s);
      s = t;
      k = up ? int(m[s].n) - 1 : 0;
    }
    const int c = classify(m[s], k);
    if (c == 1) return {Stop::Found, length};
    if (c == 2) return {Stop::Blocked, length};
    length += m[s].step;
    if (length > limit) return {joined ? Stop::End : Stop::Long, length};
  }
}

}  // namespace

StrokeVisibilityRule stroke_visibility_rule(const Style& style, const terrain::GridMesh& mesh) {
  return {style.crease_hidden_gap, style.crease_hidden_depth * std::min(mesh.geo.dx, mesh.geo.dy),
          style.crease_min_peek};
}

Eigen::Vector3d drawn_position(const CreaseGeometry& g, std::uint32_t i, double e) {
  const Eigen::Vector3d p = g.positions[i].cast<double>();
  return {p.x(), p.y(), p.z() * e};
}

Projected lifted_projection(const View& view, const Eigen::Vector3d& p, double lift) {
  const Viewpoint viewer = view.viewpoint();
  const Eigen::Vector3d to_eye = viewer.to_eye(p);
  const double d = viewer.orthographic() ? viewer.distance(p) : to_eye.norm();
  return project(view,
                 d > 0 ? Eigen::Vector3d(p + std::min(lift, 0.5 * d) / to_eye.norm() * to_eye) : p);
}

std::optional<double> farthest_surface(const View& view, const std::vector<float>& toward_depth,
                                       long x, long y) {
  const long W = view.width, H = view.height;
  auto far_of = [&](double d) { return far_depth(view.reversed_z, d); };
  std::optional<double> farthest;
  for (long dy = -1; dy <= 1; ++dy)
    for (long dx = -1; dx <= 1; ++dx) {
      const double d = toward_depth[std::size_t(std::clamp(y + dy, 0L, H - 1) * W +
                                                std::clamp(x + dx, 0L, W - 1))];
      if (far_of(d) < 1.0 && (!farthest || far_of(d) > far_of(*farthest))) farthest = d;
    }
  return farthest;
}

// Hidden runs drawn: a bridgeable sample closed when shown samples lie within the gap on
// both sides along the strokes.
static void close_hidden_runs(std::vector<SegmentSamples>& m, const SegmentChains& chains,
                              const StrokeVisibilityRule& rule) {
  const std::size_t ns = m.size();
  for (std::uint32_t s = 0; s < ns; ++s) {
    SegmentSamples& ms = m[s];
    ms.closed = ms.visible;
    const double limit = rule.gap_px - ms.step;
    if (!(rule.gap_px > 0) || limit < 0) continue;
    auto classify = [](const SegmentSamples& o, int j) {
      return bit(o.visible, j) ? 1 : bit(o.bridgeable, j) ? 0 : 2;
    };
    for (int k = 0; k < int(ms.n); ++k) {
      if (!bit(ms.bridgeable, k)) continue;
      const Walk up = walk(m, chains, s, k, true, limit, classify, false);
      if (up.stop != Stop::Found) continue;
      if (walk(m, chains, s, k, false, limit - up.length, classify, false).stop == Stop::Found)
        ms.closed |= 1u << k;
    }
  }
}

// Peeks left out; a tributary's run ends where it joins a line that goes on, as its
// stroke does (crease_strokes), so a stub of it hidden upstream is a peek there too.
static void leave_out_peeks(std::vector<SegmentSamples>& m, const SegmentChains& chains,
                            const StrokeVisibilityRule& rule) {
  const std::size_t ns = m.size();
  for (std::uint32_t s = 0; s < ns; ++s) {
    SegmentSamples& ms = m[s];
    ms.shown = ms.closed;
    const double limit = rule.min_peek_px - ms.step;
    if (!(rule.min_peek_px > 0) || limit < 0) continue;
    auto classify = [](const SegmentSamples& o, int j) { return bit(o.closed, j) ? 0 : 2; };
    for (int k = 0; k < int(ms.n); ++k) {
      if (!bit(ms.closed, k)) continue;
      const Walk up = walk(m, chains, s, k, true, limit, classify, true);
      if (up.stop == Stop::Long) continue;
      const Walk down = walk(m, chains, s, k, false, limit - up.length, classify, true);
      if (down.stop == Stop::Long) continue;
      if (up.stop == Stop::Blocked || down.stop == Stop::Blocked) ms.shown &= ~(1u << k);
    }
  }
}

std::vector<SegmentSamples> stroke_visibility(const CreaseGeometry& g, const SegmentChains& chains,
                                              const std::vector<float>& drawn, const View& view,
                                              double exaggeration, double lift,
                                              const std::vector<float>& toward_depth,
                                              const StrokeVisibilityRule& rule) {
  const long W = view.width, H = view.height;
  auto far_of = [&](double d) { return far_depth(view.reversed_z, d); };
  // Distance along the view axis of a window depth (crease_visibility.comp's eye_distance).
  auto eye_distance = [&](double d) { return view.depth_distance(d); };
  const std::size_t ns = g.n_segments();
  std::vector<SegmentSamples> m(ns);
  for (std::uint32_t s = 0; s < ns; ++s) {
    if (!(drawn[s] > 0)) continue;
    Projected end[2],
        lifted[2];  // where each end lies; the point its depth is taken at (line_clip)
    for (int j = 0; j < 2; ++j) {
      const Eigen::Vector3d p = drawn_position(g, g.segments[2 * s + j], exaggeration);
      end[j] = project(view, p);
      lifted[j] = lifted_projection(view, p, lift);
    }
    if (!lifted[0].in_front || !lifted[1].in_front) continue;  // as segment_quad_vertex drops it
    const double depth[2] = {lifted[0].depth, lifted[1].depth};
    const Eigen::Vector2d a(end[0].u, end[0].v), b(end[1].u, end[1].v);
    const double len = (b - a).norm();
    SegmentSamples& ms = m[s];
    ms.n = std::uint32_t(std::clamp(int(std::ceil(len)), 1, kStrokeSamples));
    ms.step = float(len / ms.n);
    for (int k = 0; k < int(ms.n); ++k) {
      const double t = (k + 0.5) / ms.n;
      const Eigen::Vector2d q = a + t * (b - a);
      if (!(q.x() >= 0 && q.x() < double(W) && q.y() >= 0 && q.y() < double(H)))
        continue;  // off the image
      // Window depth is affine along the segment on screen, as the rasterizer interpolates it.
      const double line = depth[0] + t * (depth[1] - depth[0]);
      const auto surface =
          farthest_surface(view, toward_depth, long(std::floor(q.x())), long(std::floor(q.y())));
      if (!surface) continue;  // no surface about the sample
      if (far_of(line) <= far_of(*surface))
        ms.visible |= 1u << k;
      else if (eye_distance(line) - eye_distance(*surface) <= rule.gap_depth)
        ms.bridgeable |= 1u << k;
    }
  }
  close_hidden_runs(m, chains, rule);
  leave_out_peeks(m, chains, rule);
  return m;
}

std::vector<double> shown_pixels(const std::vector<SegmentSamples>& samples) {
  std::vector<double> px(samples.size(), 0.0);
  for (std::size_t s = 0; s < px.size(); ++s)
    px[s] = double(samples[s].step) * double(std::popcount(samples[s].shown));
  return px;
}

SampleComparison compare_samples(const std::vector<SegmentSamples>& a,
                                 const std::vector<SegmentSamples>& b) {
  SampleComparison c;
  for (std::size_t s = 0; s < a.size() && s < b.size(); ++s) {
    if (a[s].n == 0 && b[s].n == 0) continue;
    ++c.segments;
    if (a[s].n != b[s].n) {
      ++c.other_count;
      continue;
    }
    c.samples += b[s].n;
    const std::uint32_t x[4] = {a[s].visible, a[s].bridgeable, a[s].closed, a[s].shown};
    const std::uint32_t y[4] = {b[s].visible, b[s].bridgeable, b[s].closed, b[s].shown};
    for (int j = 0; j < 4; ++j) c.differ[j] += std::size_t(std::popcount(x[j] ^ y[j]));
    c.hidden_drawn += std::size_t(std::popcount(b[s].shown & ~b[s].visible));
    c.peeks += std::size_t(std::popcount(b[s].closed & ~b[s].shown));
  }
  return c;
}

}  // namespace renderer
