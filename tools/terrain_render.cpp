// terrain-render: headless OpenGL renderer of PN-triangle terrain with drainage creases and
// Toward/Away silhouettes (Mower's Creases algorithm); single frames, batches, flight paths.
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>

#include "common.hpp"
#include "drainage/dv_file.hpp"
#include "drainage/dv_views.hpp"
#include "renderer/crease.hpp"
#include "renderer/frames.hpp"
#include "renderer/gl_context.hpp"
#include "renderer/line_stats.hpp"
#include "renderer/stroke_visibility.hpp"
#include "renderer/terrain_renderer.hpp"
#include "terrain/atomic_file.hpp"
#include "terrain/hillshade.hpp"
#include "terrain/image_io.hpp"
#include "terrain/mesh_io.hpp"

namespace tt = terrain::tools;
namespace rr = renderer;

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Options shared by frame and batch: the defaults of every frame and the style.
struct RenderOptions {
  rr::FrameParams frame;
  rr::Style style;
  std::vector<double> eye;
  std::string size = "1280x720", layers = "mask,creases,silhouettes";
  std::string pel_light = "headlight", pel_colour = "#8c1a1a";
  std::string edges = "contour,boundary,crease", edge_caps = "exact", edge_colour = "#262626";
  std::string flow_scale = "log";
  std::string background = "#dde4ec", mask = "white", crease_colour = "blue", silhouette_colour = "black";
  bool literal = false, seed_rules = false, line_stats = false;
  rr::CreaseRules rules{.min_accumulated = 100, .smooth_spacings = 0.5};
  // Given on the command line (frame: without them, the default view, rr::relief_view).
  CLI::Option *view_az = nullptr, *light_az = nullptr, *light_alt = nullptr;
};

// The range of a per-frame value, shared with the frames CSV (rr::frame_range).
CLI::Range frame_range(const char* column) {
  const auto [lo, hi] = rr::frame_range(column);
  return CLI::Range(lo, hi);
}

void add_render_options(CLI::App* app, RenderOptions& o) {
  auto& f = o.frame;
  app->add_option("--size", o.size, "Image size WIDTHxHEIGHT in pixels")->capture_default_str();
  app->add_option("--eye", o.eye, "Viewpoint E N Z: easting, northing (mesh CRS) and elevation in metres; "
                                  "default (frame): the part of highest relief, seen from its open side and "
                                  "side-lit; with --view-az: the whole terrain framed along that bearing")
      ->expected(3);
  o.view_az = app->add_option("--view-az", f.camera.view_az, "Bearing of the line of sight, degrees clockwise from grid north")
      ->capture_default_str();
  app->add_option("--view-alt", f.camera.view_alt, "Angle of the line of sight below the horizon, degrees")
      ->check(frame_range("view_alt"))
      ->capture_default_str();
  app->add_option("--fov", f.camera.fov, "Vertical field of view, degrees")
      ->check(frame_range("fov"))
      ->capture_default_str();
  o.light_az = app->add_option("--light-az", f.light.azimuth,
                               "Light azimuth, degrees clockwise from north (frame's default view: from its left)")
      ->capture_default_str();
  o.light_alt = app->add_option("--light-alt", f.light.altitude, "Light altitude above the horizon, degrees")
      ->check(frame_range("light_alt"))
      ->capture_default_str();
  app->add_option("--sw", f.score.sw, "Crease score: slope weight")->check(frame_range("sw"))->capture_default_str();
  app->add_option("--iw", f.score.iw, "Crease score: illumination weight")
      ->check(frame_range("iw"))
      ->capture_default_str();
  app->add_option("--fw", f.score.fw, "Crease score: flow weight")->check(frame_range("fw"))->capture_default_str();
  app->add_option("--min-score", f.score.min_score,
                  "Crease score: minimum (rs_min at the eye); 0 draws every crease, 1 none")
      ->check(frame_range("min_score"))
      ->capture_default_str();
  app->add_option("--falloff", f.score.falloff,
                  "Crease score: k in rs_min(d) = min + (1 - min) k clamp(d / far, 0, 1); 0 = no distance term")
      ->check(frame_range("falloff"))
      ->capture_default_str();
  app->add_option("--far-distance", f.score.far_distance,
                  "Crease score: distance (m) at which rs_min stops rising; 0 = across the scene, from its nearest to its farthest point")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app->add_option("--min-accumulation", o.rules.min_accumulated,
                  "Creases start where at least this many drainage points drain (channel initiation; 0: every "
                  "D8 link, as the paper)")
      ->capture_default_str();
  app->add_flag("--seed-rules", o.seed_rules,
                "Creases as the paper draws them: every basin normalized by its own total (also the small "
                "ones that drain off the grid edge) on a linear scale, every D8 path across flats, and D8 "
                "polylines unsmoothed "
                "(docs/terrain-render.md)");
  app->add_option("--edge-basin-share", o.rules.edge_basin_min_share,
                  "Basins that drain off the grid edge are normalized by at least this share of the network's "
                  "points (0: by their own, as the paper)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  app->add_option("--flow-scale", o.flow_scale,
                  "Flow term of the crease score: log = ln(accumulated) / ln(basin total), a tributary by its "
                  "order of magnitude in its basin; linear = accumulated / basin total (the paper)")
      ->check(CLI::IsMember({"log", "linear"}))
      ->capture_default_str();
  app->add_option("--crease-smooth", o.rules.smooth_spacings,
                  "Smooth the D8 staircase of crease lines: Gaussian sigma along the line, in mesh spacings, and "
                  "at least 1.5 drainage samples (0: the D8 polyline as it is)")
      ->check(CLI::Range(0.0, 4.0))
      ->capture_default_str();
  app->add_flag("--line-stats", o.line_stats,
                "Also measure the drawn creases: length in pixels, shares near the grid boundary, on flat ground "
                "and in valleys, strokes; and the drawn silhouettes: pixels, pieces; batch: per frame in "
                "line_stats.csv, and the crease flicker between frames");
  app->add_flag("--literal-score", o.literal,
                "Divide the weighted sum by 3 (the paper's equation 6) instead of by the weight sum");
  app->add_option("--pel-threshold", f.pel.threshold,
                  "PELs: keep lines where |grad f| / max |grad f| exceeds this (tau)")
      ->check(frame_range("pel_threshold"))
      ->capture_default_str();
  app->add_option("--pel-light", o.pel_light,
                  "PELs: f = max(0, n . L) with L the headlight (towards the eye) or the scene light (--light-az/alt)")
      ->check(CLI::IsMember({"headlight", "scene"}))
      ->capture_default_str();
  app->add_option("--pel-colour", o.pel_colour, "PEL colour")->capture_default_str();
  app->add_option("--pel-width", o.style.pel_width, "PEL width in pixels")
      ->check(CLI::Range(0.5, 20.0))
      ->capture_default_str();
  app->add_option("--pel-min-length", o.style.pel_min_length,
                  "PELs: lines shorter than this many mesh spacings on the mesh fade out, to nothing at half of "
                  "it: where the fields' noise crosses zero over a few faces (0: keep every line; anti-aliased "
                  "lines only)")
      ->check(CLI::Range(0.0, 100.0))
      ->capture_default_str();
  app->add_option("--pel-smooth", o.style.pel_smooth,
                  "PELs: smooth the lines, whose crossings of the mesh zigzag from face to face, with this many "
                  "Laplacian steps along them (0: as extracted; anti-aliased lines only)")
      ->check(CLI::Range(0, 16))
      ->capture_default_str();
  app->add_option("--layers", o.layers,
                  "Layers to composite: shaded or mask, creases, silhouettes (Toward/Away) or silhouettes-adjacency "
                  "(the Adjacency method), pels, edges (comma list; pels need a mesh from denoise-normals)")
      ->capture_default_str();
  app->add_option("--edges", o.edges, "Edges layer: which object-space edges of the mesh facets (comma list of "
                                      "contour, boundary, crease)")
      ->capture_default_str();
  app->add_option("--crease-angle", o.style.crease_angle,
                  "Edges layer: an edge is a crease where its two face normals differ by more than this, degrees")
      ->check(CLI::Range(0.0, 180.0))
      ->capture_default_str();
  app->add_option("--edge-caps", o.edge_caps,
                  "Edges layer: joins of consecutive edges: exact (mitred from the vertex's edges, no gap, no "
                  "overlap), cheap (square caps, no adjacency read) or none")
      ->check(CLI::IsMember({"exact", "cheap", "none"}))
      ->capture_default_str();
  app->add_option("--edge-width", o.style.edge_width, "Edges layer: width in pixels")
      ->check(CLI::Range(0.5, 20.0))
      ->capture_default_str();
  app->add_option("--edge-colour", o.edge_colour, "Edges layer: colour")->capture_default_str();
  app->add_option("--background", o.background, "Background colour (#rrggbb, r,g,b or a name)")->capture_default_str();
  app->add_option("--mask-colour", o.mask, "Surface colour of the mask layer")->capture_default_str();
  app->add_option("--crease-colour", o.crease_colour, "Crease colour")->capture_default_str();
  app->add_option("--silhouette-colour", o.silhouette_colour, "Silhouette colour")->capture_default_str();
  app->add_option("--crease-width", o.style.crease_width,
                  "Crease width in pixels where little drains (basin share 0); it grows with the square root "
                  "of the share of the basin that drains there")
      ->check(CLI::Range(0.5, 20.0))
      ->capture_default_str();
  app->add_option("--crease-width-max", o.style.crease_width_max, "Crease width in pixels at a basin's outlet (share 1)")
      ->check(CLI::Range(0.5, 20.0))
      ->capture_default_str();
  app->add_flag("!--aliased", o.style.antialias,
                "Pixel-exact lines: every crease and PEL pixel is the line colour or not (no coverage, no fade, "
                "no silhouette softening); for comparisons by pixel count");
  app->add_option("--crease-fade", o.style.crease_fade,
                  "Creases fade in over this band of the rendering score above the threshold instead of popping "
                  "in (0: cut at the threshold)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  app->add_option("--crease-bridge", o.style.crease_bridge,
                  "Draw a gap in a channel's crease up to this long (mesh spacings), where the score dips "
                  "between two drawn parts (0: no bridging)")
      ->check(CLI::Range(0.0, 100.0))
      ->capture_default_str();
  app->add_option("--crease-min-stroke", o.style.crease_min_stroke,
                  "Leave out crease strokes shorter than this (mesh spacings): dashes below the source mesh's "
                  "resolution (0: keep every stroke)")
      ->check(CLI::Range(0.0, 100.0))
      ->capture_default_str();
  app->add_option("--crease-hidden-gap", o.style.crease_hidden_gap,
                  "Draw a hidden run of a crease stroke up to this long (pixels) between its shown parts, when none "
                  "of it is more than --crease-hidden-depth behind the surface: a gully's floor, not dashes "
                  "(0: draw none)")
      ->check(CLI::Range(0.0, 256.0))
      ->capture_default_str();
  app->add_option("--crease-hidden-depth", o.style.crease_hidden_depth,
                  "How far behind the surface a hidden run drawn by --crease-hidden-gap may lie (mesh spacings)")
      ->check(CLI::Range(0.0, 100.0))
      ->capture_default_str();
  app->add_option("--crease-min-peek", o.style.crease_min_peek,
                  "Leave out a shown run of a crease stroke up to this long (pixels) beside a hidden part: a dot "
                  "where a channel peeks out between ridges (0: keep every run)")
      ->check(CLI::Range(0.0, 256.0))
      ->capture_default_str();
  app->add_option("--silhouette-width", o.style.silhouette_width,
                  "Silhouette width in pixels (anti-aliased: a band 0.8 px wider about the line of the silhouette "
                  "pixels)")
      ->check(CLI::Range(1, 9))
      ->capture_default_str();
  app->add_option("--silhouette-min-length", o.style.silhouette_min_length,
                  "Silhouette pieces (connected pixels) shorter than this share of the frame's height fade out, "
                  "to nothing at half of it: the scattered dashes of rolling ground seen from above (0: keep "
                  "every piece; anti-aliased lines only)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  app->add_option("--exaggeration", o.style.exaggeration, "Vertical exaggeration")
      ->check(CLI::Range(0.01, 100.0))
      ->capture_default_str();
  app->add_option("--crease-lift", o.style.crease_lift,
                  "Lines (creases, PELs, edges) are drawn where they lie on the surface, at the depth of their points moved this far (m) towards the eye, so the tessellated surface does not hide them in their valleys; default 0.5 x mesh spacing")
      ->check(CLI::NonNegativeNumber);
  app->add_option("--pixels-per-edge", o.style.pixels_per_edge,
                  "Adaptive tessellation target: screen length of a tessellated edge, pixels")
      ->check(CLI::Range(1.0, 100.0))
      ->capture_default_str();
}

// Resolves the string options; returns width and height.
std::pair<int, int> finish_options(RenderOptions& o, rr::Layers& layers) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(o.size.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X'))
    throw CLI::ValidationError("--size", "expected WIDTHxHEIGHT, e.g. 1280x720, got '" + o.size + "'");
  if (w < 16 || h < 16 || w > 16384 || h > 16384)
    throw CLI::ValidationError("--size", "width and height must be in 16 .. 16384");
  if (!o.eye.empty()) o.frame.camera.eye = Eigen::Vector3d(o.eye[0], o.eye[1], o.eye[2]);
  o.frame.score.literal_divisor = o.literal;
  o.rules.log_flow = o.flow_scale == "log";
  if (o.seed_rules)
    o.rules.edge_basin_min_share = 0, o.rules.log_flow = false, o.rules.one_line_per_flat = false,
    o.rules.smooth_spacings = 0;
  if (o.frame.score.sw + o.frame.score.iw + o.frame.score.fw <= 0)
    throw CLI::ValidationError("--sw/--iw/--fw", "at least one weight must be > 0");
  layers = rr::parse_layers(o.layers);
  o.style.background = rr::parse_colour(o.background);
  o.style.mask = rr::parse_colour(o.mask);
  o.style.crease_colour = rr::parse_colour(o.crease_colour);
  o.style.silhouette_colour = rr::parse_colour(o.silhouette_colour);
  o.style.pel_colour = rr::parse_colour(o.pel_colour);
  o.frame.pel.headlight = o.pel_light == "headlight";
  o.style.edge_kinds = rr::parse_edge_kinds(o.edges);
  o.style.edge_caps = o.edge_caps == "exact" ? rr::EdgeCaps::Exact
                      : o.edge_caps == "cheap" ? rr::EdgeCaps::Cheap
                                               : rr::EdgeCaps::None;
  o.style.edge_colour = rr::parse_colour(o.edge_colour);
  return {w, h};
}

struct Scene {
  terrain::GridMesh mesh;
  std::optional<rr::CreaseGeometry> creases;
  rr::SegmentTraits traits;  // of the creases' segments
  rr::SegmentChains chains;  // the strokes they follow, as the DM pass holds them
};

Scene load_scene(const std::string& mesh_path, const std::string& dv_path, const rr::CreaseRules& rules,
                 const tt::Verbosity& verb) {
  auto t0 = Clock::now();
  Scene s{terrain::read_mesh_ply(mesh_path), std::nullopt, {}, {}};
  tt::step(verb, fmt::format("read mesh {} x {} ({} patches): {:.2f} s", s.mesh.topo.cols, s.mesh.topo.rows,
                             s.mesh.n_faces(), since(t0)));
  if (!dv_path.empty()) {
    t0 = Clock::now();
    // Only the database's points under the mesh: a large (tiled) .dv is read block by block.
    const auto& g = s.mesh.geo;
    const terrain::DrainageLinks links = drainage::drainage_links_in(
        dv_path, g.origin_x, g.origin_y - double(s.mesh.topo.rows - 1) * g.dy,
        g.origin_x + double(s.mesh.topo.cols - 1) * g.dx, g.origin_y);
    s.creases = rr::build_crease_geometry(s.mesh, links, rules);
    std::string w = rr::coverage_warning(s.mesh, links);
    if (w.empty()) w = rr::surface_warning(s.mesh, *s.creases);  // one warning: the extent says it already
    if (!w.empty()) tt::warn(verb, "'" + dv_path + "': " + w);
    s.traits = rr::segment_traits(s.mesh, links, *s.creases);
    s.chains = rr::segment_chains(*s.creases);
    tt::step(verb, fmt::format("read {} and its PN normals: {} vertices, {} segments: {:.2f} s", dv_path,
                               s.creases->positions.size(), s.creases->n_segments(), since(t0)));
  }
  return s;
}

// --line-stats: the creases one frame draws (what the DM pass accepts, as the GL-free
// score gives it), with each segment's pixels left after hidden-line removal (its own
// line against the toward depth of `buffers`, the frame's read_buffers(), read once per
// frame).
struct FrameLines {
  std::vector<float> drawn;
  std::vector<double> pixels;
};
FrameLines frame_lines(const Scene& scene, const rr::TerrainRenderer& r, const rr::FrameResult& res,
                       const rr::FrameBuffers& buffers, const rr::FrameParams& fp, const rr::Style& style) {
  const double exaggeration = style.exaggeration;
  const rr::CreaseGeometry& g = *scene.creases;
  const rr::CreaseScoreParams score = rr::resolve_distances(fp.score, r.box().lo, r.box().hi, res.view.eye);
  const double fade = style.antialias ? style.crease_fade : 0.0;
  FrameLines lines{rr::segment_opacity(g, res.view.eye, terrain::light_direction(fp.light.azimuth, fp.light.altitude),
                                       exaggeration, score, fade, rr::stroke_rule(style, scene.mesh)),
                   {}};
  const double lift = rr::crease_lift(style, scene.mesh);
  if (style.antialias) {
    lines.pixels = rr::shown_pixels(rr::stroke_visibility(g, scene.chains, lines.drawn, res.view, exaggeration, lift,
                                                          buffers.toward_depth,
                                                          rr::stroke_visibility_rule(style, scene.mesh)));
    return lines;
  }
  lines.pixels = rr::segment_pixels(g, res.view, exaggeration);
  const auto visible = rr::visible_fraction(g, res.view, exaggeration, lift, buffers.toward_depth, false);
  for (std::size_t s = 0; s < visible.size(); ++s) lines.pixels[s] *= visible[s];
  return lines;
}

void check_line_stats(const RenderOptions& o, const rr::Layers& layers, const std::string& dv) {
  if (o.line_stats && (dv.empty() || !layers.creases))
    throw CLI::ValidationError("--line-stats", "measures creases: give a .dv and keep the creases layer");
}

void print_device(const rr::GlContext& ctx) {
  std::cout << "renderer: " << ctx.info().renderer << " (" << ctx.info().platform << ", OpenGL " << ctx.info().version
            << ")\n";
}

// Arguments of each subcommand, as CLI11 fills them.
struct FrameArgs {
  std::string mesh, dv, out;
  RenderOptions opts;
};
struct BatchArgs {
  std::vector<std::string> inputs;  // MESH [DV] FRAMES
  std::string dir;
  RenderOptions opts;
};
struct PathArgs {
  std::vector<double> from, to;
  int frames = 0;
  std::string out;
  rr::FrameParams params;
};

int list_devices() {
  for (const auto& d : rr::list_gl_devices())
    std::cout << d.platform << ": " << d.renderer << (d.version.empty() ? "" : " | OpenGL " + d.version)
              << (d.software ? " | software" : "") << (d.usable ? " | usable" : "")
              << (d.detail.empty() ? "" : " | " + d.detail) << "\n";
  rr::GlContext ctx;
  std::cout << "selected: " << ctx.info().platform << " (" << ctx.info().renderer << ")\n";
  return 0;
}

int run_path(const PathArgs& a, const std::string& prov) {
  terrain::check_output_path(a.out);
  rr::FlightPath p{Eigen::Vector3d(a.from[0], a.from[1], a.from[2]), Eigen::Vector3d(a.to[0], a.to[1], a.to[2]),
                   a.frames, a.params};
  terrain::write_file_atomic(a.out, "# " + prov + "\n" + rr::path_csv(p));
  std::cout << "output: " << a.out << "\nframes: " << a.frames << "\n";
  return 0;
}

int run_frame(FrameArgs& a, const std::string& prov, const tt::Verbosity& verb) {
  rr::Layers layers;
  const auto [w, h] = finish_options(a.opts, layers);
  if (!a.out.ends_with(".png")) throw terrain::Error("the output must be a .png file: '" + a.out + "'");
  tt::check_distinct_paths({a.mesh, a.dv}, {a.out});
  tt::warn_stale_temporaries(verb, {a.out});
  terrain::check_output_path(a.out);
  if (!a.dv.empty() && !drainage::is_dv_file(a.dv))
    throw terrain::Error("'" + a.dv + "' is not a drainage database (.dv)");
  check_line_stats(a.opts, layers, a.dv);
  const Scene scene = load_scene(a.mesh, a.dv, a.opts.rules, verb);
  rr::FrameParams& fp = a.opts.frame;
  if (!fp.camera.eye && !*a.opts.view_az) {  // the default view
    const auto rv = rr::relief_view(scene.mesh, a.opts.style.exaggeration, fp.camera.fov, double(w) / double(h),
                                    fp.camera.view_alt);
    fp.camera = rv.camera;
    if (!*a.opts.light_az && !*a.opts.light_alt) fp.light = rv.light;
    tt::step(verb, fmt::format("default view: the relief around {:.0f} {:.0f} ({:.0f} m), seen from bearing {:.0f}",
                               rv.centre.x(), rv.centre.y(), rv.relief, std::fmod(rv.camera.view_az + 180, 360.0)));
  }
  if (fp.camera.eye) rr::check_eye_above_terrain(scene.mesh, *fp.camera.eye, a.opts.style.exaggeration);
  auto t0 = Clock::now();
  rr::GlContext ctx;
  rr::TerrainRenderer r(ctx, scene.mesh, scene.creases ? &*scene.creases : nullptr, w, h, layers, a.opts.style);
  tt::step(verb, fmt::format("OpenGL set-up ({}): {:.2f} s", ctx.info().renderer, since(t0)));
  const rr::FrameResult res = r.render(a.opts.frame);
  terrain::write_png(a.out, w, h, 4, res.rgba, prov);
  const Eigen::Vector3d eye = res.view.eye + r.origin();
  std::cout << "output: " << a.out << "\n"
            << "size: " << w << " x " << h << "\n";
  print_device(ctx);
  std::cout << fmt::format("eye: {:.1f} {:.1f} {:.1f}\n", eye.x(), eye.y(), eye.z())
            << fmt::format("view: az {:g} alt {:g} fov {:g}\n", fp.camera.view_az, fp.camera.view_alt, fp.camera.fov)
            << fmt::format("light: az {:g} alt {:g}\n", fp.light.azimuth, fp.light.altitude)
            << "crease segments drawn: " << res.crease_segments << "\n"
            << "pel segments drawn: " << res.pel_segments << "\n"
            << "edges drawn: " << res.edges << "\n";
  for (int p = 0; p < rr::kPassCount; ++p)
    std::cout << fmt::format("{} ms: {:.2f} (wall {:.2f})\n", rr::pass_name(p), res.timings.gpu_ms[p],
                             res.timings.wall_ms[p]);
  if (a.opts.line_stats) {
    const rr::FrameBuffers buffers = r.read_buffers();
    const FrameLines lines = frame_lines(scene, r, res, buffers, a.opts.frame, a.opts.style);
    const rr::LineStats st = rr::line_stats(*scene.creases, scene.traits, lines.drawn, lines.pixels);
    std::cout << fmt::format("crease length px: {:.0f}\ncrease boundary share: {:.4f}\ncrease flat share: {:.4f}\n"
                             "crease valley share: {:.4f}\ncrease strokes: {}\ncrease mean stroke px: {:.1f}\n"
                             "crease strokes, opacity-weighted: {:.1f}\ncrease mean stroke px, opacity-weighted: {:.1f}\n",
                             st.length_px, st.boundary, st.flat, st.valley, st.strokes, st.mean_stroke_px,
                             st.weighted_strokes, st.weighted_mean_stroke_px);
    if (layers.silhouettes) {
      const rr::SilhouetteStats ss = rr::silhouette_stats(buffers.silhouette_opacity, w, h);
      std::cout << fmt::format("silhouette px: {:.0f}\nsilhouette pieces: {}\nsilhouette mean piece px: {:.1f}\n",
                               ss.pixels, ss.pieces, ss.mean_piece_px);
    }
  }
  return 0;
}

std::string frame_name(std::size_t i) { return fmt::format("frame_{:05d}.png", i); }

int run_batch(BatchArgs& a, const std::string& prov, const tt::Verbosity& verb) {
  rr::Layers layers;
  const auto [w, h] = finish_options(a.opts, layers);
  const std::string mesh_path = a.inputs[0], csv = a.inputs.back();
  const std::string dv_path = a.inputs.size() == 3 ? a.inputs[1] : "";
  if (!dv_path.empty() && !drainage::is_dv_file(dv_path))
    throw terrain::Error("'" + dv_path + "' is not a drainage database (.dv)");
  const auto frames = rr::read_frames_csv(csv, a.opts.frame);
  const std::filesystem::path dir(a.dir);
  // Every file the batch writes, checked against every input (a frames CSV or a mesh named
  // like an output is never replaced): the frames, the timings and the statistics.
  std::vector<std::string> outputs = {(dir / "timings.csv").string()};
  if (a.opts.line_stats) outputs.push_back((dir / "line_stats.csv").string());
  for (std::size_t i = 0; i < frames.size(); ++i) outputs.push_back((dir / frame_name(i)).string());
  for (const std::string& out : outputs) tt::check_distinct_paths(a.inputs, {out});
  std::filesystem::create_directories(dir);
  terrain::check_output_path(dir / "timings.csv");
  tt::warn_stale_temporaries(verb, outputs);
  check_line_stats(a.opts, layers, dv_path);
  const Scene scene = load_scene(mesh_path, dv_path, a.opts.rules, verb);
  for (std::size_t i = 0; i < frames.size(); ++i) {
    try {
      if (frames[i].camera.eye) rr::check_eye_above_terrain(scene.mesh, *frames[i].camera.eye, a.opts.style.exaggeration);
    } catch (const terrain::Error& e) {
      throw terrain::Error(fmt::format("{}: frame {}: {}", csv, i + 1, e.what()));
    }
  }
  rr::GlContext ctx;
  rr::TerrainRenderer r(ctx, scene.mesh, scene.creases ? &*scene.creases : nullptr, w, h, layers, a.opts.style);
  std::vector<rr::FrameTimings> timings;
  std::string stats_csv =
      "frame,length_px,boundary_share,flat_share,valley_share,strokes,mean_stroke_px,silhouette_px,silhouette_pieces,"
      "weighted_strokes,weighted_mean_stroke_px\n";
  std::vector<std::vector<float>> drawn;
  std::vector<std::vector<double>> pixels;
  const auto progress = tt::terminal_progress(verb, "render");
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const rr::FrameResult res = r.render(frames[i]);
    timings.push_back(res.timings);
    if (a.opts.line_stats) {
      const rr::FrameBuffers buffers = r.read_buffers();
      FrameLines lines = frame_lines(scene, r, res, buffers, frames[i], a.opts.style);
      const rr::LineStats st = rr::line_stats(*scene.creases, scene.traits, lines.drawn, lines.pixels);
      rr::SilhouetteStats ss;
      if (layers.silhouettes) ss = rr::silhouette_stats(buffers.silhouette_opacity, w, h);
      stats_csv += fmt::format("{},{:.1f},{:.5f},{:.5f},{:.5f},{},{:.2f},{:.0f},{},{:.2f},{:.2f}\n", i, st.length_px,
                               st.boundary, st.flat, st.valley, st.strokes, st.mean_stroke_px, ss.pixels, ss.pieces,
                               st.weighted_strokes, st.weighted_mean_stroke_px);
      drawn.push_back(std::move(lines.drawn));
      pixels.push_back(std::move(lines.pixels));
    }
    terrain::write_png((dir / frame_name(i)).string(), w, h, 4, res.rgba,
                       prov + fmt::format(" [frame {}]", i));
    terrain::report(progress, double(i + 1) / double(frames.size()));
  }
  terrain::write_file_atomic(dir / "timings.csv", rr::timings_csv(timings));
  if (a.opts.line_stats) terrain::write_file_atomic(dir / "line_stats.csv", stats_csv);
  std::cout << "output: " << a.dir << "\nframes: " << frames.size() << "\nsize: " << w << " x " << h << "\n";
  print_device(ctx);
  std::cout << rr::timing_tables(timings);
  if (a.opts.line_stats) std::cout << fmt::format("crease flicker: {:.4f}\n", rr::flicker(drawn, pixels));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Render PN-triangle terrain with drainage creases and Toward/Away silhouettes, headless\n"
               "(OpenGL 4.5 through EGL: a GPU where there is one, Mesa llvmpipe otherwise).",
               "terrain-render"};
  app.footer(
      "Examples:\n"
      "  terrain-render frame out/msh_50m.ply out/msh.dv -o msh.png\n"
      "  terrain-render frame out/msh_50m.ply out/msh.dv -o msh_shaded.png --layers shaded --view-az 180\n"
      "  terrain-render path --from 560000 5120000 2600 --to 563000 5117000 2600 --frames 99 -o path.csv\n"
      "  terrain-render batch out/msh_50m.ply out/msh.dv path.csv -o frames/\n"
      "  terrain-render frame out/msh_10m_denoised.ply -o pels.png --layers mask,pels,silhouettes\n"
      "  terrain-render frame out/msh_50m.ply -o edges.png --layers mask,edges --edges contour,crease --crease-angle 20\n"
      "  terrain-render --device\n\n"
      "See docs/terrain-render.md for the passes, the crease score and the camera conventions.");
  app.set_version_flag("--version", tt::version());
  app.require_subcommand(0, 1);
  app.fallthrough();  // -q / -v after the subcommand
  bool list_devices_flag = false;
  app.add_flag("--device", list_devices_flag, "List the EGL devices and OpenGL renderers found, then exit");
  tt::Verbosity verb;
  tt::add_verbosity_flags(app, verb);

  // frame
  auto* frame_cmd = app.add_subcommand("frame", "Render one frame to a PNG");
  FrameArgs fa;
  frame_cmd->add_option("MESH", fa.mesh, "Mesh (.ply from dem2mesh)")->required();
  frame_cmd->add_option("DV", fa.dv, "Drainage database (.dv from build-drainage); no creases without it");
  frame_cmd->add_option("-o,--output", fa.out, "Output PNG")->required();
  add_render_options(frame_cmd, fa.opts);

  // batch
  auto* batch_cmd = app.add_subcommand("batch", "Render every frame of a CSV list; write PNGs and timings.csv");
  BatchArgs ba;
  batch_cmd->add_option("MESH [DV] FRAMES", ba.inputs, "Mesh, optional drainage database, frame list (CSV)")
      ->required()
      ->expected(2, 3);
  batch_cmd->add_option("-o,--output", ba.dir, "Output directory (created if missing)")->required();
  add_render_options(batch_cmd, ba.opts);

  // path
  auto* path_cmd = app.add_subcommand("path", "Write a straight flight path as a frame list (CSV)");
  PathArgs pa;
  rr::FrameParams& path_params = pa.params;
  path_params.camera.view_az = std::numeric_limits<double>::quiet_NaN();
  path_params.camera.view_alt = 10.0;
  path_cmd->add_option("--from", pa.from, "Start viewpoint E N Z (metres)")->expected(3)->required();
  path_cmd->add_option("--to", pa.to, "End viewpoint E N Z (metres)")->expected(3)->required();
  path_cmd->add_option("--frames", pa.frames, "Number of frames (>= 2)")->check(CLI::Range(2, 1000000))->required();
  path_cmd->add_option("--view-az", path_params.camera.view_az, "Bearing of the line of sight; default: along the path");
  path_cmd->add_option("--view-alt", path_params.camera.view_alt, "Angle of the line of sight below the horizon")
      ->check(CLI::Range(-90.0, 90.0))
      ->capture_default_str();
  path_cmd->add_option("--fov", path_params.camera.fov, "Vertical field of view, degrees")
      ->check(CLI::Range(1.0, 170.0))
      ->capture_default_str();
  path_cmd->add_option("--light-az", path_params.light.azimuth, "Light azimuth")->capture_default_str();
  path_cmd->add_option("--light-alt", path_params.light.altitude, "Light altitude")->capture_default_str();
  path_cmd->add_option("--min-score", path_params.score.min_score, "Crease minimum score")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  path_cmd->add_option("-o,--output", pa.out, "Output CSV")->required();

  return tt::run_main(app, argc, argv, [&]() -> int {
    if (list_devices_flag) return list_devices();
    const std::string prov = tt::provenance(argc, argv);
    if (path_cmd->parsed()) return run_path(pa, prov);
    if (frame_cmd->parsed()) return run_frame(fa, prov, verb);
    if (batch_cmd->parsed()) return run_batch(ba, prov, verb);
    throw CLI::ValidationError("terrain-render", "give a subcommand: frame, batch or path (or --device)");
  });
}
