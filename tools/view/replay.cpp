#include "view/replay.hpp"

#include <fmt/format.h>

#include <array>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

namespace terrain::tools::view {

namespace {

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
  double number(std::size_t k, const std::string& what, double lo, double hi,
                bool whole = false) const {
    const std::string& w = (*this)[k];
    char* end = nullptr;
    const double v = std::strtod(w.c_str(), &end);
    if (w.empty() || end != w.c_str() + w.size() || !std::isfinite(v))
      throw terrain::Error(what + ": '" + w + "' is not a finite number");
    if (whole && v != std::floor(v))
      throw terrain::Error(what + ": '" + w + "' is not a whole number");
    if (v < lo || v > hi)
      throw terrain::Error(fmt::format("{}: {} is outside {:g} .. {:g}", what, w, lo, hi));
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

// The rest of the line after its command word, which must not be empty: a path.
std::string path_arg(const std::string& line, const std::string& usage) {
  const std::string p = after_command(line);
  if (p.empty()) throw terrain::Error("expected " + usage);
  return p;
}

// camera, orbit, zoom, key: the camera's commands; false for another command.
bool camera_command(Viewer& v, const ReplayArgs& a) {
  const std::string& cmd = a.command();
  rr::Camera& c = v.settings().frame.camera;
  const tt::ViewCamera cam = v.camera();
  const auto centre = [&] {
    const auto p = cam.pick(c, v.settings().width / 2.0, v.settings().height / 2.0);
    if (!p) throw terrain::Error("the view's centre is not on the terrain");
    return *p;
  };
  if (cmd == "camera") {
    a.expect(5, 6, "camera E N Z AZ ALT [FOV]");
    rr::RenderSettings s = v.settings();
    const char* names[] = {"eye", "view-az", "view-alt", "fov"};
    for (std::size_t k = 2; k < a.size(); ++k) {
      const std::string value = k == 2 ? a[0] + " " + a[1] + " " + a[2] : a[k];
      try {
        rr::set_option(s, *rr::find_option(names[k - 2]), value);
      } catch (const terrain::Error& e) {
        throw terrain::Error(std::string("camera: ") + (k == 2 ? "E N Z" : names[k - 2]) + ": " +
                             e.what());
      }
    }
    v.check_eye(*s.frame.camera.eye);
    c = s.frame.camera;
  } else if (cmd == "orbit") {
    a.expect(2, 2, "orbit D_AZ D_ALT");
    cam.orbit(c, centre(), a.number(0, "orbit: D_AZ", -3600, 3600),
              a.number(1, "orbit: D_ALT", -180, 180));
  } else if (cmd == "zoom") {
    a.expect(1, 1, "zoom SHARE");
    // A share of the distance to the view's centre: 1 would put the eye on the terrain.
    cam.zoom(c, centre(), a.number(0, "zoom: SHARE", -10, 0.95));
  } else if (cmd == "key") {
    a.expect(1, 1, "key home|w|a|s|d|q|e|k");
    const double step = 0.02 * double(v.surface().topo.cols) * v.surface().geo.dx;
    // Forward, right, up per key (W/S, D/A, E/Q), as the window's keys move.
    static const std::map<std::string, std::array<double, 3>> fly = {
        {"w", {1, 0, 0}},  {"s", {-1, 0, 0}}, {"d", {0, 1, 0}},
        {"a", {0, -1, 0}}, {"e", {0, 0, 1}},  {"q", {0, 0, -1}}};
    if (a[0] == "home")
      v.home();
    else if (a[0] == "k")
      v.keyframes.push_back(v.settings().frame);
    else if (const auto m = fly.find(a[0]); m != fly.end())
      cam.fly(c, step * m->second[0], step * m->second[1], step * m->second[2]);
    else
      throw terrain::Error("unknown key '" + a[0] + "' (home w a s d q e k)");
  } else {
    return false;
  }
  return true;
}

// set, layer, keyframe, save-keyframes, load-frames, next-frame, wait: the options and
// frames; false for another command.
bool frame_command(Viewer& v, const ReplayArgs& a, const std::string& line, int& wait_frames) {
  const std::string& cmd = a.command();
  if (cmd == "set") {
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
  } else if (cmd == "keyframe") {
    a.expect(0, 0, "keyframe");
    v.keyframes.push_back(v.settings().frame);
  } else if (cmd == "save-keyframes") {
    a.expect(1, 2, "save-keyframes PATH [N]");
    const int n =
        a.size() > 1 ? int(a.number(1, "save-keyframes: N", 2, rr::kMaxPathFrames, true)) : 60;
    v.save_keyframes(a[0], n);
  } else if (cmd == "load-frames") {
    v.load_frames(path_arg(line, "load-frames PATH"));
  } else if (cmd == "next-frame") {
    a.expect(0, 0, "next-frame");
    if (v.frames.empty()) throw terrain::Error("next-frame: no frames loaded (load-frames PATH)");
    v.frame_index = (v.frame_index + 1) % v.frames.size();
    v.settings().frame = v.frames[v.frame_index];
  } else if (cmd == "wait") {
    a.expect(1, 1, "wait N");
    wait_frames = int(a.number(0, "wait: N", 0, 100000, true));
  } else {
    return false;
  }
  return true;
}

// screenshot, save-view, window-shot, line-stats, timings: what the viewer writes and
// prints; false for another command.
bool output_command(Viewer& v, const ReplayArgs& a, const std::string& line) {
  const std::string& cmd = a.command();
  if (cmd == "screenshot" || cmd == "save-view") {
    a.expect(1, 2, cmd + " PATH [WxH]");
    cmd == "screenshot" ? v.screenshot(a[0], a.size() > 1 ? a[1] : "")
                        : v.save_view(a[0], a.size() > 1 ? a[1] : "");
  } else if (cmd == "window-shot") {  // offscreen: the frame alone
    const std::string p = path_arg(line, "window-shot PATH");
    if (!p.ends_with(".png"))
      throw terrain::Error("window-shot writes a PNG image: give a .png name, not '" + p + "'");
    v.check_output({p});
    v.window_shot = p;
  } else if (cmd == "line-stats") {
    a.expect(0, 0, "line-stats");
    std::cout << v.line_stats();
  } else if (cmd == "timings") {
    a.expect(0, 0, "timings");
    const auto passes = [](const rr::FrameResult& f) {  // the passes' own times
      std::string t;
      for (int p = 0; p < rr::kPassCount; ++p)
        t += fmt::format("{}{} {:.1f}", p ? ", " : "", rr::pass_name(p), f.timings.gpu_ms[p]);
      return t;
    };
    const rr::FrameResult& f = v.render(false);
    std::cout << fmt::format("full frame {}x{}: {:.1f} ms ({})\n", f.width, f.height, v.full_ms(),
                             passes(f));
    const rr::FrameResult& c = v.render(true);
    std::cout << fmt::format("cheap frame {}x{}: {:.1f} ms ({})\n", c.width, c.height, v.cheap_ms(),
                             passes(c));
  } else {
    return false;
  }
  return true;
}

}  // namespace

bool run_command(Viewer& v, const std::string& line, int& wait_frames) {
  const ReplayArgs a(line);
  if (a.empty()) return true;
  if (camera_command(v, a) || frame_command(v, a, line, wait_frames) || output_command(v, a, line))
    return true;
  if (a.command() != "quit") throw terrain::Error("unknown replay command '" + a.command() + "'");
  a.expect(0, 0, "quit");
  return false;
}

namespace {

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

}  // namespace

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

}  // namespace terrain::tools::view
