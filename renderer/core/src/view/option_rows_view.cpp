// The option table's rows of the frame, the camera and light, the crease score and network.
#include <fmt/format.h>

#include <cmath>

#include "option_rows.hpp"
#include "terrain/error.hpp"

namespace renderer::detail {

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

// The view (automatic, top, relief) and the eye point.
static void add_view_options(std::vector<OptionSpec>& t, const GroupNames& g) {
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
}

// The view's azimuth, altitude, field of view and map scale.
static void add_angle_options(std::vector<OptionSpec>& t, const GroupNames& g) {
  const auto& [frame, camera, score, rules, strokes, sil, pel, edges, colours, surface, hachure] =
      g;
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
}

// Where the eye is: the view, the eye point, azimuth, altitude, field of view, map scale.
static void add_eye_options(std::vector<OptionSpec>& t, const GroupNames& g) {
  add_view_options(t, g);
  add_angle_options(t, g);
}

// The light and the exaggeration.
static void add_light_options(std::vector<OptionSpec>& t, const GroupNames& g) {
  const auto& [frame, camera, score, rules, strokes, sil, pel, edges, colours, surface, hachure] =
      g;
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

// The options of the camera, the light and the exaggeration.
void add_camera_options(std::vector<OptionSpec>& t, const GroupNames& g) {
  add_eye_options(t, g);
  add_light_options(t, g);
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

// Which links are channels: areas, widths, seeds.
static void add_channel_options(std::vector<OptionSpec>& t, const GroupNames& g) {
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
}

// Which channel links are drawn as valleys, and how their flow and lines are shaped.
static void add_valley_options(std::vector<OptionSpec>& t, const GroupNames& g) {
  const auto& [frame, camera, score, rules, strokes, sil, pel, edges, colours, surface, hachure] =
      g;
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

// The options of the crease network: which branches become creases.
void add_network_options(std::vector<OptionSpec>& t, const GroupNames& g) {
  add_channel_options(t, g);
  add_valley_options(t, g);
}

}  // namespace renderer::detail
