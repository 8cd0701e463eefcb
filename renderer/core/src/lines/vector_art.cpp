#include "renderer/core/vector_art.hpp"

#include "renderer/core/camera.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include "renderer/core/line_stats.hpp"
#include "renderer/core/silhouette.hpp"
#include "terrain/error.hpp"

namespace renderer {

namespace {

constexpr float kWidthQuantum = 0.25f;   // pixels
constexpr float kOpacityQuantum = 0.1f;  // silhouettes and segment layers
constexpr float kTolerance = 0.25f;      // simplification, pixels

float quantise(float x, float q) { return std::round(x / q) * q; }

// A run of points along a stroke, each with the width there and the opacity of the segment
// that ends at it.
struct RunPoint {
  Eigen::Vector2f p;
  float width, opacity;
  std::array<float, 2> values{-1, -1};  // VectorPath::values at the point (creases)
};

// Points begin .. end - 1 of a run as one path at `opacity`, simplified: a stroke where its
// width varies by less than 1/8 px, else a filled outline with each kept point's width.
void emit_piece(const std::vector<RunPoint>& run, std::size_t begin, std::size_t end, float opacity,
                std::vector<VectorPath>& out) {
  Polyline line{{}, false};
  for (std::size_t j = begin; j < end; ++j) line.points.push_back(run[j].p);
  VectorPath path{{{}, false}, 0, opacity, {}};
  float lo = run[begin].width, hi = lo;
  for (const std::size_t k : simplified_points(line, kTolerance)) {
    path.line.points.push_back(run[begin + k].p);
    path.widths.push_back(run[begin + k].width);
    lo = std::min(lo, run[begin + k].width);
    hi = std::max(hi, run[begin + k].width);
  }
  if (run[begin].values[0] >= 0) {
    path.values.assign(run[begin].values.begin(), run[begin].values.end());
    for (std::size_t j = begin; j < end; ++j)
      for (std::size_t k = 0; k < path.values.size(); ++k)
        path.values[k] = std::max(path.values[k], run[j].values[k]);
  }
  path.width = quantise(0.5f * (lo + hi), kWidthQuantum);
  if (hi - lo < 0.5f * kWidthQuantum) path.widths.clear();
  out.push_back(std::move(path));
}

void emit_run(const std::vector<RunPoint>& run, std::vector<VectorPath>& out) {
  // Segment j runs from point j - 1 to point j, at run[j].opacity; parts of full opacity
  // (>= kFull) alternate with fading parts, each drawn at its mean opacity (by length).
  constexpr float kFull = 0.875f;
  std::size_t begin = 0;
  double length = 0, ink = 0;
  for (std::size_t j = 1; j < run.size(); ++j) {
    const double l = (run[j].p - run[j - 1].p).norm();
    length += l;
    ink += l * run[j].opacity;
    const bool full = run[j].opacity >= kFull;
    if (j + 1 < run.size() && (run[j + 1].opacity >= kFull) == full) continue;
    const float o = full         ? 1.0f
                    : length > 0 ? std::round(float(ink / length) * 100.0f) / 100.0f
                                 : run[j].opacity;
    if (o > 0) emit_piece(run, begin, j + 1, o, out);
    begin = j;
    length = ink = 0;
  }
}

bool bit(std::uint32_t mask, int k) { return ((mask >> k) & 1u) != 0; }

}  // namespace

VectorUnderlay parse_underlay(const std::string& name) {
  if (name == "none") return VectorUnderlay::None;
  if (name == "mask") return VectorUnderlay::Mask;
  if (name == "shaded") return VectorUnderlay::Shaded;
  throw terrain::Error("unknown vector underlay '" + name + "' (none, mask, shaded)");
}

std::vector<std::uint8_t> crease_orders(const CreaseGeometry& g) {
  const std::size_t n = g.positions.size();
  std::vector<std::uint32_t> down(n, terrain::DrainageLinks::kNone);  // a vertex's one segment
  std::vector<char> member(n, 0);
  for (std::size_t s = 0; s < g.n_segments(); ++s) {
    down[g.segments[2 * s]] = g.segments[2 * s + 1];
    member[g.segments[2 * s]] = member[g.segments[2 * s + 1]] = 1;
  }
  return terrain::strahler_orders(down, member);
}

std::vector<VectorPath> crease_paths(const CreaseGeometry& g, const std::vector<float>& drawn,
                                     const std::vector<SegmentSamples>& samples, const View& view,
                                     double exaggeration, double width_min, double width_max,
                                     std::size_t* strokes) {
  std::vector<VectorPath> out;
  std::size_t n_strokes = 0;
  if (samples.size() != g.n_segments() || drawn.size() != g.n_segments())
    throw terrain::Error("crease_paths: one opacity and one set of samples per segment expected");
  auto width_of = [&](std::uint32_t v) {
    return float(width_min +
                 (width_max - width_min) * std::sqrt(std::clamp(double(g.share[v]), 0.0, 1.0)));
  };
  const std::vector<std::uint8_t> order = crease_orders(g);
  for (const auto& stroke : crease_strokes(g, drawn)) {
    const std::size_t before = out.size();
    std::vector<RunPoint> run;
    auto flush = [&] {
      emit_run(run, out);
      run.clear();
    };
    for (const std::uint32_t s : stroke) {
      const SegmentSamples& m = samples[s];
      const std::uint32_t va = g.segments[2 * s], vb = g.segments[2 * s + 1];
      const Projected a = project(view, drawn_position(g, va, exaggeration));
      const Projected b = project(view, drawn_position(g, vb, exaggeration));
      if (m.n == 0 || !a.in_front || !b.in_front) {
        flush();
        continue;
      }
      const Eigen::Vector2f pa(float(a.u), float(a.v)), pb(float(b.u), float(b.v));
      const float wa = width_of(va), wb = width_of(vb);
      auto point = [&](double t) {
        return RunPoint{pa + float(t) * (pb - pa),
                        wa + float(t) * (wb - wa),
                        drawn[s],
                        {g.share[va] + float(t) * (g.share[vb] - g.share[va]), float(order[va])}};
      };
      const int n = int(m.n);
      for (int k = 0; k < n; ++k) {
        if (!bit(m.shown, k)) {
          flush();
          continue;
        }
        if (run.empty()) run.push_back(point(double(k) / n));
        if (k == n - 1 || !bit(m.shown, k + 1)) run.push_back(point(double(k + 1) / n));
      }
    }
    flush();
    if (out.size() > before) ++n_strokes;
  }
  if (strokes) *strokes = n_strokes;
  return out;
}

namespace {

// Open lines whose ends lie within `reach` pixels joined end to end, nearest ends first, as
// the piece rule joins their pixels (kSilhouetteJoin): one stroke of the pen, not dashes.
void join_across_gaps(std::vector<Polyline>& lines, float reach) {
  for (;;) {
    float best = reach;
    std::size_t bi = 0, bj = 0;
    int bend =
        -1;  // 0: i's back to j's front, 1: back to back, 2: front to front, 3: front to back
    for (std::size_t i = 0; i < lines.size(); ++i) {
      if (lines[i].closed || lines[i].points.empty()) continue;
      for (std::size_t j = i + 1; j < lines.size(); ++j) {
        if (lines[j].closed || lines[j].points.empty()) continue;
        const auto &a = lines[i].points, &b = lines[j].points;
        const float d[4] = {(a.back() - b.front()).norm(), (a.back() - b.back()).norm(),
                            (a.front() - b.front()).norm(), (a.front() - b.back()).norm()};
        for (int k = 0; k < 4; ++k)
          if (d[k] <= best) best = d[k], bi = i, bj = j, bend = k;
      }
    }
    if (bend < 0) return;
    auto& a = lines[bi].points;
    auto b = std::move(lines[bj].points);
    lines[bj].points.clear();
    if (bend == 1 || bend == 3) std::reverse(b.begin(), b.end());
    if (bend >= 2) std::reverse(a.begin(), a.end());  // joined at a's front: a reversed first
    a.insert(a.end(), b.begin(), b.end());
  }
}

}  // namespace

std::vector<VectorPath> silhouette_paths(const std::vector<std::uint8_t>& opacity, int w, int h,
                                         float width, std::size_t* pieces,
                                         const std::vector<float>* hidden, float heavier) {
  std::vector<std::uint8_t> mask(opacity.size());
  for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = opacity[i] > 0;
  if (pieces) *pieces = mask_pieces(mask, w, h, kSilhouetteJoin).size.size();
  std::vector<VectorPath> out;
  std::vector<Polyline> lines = chain_mask(mask, w, h);
  join_across_gaps(lines, float(kSilhouetteJoin) * 1.415f);
  for (Polyline& line : lines) {
    if (line.points.empty()) continue;
    double sum = 0, weight = 0;
    for (const Eigen::Vector2f& p : line.points) {
      const std::size_t i =
          std::size_t(std::floor(p.y())) * std::size_t(w) + std::size_t(std::floor(p.x()));
      sum += opacity[i];
      if (hidden) weight += hidden_weight((*hidden)[i]);
    }
    const float o = quantise(float(sum / double(line.points.size()) / 255.0), kOpacityQuantum);
    if (!(o > 0)) continue;
    const float line_width =
        width + quantise(heavier * float(weight / double(line.points.size())), kWidthQuantum);
    // Smoothed as the composite's band smooths the pixel staircase: two passes of the
    // (1, 2, 1) / 4 filter along the line, its ends kept (a ring's every point moves).
    auto& p = line.points;
    const std::size_t n = p.size();
    for (int pass = 0; pass < 2 && n >= 3; ++pass) {
      const std::vector<Eigen::Vector2f> q = p;
      for (std::size_t i = 0; i < n; ++i) {
        if (!line.closed && (i == 0 || i + 1 == n)) continue;
        p[i] = 0.25f * q[(i + n - 1) % n] + 0.5f * q[i] + 0.25f * q[(i + 1) % n];
      }
    }
    out.push_back({simplify(line, kTolerance), line_width, o, {}});
  }
  return out;
}

std::vector<VectorPath> segment_paths(const std::vector<SceneSegment>& segments, const View& view,
                                      double lift, const std::vector<float>& toward_depth,
                                      bool antialias, float width, std::size_t* chains) {
  const long W = view.width, H = view.height;
  auto far_of = [&](double d) { return far_depth(view.reversed_z, d); };
  // The visible pieces, by quantised opacity.
  std::map<int, std::vector<std::array<Eigen::Vector2f, 2>>> pieces;
  for (const SceneSegment& s : segments) {
    const Projected a = lifted_projection(view, s.a, lift), b = lifted_projection(view, s.b, lift);
    if (!a.in_front || !b.in_front) continue;  // as segment_quad_vertex drops it
    const int o = int(std::lround(s.opacity / kOpacityQuantum));
    if (o <= 0) continue;
    const Eigen::Vector2d pa(a.u, a.v), pb(b.u, b.v);
    const int n = std::clamp(int(std::ceil(2.0 * (pb - pa).norm())), 1, 1 << 16);  // every 0.5 px
    int first = -1;
    auto close = [&](int end) {  // samples first .. end - 1 show
      if (first < 0) return;
      const double t0 = first == 0 ? 0.0 : double(first) / n, t1 = end == n ? 1.0 : double(end) / n;
      pieces[o].push_back(
          {(pa + t0 * (pb - pa)).cast<float>(), (pa + t1 * (pb - pa)).cast<float>()});
      first = -1;
    };
    for (int k = 0; k < n; ++k) {
      const double t = (k + 0.5) / n;
      const Eigen::Vector2d q = pa + t * (pb - pa);
      bool shown = q.x() >= 0 && q.x() < double(W) && q.y() >= 0 && q.y() < double(H);
      if (shown) {
        const double line = a.depth + t * (b.depth - a.depth);
        const long x = long(std::floor(q.x())), y = long(std::floor(q.y()));
        if (antialias) {
          const auto surface = farthest_surface(view, toward_depth, x, y);
          shown = surface && far_of(line) <= far_of(*surface);
        } else {
          const double d = toward_depth[std::size_t(y * W + x)];
          shown = far_of(d) >= 1.0 || far_of(line) <= far_of(d);
        }
      }
      if (shown && first < 0) first = k;
      if (!shown) close(k);
    }
    close(n);
  }
  std::vector<VectorPath> out;
  std::size_t n_chains = 0;
  for (const auto& [o, list] : pieces)
    for (const Polyline& line : chain_segments(list, 0.01f)) {
      out.push_back({simplify(line, kTolerance), width, float(o) * kOpacityQuantum, {}});
      ++n_chains;
    }
  if (chains) *chains = n_chains;
  return out;
}

VectorLayer hachure_paths(const std::vector<Hachure>& hachures, const Style& style) {
  VectorLayer l{"hachures", style.hachure_colour, LineCap::Round, {}, 0};
  for (const Hachure& h : hachures) {
    VectorPath p;
    // Traced in steps of half a pixel; drawn as the fewest points within 0.1 px of them.
    Polyline traced;
    traced.points = h.points;
    p.line = simplify(traced, 0.1f);
    // Pen pressure: the width follows the hachure's mean tone, half to one and a half times
    // --hachure-width (one width a path: an outline per point made the MSH SVG 15 MB).
    double tone = 0;
    for (const float t : h.tone) tone += t;
    tone /= double(std::max<std::size_t>(h.tone.size(), 1));
    p.width = float(style.hachure_width * (0.5 + tone));
    p.values = {float(tone)};
    l.paths.push_back(std::move(p));
  }
  l.value_names = {"tone"};
  l.strokes = l.paths.size();
  return l;
}

}  // namespace renderer
