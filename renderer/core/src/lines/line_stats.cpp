#include "renderer/core/line_stats.hpp"
#include "renderer/core/camera.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>

#include "renderer/core/silhouette.hpp"
#include "renderer/core/stroke_visibility.hpp"

namespace renderer {

float plan_curvature_at(const terrain::GridMesh& mesh, std::size_t v) {
  const long R = long(mesh.topo.rows), C = long(mesh.topo.cols), r = long(v) / C, c = long(v) % C;
  if (r < 1 || c < 1 || r + 1 >= R || c + 1 >= C) return 0.0f;
  const double dx = mesh.geo.dx, dy = mesh.geo.dy;
  auto z = [&](long rr, long cc) { return double(mesh.positions[std::size_t(rr * C + cc)].z()); };
  // Row r - 1 is north (+y).
  const double p = (z(r, c + 1) - z(r, c - 1)) / (2 * dx),
               q = (z(r - 1, c) - z(r + 1, c)) / (2 * dy);
  const double rr = (z(r, c + 1) - 2 * z(r, c) + z(r, c - 1)) / (dx * dx);
  const double tt = (z(r - 1, c) - 2 * z(r, c) + z(r + 1, c)) / (dy * dy);
  const double ss =
      (z(r - 1, c + 1) - z(r - 1, c - 1) - z(r + 1, c + 1) + z(r + 1, c - 1)) / (4 * dx * dy);
  const double g2 = p * p + q * q;
  if (g2 < 1e-12) return 0.0f;
  return float((q * q * rr - 2 * p * q * ss + p * p * tt) / std::pow(g2, 1.5));
}

std::vector<float> plan_curvature(const terrain::GridMesh& mesh) {
  std::vector<float> k(mesh.n_vertices(), 0.0f);
  for (std::size_t v = 0; v < k.size(); ++v) k[v] = plan_curvature_at(mesh, v);
  return k;
}

SegmentTraits segment_traits(const terrain::GridMesh& mesh, const terrain::DrainageLinks& links,
                             const CreaseGeometry& g, int margin) {
  const std::size_t ns = g.n_segments();
  SegmentTraits t;
  t.boundary.resize(ns), t.flat.resize(ns), t.valley.resize(ns), t.open_end.resize(ns);
  const long LR = long(links.rows), LC = long(links.cols), m = margin;
  const std::size_t valid =
      std::size_t(std::count(links.valid.begin(), links.valid.end(), std::uint8_t(1)));
  auto near_edge = [&](std::uint32_t point) {  // within m samples of the grid's edge or of no-data
    const long r = long(point) / LC, c = long(point) % LC;
    if (r < m || c < m || r >= LR - m || c >= LC - m) return true;
    for (long rr = r - m; rr <= r + m; ++rr)
      for (long cc = c - m; cc <= c + m; ++cc)
        if (!links.valid[std::size_t(rr * LC + cc)]) return true;
    return false;
  };
  for (std::size_t s = 0; s < ns; ++s) {
    const std::uint32_t a = g.segments[2 * s], b = g.segments[2 * s + 1];
    const long r = long(g.source[a]) / LC, c = long(g.source[a]) % LC;
    t.boundary[s] = r < m || c < m || r >= LR - m || c >= LC - m;
    const std::uint32_t pb = g.source[b];
    t.open_end[s] =
        near_edge(pb) || (links.downstream[pb] == terrain::DrainageLinks::kNone &&
                          double(links.accumulated[pb]) >= kClosedBasinShare * double(valid));
    t.flat[s] = links.z[g.source[b]] >= links.z[g.source[a]];
    const Eigen::Vector3f mid = 0.5f * (g.positions[a] + g.positions[b]);
    // The curvature of the four vertices about the midpoint only (not an array over the
    // mesh: 1.4 GB of it at Logan's 2 m).
    t.valley[s] =
        vertex_value_at(
            mesh, [&](std::size_t v) { return plan_curvature_at(mesh, v); }, mid.x(), mid.y()) > 0;
  }
  return t;
}

namespace {

// The part of segment (a, b) inside [0, w] x [0, h] (Liang-Barsky); none when outside.
std::optional<std::pair<Eigen::Vector2d, Eigen::Vector2d>> clip(Eigen::Vector2d a,
                                                                Eigen::Vector2d b, double w,
                                                                double h) {
  double t0 = 0, t1 = 1;
  const Eigen::Vector2d d = b - a;
  const double p[4] = {-d.x(), d.x(), -d.y(), d.y()}, q[4] = {a.x(), w - a.x(), a.y(), h - a.y()};
  for (int k = 0; k < 4; ++k) {
    if (p[k] == 0) {
      if (q[k] < 0) return std::nullopt;
      continue;
    }
    const double r = q[k] / p[k];
    if (p[k] < 0)
      t0 = std::max(t0, r);
    else
      t1 = std::min(t1, r);
    if (t0 > t1) return std::nullopt;
  }
  return std::make_pair(Eigen::Vector2d(a + t0 * d), Eigen::Vector2d(a + t1 * d));
}

std::optional<std::pair<Eigen::Vector2d, Eigen::Vector2d>> screen_segment(const CreaseGeometry& g,
                                                                          std::size_t s,
                                                                          const View& view,
                                                                          double e) {
  auto at = [&](std::uint32_t i) { return project(view, drawn_position(g, i, e)); };
  const Projected a = at(g.segments[2 * s]), b = at(g.segments[2 * s + 1]);
  if (!a.in_front || !b.in_front) return std::nullopt;
  return clip({a.u, a.v}, {b.u, b.v}, view.width, view.height);
}

}  // namespace

SegmentTraits merged_traits(const SegmentTraits& fine, const CreaseLevel& level) {
  const std::size_t ns = level.first.size();
  SegmentTraits t;
  t.boundary.resize(ns), t.flat.resize(ns), t.valley.resize(ns), t.open_end.resize(ns);
  for (std::size_t s = 0; s < ns; ++s) {
    const std::uint32_t a = level.first[s];
    t.boundary[s] = fine.boundary[a], t.flat[s] = fine.flat[a], t.valley[s] = fine.valley[a];
    t.open_end[s] = fine.open_end[level.last[s]];
  }
  return t;
}

std::vector<double> segment_pixels(const CreaseGeometry& g, const View& view, double exaggeration) {
  std::vector<double> px(g.n_segments(), 0.0);
  for (std::size_t s = 0; s < px.size(); ++s)
    if (const auto seg = screen_segment(g, s, view, exaggeration))
      px[s] = (seg->second - seg->first).norm();
  return px;
}

std::vector<double> visible_fraction(const CreaseGeometry& g, const View& view, double exaggeration,
                                     double lift, const std::vector<float>& toward_depth,
                                     bool antialias) {
  const long W = view.width, H = view.height;
  auto far_of = [&](double d) { return far_depth(view.reversed_z, d); };
  // An end on screen and the window depth it is drawn at (line_clip).
  auto end_of = [&](std::uint32_t i, Projected& at, double& depth) {
    const Eigen::Vector3d p = drawn_position(g, i, exaggeration);
    at = project(view, p);
    depth = lifted_projection(view, p, lift).depth;
  };
  std::vector<double> f(g.n_segments(), 0.0);
  for (std::size_t s = 0; s < f.size(); ++s) {
    Projected a, b;
    double da = 0, db = 0;
    end_of(g.segments[2 * s], a, da);
    end_of(g.segments[2 * s + 1], b, db);
    if (!a.in_front || !b.in_front) continue;
    const Eigen::Vector2d A(a.u, a.v), B(b.u, b.v);
    const auto seg = clip(A, B, double(W), double(H));
    if (!seg) continue;
    const double full = (B - A).norm();
    const int n = std::max(1, int(std::ceil((seg->second - seg->first).norm())));
    int hit = 0;
    for (int k = 0; k < n; ++k) {
      const Eigen::Vector2d q = seg->first + (seg->second - seg->first) * ((k + 0.5) / n);
      // Window depth is affine along the segment on screen, as the rasterizer interpolates it.
      const double line = far_of(da + (db - da) * (full > 0 ? (q - A).norm() / full : 0.0));
      const long x = long(std::floor(q.x())), y = long(std::floor(q.y()));
      std::optional<double> surface;  // window depth
      if (antialias)
        surface = farthest_surface(view, toward_depth, x, y);
      else if (const double d = toward_depth[std::size_t(std::clamp(y, 0L, H - 1) * W +
                                                         std::clamp(x, 0L, W - 1))];
               far_of(d) < 1.0)
        surface = d;
      hit += surface && line <= far_of(*surface);
    }
    f[s] = double(hit) / n;
  }
  return f;
}

std::vector<std::vector<std::uint32_t>> crease_strokes(const CreaseGeometry& g,
                                                       const std::vector<float>& drawn) {
  const SegmentChains ch = segment_chains(g, drawn);
  std::vector<std::vector<std::uint32_t>> strokes;
  for (std::uint32_t s = 0; s < g.n_segments(); ++s) {
    if (!(drawn[s] > 0) || ch.prev[s] != kNoSegment) continue;  // continues a stroke
    std::vector<std::uint32_t> stroke{s};
    for (std::uint32_t t = ch.next[s]; t != kNoSegment && ch.prev[t] == stroke.back();
         t = ch.next[t])
      stroke.push_back(t);
    strokes.push_back(std::move(stroke));
  }
  return strokes;
}

double connected_share(const CreaseGeometry& g, const SegmentTraits& traits,
                       const std::vector<float>& drawn, const std::vector<double>& length) {
  const std::size_t ns = g.n_segments();
  const std::vector<std::uint32_t> next =
      segment_chains(g, drawn).next;  // the drawn segment going on downstream
  // 0 unknown, 1 connected, 2 a dash; resolved downstream first along each walk.
  std::vector<std::uint8_t> state(ns, 0);
  std::vector<std::uint32_t> walk;
  double total = 0, connected = 0;
  for (std::size_t s0 = 0; s0 < ns; ++s0) {
    if (drawn[s0] <= 0) continue;
    std::uint32_t s = std::uint32_t(s0);
    while (state[s] == 0) {
      walk.push_back(s);
      if (next[s] == kNoSegment) {
        state[s] = traits.open_end[s] ? 1 : 2;
        break;
      }
      s = next[s];
    }
    for (const std::uint32_t w : walk) state[w] = state[s];
    walk.clear();
    const double l = double(drawn[s0]) * length[s0];
    total += l;
    connected += state[s0] == 1 ? l : 0.0;
  }
  return total > 0 ? connected / total : 1.0;
}

LineStats line_stats(const CreaseGeometry& g, const SegmentTraits& traits,
                     const std::vector<float>& drawn, const std::vector<double>& pixels) {
  LineStats st;
  double boundary = 0, flat = 0, valley = 0;
  for (std::size_t s = 0; s < g.n_segments(); ++s) {
    const double l = double(drawn[s]) * pixels[s];
    st.length_px += l;
    boundary += traits.boundary[s] * l, flat += traits.flat[s] * l, valley += traits.valley[s] * l;
  }
  // Strokes that show: at least one of their segments has pixels.
  std::vector<float> shown(drawn.size());
  for (std::size_t s = 0; s < shown.size(); ++s) shown[s] = pixels[s] > 0 ? drawn[s] : 0.0f;
  const auto strokes = crease_strokes(g, shown);
  st.strokes = strokes.size();
  for (const auto& stroke : strokes) {
    double ink = 0, px = 0;
    for (const std::uint32_t s : stroke) ink += double(drawn[s]) * pixels[s], px += pixels[s];
    st.weighted_strokes += ink / px;  // px > 0: every segment of a shown stroke has pixels
  }
  if (st.length_px > 0)
    st.boundary = boundary / st.length_px, st.flat = flat / st.length_px,
    st.valley = valley / st.length_px;
  if (st.strokes > 0) st.mean_stroke_px = st.length_px / double(st.strokes);
  if (st.weighted_strokes > 0) st.weighted_mean_stroke_px = st.length_px / st.weighted_strokes;
  return st;
}

SilhouetteStats silhouette_stats(const std::vector<std::uint8_t>& opacity, int w, int h) {
  SilhouetteStats st;
  const MaskPieces m = mask_pieces(opacity, w, h, kSilhouetteJoin);
  st.pieces = m.size.size();
  std::vector<double> of_piece(st.pieces, 0.0);  // the piece rule's opacity, one a piece
  for (std::size_t i = 0; i < opacity.size(); ++i) {
    st.pixels += double(opacity[i]) / 255.0;
    if (m.piece[i])
      of_piece[m.piece[i] - 1] = std::max(of_piece[m.piece[i] - 1], double(opacity[i]) / 255.0);
  }
  const double weighted = std::accumulate(of_piece.begin(), of_piece.end(), 0.0);
  if (weighted > 0) st.mean_piece_px = st.pixels / weighted;
  return st;
}

double flicker(const std::vector<std::vector<float>>& drawn,
               const std::vector<std::vector<double>>& pixels) {
  double changed = 0, total = 0;
  for (std::size_t k = 0; k + 1 < drawn.size(); ++k)
    for (std::size_t s = 0; s < drawn[k].size(); ++s) {
      const double l = 0.5 * (pixels[k][s] + pixels[k + 1][s]);
      changed += std::abs(double(drawn[k][s]) - double(drawn[k + 1][s])) * l;
      total += std::max(drawn[k][s], drawn[k + 1][s]) * l;
    }
  return total > 0 ? changed / total : 0.0;
}

}  // namespace renderer
