// A frame's lines made on the CPU from what the renderer drew: the creases and their
// opacity, the vector art (SVG, PDF), the hachures traced, the ridge lines, the overlays
// drawn over the PNG, and --line-stats.
#include "renderer/scene/scene.hpp"

#include "renderer/core/camera.hpp"
#include "renderer/core/silhouette.hpp"
#include "renderer/gl/gl_contract.hpp"

#include <fmt/format.h>
#include <Eigen/LU>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <optional>

#include "drainage/dv_views.hpp"
#include "renderer/core/hachures.hpp"
#include "renderer/core/lod.hpp"
#include "renderer/core/stroke_visibility.hpp"
#include "renderer/core/vector_file.hpp"
#include "renderer/core/vector_lines.hpp"
#include "terrain/hillshade.hpp"
#include "terrain/mesh_io.hpp"
#include "terrain/mesh_pyramid.hpp"

namespace renderer {

SceneCreases frame_creases(const Scene& scene, const FrameResult& res) {
  if (!scene.creases)
    throw terrain::Error("internal: a frame's creases asked of a scene without them");
  if (res.crease_level == 0) return {*scene.creases, scene.traits, scene.chains};
  const std::size_t l = std::size_t(res.crease_level - 1);
  if (!scene.crease_levels || l >= scene.crease_levels->size())
    throw terrain::Error("internal: a frame drawn at a crease level the scene does not hold");
  return {(*scene.crease_levels)[l].geometry, scene.crease_level_traits[l],
          (*scene.crease_levels)[l].chains};
}

std::vector<float> frame_opacity(const Scene& scene, const TerrainRenderer& r,
                                 const FrameResult& res, const FrameParams& fp,
                                 const Style& style) {
  const CreaseScoreParams score =
      resolve_distances(fp.score, r.box().lo, r.box().hi, res.view.viewpoint());
  const double fade = style.antialias ? style.crease_fade : 0.0;
  return segment_opacity(frame_creases(scene, res).geometry, res.view.viewpoint(),
                         terrain::light_direction(fp.light.azimuth, fp.light.altitude),
                         style.exaggeration, score, fade,
                         stroke_rule(style, page_scale(res.view, r.box())));
}

FrameLines frame_lines(const Scene& scene, const TerrainRenderer& r, const FrameResult& res,
                       const FrameBuffers& buffers, const FrameParams& fp, const Style& style) {
  const double exaggeration = style.exaggeration;
  const SceneCreases c = frame_creases(scene, res);
  const CreaseGeometry& g = c.geometry;
  FrameLines lines{frame_opacity(scene, r, res, fp, style), {}};
  const double lift = crease_lift(style, scene.mesh);
  if (style.antialias) {
    lines.pixels = shown_pixels(stroke_visibility(g, c.chains, lines.drawn, res.view, exaggeration,
                                                  lift, buffers.toward_depth,
                                                  stroke_visibility_rule(style, scene.mesh)));
    return lines;
  }
  lines.pixels = segment_pixels(g, res.view, exaggeration);
  const auto visible =
      visible_fraction(g, res.view, exaggeration, lift, buffers.toward_depth, false);
  for (std::size_t s = 0; s < visible.size(); ++s) lines.pixels[s] *= visible[s];
  return lines;
}

FrameLines fine_lines(const Scene& scene, const FrameResult& res, FrameLines lines) {
  if (res.crease_level == 0) return lines;
  const CreaseLevel& l = scene.crease_levels->at(std::size_t(res.crease_level - 1));
  const std::vector<double> metres = segment_metres(*scene.creases);
  FrameLines fine{std::vector<float>(metres.size(), 0.0f), std::vector<double>(metres.size(), 0.0)};
  std::vector<std::uint32_t> run;  // the fine segments merged segment s replaces
  for (std::size_t s = 0; s < l.first.size(); ++s) {
    run.assign(1, l.first[s]);
    while (run.back() != l.last[s]) run.push_back(scene.chains.next[run.back()]);
    double length = 0;
    for (const std::uint32_t t : run) length += metres[t];
    for (const std::uint32_t t : run) {
      fine.drawn[t] = lines.drawn[s];
      fine.pixels[t] = length > 0 ? lines.pixels[s] * metres[t] / length : 0.0;
    }
  }
  return fine;
}

VectorArt frame_vector_art(const Scene& scene, const TerrainRenderer& r, const FrameResult& res,
                           const FrameBuffers& buffers, const FrameParams& fp, const Style& style,
                           const Layers& layers, VectorUnderlay underlay) {
  VectorArt art;
  art.width = res.width;
  art.height = res.height;
  art.underlay = underlay;
  art.background = style.background;
  art.mask_colour = style.mask;
  const std::size_t n = std::size_t(res.width) * std::size_t(res.height);
  art.surface.resize(n);
  const bool reversed = res.view.reversed_z;
  for (std::size_t i = 0; i < n; ++i)
    art.surface[i] = far_depth(reversed, buffers.toward_depth[i]) < 1.0;
  if (underlay == VectorUnderlay::Shaded) art.shaded = buffers.surface_rgba;
  const double e = style.exaggeration, lift = crease_lift(style, scene.mesh);
  if (layers.pels) {
    std::vector<SceneSegment> segs;
    for (const auto& p : r.read_pels())
      segs.push_back({Eigen::Vector3d(p.a.x(), p.a.y(), p.a.z() * e),
                      Eigen::Vector3d(p.b.x(), p.b.y(), p.b.z() * e),
                      style.antialias ? p.opacity : 1.0f});
    VectorLayer l{"pels", style.pel_colour, LineCap::Round, {}, 0};
    l.paths = segment_paths(segs, res.view, lift, buffers.toward_depth, style.antialias,
                            float(style.pel_width), &l.strokes);
    art.layers.push_back(std::move(l));
  }
  if (layers.creases && scene.creases) {
    const SceneCreases c = frame_creases(scene, res);
    const std::vector<float> drawn = frame_opacity(scene, r, res, fp, style);
    std::vector<SegmentSamples> samples = r.read_crease_samples();
    if (samples.empty())  // pixel-exact lines: the CPU reference of the anti-aliased test
      samples = stroke_visibility(c.geometry, c.chains, drawn, res.view, e, lift,
                                  buffers.toward_depth, stroke_visibility_rule(style, scene.mesh));
    VectorLayer l{"creases", style.crease_colour,       LineCap::Round, {},
                  0,         {"flow_share", "strahler"}};
    l.paths = crease_paths(c.geometry, drawn, samples, res.view, e, style.crease_width,
                           style.crease_width_max, &l.strokes);
    art.layers.push_back(std::move(l));
  }
  if (layers.edges) {
    std::vector<SceneSegment> segs;
    const auto& pos = scene.mesh.positions;
    auto at = [&](std::uint32_t v) {
      return Eigen::Vector3d(pos[v].x(), pos[v].y(), double(pos[v].z()) * e);
    };
    for (const auto& d : r.read_edges().drawn) segs.push_back({at(d[0]), at(d[1]), 1.0f});
    VectorLayer l{"edges",
                  style.edge_colour,
                  style.edge_caps == EdgeCaps::None ? LineCap::Butt : LineCap::Square,
                  {},
                  0};
    l.paths = segment_paths(segs, res.view, lift, buffers.toward_depth, false,
                            float(style.edge_width), &l.strokes);
    art.layers.push_back(std::move(l));
  }
  if (layers.silhouettes) art.layers.push_back(silhouette_layer(res, buffers, style));
  return art;
}

VectorLayer silhouette_layer(const FrameResult& res, const FrameBuffers& buffers,
                             const Style& style) {
  // The composite's band: TR_SILHOUETTE_BAND px wider than the silhouette width when anti-aliased.
  const float width =
      float(style.silhouette_width) + (style.antialias ? float(TR_SILHOUETTE_BAND) : 0.0f);
  VectorLayer l{"silhouettes", style.silhouette_colour, LineCap::Round, {}, 0};
  std::vector<float> hidden;
  if (style.antialias && style.silhouette_depth_width > 0) {
    // The distances the hidden share reads: about the silhouette pixels (0 elsewhere, unread).
    const int w = res.width, h = res.height, reach = kHiddenReach;
    std::vector<float> distance(buffers.toward_depth.size(), 0.0f);
    std::vector<std::uint8_t> mask(buffers.silhouette_opacity.size());
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const std::size_t i = std::size_t(y) * std::size_t(w) + std::size_t(x);
        if (!(mask[i] = buffers.silhouette_opacity[i] > 0)) continue;
        for (int yy = std::max(0, y - reach); yy <= std::min(h - 1, y + reach); ++yy)
          for (int xx = std::max(0, x - reach); xx <= std::min(w - 1, x + reach); ++xx) {
            const std::size_t j = std::size_t(yy) * std::size_t(w) + std::size_t(xx);
            const double d = buffers.toward_depth[j];
            if (distance[j] == 0.0f)
              distance[j] = far_depth(res.view.reversed_z, d) >= 1.0
                                ? std::numeric_limits<float>::infinity()
                                : float(res.view.depth_distance(d));
          }
      }
    hidden = silhouette_hidden_share(mask, distance, w, h);
  }
  l.paths =
      silhouette_paths(buffers.silhouette_opacity, res.width, res.height, width, &l.strokes,
                       hidden.empty() ? nullptr : &hidden, float(style.silhouette_depth_width));
  return l;
}

namespace {

// Ground that dem2mesh --fill-nodata invented (GridMesh::filled) gets no hachures, as it
// gets no drainage: its pixels count as no terrain. Nothing to do where every vertex is
// drained (no no-data under the mesh, or only voids it filled).
void leave_out_filled(HachureField& field, const terrain::GridMesh& mesh, const View& view,
                      const std::vector<float>& toward_depth) {
  if (std::all_of(mesh.filled.begin(), mesh.filled.end(), terrain::drained)) return;
  const auto& t = mesh.topo;
  const Eigen::Matrix4d inverse = view.view_projection().inverse();
  for (int v = 0; v < field.height; ++v)
    for (int u = 0; u < field.width; ++u) {
      const std::size_t i = std::size_t(v) * std::size_t(field.width) + std::size_t(u);
      if (std::isnan(field.slope[i])) continue;
      const Eigen::Vector3d p = unproject(view, inverse, u, v, toward_depth[i]);
      const long c = std::clamp(long(std::floor(p.x() / mesh.geo.dx)), 0L, long(t.cols) - 2);
      const long r = std::clamp(long(std::floor(-p.y() / mesh.geo.dy)), 0L, long(t.rows) - 2);
      const std::size_t k = std::size_t(r) * t.cols + std::size_t(c);
      if (!terrain::drained(mesh.filled[k]) || !terrain::drained(mesh.filled[k + 1]) ||
          !terrain::drained(mesh.filled[k + t.cols]) ||
          !terrain::drained(mesh.filled[k + t.cols + 1]))
        field.slope[i] = std::numeric_limits<float>::quiet_NaN();
    }
}

// Pixels within `r` of one without terrain lose their terrain (slope NaN): a hachure, as
// wide as its pen, ends before the terrain's outline rather than over the background.
void keep_off_the_outline(HachureField& field, int r) {
  const std::size_t w = std::size_t(field.width), h = std::size_t(field.height);
  if (w == 0 || h == 0) return;
  std::vector<std::uint8_t> off(w * h), row(w * h);
  for (int pass = 0; pass < r; ++pass) {
    // Each pass: the pixels with a pixel off the terrain (or off the image) in their 3 x 3
    // window, by a dilation of the off-terrain pixels along the rows, then the columns.
    for (std::size_t i = 0; i < off.size(); ++i) off[i] = std::isnan(field.slope[i]);
    for (std::size_t v = 0; v < h; ++v)
      for (std::size_t u = 0; u < w; ++u) {
        const std::size_t i = v * w + u;
        row[i] = u == 0 || u + 1 == w || off[i - 1] || off[i] || off[i + 1];
      }
    for (std::size_t v = 0; v < h; ++v)
      for (std::size_t u = 0; u < w; ++u) {
        const std::size_t i = v * w + u;
        if (v == 0 || v + 1 == h || row[i - w] || row[i] || row[i + w])
          field.slope[i] = std::numeric_limits<float>::quiet_NaN();
      }
  }
}

}  // namespace

TracedHachures trace_frame_hachures(const Scene& scene, const TerrainRenderer& r,
                                    const FrameResult& res, const FrameBuffers& buffers,
                                    const Style& style,
                                    const std::vector<const VectorLayer*>& over) {
  HachureField field = r.hachure_field(res.view, style.hachure_light_tone);  // on the GPU
  leave_out_filled(field, scene.mesh, res.view, buffers.toward_depth);
  // The widest hachure is 1.5 times the width (hachure_paths: by its tone); its cap reaches
  // half that past its end.
  keep_off_the_outline(field, int(std::ceil(0.75 * style.hachure_width)));
  field.blocked.assign(field.slope.size(), 0);
  for (std::size_t i = 0; i < field.blocked.size(); ++i)
    field.blocked[i] = (i < buffers.crease.size() && buffers.crease[i]) ||
                       (i < buffers.silhouette.size() && buffers.silhouette[i]);
  std::vector<std::uint8_t> ink;  // the pixels of the lines drawn over it (ridges, silhouettes)
  for (const VectorLayer* l : over)
    if (l && !l->paths.empty()) {
      if (ink.empty()) ink.assign(4 * field.blocked.size(), 0);
      draw_on_rgba(*l, field.width, field.height, ink);
    }
  if (!ink.empty())
    for (std::size_t i = 0; i < field.blocked.size(); ++i) field.blocked[i] |= ink[4 * i + 3] > 0;
  HachureRule rule;
  rule.spacing = style.hachure_spacing;
  rule.min_slope = std::max(rule.min_slope,
                            style.hachure_min_slope_percent / 100 * slope_percentile(field, 0.99));
  stretch_tone(field, rule.min_slope);
  const double scale = page_scale(res.view, r.box());
  if (style.hachure_rows)  // form lines at an interval from the page's scale (true metres)
    rule.row_interval = row_interval_for(
        scale / style.exaggeration, rule.spacing,
        std::atan(std::tan(median_slope(field, rule.min_slope)) / style.exaggeration));
  // Seeds that move with the ground first (frame-to-frame coherence): cells of about two
  // spacings at the page's scale, the size a power of two metres, so that it stays the same
  // while the camera moves a little (cells of 1/2, 1, 2 and 4 spacings: the flight's
  // coherence over its first 20 frames 0.55, 0.61, 0.63, 0.64; docs/terrain-render.md).
  const double cell = std::exp2(std::round(std::log2(std::max(1e-3, 2.0 * scale * rule.spacing))));
  const std::vector<Eigen::Vector2f> seeds =
      surface_seeds(res.view, buffers.toward_depth, rule.spacing, cell,
                    MeshHolding(scene.mesh, scene.levels.get()).window_origin());
  std::vector<Hachure> hachures = trace_hachures(field, rule, seeds);
  return {std::move(field), rule, std::move(hachures)};
}

VectorLayer ridge_layer(const Scene& scene, const TerrainRenderer& r, const FrameResult& res,
                        const FrameBuffers& buffers, const Style& style) {
  VectorLayer l{"ridges", style.ridge_colour, LineCap::Round, {}, 0};
  const double e = style.exaggeration;
  const double scale = std::max(page_scale(res.view, r.box()), 1e-9);
  const double min_area = style.ridge_min_area * std::sqrt(scale / 10.0);
  const double min_relief =
      style.ridge_min_relief * (r.box().hi.z() - r.box().lo.z()) / std::max(e, 1e-9);
  std::vector<SceneSegment> segs;
  for (const std::size_t k : select_ridges(scene.ridges, scale, min_area, min_relief)) {
    const SceneRidge& ridge = scene.ridges[k];
    for (std::size_t j = 0; j + 1 < ridge.points.size(); ++j) {
      const Eigen::Vector3f a = ridge.points[j], b = ridge.points[j + 1];
      segs.push_back({Eigen::Vector3d(a.x(), a.y(), double(a.z()) * e),
                      Eigen::Vector3d(b.x(), b.y(), double(b.z()) * e), 1.0f});
    }
  }
  l.paths = segment_paths(segs, res.view, crease_lift(style, scene.mesh), buffers.toward_depth,
                          style.antialias, float(style.ridge_width), &l.strokes);
  return l;
}

namespace {
// FrameOverlays::outline.
VectorLayer outline_layer(const Scene& scene, const FrameResult& res, const FrameBuffers& buffers,
                          const Style& style) {
  VectorLayer l{"outline", style.silhouette_colour, LineCap::Round, {}, 0};
  const terrain::GridMesh& m = scene.mesh;
  const double e = style.exaggeration;
  const auto at = [&](std::uint32_t v) {
    const Eigen::Vector3f& p = m.positions[v];
    return Eigen::Vector3d(p.x(), p.y(), double(p.z()) * e);
  };
  std::vector<SceneSegment> segs;
  for (const auto& [a, b] : m.outline_edges()) segs.push_back({at(a), at(b), 1.0f});
  l.paths = segment_paths(segs, res.view, crease_lift(style, m), buffers.toward_depth,
                          style.antialias, 1.5f * float(style.silhouette_width), &l.strokes);
  return l;
}

// Whether a frame draws heavier silhouettes over its picture (Style::silhouette_depth_width).
bool heavier_silhouettes(const Layers& layers, const Style& style) {
  return layers.silhouettes && style.antialias && style.silhouette_depth_width > 0;
}
}  // namespace

bool draws_overlays(const Scene& scene, const Layers& layers, const Style& style) {
  return layers.hachures || (layers.ridges && !scene.ridges.empty()) ||
         heavier_silhouettes(layers, style) || (layers.silhouettes && scene.mesh.has_holes());
}

FrameOverlays frame_overlays(const Scene& scene, const TerrainRenderer& r, const FrameResult& res,
                             const FrameBuffers& buffers, const Style& style,
                             const Layers& layers) {
  FrameOverlays o;
  if (layers.ridges && !scene.ridges.empty()) o.ridges = ridge_layer(scene, r, res, buffers, style);
  if (heavier_silhouettes(
          layers, style)) {  // the lines wider than the composite's band, drawn again over it
    VectorLayer l = silhouette_layer(res, buffers, style);
    const float band = float(style.silhouette_width) + float(TR_SILHOUETTE_BAND);
    std::erase_if(l.paths, [&](const VectorPath& p) { return p.width < band + 0.2f; });
    if (!l.paths.empty()) o.silhouettes = std::move(l);
  }
  if (layers.silhouettes && scene.mesh.has_holes())
    o.outline = outline_layer(scene, res, buffers, style);
  if (layers.hachures) {
    o.traced = trace_frame_hachures(
        scene, r, res, buffers, style,
        {o.ridges ? &*o.ridges : nullptr, o.silhouettes ? &*o.silhouettes : nullptr,
         o.outline ? &*o.outline : nullptr});
    o.hachures = hachure_paths(o.traced->hachures, style);
  }
  return o;
}

void draw_overlays(const FrameOverlays& o, int width, int height, std::vector<std::uint8_t>& rgba) {
  if (o.hachures) draw_on_rgba(*o.hachures, width, height, rgba);
  if (o.silhouettes) draw_on_rgba(*o.silhouettes, width, height, rgba);
  if (o.ridges) draw_on_rgba(*o.ridges, width, height, rgba);
  if (o.outline) draw_on_rgba(*o.outline, width, height, rgba);
}

FrameStats frame_line_stats(const Scene& scene, const TerrainRenderer& r, const FrameResult& res,
                            const FrameParams& fp, const Style& style, const Layers& layers,
                            const TracedHachures* traced,
                            const std::vector<Eigen::Vector3f>* previous_hachures) {
  const FrameBuffers buffers = r.read_buffers();
  FrameStats st;
  st.lines = frame_lines(scene, r, res, buffers, fp, style);
  const SceneCreases c = frame_creases(scene, res);
  st.creases = line_stats(c.geometry, c.traits, st.lines.drawn, st.lines.pixels);
  st.creases.connected = connected_share(c.geometry, c.traits, st.lines.drawn,
                                         segment_pixels(c.geometry, res.view, style.exaggeration));
  if (layers.silhouettes)
    st.silhouettes = silhouette_stats(buffers.silhouette_opacity, res.width, res.height);
  if (layers.hachures) {  // as write_frame_files traced them, or traced here (deterministic)
    std::optional<TracedHachures> own;
    if (!traced) own = trace_frame_hachures(scene, r, res, buffers, style);
    const TracedHachures& t = traced ? *traced : *own;
    st.hachures = hachure_stats(t.field, t.hachures, t.rule);
    const Eigen::Matrix4d inverse = res.view.view_projection().inverse();
    for (const Hachure& h : t.hachures)
      for (const Eigen::Vector2f& p : h.points)
        if (const auto s = surface_point(res.view, inverse, buffers.toward_depth, p.x(), p.y()))
          st.hachures->surface.push_back(s->cast<float>());
    if (previous_hachures)
      st.hachure_coherence =
          hachure_coherence(*previous_hachures, res.view, buffers.toward_depth, st.hachures->ink);
  }
  return st;
}

std::string line_stats_text(const FrameStats& s) {
  const LineStats& st = s.creases;
  std::string out = fmt::format(
      "crease length px: {:.0f}\ncrease boundary share: {:.4f}\ncrease flat share: {:.4f}\n"
      "crease valley share: {:.4f}\ncrease connected share: {:.4f}\ncrease strokes: {}\n"
      "crease mean stroke px: {:.1f}\ncrease strokes, opacity-weighted: {:.1f}\n"
      "crease mean stroke px, opacity-weighted: {:.1f}\n",
      st.length_px, st.boundary, st.flat, st.valley, st.connected, st.strokes, st.mean_stroke_px,
      st.weighted_strokes, st.weighted_mean_stroke_px);
  if (s.silhouettes)
    out += fmt::format(
        "silhouette px: {:.0f}\nsilhouette pieces: {}\nsilhouette mean piece px: {:.1f}\n",
        s.silhouettes->pixels, s.silhouettes->pieces, s.silhouettes->mean_piece_px);
  if (s.hachures)
    out += fmt::format(
        "hachures: {}\nhachure length px: {:.0f}\nhachure along share: {:.4f}\n"
        "hachure spacing share: {:.4f}\nhachure too close share: {:.4f}\nhachure too far share: "
        "{:.4f}\n",
        s.hachures->hachures, s.hachures->length_px, s.hachures->along_share,
        s.hachures->spacing_share, s.hachures->close_share, s.hachures->far_share);
  return out;
}

std::string line_stats_csv_header() {
  return "frame,length_px,boundary_share,flat_share,valley_share,strokes,mean_stroke_px,silhouette_"
         "px,"
         "silhouette_pieces,weighted_strokes,weighted_mean_stroke_px,connected_share,hachures,"
         "hachure_length_px,"
         "hachure_along_share,hachure_spacing_share\n";
}

std::string line_stats_csv_row(std::size_t i, const FrameStats& s) {
  const LineStats& c = s.creases;
  const SilhouetteStats ss = s.silhouettes.value_or(SilhouetteStats{});
  const HachureStats hs = s.hachures ? *s.hachures : HachureStats{};
  return fmt::format(
      "{},{:.1f},{:.5f},{:.5f},{:.5f},{},{:.2f},{:.0f},{},{:.2f},{:.2f},{:.5f},{},{:.0f},{:.5f},{:."
      "5f}\n",
      i, c.length_px, c.boundary, c.flat, c.valley, c.strokes, c.mean_stroke_px, ss.pixels,
      ss.pieces, c.weighted_strokes, c.weighted_mean_stroke_px, c.connected, hs.hachures,
      hs.length_px, hs.along_share, hs.spacing_share);
}

}  // namespace renderer
