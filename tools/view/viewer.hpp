#pragma once
// terrain-view's state: the scene, the settings and the two renderers (full size, and half
// size for the cheap frames drawn while the camera or a slider moves) in the viewer's own
// headless context; the frame resolved as terrain-render resolves it (frame_setup.hpp).
#include <chrono>
#include <functional>
#include <iostream>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "common.hpp"
#include "render_cli.hpp"
#include "renderer/core/camera.hpp"
#include "renderer/core/frames.hpp"
#include "renderer/core/options.hpp"
#include "renderer/core/vector_file.hpp"
#include "renderer/gl/gl_context.hpp"
#include "renderer/gl/terrain_renderer.hpp"
#include "renderer/scene/frame_setup.hpp"
#include "renderer/scene/scene.hpp"
#include "terrain/atomic_file.hpp"
#include "view/view_camera.hpp"

namespace terrain::tools::view {

namespace rr = renderer;
namespace tt = terrain::tools;

using Clock = std::chrono::steady_clock;
inline double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}
inline std::string quoted(const std::string& s) { return "'" + s + "'"; }

class Viewer {
 public:
  // `given`: the table options given on the command line (the automatic view chooses the
  // rest, as terrain-render frame's).
  // `vertex_bytes` (0: no bound) bounds what the mesh's vertices take, as terrain-render
  // frame's --memory: a larger mesh with a pyramid is read as terrain-render frame reads it
  // (load_scene, then hold_views for a Frame: the level the start view draws, over the blocks in
  // view, within the bound); before a full frame whose view the mesh held does not serve so, what
  // it needs is read (a StillView); before a cheap frame whose view leaves the blocks
  // held, the whole mesh at the level the view draws, or the finest within the bound
  // (a MovingView). The camera moves over the preview beyond a window held (keep_preview).
  Viewer(std::string mesh, std::string dv, rr::RenderSettings s, rr::GivenOption given,
         const tt::Verbosity& verb, std::uint64_t vertex_bytes = 0)
      : mesh_path_(std::move(mesh)),
        dv_path_(std::move(dv)),
        s_(std::move(s)),
        start_(s_),
        given_(std::move(given)),
        verb_(verb),
        vertex_bytes_(vertex_bytes),
        scene_(rr::load_scene(mesh_path_, dv_path_, s_.rules, vertex_bytes_)) {
    keep_preview();
    for (const std::string& w : scene_.warnings) tt::warn(verb_, w);
    tt::step(verb_, rr::resolve_settings(s_, scene_.mesh, given_));
    start_.style.exaggeration = s_.style.exaggeration;
    home();
    focus();
    stale_ = true;  // the renderers are made for the first frame: a bad replay line fails before
  }

  rr::RenderSettings& settings() { return s_; }
  const rr::Scene& scene() const { return scene_; }
  const rr::GlContext& gl() const { return gl_; }
  tt::ViewCamera camera() const {
    return {scene_.mesh, s_.style.exaggeration, s_.width, s_.height,
            windowed() ? preview_.get() : nullptr};
  }
  // The whole mesh's surface: the mesh held, or the preview while a window of it is held.
  const terrain::GridMesh& surface() const { return windowed() ? *preview_ : scene_.mesh; }

  // The view the viewer started with, resolved as terrain-render frame resolves it
  // (resolve_frame) with today's options: the camera given at start (or the automatic view
  // at today's field of view), and the light set since or given (or the view's).
  void home() {
    rr::RenderSettings h = s_;
    const double fov = h.frame.camera.fov;
    h.frame.camera = start_.frame.camera;
    h.frame.camera.fov = fov;
    s_.frame =
        rr::resolve_frame(h, surface(), [this](const std::string& n) {
          return given_(n) || ((n == "light-az" || n == "light-alt") && set_since_start_.count(n));
        }).frame;
  }

  // Sets one option by the table; the renderers (or the creases) are rebuilt when it needs,
  // at the next frame (a slider dragged over several values, or several options set at
  // once, rebuild once).
  void set(const std::string& name, const std::string& value) {
    const rr::OptionSpec* o = rr::find_option(name);
    if (!o) throw terrain::Error("no option '" + name + "' (terrain-view --list-options)");
    rr::RenderSettings next = s_;
    rr::set_option(next, *o, value);
    rr::validate(next);
    if (o->name == "view" && next.view == rr::ViewMode::Row)
      (void)rr::view_row_frame(next.view_row, next.frame);
    if (o->name == "eye" && next.frame.camera.eye) check_eye(*next.frame.camera.eye);
    s_ = std::move(next);
    set_since_start_.insert(o->name);  // (a value refused leaves nothing set)
    if (o->rebuilds_creases && !dv_path_.empty())
      creases_stale_ = stale_ = true;
    else if (!o->per_frame && o->name != "eye")
      stale_ = true;
  }

  // A scene read at a coarser level (the memory bound) read again at the level the current
  // view draws, with its creases; -v says which.
  // Only the blocks in view, as terrain-render frame reads them.
  void focus() {
    const std::string note = rr::hold_views(scene_, {s_.frame.camera}, s_.width, s_.height,
                                            rr::drawn_style(s_), rr::HoldFor::Frame);
    if (!note.empty()) tt::step(verb_, note);
  }

  // The preview of a scene read under the bound (the whole mesh at a coarser level), kept
  // for the camera's moves while a window of the mesh is held.
  void keep_preview() {
    preview_.reset();
    if (scene_.deferred) preview_ = std::make_shared<const terrain::GridMesh>(scene_.mesh);
  }
  bool windowed() const {
    return preview_ && rr::MeshHolding(scene_.mesh, scene_.levels.get()).window();
  }

  void bring_up_to_date() {
    if (creases_stale_) {
      scene_ = rr::load_scene(mesh_path_, dv_path_, s_.rules, vertex_bytes_);
      keep_preview();
      focus();
    }
    if (stale_) rebuild();
    creases_stale_ = stale_ = false;
  }

  void rebuild() {
    if (before_gl) before_gl();
    gl_.make_current();
    const rr::CreaseGeometry* creases = scene_.creases ? &*scene_.creases : nullptr;
    full_ = std::make_unique<rr::TerrainRenderer>(
        gl_, scene_.mesh, creases, s_.width, s_.height, s_.layers, rr::drawn_style(s_),
        rr::scene_levels(scene_, rr::drawn_style(s_)), scene_.crease_levels);
    cheap_.reset();  // made when a cheap frame is first drawn
  }

  // A frame: full size, or the cheap half-size one. With the hachures and ridges layers, a
  // full frame shows them as terrain-render draws them (renderer/core/hachures.hpp,
  // renderer::ridge_layer); a cheap frame, while moving, goes without.
  const rr::FrameResult& render(bool cheap) {
    {  // a full frame reads what terrain-render frame reads (the level and the blocks its view
       // draws, within the memory bound); a cheap one the whole level when the view leaves
       // the blocks held
      const rr::Style style = rr::drawn_style(s_);
      const std::string note =
          rr::hold_views(scene_, {s_.frame.camera}, s_.width, s_.height, style,
                         cheap ? rr::HoldFor::MovingView : rr::HoldFor::StillView);
      if (!note.empty()) tt::step(verb_, note), stale_ = true;
    }
    bring_up_to_date();
    if (before_gl) before_gl();
    gl_.make_current();
    if (cheap && !cheap_) {
      rr::Layers layers = s_.layers;
      layers.hachures = false;  // cheap frames go without (no normals target)
      // Half the pixels, and triangles of twice the edge (the levels of detail then allow
      // cells twice as wide, within the same height error): the surface as the full frame
      // draws it to a pixel at half size, in about 60 % of the time.
      rr::Style style = rr::drawn_style(s_);
      style.pixels_per_edge *= 2;
      cheap_ = std::make_unique<rr::TerrainRenderer>(
          gl_, scene_.mesh, scene_.creases ? &*scene_.creases : nullptr, std::max(16, s_.width / 2),
          std::max(16, s_.height / 2), layers, style, rr::scene_levels(scene_, style),
          scene_.crease_levels);
    }
    const auto t0 = Clock::now();
    last_ = (cheap ? cheap_ : full_)->render(s_.frame);
    last_cheap_ = cheap;
    shown_hachures_ = !cheap && rr::draws_overlays(scene_, s_.layers, rr::drawn_style(s_));
    if (!shown_hachures_) {
      (cheap ? cheap_ms_ : full_ms_) = ms_since(t0);
      return last_;
    }
    shown_ = last_;
    rr::draw_overlays(rr::frame_overlays(scene_, *full_, last_, full_->read_buffers(),
                                         rr::drawn_style(s_), s_.layers),
                      shown_.width, shown_.height, shown_.rgba);
    full_ms_ = ms_since(t0);
    return shown_;
  }
  // The frame as shown (with hachures and ridges where drawn).
  const rr::FrameResult& last() const { return shown_hachures_ ? shown_ : last_; }
  bool last_was_cheap() const { return last_cheap_; }
  double full_ms() const { return full_ms_; }
  double cheap_ms() const { return cheap_ms_; }
  std::string line_stats() {
    if (!scene_.creases || !s_.layers.creases)
      return "line statistics measure creases: give a .dv, keep creases";
    render(false);
    return rr::line_stats_text(
        rr::frame_line_stats(scene_, *full_, last_, s_.frame, rr::drawn_style(s_), s_.layers));
  }

  // The exact terrain-render command line of view `s` writing `png`.
  std::string command_line(const std::string& png, const rr::RenderSettings& s) const {
    const double mib =
        double(vertex_bytes_) / 1048576.0;  // terrain-render frame's --memory, 1024 unless given
    return "terrain-render frame " + quoted(mesh_path_) +
           (dv_path_.empty() ? "" : " " + quoted(dv_path_)) + " -o " + quoted(png) +
           rr::changed_options(s) + (mib != 1024 ? fmt::format(" --memory {:g}", mib) : "") +
           (rr::is_vector_path(png) ? tt::vector_options_text(vector) : "");
  }

  // screenshot: the full frame of the current view as a PNG, at the window's size or at
  // `size` (WxH, any size the device draws: a renderer of that size for this frame).
  void screenshot(const std::string& png, const std::string& size = "") { save(png, size, false); }

  // save-view: the PNG, the command line (printed and in PNG.txt) and the frames-CSV row
  // (PNG.csv, with its header) of the current view.
  void save_view(const std::string& png, const std::string& size = "") { save(png, size, true); }

  // Throws unless `eye` is above the terrain and near enough to draw it (as terrain-render).
  void check_eye(const Eigen::Vector3d& eye) const {
    rr::check_eye_above_terrain(surface(), eye, s_.style.exaggeration);
  }

  // Throws unless every path in `outputs` differs from every file the viewer reads (the
  // mesh, the .dv, the replay, the frames CSVs) and from each other, as the other tools
  // check their outputs.
  void check_output(const std::vector<std::string>& outputs) const {
    tt::check_distinct_paths(inputs, outputs);
    for (const std::string& o : outputs) terrain::check_output_path(o);
  }

  // A frames CSV to step through; each frame's eye checked as terrain-render batch does.
  void load_frames(const std::string& path) {
    std::vector<rr::FrameParams> loaded = rr::read_frames_csv(path, s_.frame);
    for (std::size_t i = 0; i < loaded.size(); ++i)
      if (loaded[i].camera.eye) {
        try {
          check_eye(*loaded[i].camera.eye);
        } catch (const terrain::Error& e) {
          throw terrain::Error(fmt::format("{}: frame {}: {}", path, i + 1, e.what()));
        }
      }
    inputs.push_back(path);
    frames = std::move(loaded);
    frame_index = 0;
    s_.frame = frames[0];
  }

  void save_keyframes(const std::string& path, int count) {
    check_output({path});
    terrain::write_file_atomic(path, rr::frames_csv(rr::keyframe_path(keyframes, count)));
  }

  std::vector<std::string> inputs;  // every file read: outputs must be none of them
  rr::VectorOptions vector;         // --dpi, --vector-underlay: save-view's SVG and PDF
  std::vector<rr::FrameParams> keyframes, frames;
  std::size_t frame_index = 0;
  std::string window_shot;  // window-shot PATH: the window (panel included) after its next draw
  std::function<void()>
      before_gl;  // releases the window's context before the renderer's is made current

 private:
  std::string mesh_path_, dv_path_;
  // A screenshot is a PNG; save-view writes what its extension says (.png, .svg, .pdf)
  // through terrain-render's writer, at this frame's options.
  void save(const std::string& path, const std::string& size, bool with_command) {
    if (with_command)
      rr::check_frame_path(path);
    else if (!path.ends_with(".png"))
      throw terrain::Error("a screenshot is a PNG image: give a .png name, not '" + path +
                           "' (save-view also writes .svg "
                           "and .pdf)");
    rr::RenderSettings at = s_;
    if (!size.empty()) rr::set_option(at, *rr::find_option("size"), size);
    const rr::ResolvedFrame f = rr::drawn_frame(at);
    std::vector<std::string> files =
        rr::frame_files(path, f.frame.camera.orthographic);  // with a map's world file
    if (with_command) files.insert(files.end(), {path + ".txt", path + ".csv"});
    check_output(files);
    bring_up_to_date();
    const std::string cmd = command_line(path, at);
    const auto write = [&](const rr::TerrainRenderer& r) {
      (void)rr::write_frame_files({path}, scene_, r, last_, f, vector, "terrain-view: " + cmd);
    };
    if (at.width == s_.width && at.height == s_.height) {
      render(false);
      write(*full_);
    } else {
      if (before_gl) before_gl();
      gl_.make_current();
      if (rr::is_vector_path(path)) rr::check_vector_memory(gl_, at.width, at.height);
      rr::TerrainRenderer r(gl_, scene_.mesh, scene_.creases ? &*scene_.creases : nullptr, at.width,
                            at.height, f.layers, f.style, rr::scene_levels(scene_, f.style),
                            scene_.crease_levels);
      last_ = r.render(at.frame);
      write(r);
    }
    if (!with_command) return;
    std::cout << cmd << "\n";
    terrain::write_file_atomic(path + ".txt", cmd + "\n");
    terrain::write_file_atomic(path + ".csv", rr::frames_csv({at.frame}));
  }

  rr::RenderSettings s_;
  rr::RenderSettings start_;               // as given on the command line
  rr::GivenOption given_;                  // which table options the command line gave
  std::set<std::string> set_since_start_;  // options set through the panel or the replay
  const tt::Verbosity& verb_;
  std::uint64_t vertex_bytes_;  // the memory bound on the mesh's vertices (0: none)
  rr::GlContext gl_;
  rr::Scene scene_;
  std::shared_ptr<const terrain::GridMesh> preview_;  // keep_preview
  std::unique_ptr<rr::TerrainRenderer> full_, cheap_;
  rr::FrameResult last_;   // as the renderer drew it
  rr::FrameResult shown_;  // a full frame with hachures drawn over it
  bool shown_hachures_ = false;
  bool last_cheap_ = false;
  double full_ms_ = 0, cheap_ms_ = 0;
  bool stale_ = false, creases_stale_ = false;  // set() changed what the renderers or creases hold
};

}  // namespace terrain::tools::view
