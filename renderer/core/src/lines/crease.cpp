// Crease scores and strokes: the score of a crease vertex, the stroke rule along chains of
// segments, which segments a view draws; the warnings of a crease geometry.
#include "renderer/core/crease.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "crease_internal.hpp"
#include "renderer/core/camera.hpp"
#include "renderer/core/line_stats.hpp"
#include "terrain/error.hpp"
#include "terrain/pn_surface.hpp"

namespace renderer {

using detail::vertex_segments;
using detail::VertexSegments;

Eigen::Vector3d exaggerate_normal(const Eigen::Vector3d& n, double e) {
  return Eigen::Vector3d(n.x(), n.y(), n.z() / e).normalized();
}

double crease_score(const Eigen::Vector3d& n, double flow, const Eigen::Vector3d& light,
                    double distance, const CreaseScoreParams& p) {
  const double sc = 1.0 - n.z(), ic = 1.0 - n.dot(light);
  const double divisor = p.literal_divisor ? 3.0 : (p.sw + p.iw + p.fw);
  const double raw = (p.sw * sc + p.iw * ic + p.fw * flow) / divisor;
  const double rs_min =
      p.min_score +
      (1.0 - p.min_score) * p.falloff *
          std::clamp((distance - p.near_distance) / (p.far_distance - p.near_distance), 0.0, 1.0);
  return raw - rs_min;
}

double crease_lift(const Style& style, const terrain::GridMesh& mesh) {
  return style.crease_lift >= 0 ? style.crease_lift : 0.5 * std::min(mesh.geo.dx, mesh.geo.dy);
}

CreaseScoreParams resolve_distances(const CreaseScoreParams& params, const Eigen::Vector3d& lo,
                                    const Eigen::Vector3d& hi, const Viewpoint& viewer) {
  if (params.far_distance > 0) return params;
  CreaseScoreParams p = params;
  if (viewer.orthographic()) {
    // A map has one scale: the distance term of the scene's middle everywhere, rs_min =
    // min + (1 - min) k / 2: near and far put so far either side of the middle that the
    // box's whole depth moves clamp(...) by under 1e-6 from 1/2.
    double d_lo = 1e300, d_hi = -1e300;
    for (const Eigen::Vector3d& c : box_corners({lo, hi})) {
      const double d = viewer.distance(c);
      d_lo = std::min(d_lo, d), d_hi = std::max(d_hi, d);
    }
    const double reach = 1e6 * (1 + d_hi - d_lo);
    p.near_distance = 0.5 * (d_lo + d_hi) - reach;
    p.far_distance = 0.5 * (d_lo + d_hi) + reach;
    return p;
  }
  const Eigen::Vector3d& eye = viewer.eye;
  const Eigen::Vector3d far = (eye - lo).cwiseAbs().cwiseMax((eye - hi).cwiseAbs());
  p.near_distance = (eye - eye.cwiseMax(lo).cwiseMin(hi)).norm();
  p.far_distance = std::max(far.norm(), p.near_distance + 1e-6 * (1.0 + far.norm()));
  return p;
}

SegmentChains segment_chains(const CreaseGeometry& g, const std::vector<float>& drawn) {
  const std::size_t ns = g.n_segments();
  SegmentChains ch{std::vector<std::uint32_t>(ns, kNoSegment),
                   std::vector<std::uint32_t>(ns, kNoSegment)};
  const VertexSegments v = vertex_segments(g, drawn);
  for (std::uint32_t s = 0; s < ns; ++s) {
    ch.next[s] = v.leaving[g.segments[2 * s + 1]];
    ch.prev[s] = v.entering[g.segments[2 * s]];
  }
  return ch;
}

std::vector<float> apply_stroke_rule(const SegmentChains& ch, const std::vector<float>& opacity,
                                     const std::vector<double>& length, const StrokeRule& rule) {
  const std::size_t ns = opacity.size();
  std::vector<float> bridged = opacity;
  // The opacity of the first drawn segment within rule.bridge along a chain, 0 when none.
  auto nearest_drawn = [&](std::uint32_t t, const std::vector<std::uint32_t>& step) {
    double gap = 0;
    for (int k = 0; t != kNoSegment && k < kStrokeReach && gap <= rule.bridge; ++k, t = step[t]) {
      if (opacity[t] > 0) return opacity[t];
      gap += length[t];
    }
    return 0.0f;
  };
  if (rule.bridge > 0)
    for (std::size_t s = 0; s < ns; ++s)
      if (!(opacity[s] > 0))
        bridged[s] =
            std::min(nearest_drawn(ch.prev[s], ch.prev), nearest_drawn(ch.next[s], ch.next));
  if (!(rule.min_length > 0)) return bridged;
  std::vector<float> out = bridged;
  for (std::size_t s = 0; s < ns; ++s) {
    if (!(bridged[s] > 0)) continue;
    double run = length[s];
    int k = 0;
    // Only as far as the run needs to reach the minimum (a sum of lengths only grows).
    for (std::uint32_t t = ch.prev[s];
         t != kNoSegment && k < kStrokeReach && bridged[t] > 0 && run < rule.min_length;
         t = ch.prev[t], ++k)
      run += length[t];
    k = 0;
    for (std::uint32_t c = std::uint32_t(s), t = ch.next[s];
         t != kNoSegment && k < kStrokeReach && bridged[t] > 0 && ch.prev[t] == c &&
         run < rule.min_length;
         c = t, t = ch.next[t], ++k)
      run += length[t];
    if (run < rule.min_length) out[s] = 0;
  }
  return out;
}

StrokeRule stroke_rule(const Style& style, double page_scale) {
  return StrokeRule{std::max(style.crease_bridge, style.crease_bridge_px * page_scale),
                    std::max(style.crease_min_stroke, style.crease_min_stroke_px * page_scale),
                    style.page_min_area * std::sqrt(std::max(page_scale, 0.0) / kPageAreaScale)};
}

std::vector<double> segment_metres(const CreaseGeometry& g) {
  std::vector<double> m(g.n_segments());
  for (std::size_t s = 0; s < m.size(); ++s)
    m[s] = (g.positions[g.segments[2 * s]] - g.positions[g.segments[2 * s + 1]]).norm();
  return m;
}

std::vector<float> segment_opacity(const CreaseGeometry& g, const Viewpoint& viewer,
                                   const Eigen::Vector3d& light, double e,
                                   const CreaseScoreParams& params, double fade,
                                   const StrokeRule& rule) {
  std::vector<double> score(g.positions.size());
  for (std::size_t i = 0; i < score.size(); ++i) {
    const Eigen::Vector3d p = g.positions[i].cast<double>();
    const Eigen::Vector3d pe(p.x(), p.y(), p.z() * e);
    score[i] = !g.area.empty() && double(g.area[i]) < rule.min_area
                   ? -1.0
                   : crease_score(exaggerate_normal(g.normals[i].cast<double>(), e), g.flow[i],
                                  light, viewer.distance(pe), params);
  }
  std::vector<float> opacity(g.n_segments());
  for (std::size_t s = 0; s < opacity.size(); ++s) {
    const double lowest = std::min(score[g.segments[2 * s]], score[g.segments[2 * s + 1]]);
    opacity[s] = lowest < 0.0 ? 0.0f : fade > 0 ? float(std::min(1.0, lowest / fade)) : 1.0f;
  }
  if (!(rule.bridge > 0) && !(rule.min_length > 0)) return opacity;
  return apply_stroke_rule(segment_chains(g), opacity, segment_metres(g), rule);
}

std::vector<std::uint8_t> accepted_segments(const CreaseGeometry& g, const Viewpoint& viewer,
                                            const Eigen::Vector3d& light, double e,
                                            const CreaseScoreParams& params) {
  const auto opacity = segment_opacity(g, viewer, light, e, params, 0.0);
  return std::vector<std::uint8_t>(opacity.begin(), opacity.end());
}

std::size_t count_accepted_segments(const CreaseGeometry& g, const Viewpoint& viewer,
                                    const Eigen::Vector3d& light, double e,
                                    const CreaseScoreParams& params) {
  const auto a = accepted_segments(g, viewer, light, e, params);
  return std::size_t(std::count(a.begin(), a.end(), 1));
}

std::string coverage_warning(const terrain::GridMesh& mesh, const terrain::DrainageLinks& h) {
  const auto& g = mesh.geo;
  // Sample extents in world coordinates: west, south, east, north.
  const double m[4] = {g.origin_x, g.origin_y - double(mesh.topo.rows - 1) * g.dy,
                       g.origin_x + double(mesh.topo.cols - 1) * g.dx, g.origin_y};
  const double d[4] = {h.origin.x(), h.origin.y() - double(h.rows - 1) * h.dy,
                       h.origin.x() + double(h.cols - 1) * h.dx, h.origin.y()};
  const double tol = std::max(h.dx, h.dy);
  for (int k = 0; k < 4; ++k)
    if (std::abs(m[k] - d[k]) > tol)
      return fmt::format(
          "the drainage database covers x {:.1f}..{:.1f}, y {:.1f}..{:.1f}, the mesh x "
          "{:.1f}..{:.1f}, "
          "y {:.1f}..{:.1f}: it was not made from this mesh",
          d[0], d[2], d[1], d[3], m[0], m[2], m[1], m[3]);
  return {};
}

std::string surface_warning(const terrain::GridMesh& mesh, const CreaseGeometry& g) {
  const double spacing = std::min(mesh.geo.dx, mesh.geo.dy);
  if (!(g.median_surface_offset > kSurfaceOffsetShare * spacing)) return {};
  return fmt::format(
      "its points lie a median {:.2f} m off this mesh's PN surface ({:.0f} % of its {:g} m "
      "spacing): "
      "it was sampled from another surface, so its creases will not follow this one's valleys "
      "(build it from this mesh)",
      g.median_surface_offset, 100 * g.median_surface_offset / spacing, spacing);
}

}  // namespace renderer
