#include "renderer/core/plan_map.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include <fmt/format.h>
#include <ogrsf_frmts.h>

#include "renderer/core/ridges.hpp"
#include "renderer/core/vector_file.hpp"
#include "renderer/core/vector_lines.hpp"
#include "terrain/gpkg.hpp"
#include "terrain/hillshade.hpp"
#include "terrain/memory.hpp"

namespace renderer {

namespace {
// A GeoPackage's lines are simplified within this many map pixels (Douglas-Peucker).
constexpr double kSimplifyPixels = 0.5;
}  // namespace

double default_plan_scale(const terrain::GridMesh& mesh) {
  const double w = double(mesh.topo.cols - 1) * mesh.geo.dx,
               h = double(mesh.topo.rows - 1) * mesh.geo.dy;
  const double raw = std::max(w, h) / 2048.0, decade = std::pow(10.0, std::floor(std::log10(raw)));
  for (const double m : {1.0, 2.0, 2.5, 5.0})
    if (m * decade >= raw * (1 - 1e-9)) return m * decade;
  return 10.0 * decade;
}

void check_plan_memory(const PlanView& p) {
  // The field (its fall line, slope, tone and height: 20 bytes), the occupancy grid, the
  // tracer's points and a vector file's raster: 28 bytes a pixel were measured at 145 M
  // pixels (4.1 GB).
  constexpr double kBytesPerPixel = 32;
  const double pixels = double(p.width) * double(p.height), available = terrain::available_memory();
  if (!(available > 0) || pixels * kBytesPerPixel <= available) return;
  const double fits =
      p.scale * std::sqrt(pixels * kBytesPerPixel / available);  // the scale whose map fits
  const double step = std::pow(10.0, std::floor(std::log10(fits)) - 1);
  terrain::check_memory(
      pixels * kBytesPerPixel,
      fmt::format("a map of {} x {} pixels at {:g} m a pixel", p.width, p.height, p.scale),
      fmt::format("give --scale {:g} or coarser", std::ceil(fits / step) * step));
}

namespace {

// The data's outline on the map: the edges between a face drawn and one outside the data,
// chained into lines (chain_segments: ends and meeting points end a line, a ring closes and
// repeats its first point here).
static std::vector<std::vector<Eigen::Vector2f>> plan_outline(const terrain::GridMesh& mesh,
                                                              const PlanView& plan) {
  std::vector<std::vector<Eigen::Vector2f>> out;
  if (!mesh.has_holes()) return out;
  auto at = [&](std::uint32_t v) {
    const Eigen::Vector3f& p = mesh.positions[v];
    return Eigen::Vector2f(float((double(p.x()) - plan.x0) / plan.scale),
                           float((plan.y0 - double(p.y())) / plan.scale));
  };
  std::vector<std::array<Eigen::Vector2f, 2>> segments;
  for (const auto& [a, b] : mesh.outline_edges()) segments.push_back({at(a), at(b)});
  for (Polyline& line : chain_segments(segments)) {
    if (line.closed) line.points.push_back(line.points.front());
    out.push_back(std::move(line.points));
  }
  return out;
}

// The map's outline (PlanHachures::outline) as the features of the GeoPackage's `layer`.
static void add_outline(terrain::Gpkg& gpkg, OGRLayer* layer, const terrain::GridMesh& mesh,
                        const PlanHachures& h) {
  for (const auto& points : h.outline) {
    OGRLineString line;
    double length = 0;
    for (std::size_t k = 0; k < points.size(); ++k) {
      const Eigen::Vector2d q = plan_to_local(h.plan, points[k]);
      line.addPoint(mesh.geo.origin_x + q.x(), mesh.geo.origin_y + q.y());
      if (k) length += double((points[k] - points[k - 1]).norm()) * h.plan.scale;
    }
    OGRFeature f(layer->GetLayerDefn());
    f.SetField("length_m", length);
    f.SetGeometry(&line);
    gpkg.add(layer, f);
  }
}

// The ridges a map of `plan` draws (select_ridges at its scale), in its pixels.
std::vector<PlanRidge> plan_ridges(const terrain::GridMesh& mesh, const PlanView& plan,
                                   const std::vector<SceneRidge>& ridges,
                                   const PlanHachureOptions& o) {
  float lo = std::numeric_limits<float>::max(), hi = std::numeric_limits<float>::lowest();
  for (const Eigen::Vector3f& p : mesh.positions)
    lo = std::min(lo, p.z()), hi = std::max(hi, p.z());
  const double min_area = o.ridge_min_area * std::sqrt(plan.scale / 10.0);
  std::vector<PlanRidge> out;
  for (const std::size_t k :
       select_ridges(ridges, plan.scale, min_area, o.ridge_min_relief * double(hi - lo))) {
    PlanRidge r{{}, ridges[k].basin_area, ridges[k].relief};
    for (const Eigen::Vector3f& p : ridges[k].points)
      r.points.emplace_back(float((double(p.x()) - plan.x0) / plan.scale),
                            float((plan.y0 - double(p.y())) / plan.scale));
    out.push_back(std::move(r));
  }
  return out;
}

VectorLayer ridge_paths(const std::vector<PlanRidge>& ridges, double width) {
  VectorLayer l{"ridges", Style{}.ridge_colour, LineCap::Round, {}, ridges.size()};
  for (const PlanRidge& r : ridges) l.paths.push_back({{r.points, false}, float(width), 1.0f, {}});
  return l;
}

}  // namespace

PlanHachures plan_hachures(const terrain::GridMesh& mesh, const PlanHachureOptions& o,
                           const std::vector<SceneRidge>& ridges) {
  PlanHachures out;
  out.plan = plan_view(mesh, o.scale > 0 ? o.scale : default_plan_scale(mesh));
  check_plan_memory(out.plan);
  const Eigen::Vector3d light = terrain::light_direction(o.light_azimuth, o.light_altitude);
  HachureField field = plan_hachure_field(mesh, out.plan, o.light_tone ? &light : nullptr);
  out.ridges = plan_ridges(mesh, out.plan, ridges, o);
  out.outline = plan_outline(mesh, out.plan);
  if (!out.ridges.empty()) {  // the hachures stop at the ridge lines' pixels, as drawn
    std::vector<std::uint8_t> ink(4 * field.slope.size(), 0);
    draw_on_rgba(ridge_paths(out.ridges, o.ridge_width), field.width, field.height, ink);
    field.blocked.assign(field.slope.size(), 0);
    for (std::size_t i = 0; i < field.blocked.size(); ++i) field.blocked[i] = ink[4 * i + 3] > 0;
  }
  HachureRule rule;
  rule.spacing = o.spacing;
  rule.min_slope = std::max(rule.min_slope, o.min_slope_share * slope_percentile(field, 0.99));
  out.min_slope = rule.min_slope;
  stretch_tone(field, rule.min_slope);
  if (o.rows)
    rule.row_interval =
        row_interval_for(out.plan.scale, o.spacing, median_slope(field, rule.min_slope));
  out.row_interval = rule.row_interval;
  out.hachures = trace_hachures(field, rule);
  return out;
}

std::array<double, 6> plan_geotransform(const terrain::GridMesh& mesh, const PlanView& p) {
  return {mesh.geo.origin_x + p.x0, p.scale, 0.0, mesh.geo.origin_y + p.y0, 0.0, -p.scale};
}

std::string geotransform_text(const std::array<double, 6>& gt) {
  return fmt::format("{:.3f} {:g} 0 {:.3f} 0 {:g}", gt[0], gt[1], gt[3], gt[5]);
}

std::string map_note(const std::array<double, 6>& gt, int epsg) {
  return fmt::format("north up, {:g} m a pixel; geotransform {}{}", gt[1], geotransform_text(gt),
                     epsg ? fmt::format("; EPSG:{}", epsg) : "");
}

std::string world_file(const std::array<double, 6>& gt) {
  return fmt::format("{:.10g}\n{:.10g}\n{:.10g}\n{:.10g}\n{:.10g}\n{:.10g}\n", gt[1], gt[4], gt[2],
                     gt[5], gt[0] + 0.5 * gt[1] + 0.5 * gt[2], gt[3] + 0.5 * gt[4] + 0.5 * gt[5]);
}

namespace {

// The map's ridge lines into layer `rl` (fields basin_m2, relief_m, length_m).
void add_ridges(terrain::Gpkg& gpkg, OGRLayer* rl, const terrain::GridMesh& mesh,
                const PlanHachures& h) {
  for (const PlanRidge& r : h.ridges) {
    OGRLineString line;
    double length = 0;
    for (std::size_t k = 0; k < r.points.size(); ++k) {
      const Eigen::Vector2d q = plan_to_local(h.plan, r.points[k]);
      line.addPoint(mesh.geo.origin_x + q.x(), mesh.geo.origin_y + q.y());
      if (k) length += double((r.points[k] - r.points[k - 1]).norm()) * h.plan.scale;
    }
    OGRFeature f(rl->GetLayerDefn());
    f.SetField("basin_m2", r.basin_area);
    f.SetField("relief_m", r.relief);
    f.SetField("length_m", length);
    f.SetGeometry(&line);
    gpkg.add(rl, f);
  }
}

}  // namespace

std::size_t write_hachures_gpkg(const terrain::GridMesh& mesh, const PlanHachures& h,
                                const std::string& path) {
  terrain::Gpkg gpkg(path, mesh.geo.crs_wkt);
  OGRLayer* layer = gpkg.layer(
      "hachures", wkbLineString,
      {{"slope_deg", OFTReal}, {"tone", OFTReal}, {"length_m", OFTReal}, {"row_m", OFTReal}},
      {"0,0,0,255", 0.15, "0.08 + 0.25 * \"tone\"",
       "Hachures: width by tone (darker where steeper or in shadow)"});
  OGRLayer* rl =
      h.ridges.empty()
          ? nullptr
          : gpkg.layer("ridges", wkbLineString,
                       {{"basin_m2", OFTReal}, {"relief_m", OFTReal}, {"length_m", OFTReal}},
                       {"60,40,20,255", 0.45, "", "Ridge lines: the crests between basins"});
  OGRLayer* ol =
      h.outline.empty()
          ? nullptr
          : gpkg.layer("outline", wkbLineString, {{"length_m", OFTReal}},
                       {"0,0,0,255", 0.4, "", "The data's outline: where the DEM has data"});
  gpkg.begin();
  for (const Hachure& hh : h.hachures) {
    OGRLineString traced;
    double slope = 0, tone = 0, length = 0;
    for (std::size_t k = 0; k < hh.points.size(); ++k) {
      const Eigen::Vector2d q = plan_to_local(h.plan, hh.points[k]);
      traced.addPoint(mesh.geo.origin_x + q.x(), mesh.geo.origin_y + q.y());
      slope += hh.slope[k], tone += hh.tone[k];
      if (k) length += double((hh.points[k] - hh.points[k - 1]).norm()) * h.plan.scale;
    }
    // Simplified to the map's pixel: the tracer's half-pixel steps are 4 vertices a pixel.
    std::unique_ptr<OGRGeometry> simple(traced.Simplify(kSimplifyPixels * h.plan.scale));
    const OGRGeometry& line =
        simple && !simple->IsEmpty() ? *simple : static_cast<const OGRGeometry&>(traced);
    const double n = double(std::max<std::size_t>(hh.points.size(), 1));
    OGRFeature f(layer->GetLayerDefn());
    f.SetField("slope_deg", slope / n * 180.0 / M_PI);
    f.SetField("tone", tone / n);
    f.SetField("length_m", length);
    if (h.row_interval > 0) f.SetField("row_m", double(hh.row + 1) * h.row_interval);
    f.SetGeometry(&line);  // copied
    gpkg.add(layer, f);
  }
  if (rl) add_ridges(gpkg, rl, mesh, h);
  if (ol) add_outline(gpkg, ol, mesh, h);
  gpkg.commit();
  return h.hachures.size();
}

VectorArt plan_vector_art(const PlanHachures& h, const PlanHachureOptions& o) {
  VectorArt art;
  art.width = h.plan.width, art.height = h.plan.height;
  art.underlay = VectorUnderlay::None;
  Style style;
  style.hachure_width = o.width;
  art.layers.push_back(hachure_paths(h.hachures, style));
  if (!h.ridges.empty()) art.layers.push_back(ridge_paths(h.ridges, o.ridge_width));
  if (!h.outline.empty()) {
    VectorLayer l{"outline", Style{}.silhouette_colour, LineCap::Round, {}, h.outline.size()};
    for (const auto& line : h.outline) l.paths.push_back({{line, false}, float(o.width), 1.0f, {}});
    art.layers.push_back(std::move(l));
  }
  return art;
}

}  // namespace renderer
