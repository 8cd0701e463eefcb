#include "view/window.hpp"

#include <epoxy/gl.h>  // before GLFW, which would include GL/gl.h
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <fmt/format.h>
#include <imgui.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <optional>

#include "terrain/image_io.hpp"
#include "view/replay.hpp"

namespace terrain::tools::view {

namespace {

// A list option's widget: a checkbox per choice. Returns the new value, or "" unchanged.
std::string list_widget(const rr::OptionSpec& o, const std::string& label,
                        const std::string& value) {
  std::string next;
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
  return next;
}

// The widget of option `o` showing `value`. Returns the new value, or "" unchanged.
std::string option_widget(const rr::OptionSpec& o, const std::string& label,
                          const std::string& value) {
  std::string next;
  switch (o.type) {
    case rr::OptionType::Number: {
      float f = value == "auto" ? -1.0f : std::stof(value);
      if (!o.unbounded() ? ImGui::SliderFloat(label.c_str(), &f, float(o.min), float(o.max))
                         : ImGui::DragFloat(label.c_str(), &f, 1.0f))
        next = fmt::format("{}", f);
      break;
    }
    case rr::OptionType::Integer: {
      int i = std::stoi(value);
      if (!o.unbounded() ? ImGui::SliderInt(label.c_str(), &i, int(o.min), int(o.max))
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
    case rr::OptionType::List:
      next = list_widget(o, label, value);
      break;
    case rr::OptionType::Size:
    case rr::OptionType::Point:
      ImGui::Text("%s: %s", o.name.c_str(), value.c_str());
      break;
  }
  return next;
}

// The option panel, generated from the table: a widget per option, in its group.
void option_panel(Viewer& v, std::string& message) {
  rr::RenderSettings& s = v.settings();
  std::vector<std::string> groups;  // in the order they first appear, as --help lists them
  for (const rr::OptionSpec& o : rr::render_options())
    if (std::find(groups.begin(), groups.end(), o.group) == groups.end()) groups.push_back(o.group);
  for (const std::string& group : groups) {
    if (!ImGui::CollapsingHeader(group.c_str(),
                                 group == "Frame" ? ImGuiTreeNodeFlags_DefaultOpen : 0))
      continue;
    for (const rr::OptionSpec& o : rr::render_options()) {
      if (o.group != group) continue;
      const std::string label = o.name + (o.unit.empty() ? "" : " (" + o.unit + ")");
      const std::string value = o.get(s);
      const std::string next = option_widget(o, label, value);
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

// The window, its ImGui context and the texture that shows the frame; what the loop keeps
// from one drawn frame to the next.
class Window {
 public:
  Window(Viewer& v, const std::vector<std::string>& replay, std::string save_dir)
      : v_(v), replay_(replay), save_dir_(std::move(save_dir)) {
    if (!glfwInit()) throw terrain::Error("cannot open a window (no display? use --offscreen)");
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    v.gl().release_current();  // GLFW makes its context current while it creates the window
    window_ =
        glfwCreateWindow(v.settings().width, v.settings().height, "terrain-view", nullptr, nullptr);
    if (!window_) {
      glfwTerminate();
      throw terrain::Error("cannot open a window (no display? use --offscreen)");
    }
    v.before_gl = [] { glfwMakeContextCurrent(nullptr); };
    glfwMakeContextCurrent(window_);
    glfwSwapInterval(1);
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;
    ImGui_ImplGlfw_InitForOpenGL(window_, true);
    ImGui_ImplOpenGL3_Init("#version 330");
    glGenTextures(1, &texture_);
    save_size_ = fmt::format("{}x{}", v.settings().width, v.settings().height);
  }
  ~Window() {
    glDeleteTextures(1, &texture_);
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    glfwDestroyWindow(window_);
    glfwTerminate();
    v_.before_gl = nullptr;
    v_.gl().make_current();  // the renderers free their GL objects in their own context
  }
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;

  // One drawn frame: input, panel, a replay command, the frame; false when it is done.
  bool frame() {
    if (!running_ || glfwWindowShouldClose(window_)) return false;
    glfwPollEvents();
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    const rr::RenderSettings before = v_.settings();
    mouse_and_keys();
    panel();
    replay_step();
    if (rr::changed_options(before) != rr::changed_options(v_.settings()))
      last_input_ = Clock::now(), dirty_ = true;
    show();
    return true;
  }

 private:
  // Camera: left drag orbits about the terrain point under the cursor, right or middle drag
  // pans, the wheel zooms towards it; W/A/S/D, Q/E fly (Shift: faster); Home; K; N.
  void mouse_and_keys() {
    const ImGuiIO& io = ImGui::GetIO();
    rr::RenderSettings& s = v_.settings();
    rr::Camera& c = s.frame.camera;
    const tt::ViewCamera cam = v_.camera();
    double mx = 0, my = 0;
    glfwGetCursorPos(window_, &mx, &my);
    if (!io.WantCaptureMouse) {
      const bool any = ImGui::IsMouseDown(0) || ImGui::IsMouseDown(1) || ImGui::IsMouseDown(2);
      if (any && !pivot_) pivot_ = cam.pick(c, mx, my);
      if (!any) pivot_.reset();
      if (pivot_ && ImGui::IsMouseDown(0))
        cam.orbit(c, *pivot_, 0.3 * (mx - last_x_), 0.3 * (my - last_y_));
      if (pivot_ && (ImGui::IsMouseDown(1) || ImGui::IsMouseDown(2)))
        cam.pan(c, *pivot_, mx - last_x_, my - last_y_);
      if (io.MouseWheel != 0)
        if (const auto p = cam.pick(c, mx, my)) cam.zoom(c, *p, io.MouseWheel > 0 ? 0.15 : -0.15);
    }
    last_x_ = mx, last_y_ = my;
    if (io.WantCaptureKeyboard) return;
    // Per drawn frame: 0.5 % of the terrain's width (Shift: 2.5 %), as a replay's key moves 2 %.
    const double step =
        (io.KeyShift ? 0.025 : 0.005) * double(v_.surface().topo.cols) * v_.surface().geo.dx;
    const auto down = [&](int k) { return glfwGetKey(window_, k) == GLFW_PRESS; };
    cam.fly(c, step * (down(GLFW_KEY_W) - down(GLFW_KEY_S)),
            step * (down(GLFW_KEY_D) - down(GLFW_KEY_A)),
            step * (down(GLFW_KEY_E) - down(GLFW_KEY_Q)));
    if (ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Home))) v_.home();
    if (ImGui::IsKeyPressed(GLFW_KEY_K, false)) v_.keyframes.push_back(s.frame);
    if (ImGui::IsKeyPressed(GLFW_KEY_N, false) && !v_.frames.empty()) {
      v_.frame_index = (v_.frame_index + 1) % v_.frames.size();
      s.frame = v_.frames[v_.frame_index];
    }
  }

  // Runs `save` and shows its error on the panel.
  void saving(const std::function<void()>& save) {
    try {
      save();
    } catch (const terrain::Error& e) {
      message_ = e.what();
    }
  }

  // The panel: timings, the camera, the buttons and the option table's widgets.
  void panel() {
    const rr::Camera& c = v_.settings().frame.camera;
    ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(380, float(v_.settings().height) - 16), ImGuiCond_FirstUseEver);
    ImGui::Begin("terrain-view");
    const double ms = v_.last_was_cheap() ? v_.cheap_ms() : v_.full_ms();
    ImGui::Text("%s frame %dx%d: %.1f ms (%.1f fps)", v_.last_was_cheap() ? "cheap" : "full",
                v_.last().width, v_.last().height, ms, 1000.0 / std::max(1e-3, ms));
    std::string passes;
    for (int p = 0; p < rr::kPassCount; ++p)
      passes += fmt::format("{} {:.1f}  ", rr::pass_name(p), v_.last().timings.gpu_ms[p]);
    ImGui::TextWrapped("GL ms: %s", passes.c_str());
    if (c.eye)
      ImGui::Text("eye %.0f %.0f %.0f  az %.1f alt %.1f", c.eye->x(), c.eye->y(), c.eye->z(),
                  c.view_az, c.view_alt);
    if (ImGui::Button("Line statistics")) stats_ = v_.line_stats();
    ImGui::SameLine();
    const std::filesystem::path dir(save_dir_);
    if (ImGui::Button("Save view"))
      saving([&] {
        v_.save_view((dir / fmt::format("view_{:03d}.png", saved_++)).string(), save_size_);
      });
    ImGui::SameLine();
    ImGui::SetNextItemWidth(90);
    char size_text[32];
    std::snprintf(size_text, sizeof size_text, "%s", save_size_.c_str());
    if (ImGui::InputText("size", size_text, sizeof size_text)) save_size_ = size_text;
    ImGui::SameLine();
    if (ImGui::Button("Keyframe (K)")) v_.keyframes.push_back(v_.settings().frame);
    if (v_.keyframes.size() >= 2 && ImGui::Button("Save keyframes"))
      saving([&] { v_.save_keyframes((dir / "keyframes.csv").string(), 60); });
    if (!stats_.empty()) ImGui::TextUnformatted(stats_.c_str());
    if (!message_.empty()) ImGui::TextColored(ImVec4(0.8f, 0.1f, 0.1f, 1), "%s", message_.c_str());
    option_panel(v_, message_);
    ImGui::End();
  }

  // The replay: one command a frame, `wait N` skips N frames.
  void replay_step() {
    if (wait_ > 0) {
      --wait_;
      return;
    }
    if (next_line_ >= replay_.size()) return;
    try {
      running_ = run_command(v_, replay_[next_line_], wait_);
    } catch (const std::exception& e) {
      throw replay_error(next_line_, e);
    }
    ++next_line_;
  }

  // The frame behind the panel: while input moves the view and a full frame is slow
  // (> 50 ms), the half-size frame; the full frame once the input has been still 200 ms.
  void show() {
    const bool moving = ms_since(last_input_) < 200;
    if (dirty_ || (!moving && v_.last_was_cheap())) {
      v_.render(moving && v_.full_ms() > 50);
      dirty_ = false;
      const rr::FrameResult& f = v_.last();
      v_.gl().release_current();
      glfwMakeContextCurrent(window_);
      glBindTexture(GL_TEXTURE_2D, texture_);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
      glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
      glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, f.width, f.height, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                   f.rgba.data());
    }
    v_.gl().release_current();
    glfwMakeContextCurrent(window_);
    ImGui::GetBackgroundDrawList()->AddImage(
        reinterpret_cast<ImTextureID>(std::uintptr_t(texture_)), ImVec2(0, 0),
        ImGui::GetIO().DisplaySize);
    ImGui::Render();
    int fw = 0, fh = 0;
    glfwGetFramebufferSize(window_, &fw, &fh);
    glViewport(0, 0, fw, fh);
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    if (!v_.window_shot.empty() && !dirty_) window_shot(fw, fh);
    glfwSwapBuffers(window_);
  }

  // window-shot: the window as drawn, panel included.
  void window_shot(int fw, int fh) {
    std::vector<std::uint8_t> rgba(std::size_t(fw) * std::size_t(fh) * 4), flipped(rgba.size());
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, fw, fh, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    const std::size_t row = std::size_t(fw) * 4;
    for (int y = 0; y < fh; ++y)
      std::copy_n(rgba.data() + std::size_t(fh - 1 - y) * row, row,
                  flipped.data() + std::size_t(y) * row);
    for (std::size_t i = 3; i < flipped.size(); i += 4) flipped[i] = 255;
    terrain::write_png(v_.window_shot, fw, fh, 4, flipped, "terrain-view window");
    v_.window_shot.clear();
  }

  Viewer& v_;
  const std::vector<std::string>& replay_;
  std::string save_dir_, message_, stats_, save_size_;
  GLFWwindow* window_ = nullptr;
  GLuint texture_ = 0;
  std::size_t next_line_ = 0;
  int wait_ = 0, saved_ = 0;
  bool dirty_ = true, running_ = true;
  Clock::time_point last_input_ = Clock::now() - std::chrono::seconds(1);
  double last_x_ = 0, last_y_ = 0;
  std::optional<Eigen::Vector3d> pivot_;
};

}  // namespace

int run_window(Viewer& v, const std::vector<std::string>& replay, const std::string& save_dir) {
  Window w(v, replay, save_dir);
  while (w.frame()) {
  }
  return 0;
}

}  // namespace terrain::tools::view
