#pragma once
// What one frame of terrain-render draws: camera, light, crease score and layers.
// Plain data; the defaults are the option table's (options.hpp), the ones --help shows.
//
// Angles (one place, documented in docs/terrain-render.md):
//   view_az   compass bearing of the line of sight, degrees clockwise from grid north
//   view_alt  angle of the line of sight below the horizon, degrees (0 level, 90 straight
//             down); the paper's "view altitude"
//   fov       vertical field of view, degrees
//   light_az, light_alt  direction towards the light: bearing from grid north and angle
//             above the horizon, as in hillshading
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include <Eigen/Core>

namespace renderer {

// The crease rendering score of a drainage vertex (docs/algorithms.md 9.1):
//   rs = (sw*sc + iw*ic + fw*fc) / D - rs_min(d)
//   sc = 1 - n.z (slope), ic = 1 - n.l (illumination), fc = normalized flow,
//   D = sw + iw + fw (default) or 3 (literal: the paper's equation 6),
//   rs_min(d) = min_score + (1 - min_score) * falloff * clamp((d - near) / (far - near), 0, 1),
//   d = distance from the eye to the vertex. A vertex is drawn when rs >= 0.
struct CreaseScoreParams {
  double sw = 1.0 / 3, iw = 1.0 / 3, fw = 1.0 / 3;  // equal weights (the paper's Figure 15)
  double min_score = 0.25;                          // rs_base
  double falloff = 0.2;          // k: how far rs_min rises towards 1 at far_distance
  double far_distance = 0;       // d_far in metres; 0: across the scene (resolve_distances)
  double near_distance = 0;      // d_near: where rs_min starts rising (< far_distance)
  bool literal_divisor = false;  // divide by 3 instead of the weight sum
};

struct Camera {
  // Eye in world (CRS) coordinates, metres; unset: framed automatically (frame_terrain).
  std::optional<Eigen::Vector3d> eye;
  double view_az = 225.0, view_alt = 30.0, fov = 35.0;
  // Orthographic (--view top): every ray parallel to the line of sight, the image at
  // map_scale metres a pixel (0: the scene fitted to the image, centred); the eye then only
  // says where the image is centred (its projection), and fov is not used.
  bool orthographic = false;
  double map_scale = 0;
};

// The camera a frame gets when none is given (no eye, no view azimuth): the automatic view
// of the whole terrain (auto_view), straight down with north up (Top), or the part of
// highest relief (relief_view), or a row of a frames CSV (a flight's frame: its camera,
// light and per-frame options; view_row_frame).
enum class ViewMode { Auto, Top, Relief, Row };

struct Light {
  double azimuth = 315.0, altitude = 45.0;
};

// Which images the composite shows.
struct Layers {
  bool shaded = false;  // the shaded relief (Lambert, light above)
  bool mask = true;     // the surface in the mask colour (hidden-line mask)
  bool creases = true;
  bool silhouettes = true;
  bool pels = false;  // photic extremum lines (needs the mesh's Voronoi weights)
  // How the silhouettes are found: Toward/Away depths, or the Adjacency method (triangle
  // IDs; Mower 2014, Algorithm 1). Both are Mower's; layer names silhouettes and
  // silhouettes-adjacency.
  bool adjacency = false;
  // Object-space feature edges of the mesh (McGuire & Hughes 2004): contour, boundary and
  // crease edges (Style::edge_kinds), drawn as screen-space quads with caps.
  bool edges = false;
  // Hachures (renderer/core/hachures.hpp): strokes along the fall line, denser where
  // the tone is darker, traced on the CPU from the frame's depth and drawn over it (PNG)
  // or as their own layer (SVG, PDF). On by default: without them the picture does not
  // show the relief (docs/terrain-render.md, "The default picture").
  bool hachures = true;
  // Ridge lines (renderer::ridge_layer): the crests between the basins of the frame's .dv,
  // selected by the page, drawn over the other lines (PNG) or as their own top layer (SVG,
  // PDF). On by default with a .dv: the crest carries the heaviest line (Imhof).
  bool ridges = true;
};
// The layers by name, in the order --layers lists them (the one list of names: the option
// table's choices, parse_layers and layers_text read it).
struct LayerName {
  const char* name;
  bool Layers::*flag;
};
inline constexpr LayerName kLayerNames[] = {{"shaded", &Layers::shaded},
                                            {"mask", &Layers::mask},
                                            {"creases", &Layers::creases},
                                            {"silhouettes", &Layers::silhouettes},
                                            {"silhouettes-adjacency", &Layers::adjacency},
                                            {"pels", &Layers::pels},
                                            {"edges", &Layers::edges},
                                            {"hachures", &Layers::hachures},
                                            {"ridges", &Layers::ridges}};
// Parses "shaded,creases,..." (kLayerNames); Error on an unknown name, an empty list, both
// shaded and mask, or both silhouette methods.
Layers parse_layers(const std::string& list);
// "mask,creases,silhouettes,hachures,ridges": what parse_layers reads back.
std::string layers_text(const Layers& l);

// The one number reader of options and frames CSVs: the whole of `text` a finite decimal
// number (a leading '+' allowed; "nan", "inf", "1e999", "3 m" are not).
bool parse_number(std::string_view text, double& v);

// The frame's width and height in pixels (--size; the renderer's targets).
inline constexpr int kMinFrameSide = 16, kMaxFrameSide = 16384;

// How the quads of consecutive object-space edges join (docs/terrain-render.md):
//   None   quads end at the vertices (gaps on the outside of every turn; for comparison)
//   Cheap  each quad extended by half its width at both ends (square caps; no adjacency
//          read, never a gap, overshoots outside sharp turns)
//   Exact  where exactly two drawn edges meet at a vertex, both quads end on the same
//          mitre line (read from the vertex's edges): no gap and no overlap; square caps
//          at line ends, junctions and turns sharper than the mitre limit
enum class EdgeCaps { None, Cheap, Exact };

struct Style {
  Eigen::Vector3f background{0xdd / 255.f, 0xe4 / 255.f, 0xec / 255.f}, mask{1, 1, 1};
  // --background none: no background; the frame's pixels carry their coverage as alpha
  // (lines over the ground outside the terrain partly transparent), a map to lay over others.
  bool transparent = false;
  Eigen::Vector3f crease_colour{0.05f, 0.2f, 0.55f}, silhouette_colour{0, 0, 0};
  double crease_width = 1.0,
         crease_width_max = 3.0;  // pixels at basin share 0 and 1 (by its square root)
  // Creases and PELs as anti-aliased capsules (coverage in the fragment shader, round
  // caps and joins, silhouettes softened) or as pixel-exact quads (false: every line
  // pixel has exactly the line colour; the tests that count pixels use it).
  bool antialias = true;
  // Creases fade in over this band of the rendering score above the threshold (opacity
  // min(score) / fade, clamped to 1) instead of appearing at full strength; 0 cuts.
  // Anti-aliased lines only.
  double crease_fade = 0.03;
  // Strokes, not dashes (renderer::StrokeRule), set by the page, not by the mesh: a gap in
  // a channel's line up to crease_bridge metres or crease_bridge_px pixels at the page
  // scale (page_scale), whichever is longer, is drawn; a stroke shorter than
  // crease_min_stroke metres or crease_min_stroke_px pixels is not. 0 turns a term off.
  // 28 px (2 until issue 67) joins tributaries to their trunks across flat, lit mouths that
  // score below the far threshold: Mandakini's connected share 0.59 -> 0.92.
  double crease_bridge = 50.0, crease_bridge_px = 28.0;
  double crease_min_stroke = 200.0, crease_min_stroke_px = 4.0;
  // Channels selected by the page (Topfer's radical law: the number of objects a map keeps
  // grows with the square root of its scale, so on a page of fixed size the channel-
  // initiation area grows with the square root of the page scale): creases begin where at
  // least page_min_area x sqrt(page scale / 10 m a pixel) m^2 drains (and CreaseRules::
  // min_area, the network's own floor). 0: off.
  double page_min_area = 40000.0;
  // Hachures (Layers::hachures): spacing where the tone is black (pixels), width, colour,
  // the tone: the light's (true: shadowed slopes dark) or the slope's (Lehmann), and the
  // style: Imhof's rows between form lines (true) or continuous slope lines.
  double hachure_spacing = 3.0, hachure_width = 1.5;
  // Figure and ground: ground flatter than this percentage of the frame's steep slopes (the
  // 99th percentile of its pixels' drawn slopes) gets no hachure (HachureRule::min_slope
  // at least).
  double hachure_min_slope_percent = 20;
  Eigen::Vector3f hachure_colour{0.2f, 0.2f, 0.2f};
  // Ridge lines (Layers::ridges): a crest is drawn where the smaller basin it parts drains
  // at least ridge_min_area x sqrt(page scale / 10 m a pixel) m^2 (Topfer's law, as the
  // creases' page_min_area) and it rises at least ridge_min_relief of the scene's relief
  // above that basin's outlet; width (pixels) and colour.
  double ridge_min_area = 1e7, ridge_min_relief = 0.05, ridge_width = 2.2;
  Eigen::Vector3f ridge_colour{0x3b / 255.f, 0x29 / 255.f, 0x1a / 255.f};  // #3b291a
  bool hachure_light_tone = true, hachure_rows = false;
  // Hidden runs and peeks (anti-aliased lines only; renderer::StrokeVisibilityRule): a
  // hidden run of a stroke up to crease_hidden_gap pixels long between shown parts, none of
  // it more than crease_hidden_depth mesh spacings behind the surface, is drawn; a shown run
  // up to crease_min_peek pixels long beside a hidden part is not. 0 turns a rule off.
  double crease_hidden_gap = 8.0, crease_hidden_depth = 1.5, crease_min_peek = 6.0;
  int silhouette_width = 1;  // pixels
  // Silhouette pieces (anti-aliased lines only; renderer::silhouette_piece_opacity): a
  // piece of silhouette pixels shorter than this share of the frame's height fades out,
  // to nothing at three quarters of it (kSilhouetteFade; 58 pixels in full at 720 rows, 43
  // gone); 0 keeps every piece.
  double silhouette_min_length = 0.08;
  // Silhouettes as strokes weighted by what they hide (anti-aliased lines only;
  // renderer::silhouette_hidden_share): a silhouette line is this many pixels wider times the
  // mean hidden_weight of its pixels (in full where the surface behind it lies a quarter
  // farther than the line, and at the skyline), drawn over the picture; 0: all as wide.
  double silhouette_depth_width = 1.5;
  // Formulated silhouettes (renderer::formulated_view; Toward/Away method only): drawn with
  // the silhouettes, from an eye lowered to formulated_altitude degrees below the horizon
  // on the view's bearing, where the far side falls at least formulated_strength degrees
  // more steeply than that sight line.
  bool formulated = true;
  double formulated_altitude = 5.0, formulated_strength = 10.0;
  double exaggeration = 1.0;  // vertical exaggeration
  double crease_lift =
      -1;  // metres towards the eye, for the depth test only; < 0: 0.5 x mesh spacing
  double pixels_per_edge = 6.0;  // tessellation target: screen length of a triangle edge
  // TFT draws the patches that tessellate into their own flat triangle (every edge within
  // pixels_per_edge) as triangles, without the tessellation stages; false tessellates
  // every patch (the test of the two ways against each other). Not an option.
  bool flat_patches = true;
  // Levels of detail (renderer/core/lod.hpp): each block of patches is drawn at the coarsest
  // level whose error spans at most this many pixels; 0: every patch at full detail.
  double lod_error = 0.25;
  bool levels_of_detail() const { return lod_error > 0; }
  // And no coarser than a level whose cell spans this many pixels (lod_cell_px): < 0 the
  // tessellation target, pixels_per_edge; 0 none (tests of the levels' joins). Not an option.
  double lod_cell = -1;
  Eigen::Vector3f pel_colour{0x8c / 255.f, 0x1a / 255.f, 0x1a / 255.f};  // #8c1a1a
  double pel_width = 1.0;                                                // pixels
  // PEL pieces (anti-aliased lines only; renderer::pel_piece_opacity), in mesh spacings: a
  // PEL piece shorter than this on the mesh fades out, to nothing at half of it; 0 keeps
  // every piece.
  double pel_min_length = 4.0;
  // PEL smoothing (anti-aliased lines only; renderer::smooth_pels): iterations of a
  // Laplacian step along the lines, whose crossings zigzag from face to face; 0: as
  // extracted.
  int pel_smooth = 3;
  // Object-space edges: which kinds (EdgeKind bits of feature_edges.hpp), the crease angle
  // (degrees between the two face normals; 0 = every bend), the joins, width and colour.
  std::uint8_t edge_kinds = 7;  // contour | boundary | crease
  double crease_angle = 30.0;
  EdgeCaps edge_caps = EdgeCaps::Exact;
  double edge_width = 1.5;                                                // pixels
  Eigen::Vector3f edge_colour{0x26 / 255.f, 0x26 / 255.f, 0x26 / 255.f};  // #262626
};

// The largest screen span of a level's cell (its plan diagonal at the block's nearest
// point) that select_lod draws: by default the tessellation target, since a patch over a
// larger cell is tessellated, at about twenty times a flat patch's cost on llvmpipe, and
// one within it is drawn as its own flat triangle.
inline double lod_cell_px(const Style& s) {
  return s.lod_cell < 0 ? s.pixels_per_edge : s.lod_cell;
}

// Parses "contour,boundary,crease" into EdgeKind bits; Error on an unknown or empty list.
std::uint8_t parse_edge_kinds(const std::string& list);

// Photic extremum lines (pel.hpp): threshold tau on |grad f| / max |grad f|, and the
// light that defines f = max(0, n . L): a headlight (L = the direction towards the eye,
// -view direction) by default, or the frame's light.
struct PelParams {
  double threshold = 0.1;
  bool headlight = true;
};

struct FrameParams {
  Camera camera;
  Light light;
  CreaseScoreParams score;
  PelParams pel;
};

// Parses a colour "#rrggbb", "r,g,b" (0..255) or a name (white, black, grey, blue, ...).
Eigen::Vector3f parse_colour(const std::string& text);

}  // namespace renderer
