// The option table's rows of the crease strokes, silhouettes, PELs and edges, colours and
// surface, hachures and ridges.
#include <fmt/format.h>

#include <cmath>

#include "option_rows.hpp"
#include "terrain/error.hpp"

namespace renderer::detail {

// The crease strokes' widths, fades, bridges and shortest strokes.
static void add_crease_width_options(std::vector<OptionSpec>& t, const GroupNames& g) {
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
      "crease-bridge-px", strokes, 0, 256, "pixels", "28",
      "... or up to this long in pixels at the page scale (metres per pixel at the depth of the "
      "scene's centre): a tributary joins its trunk across a flat, lit mouth that scores below "
      "the far threshold (0: this term off)",
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
}

// The crease strokes' page area, hidden runs and lift.
static void add_crease_run_options(std::vector<OptionSpec>& t, const GroupNames& g) {
  const auto& [frame, camera, score, rules, strokes, sil, pel, edges, colours, surface, hachure] =
      g;
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

// The options of the crease strokes: widths, fades, bridges, hidden runs.
void add_strokes_options(std::vector<OptionSpec>& t, const GroupNames& g) {
  add_crease_width_options(t, g);
  add_crease_run_options(t, g);
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

// The silhouettes: widths, pieces, the formulated ones.
static void add_silhouette_options(std::vector<OptionSpec>& t, const GroupNames& g) {
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
}

// The PELs and the object-space edges.
static void add_pel_edge_options(std::vector<OptionSpec>& t, const GroupNames& g) {
  const auto& [frame, camera, score, rules, strokes, sil, pel, edges, colours, surface, hachure] =
      g;
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

void add_lines_options(std::vector<OptionSpec>& t, const GroupNames& g) {
  add_silhouette_options(t, g);
  add_pel_edge_options(t, g);
}

// The options of colours and the surface.
void add_look_options(std::vector<OptionSpec>& t, const GroupNames& g) {
  const auto& [frame, camera, score, rules, strokes, sil, pel, edges, colours, surface, hachure] =
      g;
  t.push_back(colour(
      "background", colours, "#dde4ec",
      "Background colour (#rrggbb, r,g,b or a name), or none: transparent (the PNG's or "
      "GeoTIFF's alpha, a map to lay over other layers in a GIS)",
      [](auto& s) -> auto& { return s.style.background; }));
  t.back().accepts = [](const std::string& v) { return v == "none"; };
  t.back().get = [](const RenderSettings& s) {
    return s.style.transparent ? std::string("none") : colour_text(s.style.background);
  };
  t.back().store = [](RenderSettings& s, const std::string& v) {
    s.style.transparent = v == "none";
    if (!s.style.transparent) s.style.background = parse_colour(v);
  };
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

}  // namespace renderer::detail
