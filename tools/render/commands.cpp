#include "render/commands.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <map>

#include "drainage/dv_file.hpp"
#include "renderer/core/camera.hpp"
#include "renderer/core/frames.hpp"
#include "renderer/core/options.hpp"
#include "renderer/core/plan_map.hpp"
#include "renderer/core/vector_file.hpp"
#include "renderer/gl/gl_context.hpp"
#include "renderer/gl/terrain_renderer.hpp"
#include "renderer/scene/frame_setup.hpp"
#include "renderer/scene/scene.hpp"
#include "terrain/atomic_file.hpp"
#include "terrain/dem_io.hpp"
#include "terrain/image_io.hpp"
#include "terrain/memory.hpp"

namespace terrain::tools::render {

namespace tt = terrain::tools;
namespace rr = renderer;

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// The scene's warnings from the `first` on (those not reported yet), and its creases.
void report_creases(const rr::Scene& scene, const std::string& dv, const tt::Verbosity& v,
                    std::size_t first = 0) {
  for (std::size_t i = first; i < scene.warnings.size(); ++i) tt::warn(v, scene.warnings[i]);
  if (scene.creases)
    tt::step(v,
             fmt::format(
                 "read {} and its PN normals: {} vertices, {} segments, {} ridge lines: {:.2f} s "
                 "(the ridge lines {:.2f} s)",
                 dv, scene.creases->positions.size(), scene.creases->n_segments(),
                 scene.ridges.size(), scene.creases_seconds, scene.ridges_seconds));
}

// A scene read at a coarser level (--memory) read again at the level `cameras`' views draw,
// with its creases (with `window`, only its blocks in view: hold_views); reported at -v. Nothing
// for a scene read whole.
void focus(rr::Scene& scene, const std::vector<rr::Camera>& cameras, const rr::RenderSettings& s,
           const rr::Style& style, const std::string& dv, const tt::Verbosity& v,
           bool window = false) {
  const std::size_t reported = scene.warnings.size();  // by scene_of
  const std::string note = rr::hold_views(scene, cameras, s.width, s.height, style,
                                          window ? rr::HoldFor::Frame : rr::HoldFor::Frames);
  if (note.empty()) return;
  tt::step(v, fmt::format("{}: {} x {} vertices, {:.2f} s", note, scene.mesh.topo.cols,
                          scene.mesh.topo.rows, scene.mesh_seconds));
  report_creases(scene, dv, v, reported);
}

// `vertex_bytes`: load_scene's bound on the mesh's vertices (0: none).
rr::Scene scene_of(const std::string& mesh, const std::string& dv, const rr::RenderSettings& s,
                   const tt::Verbosity& v, std::uint64_t vertex_bytes = 0) {
  if (!dv.empty() && !drainage::is_dv_file(dv))
    throw terrain::Error("'" + dv + "' is not a drainage database (.dv)");
  rr::Scene scene = rr::load_scene(mesh, dv, s.rules, vertex_bytes);
  tt::step(v, fmt::format("read mesh {} x {} ({} patches) from {}: {:.2f} s", scene.mesh.topo.cols,
                          scene.mesh.topo.rows, scene.mesh.n_faces(), scene.mesh_source,
                          scene.mesh_seconds));
  report_creases(scene, dv, v);
  return scene;
}

void check_line_stats(const TableArgs& a, const rr::RenderSettings& s, const std::string& dv) {
  if (a.line_stats && (dv.empty() || !s.layers.creases))
    throw CLI::ValidationError("--line-stats",
                               "measures creases: give a .dv and keep the creases layer");
}

// " (of ..., merged: up to 8 segments in one, within ... m)" for a frame drawn at a coarser crease
// level.
std::string crease_level_text(const rr::Scene& scene, const rr::FrameResult& res) {
  if (res.crease_level == 0 || !scene.crease_levels ||
      std::size_t(res.crease_level) > scene.crease_levels->size())
    return "";
  const rr::CreaseLevel& l = (*scene.crease_levels)[std::size_t(res.crease_level - 1)];
  return fmt::format(" (of {}, merged: up to {} segments in one, within {:.1f} m)",
                     l.geometry.n_segments(), l.step, l.error_metres);
}

void print_device(const rr::GlContext& ctx) {
  std::cout << "renderer: " << ctx.info().renderer << " (" << ctx.info().platform << ", OpenGL "
            << ctx.info().version << ")\n";
}

}  // namespace

int list_devices() {
  for (const auto& d : rr::list_gl_devices())
    std::cout << d.platform << ": " << d.renderer
              << (d.version.empty() ? "" : " | OpenGL " + d.version)
              << (d.software ? " | software" : "") << (d.usable ? " | usable" : "")
              << (d.detail.empty() ? "" : " | " + d.detail) << "\n";
  rr::GlContext ctx;
  std::cout << "selected: " << ctx.info().platform << " (" << ctx.info().renderer << ")\n";
  return 0;
}

int run_path(const TableArgs& a, const std::vector<double>& from, const std::vector<double>& to,
             int frames, const std::string& out, const std::string& prov) {
  terrain::check_output_path(out);
  rr::FrameParams params = settings_of(a).frame;
  if (!a.was_given("view-az"))
    params.camera.view_az = std::numeric_limits<double>::quiet_NaN();  // along the path
  const rr::FlightPath p{Eigen::Vector3d(from[0], from[1], from[2]),
                         Eigen::Vector3d(to[0], to[1], to[2]), frames, params};
  terrain::write_file_atomic(out, "# " + prov + "\n" + rr::path_csv(p));
  std::cout << "output: " << out << "\nframes: " << frames << "\n";
  return 0;
}

void add_output_options(CLI::App* cmd, OutputArgs& o, bool batch) {
  add_vector_options(cmd, o.vector);
  if (batch)
    cmd->add_option("--format", o.formats, "Files per frame, a comma list of png, svg, pdf")
        ->capture_default_str();
  add_vertex_memory_option(cmd, o.memory_mib,
                           batch ? "at the finest level any frame's view draws, within this"
                                 : "at the finest level the view draws over the blocks in view, "
                                   "within this");
}

// The write times at -v.
void report_write(const tt::Verbosity& verb, const std::vector<std::string>& outs,
                  const rr::WriteTimes& t) {
  if (t.vector_bytes == 0) return;
  tt::step(verb,
           fmt::format("{}: GPU readback {:.0f} ms, paths {:.0f} ms, cairo {:.0f} ms, {:.2f} MB{}",
                       fmt::join(outs, ", "), t.readback_ms, t.paths_ms, t.cairo_ms,
                       double(t.vector_bytes) / 1e6, t.layers));
}

// What terrain-render frame prints: the file, the device, the view, the lines drawn, the
// map's georeference and the passes' times.
void print_frame(const std::string& out, const rr::GlContext& ctx, const rr::Scene& scene,
                 const rr::TerrainRenderer& r, const rr::FrameResult& res,
                 const rr::ResolvedFrame& f, const std::string& exaggeration,
                 const rr::WriteTimes& wt) {
  const rr::FrameParams& fp = f.frame;
  const Eigen::Vector3d eye = res.view.eye + r.origin();
  std::cout << "output: " << out << "\n"
            << "size: " << res.width << " x " << res.height << "\n";
  print_device(ctx);
  std::cout << fmt::format("eye: {:.1f} {:.1f} {:.1f}\n", eye.x(), eye.y(), eye.z())
            << (res.view.orthographic()
                    ? fmt::format("view: orthographic, az {:g} alt {:g}, {:g} m a pixel\n",
                                  fp.camera.view_az, fp.camera.view_alt, res.view.map_scale)
                    : fmt::format("view: az {:g} alt {:g} fov {:g}\n", fp.camera.view_az,
                                  fp.camera.view_alt, fp.camera.fov))
            << fmt::format("light: az {:g} alt {:g}\n", fp.light.azimuth, fp.light.altitude)
            << exaggeration << "\n"
            << "crease segments drawn: " << res.crease_segments << crease_level_text(scene, res)
            << "\n"
            << "pel segments drawn: " << res.pel_segments << "\n"
            << "edges drawn: " << res.edges << "\n"
            << "surface patches drawn: " << res.patches << " of " << scene.mesh.n_faces() << "\n";
  if (const auto gt = rr::map_geotransform(res.view, r.origin())) {
    std::cout << "geotransform: " << rr::geotransform_text(*gt) << "\n";
    if (const std::vector<std::string> files = rr::frame_files(out, true); files.size() > 1)
      std::cout << "world file: " << files[1] << "\n";
  }
  for (int p = 0; p < rr::kPassCount; ++p)
    std::cout << fmt::format("{} ms: {:.2f} (wall {:.2f})\n", rr::pass_name(p),
                             res.timings.gpu_ms[p], res.timings.wall_ms[p]);
  if (f.layers.hachures)  // the field (GPU), the lines read back, the tracing (CPU); then cairo on
                          // the PNG
    std::cout << fmt::format(
        "hachures ms: {:.2f} (lines read back {:.2f}; then drawn on the PNG {:.2f})\n",
        wt.hachure_ms + wt.readback_ms, wt.readback_ms, wt.hachure_draw_ms);
}

int run_frame(const TableArgs& a, const OutputArgs& o, const std::string& mesh,
              const std::string& dv, const std::string& out, const std::string& prov,
              const tt::Verbosity& verb) {
  rr::RenderSettings s = settings_of(a);
  rr::check_frame_path(out);
  // A GeoTIFF is laid over other layers in a GIS: its background transparent unless given.
  if (std::string(rr::frame_format(out)->name) == "tif" && !a.was_given("background"))
    s.style.transparent = true;
  tt::check_distinct_paths({mesh, dv}, {out});
  tt::warn_stale_temporaries(verb, {out});
  terrain::check_output_path(out);
  check_line_stats(a, s, dv);
  rr::Scene scene = scene_of(mesh, dv, s, verb, std::uint64_t(o.memory_mib * 1048576.0));
  const rr::GivenOption given = [&](const std::string& n) { return a.was_given(n); };
  const std::string exaggeration = rr::resolve_settings(s, scene.mesh, given);
  const rr::ResolvedFrame f = rr::resolve_frame(s, scene.mesh, given);
  if (!f.description.empty()) tt::step(verb, f.description);
  const rr::FrameParams& fp = f.frame;
  const std::vector<std::string> files =
      rr::frame_files(out, fp.camera.orthographic);  // with a map's world file
  tt::check_distinct_paths({mesh, dv}, files);
  tt::warn_stale_temporaries(verb, {files.begin() + 1, files.end()});
  for (const std::string& file : files) terrain::check_output_path(file);
  focus(scene, {fp.camera}, s, f.style, dv, verb, true);
  auto t0 = Clock::now();
  rr::GlContext ctx;
  if (rr::is_vector_path(out)) rr::check_vector_memory(ctx, s.width, s.height);
  rr::TerrainRenderer r(ctx, scene.mesh, scene.creases ? &*scene.creases : nullptr, s.width,
                        s.height, f.layers, f.style, scene.levels, scene.crease_levels);
  tt::step(verb, fmt::format("OpenGL set-up ({}): {:.2f} s", ctx.info().renderer, since(t0)));
  t0 = Clock::now();
  const rr::FrameResult res = r.render(fp);
  tt::step(verb, fmt::format("frame: {:.0f} ms", 1e3 * since(t0)));
  if (const std::string why =
          rr::no_terrain_problem(scene.mesh, res.view, r.box(), f.style.exaggeration);
      !why.empty())
    throw terrain::Error(why);
  rr::TracedHachures traced;  // traced once: for the file and for --line-stats
  const rr::WriteTimes wt =
      rr::write_frame_files({out}, scene, r, res, f, o.vector, prov + "; " + exaggeration,
                            a.line_stats ? &traced : nullptr);
  report_write(verb, {out}, wt);
  print_frame(out, ctx, scene, r, res, f, exaggeration, wt);
  if (a.line_stats)
    std::cout << rr::line_stats_text(rr::frame_line_stats(scene, r, res, fp, f.style, f.layers,
                                                          f.layers.hachures ? &traced : nullptr));
  return 0;
}

std::string frame_name(std::size_t i, const std::string& ext = "png") {
  return fmt::format("frame_{:05d}.{}", i, ext);
}

// --format: frame formats (rr::kFrameFormats: png, svg, pdf), each once, at least one.
std::vector<std::string> parse_formats(const std::string& list) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start <= list.size()) {
    const std::size_t end = std::min(list.find(',', start), list.size());
    const std::string f = list.substr(start, end - start);
    if (!rr::frame_format_named(f))
      throw CLI::ValidationError("--format",
                                 "unknown format '" + f + "' (" + rr::frame_format_names() + ")");
    if (std::find(out.begin(), out.end(), f) != out.end())
      throw CLI::ValidationError("--format", "'" + f + "' is given twice");
    out.push_back(f);
    start = end + 1;
  }
  return out;
}

namespace {

// Every file a batch writes: the frames (with a map's world file), the timings and the
// statistics; checked against every input (a frames CSV or a mesh named like an output is
// never replaced).
std::vector<std::string> batch_outputs(const TableArgs& a, const std::vector<std::string>& formats,
                                       const std::vector<rr::FrameParams>& frames,
                                       const std::filesystem::path& dir) {
  std::vector<std::string> outputs = {(dir / "timings.csv").string()};
  if (a.line_stats) outputs.push_back((dir / "line_stats.csv").string());
  for (std::size_t i = 0; i < frames.size(); ++i)
    for (const std::string& f : formats)
      for (const std::string& file :
           rr::frame_files((dir / frame_name(i, f)).string(), frames[i].camera.orthographic))
        outputs.push_back(file);
  return outputs;
}

void check_eyes(const rr::Scene& scene, const std::vector<rr::FrameParams>& frames,
                const rr::RenderSettings& s, const std::string& csv) {
  for (std::size_t i = 0; i < frames.size(); ++i) {
    try {
      if (frames[i].camera.eye)
        rr::check_eye_above_terrain(scene.mesh, *frames[i].camera.eye, s.style.exaggeration);
    } catch (const terrain::Error& e) {
      throw terrain::Error(fmt::format("{}: frame {}: {}", csv, i + 1, e.what()));
    }
  }
}

// --line-stats over a batch: each frame's row, and what the flicker and the hachures'
// coherence between frames are measured on.
struct BatchLineStats {
  std::string csv = rr::line_stats_csv_header();
  std::vector<std::vector<float>> drawn;
  std::vector<std::vector<double>> pixels;
  std::vector<Eigen::Vector3f> previous_hachures;  // the last frame's, on the surface
  rr::Coherence coherence;

  void add(std::size_t i, const rr::Scene& scene, const rr::TerrainRenderer& r,
           const rr::FrameResult& res, const rr::ResolvedFrame& f, rr::TracedHachures& traced) {
    rr::FrameStats st = rr::frame_line_stats(scene, r, res, f.frame, f.style, f.layers,
                                             f.layers.hachures ? &traced : nullptr,
                                             i ? &previous_hachures : nullptr);
    csv += rr::line_stats_csv_row(i, st);
    rr::FrameLines fine =
        rr::fine_lines(scene, res, std::move(st.lines));  // frames may draw other levels
    drawn.push_back(std::move(fine.drawn));
    pixels.push_back(std::move(fine.pixels));
    if (st.hachures) previous_hachures = std::move(st.hachures->surface);
    coherence.counted += st.hachure_coherence.counted, coherence.near += st.hachure_coherence.near;
  }
};

// What terrain-render batch prints: the folder, the frames, the device, the timing tables
// and, with --line-stats (`stats`), the flicker and the hachures' coherence.
void print_batch(const std::string& out_dir, std::size_t frames, int width, int height,
                 std::size_t blank, const rr::GlContext& ctx,
                 const std::vector<rr::FrameTimings>& timings, const BatchLineStats* stats,
                 bool hachures) {
  std::cout << "output: " << out_dir << "\nframes: " << frames << "\nsize: " << width << " x "
            << height << "\n";
  if (blank > 0) std::cout << "frames without terrain: " << blank << "\n";
  print_device(ctx);
  std::cout << rr::timing_tables(timings);
  if (stats)
    std::cout << fmt::format("crease flicker: {:.4f}\n", rr::flicker(stats->drawn, stats->pixels));
  if (stats && hachures)
    std::cout << fmt::format("hachure coherence: {:.4f}\n", stats->coherence.share());
}

}  // namespace

namespace {

// A GeoPackage holds a map's lines: refused before any frame is written unless all are maps.
void check_map_frames(const std::vector<std::string>& formats,
                      const std::vector<rr::FrameParams>& frames, const std::string& csv) {
  if (std::find(formats.begin(), formats.end(), "gpkg") == formats.end()) return;
  for (std::size_t i = 0; i < frames.size(); ++i)
    if (!frames[i].camera.orthographic)
      throw terrain::Error(fmt::format(
          "{}: frame {} is no map (a top view): --format gpkg holds a map's lines in map "
          "coordinates; leave gpkg out",
          csv, i + 1));
}

}  // namespace

int run_batch(const TableArgs& a, const OutputArgs& o, const std::vector<std::string>& inputs,
              const std::string& out_dir, const std::string& prov, const tt::Verbosity& verb) {
  rr::RenderSettings s = settings_of(a);
  const std::vector<std::string> formats = parse_formats(o.formats);
  const std::string mesh_path = inputs[0], csv = inputs.back(),
                    dv_path = inputs.size() == 3 ? inputs[1] : "";
  if (!dv_path.empty() && !drainage::is_dv_file(dv_path))
    throw terrain::Error("'" + dv_path + "' is not a drainage database (.dv)");
  const auto frames = rr::read_frames_csv(csv, s.frame);
  check_map_frames(formats, frames, csv);
  const std::filesystem::path dir(out_dir);
  const std::vector<std::string> outputs = batch_outputs(a, formats, frames, dir);
  for (const std::string& out : outputs) tt::check_distinct_paths(inputs, {out});
  std::filesystem::create_directories(dir);
  terrain::check_output_path(dir / "timings.csv");
  tt::warn_stale_temporaries(verb, outputs);
  check_line_stats(a, s, dv_path);
  rr::Scene scene = scene_of(mesh_path, dv_path, s, verb, std::uint64_t(o.memory_mib * 1048576.0));
  tt::step(verb, rr::resolve_settings(s, scene.mesh,
                                      [&](const std::string& n) { return a.was_given(n); }));
  std::vector<rr::Camera> cameras;
  for (const rr::FrameParams& fp : frames) cameras.push_back(fp.camera);
  focus(scene, cameras, s, rr::drawn_frame(s).style, dv_path, verb);
  check_eyes(scene, frames, s, csv);
  rr::GlContext ctx;
  rr::ResolvedFrame f = rr::drawn_frame(s);
  if (formats != std::vector<std::string>{"png"}) rr::check_vector_memory(ctx, s.width, s.height);
  rr::TerrainRenderer r(ctx, scene.mesh, scene.creases ? &*scene.creases : nullptr, s.width,
                        s.height, f.layers, f.style, scene.levels, scene.crease_levels);
  std::vector<rr::FrameTimings> timings;
  BatchLineStats stats;
  const auto progress = tt::terminal_progress(verb, "render");
  std::size_t blank = 0;  // frames that show no terrain
  for (std::size_t i = 0; i < frames.size(); ++i) {
    f.frame = frames[i];
    const rr::FrameResult res = r.render(f.frame);
    timings.push_back(res.timings);
    if (const std::string why =
            rr::no_terrain_problem(scene.mesh, res.view, r.box(), f.style.exaggeration);
        !why.empty()) {
      tt::warn(verb, fmt::format("{}: frame {}: {}", csv, i + 1, why));
      ++blank;
    }
    std::vector<std::string> paths;
    for (const std::string& format : formats)
      paths.push_back((dir / frame_name(i, format)).string());
    rr::TracedHachures traced;  // traced once: for the files and for --line-stats
    report_write(verb, paths,
                 rr::write_frame_files(paths, scene, r, res, f, o.vector,
                                       prov + fmt::format(" [frame {}]", i),
                                       a.line_stats ? &traced : nullptr));
    if (a.line_stats) stats.add(i, scene, r, res, f, traced);
    terrain::report(progress, double(i + 1) / double(frames.size()));
  }
  terrain::write_file_atomic(dir / "timings.csv", rr::timings_csv(timings));
  if (a.line_stats) terrain::write_file_atomic(dir / "line_stats.csv", stats.csv);
  print_batch(out_dir, frames.size(), s.width, s.height, blank, ctx, timings,
              a.line_stats ? &stats : nullptr, f.layers.hachures);
  return 0;
}

}  // namespace terrain::tools::render
