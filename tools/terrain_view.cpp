// terrain-view: the interactive window over terrain-render's renderer. It draws exactly
// what `terrain-render frame` draws with the same options (the same scene, renderer and
// passes, in its own headless context; the window shows the frame read back), with the
// option table's panel, camera moves, saved views and keyframes, and a scriptable replay
// (--replay) that also runs without a window (--offscreen).
#include <epoxy/gl.h>  // before GLFW, which would include GL/gl.h
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <fmt/format.h>
#include <imgui.h>

#include <algorithm>
#include <cctype>
#include <optional>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <set>
#include <sstream>

#include "common.hpp"
#include "render_cli.hpp"
#include "renderer/camera.hpp"
#include "renderer/frame_setup.hpp"
#include "renderer/frames.hpp"
#include "renderer/gl_context.hpp"
#include "renderer/options.hpp"
#include "renderer/scene.hpp"
#include "renderer/terrain_renderer.hpp"
#include "renderer/vector_file.hpp"
#include "terrain/atomic_file.hpp"
#include "terrain/image_io.hpp"
#include "view_camera.hpp"

namespace tt = terrain::tools;
namespace rr = renderer;

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

std::string quoted(const std::string& s) { return "'" + s + "'"; }

// The scene, the settings and the two renderers (full size, and half size for the cheap
// frames drawn while the camera or a slider moves), in the viewer's headless context.
class Viewer {
 public:
  // `given`: the table options given on the command line (the automatic view chooses the
  // rest, as terrain-render frame's).
  Viewer(std::string mesh, std::string dv, rr::RenderSettings s, rr::GivenOption given, const tt::Verbosity& verb)
      : mesh_path_(std::move(mesh)),
        dv_path_(std::move(dv)),
        s_(std::move(s)),
        start_(s_),
        given_(std::move(given)),
        verb_(verb),
        scene_(rr::load_scene(mesh_path_, dv_path_, s_.rules)) {
    for (const std::string& w : scene_.warnings) tt::warn(verb_, w);
    home();
    rebuild();
  }

  rr::RenderSettings& settings() { return s_; }
  const rr::Scene& scene() const { return scene_; }
  const rr::GlContext& gl() const { return gl_; }
  tt::ViewCamera camera() const { return {scene_.mesh, s_.style.exaggeration, s_.width, s_.height}; }

  // The view the viewer started with, resolved as terrain-render frame resolves it
  // (resolve_frame) with today's options: the camera given at start (or the automatic view
  // at today's field of view), and the light set since or given (or the view's).
  void home() {
    rr::RenderSettings h = s_;
    const double fov = h.frame.camera.fov;
    h.frame.camera = start_.frame.camera;
    h.frame.camera.fov = fov;
    s_.frame = rr::resolve_frame(h, scene_.mesh, [this](const std::string& n) {
                 return given_(n) || ((n == "light-az" || n == "light-alt") && set_since_start_.count(n));
               }).frame;
  }

  // Sets one option by the table; the renderers (or the creases) are rebuilt when it needs,
  // at the next frame (a slider dragged over several values, or several options set at
  // once, rebuild once).
  void set(const std::string& name, const std::string& value) {
    const rr::OptionSpec* o = rr::find_option(name);
    if (!o) throw terrain::Error("no option '" + name + "' (terrain-view --list-options)");
    set_since_start_.insert(o->name);
    rr::RenderSettings next = s_;
    rr::set_option(next, *o, value);
    rr::validate(next);
    if (o->name == "view" && next.view == rr::ViewMode::Row) (void)rr::view_row_frame(next.view_row, next.frame);
    if (o->name == "eye" && next.frame.camera.eye) check_eye(*next.frame.camera.eye);
    s_ = std::move(next);
    if (o->group == "Crease network" && !dv_path_.empty()) creases_stale_ = stale_ = true;
    else if (!o->per_frame && o->name != "eye") stale_ = true;
  }

  void bring_up_to_date() {
    if (creases_stale_) scene_ = rr::load_scene(mesh_path_, dv_path_, s_.rules);
    if (stale_) rebuild();
    creases_stale_ = stale_ = false;
  }

  void rebuild() {
    if (before_gl) before_gl();
    gl_.make_current();
    const rr::CreaseGeometry* creases = scene_.creases ? &*scene_.creases : nullptr;
    full_ = std::make_unique<rr::TerrainRenderer>(gl_, scene_.mesh, creases, s_.width, s_.height, s_.layers, rr::drawn_style(s_));
    cheap_.reset();  // made when a cheap frame is first drawn
  }

  // A frame: full size, or the cheap half-size one.
  const rr::FrameResult& render(bool cheap) {
    bring_up_to_date();
    if (before_gl) before_gl();
    gl_.make_current();
    if (cheap && !cheap_)
      cheap_ = std::make_unique<rr::TerrainRenderer>(gl_, scene_.mesh, scene_.creases ? &*scene_.creases : nullptr,
                                                     std::max(16, s_.width / 2), std::max(16, s_.height / 2),
                                                     s_.layers, rr::drawn_style(s_));
    const auto t0 = Clock::now();
    last_ = (cheap ? cheap_ : full_)->render(s_.frame);
    (cheap ? cheap_ms_ : full_ms_) = ms_since(t0);
    last_cheap_ = cheap;
    return last_;
  }
  const rr::FrameResult& last() const { return last_; }
  bool last_was_cheap() const { return last_cheap_; }
  double full_ms() const { return full_ms_; }
  double cheap_ms() const { return cheap_ms_; }
  std::string line_stats() {
    if (!scene_.creases || !s_.layers.creases) return "line statistics measure creases: give a .dv, keep creases";
    render(false);
    return rr::line_stats_text(rr::frame_line_stats(scene_, *full_, last_, s_.frame, rr::drawn_style(s_), s_.layers));
  }

  // The exact terrain-render command line of view `s` writing `png`.
  std::string command_line(const std::string& png, const rr::RenderSettings& s) const {
    return "terrain-render frame " + quoted(mesh_path_) + (dv_path_.empty() ? "" : " " + quoted(dv_path_)) + " -o " +
           quoted(png) + rr::changed_options(s);
  }

  // screenshot: the full frame of the current view as a PNG, at the window's size or at
  // `size` (WxH, any size the device draws: a renderer of that size for this frame).
  void screenshot(const std::string& png, const std::string& size = "") { save(png, size, false); }

  // save-view: the PNG, the command line (printed and in PNG.txt) and the frames-CSV row
  // (PNG.csv, with its header) of the current view.
  void save_view(const std::string& png, const std::string& size = "") { save(png, size, true); }

  // Throws unless `eye` is above the terrain and near enough to draw it (as terrain-render).
  void check_eye(const Eigen::Vector3d& eye) const {
    rr::check_eye_above_terrain(scene_.mesh, eye, s_.style.exaggeration);
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
  std::vector<rr::FrameParams> keyframes, frames;
  std::size_t frame_index = 0;
  std::string window_shot;          // window-shot PATH: the window (panel included) after its next draw
  std::function<void()> before_gl;  // releases the window's context before the renderer's is made current

 private:
  std::string mesh_path_, dv_path_;
  // A screenshot is a PNG; save-view writes what its extension says (.png, .svg, .pdf)
  // through terrain-render's writer, at this frame's options.
  void save(const std::string& path, const std::string& size, bool with_command) {
    if (with_command)
      rr::check_frame_path(path);
    else if (!path.ends_with(".png"))
      throw terrain::Error("a screenshot is a PNG image: give a .png name, not '" + path + "' (save-view also writes .svg "
                           "and .pdf)");
    check_output(with_command ? std::vector<std::string>{path, path + ".txt", path + ".csv"}
                              : std::vector<std::string>{path});
    bring_up_to_date();
    rr::RenderSettings at = s_;
    if (!size.empty()) rr::set_option(at, *rr::find_option("size"), size);
    const rr::ResolvedFrame f{at.frame, rr::drawn_style(at), at.layers, at.width, at.height, ""};
    const std::string cmd = command_line(path, at);
    const auto write = [&](const rr::TerrainRenderer& r) {
      (void)rr::write_frame_files({path}, scene_, r, last_, f, {}, "terrain-view: " + cmd);
    };
    if (at.width == s_.width && at.height == s_.height) {
      render(false);
      write(*full_);
    } else {
      if (before_gl) before_gl();
      gl_.make_current();
      if (rr::is_vector_path(path)) rr::check_vector_memory(gl_, at.width, at.height);
      rr::TerrainRenderer r(gl_, scene_.mesh, scene_.creases ? &*scene_.creases : nullptr, at.width, at.height, f.layers,
                            f.style);
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
  rr::GlContext gl_;
  rr::Scene scene_;
  std::unique_ptr<rr::TerrainRenderer> full_, cheap_;
  rr::FrameResult last_;
  bool last_cheap_ = false;
  double full_ms_ = 0, cheap_ms_ = 0;
  bool stale_ = false, creases_stale_ = false;  // set() changed what the renderers or creases hold
};

// The words of one replay line, each command checked as the option table checks options:
// its number of arguments, and each number whole, finite and in its range.
class ReplayArgs {
 public:
  explicit ReplayArgs(const std::string& line) {
    std::istringstream in(line);
    for (std::string w; in >> w;) words_.push_back(w);
  }
  const std::string& command() const { return words_.front(); }
  bool empty() const { return words_.empty() || words_.front()[0] == '#'; }
  std::size_t size() const { return words_.size() - 1; }
  const std::string& operator[](std::size_t k) const { return words_[k + 1]; }
  // Throws "USAGE" unless the command has lo .. hi arguments.
  void expect(std::size_t lo, std::size_t hi, const std::string& usage) const {
    if (size() < lo || size() > hi) throw terrain::Error("expected " + usage);
  }
  // Argument k as a finite number in [lo, hi] (whole when `whole`).
  double number(std::size_t k, const std::string& what, double lo, double hi, bool whole = false) const {
    const std::string& w = (*this)[k];
    char* end = nullptr;
    const double v = std::strtod(w.c_str(), &end);
    if (w.empty() || end != w.c_str() + w.size() || !std::isfinite(v))
      throw terrain::Error(what + ": '" + w + "' is not a finite number");
    if (whole && v != std::floor(v)) throw terrain::Error(what + ": '" + w + "' is not a whole number");
    if (v < lo || v > hi) throw terrain::Error(fmt::format("{}: {} is outside {:g} .. {:g}", what, w, lo, hi));
    return v;
  }

 private:
  std::vector<std::string> words_;
};

// The rest of `line` after its command word: a path, which may hold spaces.
std::string after_command(const std::string& line) {
  std::istringstream in(line);
  std::string cmd, r;
  in >> cmd;
  std::getline(in >> std::ws, r);
  while (!r.empty() && std::isspace(static_cast<unsigned char>(r.back()))) r.pop_back();
  return r;
}

// One replay command (see --help); returns false at quit.
bool run_command(Viewer& v, const std::string& line, int& wait_frames) {
  const ReplayArgs a(line);
  if (a.empty()) return true;
  const std::string& cmd = a.command();
  rr::Camera& c = v.settings().frame.camera;
  const tt::ViewCamera cam = v.camera();
  const auto centre = [&] {
    const auto p = cam.pick(c, v.settings().width / 2.0, v.settings().height / 2.0);
    if (!p) throw terrain::Error("the view's centre is not on the terrain");
    return *p;
  };
  const auto path_arg = [&](const std::string& usage) {
    const std::string p = after_command(line);
    if (p.empty()) throw terrain::Error("expected " + usage);
    return p;
  };
  if (cmd == "camera") {
    a.expect(5, 6, "camera E N Z AZ ALT [FOV]");
    rr::RenderSettings s = v.settings();
    const char* names[] = {"view-az", "view-alt", "fov"};
    for (std::size_t k = 3; k < a.size(); ++k) {
      try {
        rr::set_option(s, *rr::find_option(names[k - 3]), a[k]);
      } catch (const terrain::Error& e) {
        throw terrain::Error(std::string("camera: ") + names[k - 3] + ": " + e.what());
      }
    }
    try {
      rr::set_option(s, *rr::find_option("eye"), a[0] + " " + a[1] + " " + a[2]);
    } catch (const terrain::Error& e) {
      throw terrain::Error(std::string("camera: E N Z: ") + e.what());
    }
    v.check_eye(*s.frame.camera.eye);
    c = s.frame.camera;
  } else if (cmd == "orbit") {
    a.expect(2, 2, "orbit D_AZ D_ALT");
    cam.orbit(c, centre(), a.number(0, "orbit: D_AZ", -3600, 3600), a.number(1, "orbit: D_ALT", -180, 180));
  } else if (cmd == "zoom") {
    a.expect(1, 1, "zoom SHARE");
    // A share of the distance to the view's centre: 1 would put the eye on the terrain.
    cam.zoom(c, centre(), a.number(0, "zoom: SHARE", -10, 0.95));
  } else if (cmd == "set") {
    if (a.size() < 1) throw terrain::Error("expected set NAME VALUE");
    std::string value = after_command(line).substr(a[0].size());  // the value may hold spaces (eye)
    value.erase(0, value.find_first_not_of(" \t"));
    v.set(a[0], value);
  } else if (cmd == "layer") {
    a.expect(2, 2, "layer NAME on|off");
    if (a[1] != "on" && a[1] != "off") throw terrain::Error("expected layer NAME on|off");
    std::string out;
    std::istringstream ls(rr::find_option("layers")->get(v.settings()));
    for (std::string l; std::getline(ls, l, ',');)
      if (l != a[0]) out += (out.empty() ? "" : ",") + l;
    if (a[1] == "on") out += (out.empty() ? "" : ",") + a[0];
    v.set("layers", out);
  } else if (cmd == "key") {
    a.expect(1, 1, "key home|w|a|s|d|q|e|k");
    const std::string& k = a[0];
    const double step = 0.02 * double(v.scene().mesh.topo.cols) * v.scene().mesh.geo.dx;
    if (k == "home")
      v.home();
    else if (k == "w")
      cam.fly(c, step, 0, 0);
    else if (k == "s")
      cam.fly(c, -step, 0, 0);
    else if (k == "a")
      cam.fly(c, 0, -step, 0);
    else if (k == "d")
      cam.fly(c, 0, step, 0);
    else if (k == "q")
      cam.fly(c, 0, 0, -step);
    else if (k == "e")
      cam.fly(c, 0, 0, step);
    else if (k == "k")
      v.keyframes.push_back(v.settings().frame);
    else
      throw terrain::Error("unknown key '" + k + "' (home w a s d q e k)");
  } else if (cmd == "keyframe") {
    a.expect(0, 0, "keyframe");
    v.keyframes.push_back(v.settings().frame);
  } else if (cmd == "save-keyframes") {
    a.expect(1, 2, "save-keyframes PATH [N]");
    const int n = a.size() > 1 ? int(a.number(1, "save-keyframes: N", 2, rr::kMaxPathFrames, true)) : 60;
    v.save_keyframes(a[0], n);
  } else if (cmd == "load-frames") {
    v.load_frames(path_arg("load-frames PATH"));
  } else if (cmd == "next-frame") {
    a.expect(0, 0, "next-frame");
    if (v.frames.empty()) throw terrain::Error("next-frame: no frames loaded (load-frames PATH)");
    v.frame_index = (v.frame_index + 1) % v.frames.size();
    v.settings().frame = v.frames[v.frame_index];
  } else if (cmd == "wait") {
    a.expect(1, 1, "wait N");
    wait_frames = int(a.number(0, "wait: N", 0, 100000, true));
  } else if (cmd == "screenshot" || cmd == "save-view") {
    a.expect(1, 2, cmd + " PATH [WxH]");
    cmd == "screenshot" ? v.screenshot(a[0], a.size() > 1 ? a[1] : "") : v.save_view(a[0], a.size() > 1 ? a[1] : "");
  } else if (cmd == "window-shot") {  // offscreen: the frame alone
    const std::string p = path_arg("window-shot PATH");
    if (!p.ends_with(".png")) throw terrain::Error("window-shot writes a PNG image: give a .png name, not '" + p + "'");
    v.check_output({p});
    v.window_shot = p;
  } else if (cmd == "line-stats") {
    a.expect(0, 0, "line-stats");
    std::cout << v.line_stats();
  } else if (cmd == "timings") {
    a.expect(0, 0, "timings");
    const rr::FrameResult& f = v.render(false);
    std::cout << fmt::format("full frame {}x{}: {:.1f} ms\n", f.width, f.height, v.full_ms());
    v.render(true);
    std::cout << fmt::format("cheap frame {}x{}: {:.1f} ms\n", v.last().width, v.last().height, v.cheap_ms());
  } else if (cmd == "quit") {
    a.expect(0, 0, "quit");
    return false;
  } else {
    throw terrain::Error("unknown replay command '" + cmd + "'");
  }
  return true;
}

// `message` fit for one line of stderr: control and non-ASCII bytes (a binary file given
// as a replay) as '?', at most 300 characters.
std::string printable(const std::string& message) {
  std::string out;
  for (const char ch : message) {
    const auto u = static_cast<unsigned char>(ch);
    out += u >= 0x20 && u < 0x7f ? ch : '?';
    if (out.size() >= 300) return out + "...";
  }
  return out;
}

// A replay command's error, with its line number.
terrain::Error replay_error(std::size_t index, const std::exception& e) {
  return terrain::Error(printable(fmt::format("replay line {}: {}", index + 1, e.what())));
}

std::vector<std::string> read_replay(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw terrain::Error("cannot read '" + path + "'");
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

// The replay without a window.
int run_offscreen(Viewer& v, const std::vector<std::string>& replay) {
  int wait = 0;
  for (std::size_t i = 0; i < replay.size(); ++i) {
    try {
      if (!run_command(v, replay[i], wait)) break;
      if (!v.window_shot.empty()) v.screenshot(v.window_shot), v.window_shot.clear();
    } catch (const std::exception& e) {
      throw replay_error(i, e);
    }
  }
  return 0;
}

// The option panel, generated from the table: a widget per option, in its group.
void option_panel(Viewer& v, std::string& message) {
  rr::RenderSettings& s = v.settings();
  std::vector<std::string> groups;  // in the order they first appear, as --help lists them
  for (const rr::OptionSpec& o : rr::render_options())
    if (std::find(groups.begin(), groups.end(), o.group) == groups.end()) groups.push_back(o.group);
  for (const std::string& group : groups) {
    if (!ImGui::CollapsingHeader(group.c_str(), group == "Frame" ? ImGuiTreeNodeFlags_DefaultOpen : 0)) continue;
    for (const rr::OptionSpec& o : rr::render_options()) {
      if (o.group != group) continue;
      const std::string label = o.name + (o.unit.empty() ? "" : " (" + o.unit + ")");
      std::string value = o.get(s), next;
      switch (o.type) {
        case rr::OptionType::Number: {
          float f = value == "auto" ? -1.0f : std::stof(value);
          const bool bounded = o.max < 1e6;
          if (bounded ? ImGui::SliderFloat(label.c_str(), &f, float(o.min), float(o.max))
                      : ImGui::DragFloat(label.c_str(), &f, 1.0f))
            next = fmt::format("{}", f);
          break;
        }
        case rr::OptionType::Integer: {
          int i = std::stoi(value);
          if (o.max < 1e6 ? ImGui::SliderInt(label.c_str(), &i, int(o.min), int(o.max))
                          : ImGui::DragInt(label.c_str(), &i, 1.0f, int(o.min), 1 << 30))
            next = std::to_string(i);
          break;
        }
        case rr::OptionType::Bool: {
          bool b = value == "true";
          if (ImGui::Checkbox(label.c_str(), &b)) next = b ? "true" : "false";
          break;
        }
        case rr::OptionType::Enum:
          if (ImGui::BeginCombo(label.c_str(), value.c_str())) {
            for (const std::string& c : o.choices)
              if (ImGui::Selectable(c.c_str(), c == value)) next = c;
            ImGui::EndCombo();
          }
          break;
        case rr::OptionType::Colour: {
          float rgb[3];
          std::sscanf(value.c_str(), "%f,%f,%f", &rgb[0], &rgb[1], &rgb[2]);
          for (float& x : rgb) x /= 255.0f;
          if (ImGui::ColorEdit3(label.c_str(), rgb))
            next = fmt::format("{},{},{}", rgb[0] * 255.0f, rgb[1] * 255.0f, rgb[2] * 255.0f);
          break;
        }
        case rr::OptionType::List: {
          ImGui::TextUnformatted(label.c_str());
          for (const std::string& c : o.choices) {
            bool on = ("," + value + ",").find("," + c + ",") != std::string::npos;
            ImGui::SameLine();
            if (ImGui::Checkbox((c + "##" + o.name).c_str(), &on)) {
              std::string list;
              for (const std::string& d : o.choices) {
                const bool has = d == c ? on : ("," + value + ",").find("," + d + ",") != std::string::npos;
                if (has) list += (list.empty() ? "" : ",") + d;
              }
              next = list;
            }
          }
          break;
        }
        case rr::OptionType::Size:
        case rr::OptionType::Point:
          ImGui::Text("%s: %s", o.name.c_str(), value.c_str());
          break;
      }
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", o.help.c_str());
      if (!next.empty()) {
        try {
          v.set(o.name, next);
          message.clear();
        } catch (const terrain::Error& e) {
          message = "--" + o.name + ": " + e.what();
        }
      }
    }
  }
}

int run_window(Viewer& v, const std::vector<std::string>& replay, const std::string& save_dir) {
  if (!glfwInit()) throw terrain::Error("cannot open a window (no display? use --offscreen)");
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  rr::RenderSettings& s = v.settings();
  v.gl().release_current();  // GLFW makes its context current while it creates the window
  GLFWwindow* window = glfwCreateWindow(s.width, s.height, "terrain-view", nullptr, nullptr);
  if (!window) {
    glfwTerminate();
    throw terrain::Error("cannot open a window (no display? use --offscreen)");
  }
  v.before_gl = [] { glfwMakeContextCurrent(nullptr); };
  glfwMakeContextCurrent(window);
  glfwSwapInterval(1);
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;
  ImGui_ImplGlfw_InitForOpenGL(window, true);
  ImGui_ImplOpenGL3_Init("#version 330");
  GLuint texture = 0;
  glGenTextures(1, &texture);

  std::string message, stats, save_size = fmt::format("{}x{}", v.settings().width, v.settings().height);
  std::size_t next_line = 0;
  int wait = 0, saved = 0;
  bool dirty = true, running = true;
  auto last_input = Clock::now() - std::chrono::seconds(1);
  double last_x = 0, last_y = 0;
  std::optional<Eigen::Vector3d> pivot;
  while (running && !glfwWindowShouldClose(window)) {
    glfwPollEvents();
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    const ImGuiIO& io = ImGui::GetIO();
    rr::Camera& c = s.frame.camera;
    const rr::RenderSettings before = s;
    const tt::ViewCamera cam = v.camera();
    // Camera: left drag orbits about the terrain point under the cursor, right or middle
    // drag pans, the wheel zooms towards it; W/A/S/D, Q/E fly (Shift: faster); Home; K.
    double mx = 0, my = 0;
    glfwGetCursorPos(window, &mx, &my);
    if (!io.WantCaptureMouse) {
      const bool any = ImGui::IsMouseDown(0) || ImGui::IsMouseDown(1) || ImGui::IsMouseDown(2);
      if (any && !pivot) pivot = cam.pick(c, mx, my);
      if (!any) pivot.reset();
      if (pivot && ImGui::IsMouseDown(0)) cam.orbit(c, *pivot, 0.3 * (mx - last_x), 0.3 * (my - last_y));
      if (pivot && (ImGui::IsMouseDown(1) || ImGui::IsMouseDown(2))) cam.pan(c, *pivot, mx - last_x, my - last_y);
      if (io.MouseWheel != 0)
        if (const auto p = cam.pick(c, mx, my)) cam.zoom(c, *p, io.MouseWheel > 0 ? 0.15 : -0.15);
    }
    last_x = mx, last_y = my;
    if (!io.WantCaptureKeyboard) {
      // Per drawn frame: 0.5 % of the terrain's width (Shift: 2.5 %), as a replay's key moves 2 %.
      const double step = (io.KeyShift ? 0.025 : 0.005) * double(v.scene().mesh.topo.cols) * v.scene().mesh.geo.dx;
      const auto down = [&](int k) { return glfwGetKey(window, k) == GLFW_PRESS; };
      cam.fly(c, step * (down(GLFW_KEY_W) - down(GLFW_KEY_S)), step * (down(GLFW_KEY_D) - down(GLFW_KEY_A)),
              step * (down(GLFW_KEY_E) - down(GLFW_KEY_Q)));
      if (ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Home))) v.home();
      if (ImGui::IsKeyPressed(GLFW_KEY_K, false)) v.keyframes.push_back(s.frame);
      if (ImGui::IsKeyPressed(GLFW_KEY_N, false) && !v.frames.empty()) {
        v.frame_index = (v.frame_index + 1) % v.frames.size();
        s.frame = v.frames[v.frame_index];
      }
    }

    ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(380, float(s.height) - 16), ImGuiCond_FirstUseEver);
    ImGui::Begin("terrain-view");
    const rr::FrameTimings& t = v.last().timings;
    ImGui::Text("%s frame %dx%d: %.1f ms (%.1f fps)", v.last_was_cheap() ? "cheap" : "full", v.last().width,
                v.last().height, v.last_was_cheap() ? v.cheap_ms() : v.full_ms(),
                1000.0 / std::max(1e-3, v.last_was_cheap() ? v.cheap_ms() : v.full_ms()));
    std::string passes;
    for (int p = 0; p < rr::kPassCount; ++p) passes += fmt::format("{} {:.1f}  ", rr::pass_name(p), t.gpu_ms[p]);
    ImGui::TextWrapped("GL ms: %s", passes.c_str());
    if (c.eye)
      ImGui::Text("eye %.0f %.0f %.0f  az %.1f alt %.1f", c.eye->x(), c.eye->y(), c.eye->z(), c.view_az, c.view_alt);
    if (ImGui::Button("Line statistics")) stats = v.line_stats();
    ImGui::SameLine();
    if (ImGui::Button("Save view")) {
      try {
        v.save_view((std::filesystem::path(save_dir) / fmt::format("view_{:03d}.png", saved++)).string(), save_size);
      } catch (const terrain::Error& e) {
        message = e.what();
      }
    }
    ImGui::SameLine();
    ImGui::SetNextItemWidth(90);
    char size_text[32];
    std::snprintf(size_text, sizeof size_text, "%s", save_size.c_str());
    if (ImGui::InputText("size", size_text, sizeof size_text)) save_size = size_text;
    ImGui::SameLine();
    if (ImGui::Button("Keyframe (K)")) v.keyframes.push_back(s.frame);
    if (v.keyframes.size() >= 2 && ImGui::Button("Save keyframes")) {
      try {
        v.save_keyframes((std::filesystem::path(save_dir) / "keyframes.csv").string(), 60);
      } catch (const terrain::Error& e) {
        message = e.what();
      }
    }
    if (!stats.empty()) ImGui::TextUnformatted(stats.c_str());
    if (!message.empty()) ImGui::TextColored(ImVec4(0.8f, 0.1f, 0.1f, 1), "%s", message.c_str());
    option_panel(v, message);
    ImGui::End();

    // The replay: one command a frame, `wait N` skips N frames.
    if (wait > 0) {
      --wait;
    } else if (next_line < replay.size()) {
      try {
        running = run_command(v, replay[next_line], wait);
      } catch (const std::exception& e) {
        throw replay_error(next_line, e);
      }
      ++next_line;
    }
    const bool changed = rr::changed_options(before) != rr::changed_options(s);
    if (changed) last_input = Clock::now(), dirty = true;
    // While input moves the view and a full frame is slow (> 50 ms), the half-size frame;
    // the full frame once the input has been still for 200 ms.
    const bool moving = ms_since(last_input) < 200;
    if (dirty || (!moving && v.last_was_cheap())) {
      v.render(moving && v.full_ms() > 50);
      dirty = false;
      const rr::FrameResult& f = v.last();
      v.gl().release_current();
      glfwMakeContextCurrent(window);
      glBindTexture(GL_TEXTURE_2D, texture);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
      glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
      glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, f.width, f.height, 0, GL_RGBA, GL_UNSIGNED_BYTE, f.rgba.data());
    }
    v.gl().release_current();
    glfwMakeContextCurrent(window);
    ImGui::GetBackgroundDrawList()->AddImage(reinterpret_cast<ImTextureID>(std::uintptr_t(texture)), ImVec2(0, 0),
                                             io.DisplaySize);
    ImGui::Render();
    int fw = 0, fh = 0;
    glfwGetFramebufferSize(window, &fw, &fh);
    glViewport(0, 0, fw, fh);
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    if (!v.window_shot.empty() && !dirty) {
      std::vector<std::uint8_t> rgba(std::size_t(fw) * std::size_t(fh) * 4), flipped(rgba.size());
      glPixelStorei(GL_PACK_ALIGNMENT, 1);
      glReadPixels(0, 0, fw, fh, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
      const std::size_t row = std::size_t(fw) * 4;
      for (int y = 0; y < fh; ++y)
        std::copy_n(rgba.data() + std::size_t(fh - 1 - y) * row, row, flipped.data() + std::size_t(y) * row);
      for (std::size_t i = 3; i < flipped.size(); i += 4) flipped[i] = 255;
      terrain::write_png(v.window_shot, fw, fh, 4, flipped, "terrain-view window");
      v.window_shot.clear();
    }
    glfwSwapBuffers(window);
  }
  glDeleteTextures(1, &texture);
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  glfwDestroyWindow(window);
  glfwTerminate();
  v.before_gl = nullptr;
  v.gl().make_current();  // the renderers free their GL objects in their own context
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Interactive terrain viewer: draws what terrain-render frame draws, with every render option\n"
      "on a panel, camera moves, saved views and keyframes.",
      "terrain-view"};
  app.footer(
      "Mouse: left drag orbits about the terrain point under the cursor, right or middle drag pans, the wheel\n"
      "zooms towards it. Keys: W/A/S/D fly, Q/E down/up (Shift: faster), Home: the default view, K: a\n"
      "keyframe, N: the next frame of --frames.\n\n"
      "Replay commands (--replay FILE, one a line): camera E N Z AZ ALT [FOV] | orbit D_AZ D_ALT | zoom SHARE |\n"
      "set NAME VALUE | layer NAME on|off | key home|w|a|s|d|q|e|k | keyframe | save-keyframes PATH [N] |\n"
      "load-frames PATH | next-frame | wait N | screenshot PATH.png [WxH] | window-shot PATH.png |\n"
      "save-view PATH.png|.svg|.pdf [WxH] | line-stats |\n"
      "timings | quit\n\n"
      "Examples:\n"
      "  terrain-view out/msh_50m.ply out/msh_breached.dv\n"
      "  terrain-view out/msh_50m.ply out/msh_breached.dv --replay tour.txt --offscreen\n"
      "  terrain-view --list-options\n\n"
      "See docs/terrain-view.md.");
  app.set_version_flag("--version", tt::version());
  std::string mesh, dv, replay_path, frames_path, save_dir = ".";
  bool offscreen = false, list = false;
  tt::Verbosity verb;
  tt::TableArgs opts;
  app.add_option("MESH", mesh, "Mesh (.ply from dem2mesh)");
  app.add_option("DV", dv, "Drainage database (.dv from build-drainage); no creases without it");
  app.add_option("--replay", replay_path, "Run the commands of this file (see below)");
  app.add_flag("--offscreen", offscreen, "No window: run the replay through EGL only (a machine without a display)");
  app.add_option("--frames", frames_path, "A frames CSV to step through (N, or next-frame)");
  app.add_option("--save-dir", save_dir, "Where the panel's Save buttons write")->capture_default_str();
  app.add_flag("--list-options", list, "Print the panel's options (name, group, type, default) and exit");
  tt::add_verbosity_flags(app, verb);
  tt::add_table_options(&app, opts, false);

  return tt::run_main(app, argc, argv, [&]() -> int {
    if (list) {
      for (const rr::OptionSpec& o : rr::render_options())
        std::cout << o.name << "\t" << o.group << "\t" << rr::option_type_name(o.type) << "\t" << o.default_text << "\n";
      return 0;
    }
    if (mesh.empty()) throw CLI::ValidationError("MESH", "give a mesh (.ply)");
    if (offscreen && replay_path.empty()) throw CLI::ValidationError("--offscreen", "needs --replay FILE");
    const std::vector<std::string> replay = replay_path.empty() ? std::vector<std::string>{} : read_replay(replay_path);
    Viewer v(mesh, dv, tt::settings_of(opts), [&opts](const std::string& n) { return opts.was_given(n); }, verb);
    v.inputs = {mesh, dv, replay_path};
    if (!frames_path.empty()) v.load_frames(frames_path);
    return offscreen ? run_offscreen(v, replay) : run_window(v, replay, save_dir);
  });
}
