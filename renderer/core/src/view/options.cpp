#include "renderer/core/options.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <map>

#include "renderer/core/frames.hpp"
#include "terrain/error.hpp"

namespace renderer {

namespace {

std::string text_of(double v) {
  return fmt::format("{}", v);
}  // shortest text that reads back exactly

std::string colour_text(const Eigen::Vector3f& c) {
  return fmt::format("{},{},{}", double(c.x()) * 255.0, double(c.y()) * 255.0,
                     double(c.z()) * 255.0);
}

std::string join(const std::vector<std::string>& v) {
  std::string out;
  for (const auto& s : v) out += (out.empty() ? "" : ",") + s;
  return out;
}

// Table rows. `ref` is a generic lambda returning a reference to the field in a (const or
// not) RenderSettings.
template <class Ref>
OptionSpec number(std::string name, std::string group, double min, double max, std::string unit,
                  std::string def, std::string help, Ref ref, bool per_frame = false) {
  OptionSpec o{std::move(name),
               std::move(group),
               OptionType::Number,
               min,
               max,
               std::move(unit),
               {},
               std::move(def),
               std::move(help),
               per_frame,
               {},
               {},
               {},
               {},
               false};
  o.get = [ref](const RenderSettings& s) { return text_of(double(ref(s))); };
  o.store = [ref](RenderSettings& s, const std::string& t) {
    double v = 0;
    parse_number(t, v);
    ref(s) = static_cast<std::remove_reference_t<decltype(ref(s))>>(v);
  };
  return o;
}

template <class Ref>
OptionSpec integer(std::string name, std::string group, double min, double max, std::string unit,
                   std::string def, std::string help, Ref ref) {
  OptionSpec o = number(std::move(name), std::move(group), min, max, std::move(unit),
                        std::move(def), std::move(help), ref);
  o.type = OptionType::Integer;
  return o;
}

OptionSpec flag(std::string name, std::string group, std::string help,
                std::function<bool(const RenderSettings&)> get,
                std::function<void(RenderSettings&, bool)> set) {
  OptionSpec o{std::move(name),
               std::move(group),
               OptionType::Bool,
               0,
               0,
               "",
               {},
               "false",
               std::move(help),
               false,
               {},
               {},
               {},
               {},
               false};
  o.get = [get](const RenderSettings& s) { return std::string(get(s) ? "true" : "false"); };
  o.store = [set](RenderSettings& s, const std::string& t) { set(s, t == "true"); };
  return o;
}

OptionSpec choice(std::string name, std::string group, OptionType type,
                  std::vector<std::string> choices, std::string def, std::string help,
                  std::function<std::string(const RenderSettings&)> get,
                  std::function<void(RenderSettings&, const std::string&)> store) {
  return {std::move(name),
          std::move(group),
          type,
          0,
          0,
          "",
          std::move(choices),
          std::move(def),
          std::move(help),
          false,
          std::move(get),
          std::move(store),
          {},
          {},
          false};
}

template <class Ref>
OptionSpec colour(std::string name, std::string group, std::string def, std::string help, Ref ref) {
  return choice(
      std::move(name), std::move(group), OptionType::Colour, {}, std::move(def), std::move(help),
      [ref](const RenderSettings& s) { return colour_text(ref(s)); },
      [ref](RenderSettings& s, const std::string& t) { ref(s) = parse_colour(t); });
}

std::vector<std::string> layer_names() {
  std::vector<std::string> v;
  for (const LayerName& n : kLayerNames) v.push_back(n.name);
  return v;
}

std::string edges_text(std::uint8_t kinds) {
  std::vector<std::string> v;
  if (kinds & 1) v.push_back("contour");
  if (kinds & 2) v.push_back("boundary");
  if (kinds & 4) v.push_back("crease");
  return join(v);
}

// The table's groups: the --help sections and the viewer's panel headers, in order.
struct GroupNames {
  std::string frame = "Frame", camera = "Camera and light", score = "Crease score",
              rules = "Crease network", strokes = "Crease strokes", sil = "Silhouettes",
              pel = "PELs", edges = "Edges", colours = "Colours", surface = "Surface",
              hachure = "Hachures and ridges";
};

// The options of the frame: size, line scale, layers, view.
void add_frame_options(std::vector<OptionSpec>& t, const GroupNames& g) {
  const auto& [frame, camera, score, rules, strokes, sil, pel, edges, colours, surface, hachure] =
      g;
  t.push_back(choice(
      "size", frame, OptionType::Size, {}, "1280x720", "Image size WIDTHxHEIGHT in pixels",
      [](const RenderSettings& s) { return fmt::format("{}x{}", s.width, s.height); },
      [](RenderSettings& s, const std::string& v) {  // checked by set_option: WxH or WXH
        char x = 0;
        std::sscanf(v.c_str(), "%d%c%d", &s.width, &x, &s.height);
      }));
  t.push_back(number(
      "line-scale", frame, 0.1, 20, "", "1",
      "Every line width (creases, silhouettes, PELs, edges) and the crease strokes' pixel lengths "
      "(hidden gap, "
      "peek) times this: 3 keeps a 4961x3508 print (A3 at 300 dpi) looking like a 1280x720 frame",
      [](auto& s) -> auto& { return s.line_scale; }));
  t.push_back(choice(
      "layers", frame, OptionType::List, layer_names(), "mask,creases,silhouettes,hachures,ridges",
      "Layers to draw (comma list): shaded (relief), mask (white surface), creases, silhouettes "
      "(Toward/Away, with the formulated ones) or silhouettes-adjacency, pels (photic extremum "
      "lines; "
      "needs a mesh from denoise-normals), edges (object-space edges of the mesh facets), hachures "
      "(strokes down the slopes, denser where the relief is in shadow), ridges (the crests between "
      "the .dv's basins)",
      [](const RenderSettings& s) { return layers_text(s.layers); },
      [](RenderSettings& s, const std::string& v) { s.layers = parse_layers(v); }));
}

// The options of the camera, the light and the exaggeration.
void add_camera_options(std::vector<OptionSpec>& t, const GroupNames& g) {
  const auto& [frame, camera, score, rules, strokes, sil, pel, edges, colours, surface, hachure] =
      g;
  t.push_back(choice(
      "view", camera, OptionType::Enum, {"auto", "top", "relief"}, "auto",
      "The camera when no --eye and no --view-az is given (frame): auto, the whole terrain filling "
      "the frame, "
      "seen across its main relief, lit from the upper left; top, straight down, north up, "
      "orthographic (a map; --map-scale); relief, the part "
      "of highest relief seen from its open side; FRAMES.csv:ROW, that row of a frames CSV (a "
      "flight's frame "
      "ROW, 0 the first as batch numbers them; its camera, light and per-frame options)",
      [](const RenderSettings& s) {
        return s.view == ViewMode::Row ? s.view_row
                                       : std::string(s.view == ViewMode::Auto  ? "auto"
                                                     : s.view == ViewMode::Top ? "top"
                                                                               : "relief");
      },
      [](RenderSettings& s, const std::string& v) {
        s.view = v == "top"      ? ViewMode::Top
                 : v == "relief" ? ViewMode::Relief
                 : v == "auto"   ? ViewMode::Auto
                                 : ViewMode::Row;
        s.view_row = s.view == ViewMode::Row ? v : std::string();
      }));
  t.back().accepts = is_view_row;  // FRAMES.csv:ROW, read when the frame is drawn
  t.push_back(choice(
      "eye", camera, OptionType::Point, {}, "",
      "Viewpoint E N Z: easting, northing (mesh CRS) and elevation in metres; default (frame): "
      "--view; with "
      "--view-az: the whole terrain framed along that bearing",
      [](const RenderSettings& s) {
        const auto& e = s.frame.camera.eye;
        return e ? fmt::format("{} {} {}", e->x(), e->y(), e->z()) : std::string();
      },
      [](RenderSettings& s, const std::string& v) {
        double x = 0, y = 0, z = 0;
        if (v.empty())
          s.frame.camera.eye.reset();
        else if (std::sscanf(v.c_str(), "%lf %lf %lf", &x, &y, &z) == 3)
          s.frame.camera.eye = Eigen::Vector3d(x, y, z);
      }));
  t.push_back(number(
      "view-az", camera, -1e9, 1e9, "degrees", "225",
      "Bearing of the line of sight, degrees clockwise from grid north",
      [](auto& s) -> auto& { return s.frame.camera.view_az; }, true));
  t.push_back(number(
      "view-alt", camera, -90, 90, "degrees", "30",
      "Angle of the line of sight below the horizon, degrees",
      [](auto& s) -> auto& { return s.frame.camera.view_alt; }, true));
  t.push_back(number(
      "fov", camera, 1, 170, "degrees", "35", "Vertical field of view, degrees",
      [](auto& s) -> auto& { return s.frame.camera.fov; }, true));
  t.push_back(number(
      "map-scale", camera, 0, 1e9, "m", "0",
      "With --view top (orthographic, north up): metres a pixel, the image centred on the terrain; "
      "0 fits the "
      "whole terrain to the image. The files carry the map's geotransform (SVG <desc>, PDF "
      "subject, PNG text and a "
      ".pgw world file)",
      [](auto& s) -> auto& { return s.frame.camera.map_scale; }));
  t.push_back(number(
      "light-az", camera, -1e9, 1e9, "degrees", "315",
      "Light azimuth, degrees clockwise from north (frame's default view: from its left)",
      [](auto& s) -> auto& { return s.frame.light.azimuth; }, true));
  t.push_back(number(
      "light-alt", camera, -90, 90, "degrees", "45", "Light altitude above the horizon, degrees",
      [](auto& s) -> auto& { return s.frame.light.altitude; }, true));
  t.push_back(number(
      "exaggeration", camera, 0.01, 100, "", "1",
      "Vertical exaggeration; not given: automatic, from the relief against the terrain's extent "
      "(1 where the relief "
      "is strong, up to 5 on lowland; terrain-inspect info prints it)",
      [](auto& s) -> auto& { return s.style.exaggeration; }));
}

// The options of the crease score (and the PEL threshold, per frame too).
void add_score_options(std::vector<OptionSpec>& t, const GroupNames& g) {
  const auto& [frame, camera, score, rules, strokes, sil, pel, edges, colours, surface, hachure] =
      g;
  t.push_back(number(
      "sw", score, 0, 1, "", text_of(1.0 / 3), "Crease score: slope weight",
      [](auto& s) -> auto& { return s.frame.score.sw; }, true));
  t.push_back(number(
      "iw", score, 0, 1, "", text_of(1.0 / 3), "Crease score: illumination weight",
      [](auto& s) -> auto& { return s.frame.score.iw; }, true));
  t.push_back(number(
      "fw", score, 0, 1, "", text_of(1.0 / 3), "Crease score: flow weight",
      [](auto& s) -> auto& { return s.frame.score.fw; }, true));
  t.push_back(number(
      "min-score", score, 0, 1, "", "0.25",
      "Crease score: minimum (rs_min at the eye); 0 draws every crease, 1 none",
      [](auto& s) -> auto& { return s.frame.score.min_score; }, true));
  t.push_back(number(
      "falloff", score, 0, 1, "", "0.2",
      "Crease score: k in rs_min(d) = min + (1 - min) k clamp(d / far, 0, 1); 0 = no distance term",
      [](auto& s) -> auto& { return s.frame.score.falloff; }, true));
  t.push_back(number(
      "far-distance", score, 0, 1e9, "m", "0",
      "Crease score: distance (m) at which rs_min stops rising; 0 = across the scene, from its "
      "nearest "
      "to its farthest point",
      [](auto& s) -> auto& { return s.frame.score.far_distance; }));
  t.push_back(flag(
      "literal-score", score,
      "Divide the weighted sum by 3 (the paper's equation 6) instead of by the weight sum",
      [](const RenderSettings& s) { return s.frame.score.literal_divisor; },
      [](RenderSettings& s, bool v) { s.frame.score.literal_divisor = v; }));
  t.push_back(number(
      "pel-threshold", pel, 0, 1, "", "0.1",
      "PELs: keep lines where |grad f| / max |grad f| exceeds this (tau)",
      [](auto& s) -> auto& { return s.frame.pel.threshold; }, true));
}

// The options of the crease network: which branches become creases.
void add_network_options(std::vector<OptionSpec>& t, const GroupNames& g) {
  const auto& [frame, camera, score, rules, strokes, sil, pel, edges, colours, surface, hachure] =
      g;
  t.push_back(number(
      "min-area", rules, 0, 1e15, "m^2", "10000",
      "Creases start where at least this area drains (channel initiation, m^2: 1 ha is 100 "
      "drainage points "
      "at 10 m, 400 at 5 m; 0: every D8 link, as the paper); --page-min-area may ask more of a "
      "page",
      [](auto& s) -> auto& { return s.rules.min_area; }));
  t.push_back(number(
      "min-drainage-width", rules, 0, 1e6, "m", "30",
      "Creases only where the area draining through a point, over its longest flow path from the "
      "divide, is at "
      "least this wide (m; and 2 drainage spacings): flow down a plane, whose D8 tracks gather one "
      "cell "
      "per cell, draws no fan of parallel lines (0: off)",
      [](auto& s) -> auto& { return s.rules.min_width; }));
  t.push_back(flag(
      "seed-rules", rules,
      "Creases as the paper draws them: every basin normalized by its own total (also the small "
      "ones that drain "
      "off the grid edge) on a linear scale, every D8 path across flats, down planes and along the "
      "grid's edge, "
      "every branch whether or not in a valley, and D8 polylines unsmoothed "
      "(docs/terrain-render.md)",
      [](const RenderSettings& s) {
        return s.rules.edge_basin_min_share == 0 && !s.rules.log_flow &&
               !s.rules.one_line_per_flat && s.rules.smooth_spacings == 0 &&
               s.rules.min_width == 0 && !s.rules.off_edge_runs && !s.rules.valley_branches;
      },
      [](RenderSettings& s, bool v) {
        if (v)
          s.rules.edge_basin_min_share = 0, s.rules.log_flow = false,
          s.rules.one_line_per_flat = false, s.rules.smooth_spacings = 0, s.rules.min_width = 0,
          s.rules.off_edge_runs = false, s.rules.valley_branches = false;
      }));
  t.push_back(choice(
      "crease-links", rules, OptionType::Enum, {"valleys", "all"}, "valleys",
      "Which branches of the network may become creases: valleys, only those along which the "
      "surface is concave "
      "across the flow (the mean second difference of the heights --valley-width to either side "
      "above "
      "--valley-curvature; main stems draining a quarter of their basin anywhere), so that flow "
      "down planes and "
      "across flats draws no parallel tracks; all, every branch (the paper)",
      [](const RenderSettings& s) {
        return std::string(s.rules.valley_branches ? "valleys" : "all");
      },
      [](RenderSettings& s, const std::string& v) { s.rules.valley_branches = v == "valleys"; }));
  t.push_back(number(
      "valley-curvature", rules, -1, 1, "1/m", "0.0005",
      "--crease-links valleys: the least mean concavity across the flow of a branch kept (0.0005 "
      "at 30 m: its "
      "sides 0.45 m above it)",
      [](auto& s) -> auto& { return s.rules.valley_curvature; }));
  t.push_back(number(
      "valley-width", rules, 0, 1e4, "m", "30",
      "--crease-links valleys: how far to either side of a link the concavity is measured (at "
      "least the mesh "
      "spacing)",
      [](auto& s) -> auto& { return s.rules.valley_width; }));
  t.push_back(number(
      "edge-basin-share", rules, 0, 1, "", "0.05",
      "Basins that drain off the grid edge are normalized by at least this share of the network's "
      "points (0: by their own, as the paper)",
      [](auto& s) -> auto& { return s.rules.edge_basin_min_share; }));
  t.push_back(choice(
      "flow-scale", rules, OptionType::Enum, {"log", "linear"}, "log",
      "Flow term of the crease score: log = ln(accumulated) / ln(basin total), a tributary by its "
      "order of "
      "magnitude in its basin; linear = accumulated / basin total (the paper)",
      [](const RenderSettings& s) { return std::string(s.rules.log_flow ? "log" : "linear"); },
      [](RenderSettings& s, const std::string& v) { s.rules.log_flow = v == "log"; }));
  t.push_back(number(
      "crease-smooth", rules, 0, 4, "mesh spacings", "0.5",
      "Smooth the D8 staircase of crease lines: Gaussian sigma along the line, in mesh spacings, "
      "and at "
      "least 1.5 drainage samples (0: the D8 polyline as it is)",
      [](auto& s) -> auto& { return s.rules.smooth_spacings; }));
}

// The options of the crease strokes: widths, fades, bridges, hidden runs.
void add_strokes_options(std::vector<OptionSpec>& t, const GroupNames& g) {
  const auto& [frame, camera, score, rules, strokes, sil, pel, edges, colours, surface, hachure] =
      g;
  t.push_back(number(
      "crease-width", strokes, 0.5, 20, "pixels", "1",
      "Crease width in pixels where little drains (basin share 0); it grows with the square root "
      "of "
      "the share of the basin that drains there",
      [](auto& s) -> auto& { return s.style.crease_width; }));
  t.push_back(number(
      "crease-width-max", strokes, 0.5, 20, "pixels", "3",
      "Crease width in pixels at a basin's outlet (share 1)",
      [](auto& s) -> auto& { return s.style.crease_width_max; }));
  t.push_back(flag(
      "aliased", strokes,
      "Pixel-exact lines: every crease and PEL pixel is the line colour or not (no coverage, no "
      "fade, no "
      "silhouette softening); for comparisons by pixel count",
      [](const RenderSettings& s) { return !s.style.antialias; },
      [](RenderSettings& s, bool v) { s.style.antialias = !v; }));
  t.push_back(number(
      "crease-fade", strokes, 0, 1, "", "0.03",
      "Creases fade in over this band of the rendering score above the threshold instead of "
      "popping "
      "in (0: cut at the threshold)",
      [](auto& s) -> auto& { return s.style.crease_fade; }));
  t.push_back(number(
      "crease-bridge", strokes, 0, 1e5, "m", "50",
      "Draw a gap in a channel's crease up to this long (m; or --crease-bridge-px at the page "
      "scale, "
      "whichever is longer), where the score dips between two drawn parts (0: this term off)",
      [](auto& s) -> auto& { return s.style.crease_bridge; }));
  t.push_back(number(
      "crease-bridge-px", strokes, 0, 256, "pixels", "2",
      "... or up to this long in pixels at the page scale (metres per pixel at the depth of the "
      "scene's centre; 0: this term off)",
      [](auto& s) -> auto& { return s.style.crease_bridge_px; }));
  t.push_back(number(
      "crease-min-stroke", strokes, 0, 1e5, "m", "200",
      "Leave out crease strokes shorter than this (m; or --crease-min-stroke-px at the page scale, "
      "whichever is longer): dashes, not channels (0: this term off)",
      [](auto& s) -> auto& { return s.style.crease_min_stroke; }));
  t.push_back(number(
      "crease-min-stroke-px", strokes, 0, 256, "pixels", "4",
      "... or shorter than this in pixels at the page scale: dots on the page, whatever the mesh's "
      "spacing (0: this term off)",
      [](auto& s) -> auto& { return s.style.crease_min_stroke_px; }));
  t.push_back(number(
      "page-min-area", strokes, 0, 1e12, "m^2", "40000",
      "Channels selected by the page: creases begin where at least this area drains on a page of "
      "10 m a pixel, times the square root of the page scale over 10 m (Topfer's radical law: a "
      "map keeps objects as the square root of its scale); never below --min-area (0: off)",
      [](auto& s) -> auto& { return s.style.page_min_area; }));
  t.push_back(number(
      "crease-hidden-gap", strokes, 0, 256, "pixels", "8",
      "Draw a hidden run of a crease stroke up to this long (pixels) between its shown parts, when "
      "none "
      "of it is more than --crease-hidden-depth behind the surface: a gully's floor, not dashes "
      "(0: "
      "draw none)",
      [](auto& s) -> auto& { return s.style.crease_hidden_gap; }));
  t.push_back(number(
      "crease-hidden-depth", strokes, 0, 100, "mesh spacings", "1.5",
      "How far behind the surface a hidden run drawn by --crease-hidden-gap may lie (mesh "
      "spacings)",
      [](auto& s) -> auto& { return s.style.crease_hidden_depth; }));
  t.push_back(number(
      "crease-min-peek", strokes, 0, 256, "pixels", "6",
      "Leave out a shown run of a crease stroke up to this long (pixels) beside a hidden part: a "
      "dot "
      "where a channel peeks out between ridges (0: keep every run)",
      [](auto& s) -> auto& { return s.style.crease_min_peek; }));
  t.push_back(number(
      "crease-lift", strokes, 0, 1e6, "m", "auto",
      "Lines (creases, PELs, edges) are drawn where they lie on the surface, at the depth of their "
      "points moved this far (m) towards the eye, so the tessellated surface does not hide them in "
      "their valleys; auto: 0.5 x mesh spacing",
      [](auto& s) -> auto& { return s.style.crease_lift; }));
  t.back().get = [](const RenderSettings& s) {
    return s.style.crease_lift < 0 ? std::string("auto") : text_of(s.style.crease_lift);
  };
  t.back().store = [](RenderSettings& s, const std::string& v) {
    s.style.crease_lift = -1;  // auto
    if (v != "auto") parse_number(v, s.style.crease_lift);
  };
}

// The options of silhouettes, PELs and object-space edges.
void add_hachure_options(std::vector<OptionSpec>& t, const GroupNames& g) {
  const auto& [frame, camera, score, rules, strokes, sil, pel, edges, colours, surface, hachure] =
      g;
  t.push_back(number(
      "hachure-spacing", hachure, 1, 256, "pixels", "3",
      "--layers hachures: the spacing of the hachures where the tone is black; six times it where "
      "white",
      [](auto& s) -> auto& { return s.style.hachure_spacing; }));
  t.push_back(number(
      "hachure-width", hachure, 0.1, 20, "pixels", "1.5",
      "--layers hachures: the width of a hachure",
      [](auto& s) -> auto& { return s.style.hachure_width; }));
  t.push_back(choice(
      "hachure-tone", hachure, OptionType::Enum, {"light", "slope"}, "light",
      "--layers hachures: what sets their density: light, the shadow (1 - n.l: slopes facing away "
      "from the "
      "light dark); slope, the steepness (Lehmann: tan of the slope, black at 45 degrees)",
      [](const RenderSettings& s) {
        return std::string(s.style.hachure_light_tone ? "light" : "slope");
      },
      [](RenderSettings& s, const std::string& v) { s.style.hachure_light_tone = v == "light"; }));
  t.push_back(number(
      "hachure-min-slope", hachure, 0, 100, "%", "20",
      "--layers hachures: ground flatter than this percentage of the frame's steep slopes (the "
      "99th percentile of "
      "its slopes as drawn) stays white, as the QGIS Hachures script's relative slope threshold; "
      "0: only ground "
      "under 3 degrees",
      [](auto& s) -> auto& { return s.style.hachure_min_slope_percent; }));
  t.push_back(choice(
      "hachure-style", hachure, OptionType::Enum, {"lines", "rows"}, "lines",
      "--layers hachures: lines, continuous slope lines (Buchin et al.), or rows, Imhof's rows "
      "between form lines "
      "(contours at an interval chosen from the view's scale)",
      [](const RenderSettings& s) { return std::string(s.style.hachure_rows ? "rows" : "lines"); },
      [](RenderSettings& s, const std::string& v) { s.style.hachure_rows = v == "rows"; }));
  t.push_back(colour(
      "hachure-colour", hachure, "#333333", "--layers hachures: their colour",
      [](auto& s) -> auto& { return s.style.hachure_colour; }));
  t.push_back(number(
      "ridge-min-area", hachure, 0, 1e12, "m^2", "1e+07",
      "--layers ridges: a crest is drawn where the smaller basin it parts drains at least this "
      "area times "
      "sqrt(the page's metres a pixel / 10) (Topfer's law: fewer crests on a smaller-scale page)",
      [](auto& s) -> auto& { return s.style.ridge_min_area; }));
  t.push_back(number(
      "ridge-min-relief", hachure, 0, 1, "of the scene's relief", "0.05",
      "--layers ridges: and where it rises at least this share of the scene's relief above that "
      "basin's outlet",
      [](auto& s) -> auto& { return s.style.ridge_min_relief; }));
  t.push_back(number(
      "ridge-width", hachure, 0.1, 20, "pixels", "2.2",
      "--layers ridges: the width of a ridge line",
      [](auto& s) -> auto& { return s.style.ridge_width; }));
  t.push_back(colour(
      "ridge-colour", hachure, "#3b291a", "--layers ridges: their colour",
      [](auto& s) -> auto& { return s.style.ridge_colour; }));
}

void add_lines_options(std::vector<OptionSpec>& t, const GroupNames& g) {
  const auto& [frame, camera, score, rules, strokes, sil, pel, edges, colours, surface, hachure] =
      g;
  t.push_back(integer(
      "silhouette-width", sil, 1, 9, "pixels", "1",
      "Silhouette width in pixels (anti-aliased: a band 0.8 px wider about the line of the "
      "silhouette "
      "pixels)",
      [](auto& s) -> auto& { return s.style.silhouette_width; }));
  t.push_back(number(
      "silhouette-min-length", sil, 0, 1, "of the frame's height", "0.08",
      "Silhouette pieces (pixels joined across gaps of up to 4 pixels) shorter than this share of "
      "the frame's "
      "height fade out, to nothing at three quarters of it: strokes, not the scattered dashes of "
      "rolling "
      "ground seen from above (0: keep every piece; anti-aliased lines only)",
      [](auto& s) -> auto& { return s.style.silhouette_min_length; }));
  t.push_back(number(
      "silhouette-depth-width", sil, 0, 10, "pixels", "1.5",
      "Silhouettes are this many pixels wider where they hide most: in full where the ground "
      "behind lies a "
      "quarter farther than the line, and at the skyline (Imhof: the skyline carries the heaviest "
      "line); less "
      "by the depth hidden; 0: every silhouette as wide (anti-aliased lines only)",
      [](auto& s) -> auto& { return s.style.silhouette_depth_width; }));
  t.push_back(choice(
      "formulated", sil, OptionType::Enum, {"on", "off"}, "on",
      "Formulated silhouettes (Whelan and Visvalingam), drawn with the silhouettes: on the visible "
      "surface, "
      "the lines that would be silhouettes were the eye lowered to --formulated-altitude (crests "
      "and the "
      "near rims of valleys, which a view from above has few silhouettes to show)",
      [](const RenderSettings& s) { return std::string(s.style.formulated ? "on" : "off"); },
      [](RenderSettings& s, const std::string& v) { s.style.formulated = v == "on"; }));
  t.push_back(number(
      "formulated-altitude", sil, 0, 89, "degrees", "5",
      "Formulated silhouettes: the lowered eye's line of sight, degrees below the horizon on the "
      "view's "
      "bearing (the top view looks towards the image's top)",
      [](auto& s) -> auto& { return s.style.formulated_altitude; }));
  t.push_back(number(
      "formulated-strength", sil, 0, 89, "degrees", "10",
      "Formulated silhouettes: a line is drawn where the far side falls at least this many degrees "
      "more "
      "steeply than the lowered sight line (how much it would hide)",
      [](auto& s) -> auto& { return s.style.formulated_strength; }));
  t.push_back(choice(
      "pel-light", pel, OptionType::Enum, {"headlight", "scene"}, "headlight",
      "PELs: f = max(0, n . L) with L the headlight (towards the eye) or the scene light "
      "(--light-az/alt)",
      [](const RenderSettings& s) {
        return std::string(s.frame.pel.headlight ? "headlight" : "scene");
      },
      [](RenderSettings& s, const std::string& v) { s.frame.pel.headlight = v == "headlight"; }));
  t.push_back(number(
      "pel-width", pel, 0.5, 20, "pixels", "1", "PEL width in pixels",
      [](auto& s) -> auto& { return s.style.pel_width; }));
  t.push_back(number(
      "pel-min-length", pel, 0, 100, "mesh spacings", "4",
      "PELs: lines shorter than this many mesh spacings on the mesh fade out, to nothing at half "
      "of "
      "it: where the fields' noise crosses zero over a few faces (0: keep every line; anti-aliased "
      "lines only)",
      [](auto& s) -> auto& { return s.style.pel_min_length; }));
  t.push_back(integer(
      "pel-smooth", pel, 0, 16, "iterations", "3",
      "PELs: iterations of a Laplacian step along the lines, whose crossings zigzag from face to "
      "face "
      "(0: as extracted; anti-aliased lines only)",
      [](auto& s) -> auto& { return s.style.pel_smooth; }));
  t.push_back(choice(
      "edges", edges, OptionType::List, {"contour", "boundary", "crease"},
      "contour,boundary,crease",
      "Edges layer: which object-space edges of the mesh facets (comma list of contour, boundary, "
      "crease)",
      [](const RenderSettings& s) { return edges_text(s.style.edge_kinds); },
      [](RenderSettings& s, const std::string& v) { s.style.edge_kinds = parse_edge_kinds(v); }));
  t.push_back(number(
      "crease-angle", edges, 0, 180, "degrees", "30",
      "Edges layer: crease edges bend by more than this (degrees between the two face normals)",
      [](auto& s) -> auto& { return s.style.crease_angle; }));
  t.push_back(choice(
      "edge-caps", edges, OptionType::Enum, {"exact", "cheap", "none"}, "exact",
      "Edges layer: how consecutive edge quads join: exact (mitred where two edges meet), cheap "
      "(square caps), "
      "none",
      [](const RenderSettings& s) {
        return std::string(s.style.edge_caps == EdgeCaps::Exact   ? "exact"
                           : s.style.edge_caps == EdgeCaps::Cheap ? "cheap"
                                                                  : "none");
      },
      [](RenderSettings& s, const std::string& v) {
        s.style.edge_caps = v == "exact"   ? EdgeCaps::Exact
                            : v == "cheap" ? EdgeCaps::Cheap
                                           : EdgeCaps::None;
      }));
  t.push_back(number(
      "edge-width", edges, 0.5, 20, "pixels", "1.5", "Edges layer: width in pixels",
      [](auto& s) -> auto& { return s.style.edge_width; }));
}

// The options of colours and the surface.
void add_look_options(std::vector<OptionSpec>& t, const GroupNames& g) {
  const auto& [frame, camera, score, rules, strokes, sil, pel, edges, colours, surface, hachure] =
      g;
  t.push_back(colour(
      "background", colours, "#dde4ec", "Background colour (#rrggbb, r,g,b or a name)",
      [](auto& s) -> auto& { return s.style.background; }));
  t.push_back(colour(
      "mask-colour", colours, "white", "Surface colour of the mask layer",
      [](auto& s) -> auto& { return s.style.mask; }));
  t.push_back(colour(
      "crease-colour", colours, "blue", "Crease colour",
      [](auto& s) -> auto& { return s.style.crease_colour; }));
  t.push_back(colour(
      "silhouette-colour", colours, "black", "Silhouette colour",
      [](auto& s) -> auto& { return s.style.silhouette_colour; }));
  t.push_back(colour(
      "pel-colour", colours, "#8c1a1a", "PEL colour",
      [](auto& s) -> auto& { return s.style.pel_colour; }));
  t.push_back(colour(
      "edge-colour", colours, "#262626", "Edges layer: colour",
      [](auto& s) -> auto& { return s.style.edge_colour; }));
  t.push_back(number(
      "pixels-per-edge", surface, 1, 100, "pixels", "6",
      "Adaptive tessellation target: screen length of a tessellated edge, pixels",
      [](auto& s) -> auto& { return s.style.pixels_per_edge; }));
  t.push_back(number(
      "lod-error", surface, 0, 64, "pixels", "0.25",
      "Levels of detail: each block of 64 x 64 cells is drawn at the coarsest level (every 2nd, "
      "4th, ... row and "
      "column) whose height error spans at most this on the screen (four times this where that "
      "level faces the "
      "eye throughout), and the creases merged along their runs within twice this; 0 draws every "
      "cell and crease "
      "segment",
      [](auto& s) -> auto& { return s.style.lod_error; }));
}

std::vector<OptionSpec> make_table() {
  const GroupNames g;
  const std::string& rules = g.rules;
  std::vector<OptionSpec> t;
  add_frame_options(t, g);
  add_camera_options(t, g);
  add_score_options(t, g);
  add_network_options(t, g);
  add_strokes_options(t, g);
  add_lines_options(t, g);
  add_look_options(t, g);
  add_hachure_options(t, g);
  // What --line-scale multiplies with a range the renderer draws it in (terrain_renderer.cpp's
  // buffers and pixel loops), and what rebuilds the creases.
  const std::map<std::string, OptionSpec::Range> drawn = {
      {"silhouette-width", {1, 9}},    {"edge-width", {0, 64}},
      {"crease-hidden-gap", {0, 256}}, {"crease-min-peek", {0, 256}},
      {"crease-bridge-px", {0, 256}},  {"crease-min-stroke-px", {0, 256}},
      {"hachure-spacing", {1, 256}},   {"hachure-width", {0.1, 64}},
      {"ridge-width", {0.1, 64}}};
  for (OptionSpec& o : t) {
    if (const auto d = drawn.find(o.name); d != drawn.end()) {
      o.drawn = d->second;
      o.help += fmt::format(" (drawn, times --line-scale: {:g} .. {:g} {})", d->second.min,
                            d->second.max, o.unit);
    }
    o.rebuilds_creases = o.group == rules;
  }
  return t;
}

}  // namespace

Style drawn_style(const RenderSettings& s) {
  Style st = s.style;
  const double k = s.line_scale;
  st.crease_width *= k;
  st.crease_width_max *= k;
  st.silhouette_width = int(std::lround(st.silhouette_width * k));  // validate keeps it in 1 .. 9
  st.pel_width *= k;
  st.edge_width *= k;
  st.crease_hidden_gap *= k;
  st.crease_min_peek *= k;
  st.crease_bridge_px *= k;
  st.hachure_spacing *= k;
  st.hachure_width *= k;
  st.ridge_width *= k;
  st.crease_min_stroke_px *= k;
  return st;
}

const char* option_type_name(OptionType t) {
  static const char* const kNames[] = {"NUMBER", "INTEGER", "FLAG", "CHOICE",
                                       "COLOUR", "LIST",    "WxH",  "E N Z"};
  return kNames[int(t)];
}

const std::vector<OptionSpec>& render_options() {
  static const std::vector<OptionSpec> table = make_table();
  return table;
}

std::string csv_column(const OptionSpec& o) {
  std::string c = o.name;
  std::replace(c.begin(), c.end(), '-', '_');
  return c;
}

const OptionSpec* find_option(const std::string& name) {
  for (const OptionSpec& o : render_options())
    if (o.name == name || csv_column(o) == name) return &o;
  return nullptr;
}

void set_option(RenderSettings& s, const OptionSpec& o, const std::string& text) {
  switch (o.type) {
    case OptionType::Number:
    case OptionType::Integer: {
      if (text == "auto" && o.default_text == "auto") break;  // an option whose default is computed
      double v = 0;
      if (!parse_number(text, v) || !std::isfinite(v))
        throw terrain::Error("'" + text + "' is not a number");
      if (o.type == OptionType::Integer && v != std::floor(v))
        throw terrain::Error("'" + text + "' is not a whole number");
      if (v < o.min || v > o.max)
        throw terrain::Error(fmt::format("{} is outside {:g} .. {:g}{}", text, o.min, o.max,
                                         o.unit.empty() ? "" : " " + o.unit));
      break;
    }
    case OptionType::Bool:
      if (text != "true" && text != "false")
        throw terrain::Error("'" + text + "' is not true or false");
      break;
    case OptionType::Enum:
      if (o.accepts && o.accepts(text)) break;
      if (std::find(o.choices.begin(), o.choices.end(), text) == o.choices.end())
        throw terrain::Error(fmt::format("'{}' is not one of {}", text, join(o.choices)));
      break;
    case OptionType::Size: {
      int w = 0, h = 0;
      char x = 0, extra = 0;
      if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X'))
        throw terrain::Error("expected WIDTHxHEIGHT, e.g. 1280x720, got '" + text + "'");
      if (w < kMinFrameSide || h < kMinFrameSide || w > kMaxFrameSide || h > kMaxFrameSide)
        throw terrain::Error(
            fmt::format("width and height must be in {} .. {}", kMinFrameSide, kMaxFrameSide));
      break;
    }
    case OptionType::Point: {
      double v[3];
      char extra = 0;
      if (!text.empty() &&
          std::sscanf(text.c_str(), "%lf %lf %lf %c", &v[0], &v[1], &v[2], &extra) != 3)
        throw terrain::Error("expected three numbers E N Z, got '" + text + "'");
      if (!text.empty() && !(std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2])))
        throw terrain::Error("'" + text + "' is not three finite numbers");
      break;
    }
    case OptionType::Colour:
      (void)parse_colour(text);  // throws with the accepted forms
      break;
    case OptionType::List:
      break;  // stored below: parse_layers / parse_edge_kinds check names and combinations before
              // they assign
  }
  o.store(s, text);
}

void validate(const RenderSettings& s) {
  const auto& sc = s.frame.score;
  if (sc.sw + sc.iw + sc.fw <= 0)
    throw terrain::Error("--sw/--iw/--fw: at least one weight must be > 0");
  // The widths and lengths --line-scale multiplies, drawn: within what the renderer draws.
  for (const OptionSpec& o : render_options()) {
    if (!o.drawn) continue;
    const double v = std::stod(o.get(s));
    const double drawn =
        o.type == OptionType::Integer ? double(std::lround(v * s.line_scale)) : v * s.line_scale;
    if (drawn < o.drawn->min || drawn > o.drawn->max)
      throw terrain::Error(fmt::format(
          "--{} {:g} x --line-scale {:g} = {:g} {} is outside the {:g} .. {:g} {} drawn", o.name, v,
          s.line_scale, drawn, o.unit, o.drawn->min, o.drawn->max, o.unit));
  }
}

std::string changed_options(const RenderSettings& s) {
  const RenderSettings defaults;
  std::string out;
  for (const OptionSpec& o : render_options()) {
    const std::string v = o.get(s);
    if (v == o.get(defaults)) continue;
    if (o.type == OptionType::Bool) {
      if (v == "true") out += " --" + o.name;
      continue;
    }
    out += " --" + o.name + " " + (o.type == OptionType::Point ? v : "'" + v + "'");
  }
  return out;
}

}  // namespace renderer
