#include "renderer/scene/frame_setup.hpp"

#include <fmt/format.h>
#include <Eigen/LU>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>

#include "renderer/core/camera.hpp"
#include "renderer/core/frames.hpp"
#include "renderer/core/plan_map.hpp"
#include "renderer/core/vector_file.hpp"
#include "terrain/atomic_file.hpp"
#include "terrain/error.hpp"
#include "terrain/image_io.hpp"
#include "terrain/memory.hpp"
#include "terrain/xml_text.hpp"

namespace renderer {

std::string resolve_settings(RenderSettings& s, const terrain::GridMesh& mesh,
                             const GivenOption& given) {
  if (given("exaggeration")) return fmt::format("exaggeration: {:g}", s.style.exaggeration);
  s.style.exaggeration = auto_exaggeration(mesh);
  return fmt::format("exaggeration: {:g} (automatic)", s.style.exaggeration);
}

ResolvedFrame drawn_frame(const RenderSettings& s) {
  return {s.frame, drawn_style(s), s.layers, s.width, s.height, ""};
}

ResolvedFrame resolve_frame(const RenderSettings& s, const terrain::GridMesh& mesh,
                            const GivenOption& given) {
  ResolvedFrame f = drawn_frame(s);
  Camera& camera = f.frame.camera;
  if (!camera.eye && !given("view-az") && s.view == ViewMode::Row) {  // --view FRAMES.csv:N
    f.frame = view_row_frame(s.view_row, f.frame);
    f.description = "view: " + s.view_row;
  } else if (!camera.eye && !given("view-az")) {  // the default view: --view
    const DefaultView dv = default_view(
        mesh, s.view, s.style.exaggeration, camera.fov, double(s.width) / double(s.height),
        given("view-alt") ? std::optional<double>(camera.view_alt) : std::nullopt);
    const double map_scale = camera.map_scale;
    camera = dv.camera;
    camera.map_scale = map_scale;
    if (!given("light-az") && !given("light-alt")) f.frame.light = dv.light;
    f.description = dv.description;
  } else if (camera.eye && s.view == ViewMode::Top && (!given("view-az") || camera.view_az == 0) &&
             (!given("view-alt") || camera.view_alt == 90)) {
    camera.orthographic =
        true;  // the map centred under the eye: a panned map, as terrain-view saves one
    camera.view_az = 0;
    camera.view_alt = 90;
  }
  if (given("map-scale") && !camera.orthographic)
    throw terrain::Error(
        "--map-scale needs the orthographic view: --view top, with no --eye or one straight down, "
        "north "
        "up (--view-az 0 --view-alt 90)");
  if (camera.eye) check_eye_above_terrain(mesh, *camera.eye, s.style.exaggeration);
  return f;
}

void check_vector_memory(const GlContext& ctx, int width, int height) {
  constexpr double kVectorBytesPerPixel = 28.0;
  terrain::check_memory(
      double(width) * double(height) * (kVectorBytesPerPixel + (ctx.info().software ? 64.0 : 0.0)),
      fmt::format("the vector output of a {} x {} frame", width, height),
      "give a smaller --size, or write a PNG");
}

void check_frame_path(const std::string& path) {
  if (frame_format(path)) return;
  std::string kinds;  // ".png, .svg or .pdf": the formats' table
  const std::size_t n = std::size(kFrameFormats);
  for (std::size_t i = 0; i < n; ++i)
    kinds += (i == 0 ? "." : i + 1 < n ? ", ." : " or .") + std::string(kFrameFormats[i].name);
  throw terrain::Error("the output must be a " + kinds + " file: '" + path + "'");
}

double terrain_share(const terrain::GridMesh& mesh, const View& view, const Box& box, double e) {
  const std::size_t rows = mesh.topo.rows, cols = mesh.topo.cols;
  const std::size_t sr = std::max<std::size_t>(1, (rows - 1) / 256),
                    sc = std::max<std::size_t>(1, (cols - 1) / 256);
  // The frame's cells of kCell x kCell pixels that a vertex facing the eye projects into.
  constexpr int kCell = 16;
  const int cw = (view.width + kCell - 1) / kCell, ch = (view.height + kCell - 1) / kCell;
  std::vector<std::uint8_t> hit(std::size_t(cw) * std::size_t(ch), 0);
  const auto take = [&](std::size_t r, std::size_t c) {
    const Eigen::Vector3f& p = mesh.positions[r * cols + c];
    const Eigen::Vector3d x(p.x(), p.y(), double(p.z()) * e);
    const Eigen::Vector3f& n = mesh.normals[r * cols + c];
    const Eigen::Vector3d ne(n.x(), n.y(), double(n.z()) / e);  // the drawn surface's
    const Eigen::Vector3d to_eye =
        view.orthographic() ? Eigen::Vector3d(-view.forward) : Eigen::Vector3d(view.eye - x);
    if (to_eye.dot(ne) <= 0) return;  // seen from behind (from below the terrain)
    const Projected q = project(view, x);
    if (!q.in_front || !(q.u >= 0 && q.u < view.width && q.v >= 0 && q.v < view.height)) return;
    hit[std::size_t(int(q.v) / kCell) * std::size_t(cw) + std::size_t(int(q.u) / kCell)] = 1;
  };
  const auto lines = [](std::size_t n, std::size_t step) {  // 0, step, 2 step, ... and n - 1
    std::vector<std::size_t> v;
    for (std::size_t k = 0; k < n - 1; k += step) v.push_back(k);
    v.push_back(n - 1);
    return v;
  };
  const std::vector<std::size_t> rs = lines(rows, sr), cs = lines(cols, sc);
  for (const std::size_t r : rs)
    for (const std::size_t c : cs) take(r, c);
  // A view nearer than the vertices' spacing holds none of them: a cell whose centre's line
  // of sight crosses the terrain's box, in front of the eye, counts too (slabs).
  const Eigen::Vector3d &box_lo = box.lo, &box_hi = box.hi;
  const Eigen::Matrix4d inverse = view.view_projection().inverse();
  for (int j = 0; j < ch; ++j)
    for (int i = 0; i < cw; ++i) {
      std::uint8_t& h = hit[std::size_t(j) * std::size_t(cw) + std::size_t(i)];
      if (h) continue;
      const double u = std::min((i + 0.5) * kCell, view.width - 0.5),
                   v = std::min((j + 0.5) * kCell, view.height - 0.5);
      const Eigen::Vector3d a = unproject(view, inverse, u, v, view.reversed_z ? 1.0 : 0.0);
      const Eigen::Vector3d d = unproject(view, inverse, u, v, 0.5) - a;
      double t0 = 0, t1 = std::numeric_limits<double>::infinity();
      for (int k = 0; k < 3 && t0 <= t1; ++k) {
        if (std::abs(d[k]) < 1e-300) {
          if (a[k] < box_lo[k] || a[k] > box_hi[k]) t0 = 1, t1 = 0;
          continue;
        }
        double ta = (box_lo[k] - a[k]) / d[k], tb = (box_hi[k] - a[k]) / d[k];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta), t1 = std::min(t1, tb);
      }
      h = t0 <= t1;
    }
  return double(std::count(hit.begin(), hit.end(), 1)) / double(hit.size());
}

std::string no_terrain_problem(const terrain::GridMesh& mesh, const View& view, const Box& box,
                               double e) {
  // An eye below the lowest vertex sees the terrain's underside.
  if (!view.orthographic() && view.eye.z() < box.lo.z())
    return fmt::format(
        "the eye lies {:.0f} m below the terrain's lowest point and sees only its underside: look "
        "down at it (a --view-alt above 0), or give an --eye above it",
        box.lo.z() - view.eye.z());
  const double share = terrain_share(mesh, view, box, e);
  if (share >= kMinTerrainShare) return {};
  const std::string what =
      fmt::format("the frame shows {} of the terrain (about {:.2g} % of its {} x {} pixels)",
                  share > 0 ? "almost nothing" : "nothing", 100 * share, view.width, view.height);
  if (view.orthographic() && share == 0)
    return what +
           ": the map's centre (--eye) lies off the terrain; move it onto the terrain, or give no "
           "--eye";
  if (view.orthographic()) {  // the scale at which the terrain's extent fills the frame
    const double fill = std::max(double(mesh.topo.cols - 1) * mesh.geo.dx / view.width,
                                 double(mesh.topo.rows - 1) * mesh.geo.dy / view.height);
    return what + fmt::format(": --map-scale {:g} is too coarse; give {:.3g} or less",
                              view.map_scale, fill);
  }
  if (share > 0)
    return what + ": the eye is too far from it; bring --eye nearer or give a narrower --fov";
  return what +
         ": the view looks away from it, or at it from below; turn it toward the terrain from "
         "above "
         "(--eye, --view-az, --view-alt), or give no camera options for the automatic view";
}

std::vector<std::string> frame_files(const std::string& path, bool map) {
  const FrameFormat* f = frame_format(path);
  if (!map || !f || !f->world_file) return {path};
  return {path, std::filesystem::path(path).replace_extension(".pgw").string(), path + ".aux.xml"};
}

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// A GDAL PAM file (NAME.png.aux.xml) holding the CRS `wkt`: GDAL and QGIS read a PNG's CRS
// from it, as they read its geotransform from the world file.
std::string pam_crs(const std::string& wkt) {
  const std::string escaped = terrain::xml_escaped(wkt);
  return "<PAMDataset>\n" +
         (wkt.empty() ? std::string()
                      : "  <SRS dataAxisToSRSAxisMapping=\"1,2\">" + escaped + "</SRS>\n") +
         "</PAMDataset>\n";
}

// The frame's PNGs, the overlays drawn over the pixels, a map's with its world file.
void write_pngs(const std::vector<std::string>& pngs, const FrameResult& res, FrameOverlays& over,
                const std::optional<std::array<double, 6>>& gt, const std::string& crs_wkt,
                const std::string& description, WriteTimes& t) {
  std::vector<std::uint8_t> drawn;
  if (over.any()) {
    const auto t0 = Clock::now();
    drawn = res.rgba;
    draw_overlays(over, res.width, res.height, drawn);
    t.hachure_draw_ms = ms_since(t0);
  }
  for (const std::string& p : pngs) {
    const std::vector<std::string> files = frame_files(p, bool(gt));
    terrain::OutputSet outputs;  // the PNG and its world file
    const std::vector<std::uint8_t>& pixels = over.any() ? drawn : res.rgba;
    outputs.write([&] {
      if (std::string(frame_format(p)->name) == "tif")  // its georeference inside
        terrain::write_rgba_geotiff(outputs.stage(p), res.width, res.height, pixels, gt,
                                    gt ? crs_wkt : std::string(), description);
      else
        terrain::write_png(outputs.stage(p), res.width, res.height, 4, pixels, description);
      if (files.size() > 1) terrain::write_file_atomic(outputs.stage(files[1]), world_file(*gt));
      if (files.size() > 2)  // the CRS, where GDAL and QGIS look for it (empty without one)
        terrain::write_file_atomic(outputs.stage(files[2]), pam_crs(crs_wkt));
    });
    outputs.commit();
  }
}

// The frame's SVG and PDF files: its vector art with the overlays as its lowest and top
// line layers.
void write_vector_files(const std::vector<std::string>& vectors, const Scene& scene,
                        const TerrainRenderer& r, const FrameResult& res,
                        const FrameBuffers& buffers, const ResolvedFrame& f, const VectorOptions& o,
                        FrameOverlays& over, const std::optional<std::array<double, 6>>& gt,
                        const std::string& description, WriteTimes& t) {
  auto t0 = Clock::now();
  const std::string underlay = !o.underlay.empty() ? o.underlay
                               : f.layers.shaded   ? "shaded"
                                                   : "mask";
  VectorArt art = frame_vector_art(scene, r, res, buffers, f.frame, f.style, f.layers,
                                   parse_underlay(underlay));
  if (over.hachures) art.layers.insert(art.layers.begin(), std::move(*over.hachures));
  if (over.ridges) art.layers.push_back(std::move(*over.ridges));
  if (over.outline) art.layers.push_back(std::move(*over.outline));
  if (art.layers.empty() && art.underlay == VectorUnderlay::None)
    throw terrain::Error(std::string("the vector file would be empty: --layers draws no lines") +
                         (f.layers.creases && !scene.creases ? " (creases need a .dv)" : "") +
                         " and --vector-underlay is none");
  t.paths_ms += ms_since(t0);
  for (const VectorLayer& l : art.layers)
    t.layers += fmt::format(", {} {} paths ({} strokes)", l.name, l.paths.size(), l.strokes);
  for (const std::string& p : vectors) {
    t0 = Clock::now();
    if (std::string(frame_format(p)->name) == "gpkg") {  // a map's lines in map coordinates
      if (!gt)
        throw terrain::Error("'" + p +
                             "': a GeoPackage holds a map's lines in map coordinates: give "
                             "--view top (the orthographic map)");
      write_map_gpkg(art, *gt, scene.mesh.geo.crs_wkt, o.dpi, p);
      t.cairo_ms += ms_since(t0);
      continue;
    }
    const std::string bytes = vector_bytes(art, vector_format_of(p), o.dpi, description);
    t.cairo_ms += ms_since(t0);
    t.vector_bytes += bytes.size();
    terrain::write_file_atomic(p, bytes);
  }
}

}  // namespace

WriteTimes write_frame_files(const std::vector<std::string>& paths, const Scene& scene,
                             const TerrainRenderer& r, const FrameResult& res,
                             const ResolvedFrame& f, const VectorOptions& o,
                             const std::string& frame_description, TracedHachures* traced) {
  WriteTimes t;
  std::vector<std::string> vectors, pngs;
  for (const std::string& p : paths) {
    check_frame_path(p);
    (is_vector_path(p) ? vectors : pngs).push_back(p);
  }
  // A map (the orthographic top view): its geotransform in every file, a world file by the PNG.
  const auto gt = map_geotransform(res.view, r.origin());
  const std::string description =
      gt ? frame_description + "; map: orthographic, " + map_note(*gt, scene.mesh.geo.epsg)
         : frame_description;
  std::optional<FrameBuffers> buffers;
  auto t0 = Clock::now();
  if (draws_overlays(scene, f.layers, f.style) || !vectors.empty()) {
    buffers = r.read_buffers();
    t.readback_ms = ms_since(t0);
  }
  // The hachures and ridge lines are made on the CPU from the frame's depth, once: drawn
  // over the PNG; the lowest and the top line layers of the vector files.
  t0 = Clock::now();
  FrameOverlays over;
  if (buffers) over = frame_overlays(scene, r, res, *buffers, f.style, f.layers);
  if (traced && over.traced) *traced = std::move(*over.traced);
  t.paths_ms = t.hachure_ms = ms_since(t0);
  if (!pngs.empty()) write_pngs(pngs, res, over, gt, scene.mesh.geo.crs_wkt, description, t);
  if (!vectors.empty())
    write_vector_files(vectors, scene, r, res, *buffers, f, o, over, gt, description, t);
  return t;
}

}  // namespace renderer
