// terrain-view: the interactive window over terrain-render's renderer. It draws exactly
// what `terrain-render frame` draws with the same options (the same scene, renderer and
// passes, in its own headless context; the window shows the frame read back), with the
// option table's panel, camera moves, saved views and keyframes, and a scriptable replay
// (--replay) that also runs without a window (--offscreen).
#include <iostream>
#include <string>
#include <vector>

#include "common.hpp"
#include "render_cli.hpp"
#include "renderer/core/options.hpp"
#include "view/replay.hpp"
#include "view/viewer.hpp"
#include "view/window.hpp"

namespace tt = terrain::tools;
namespace rr = renderer;
using terrain::tools::view::Viewer;

namespace {

struct Args {
  std::string mesh, dv, replay_path, frames_path, save_dir = ".";
  double memory_mib = 1024;
  bool offscreen = false;
  std::string list;  // --list-options: tsv or json
  tt::Verbosity verb;
  tt::TableArgs opts;
  renderer::VectorOptions vector;
};

void add_help(CLI::App& app) {
  app.footer(
      "Mouse: left drag orbits about the terrain point under the cursor, right or middle drag "
      "pans, the wheel\n"
      "zooms towards it. Keys: W/A/S/D fly, Q/E down/up (Shift: faster), Home: the default view, "
      "K: a\n"
      "keyframe, N: the next frame of --frames.\n\n"
      "Replay commands (--replay FILE, one a line): camera E N Z AZ ALT [FOV] | orbit D_AZ D_ALT | "
      "zoom SHARE |\n"
      "set NAME VALUE | layer NAME on|off | key home|w|a|s|d|q|e|k | keyframe | save-keyframes "
      "PATH [N] |\n"
      "load-frames PATH | next-frame | wait N | screenshot PATH.png [WxH] | window-shot PATH.png "
      "|\n"
      "save-view PATH.png|.svg|.pdf [WxH] | line-stats |\n"
      "timings | quit\n\n"
      "Examples:\n"
      "  terrain-view out/msh_50m.ply out/msh_breached.dv\n"
      "  terrain-view out/msh_50m.ply out/msh_breached.dv --replay tour.txt --offscreen\n"
      "  terrain-view logan_2m.ply logan_2m.dv --memory 512   # a mesh larger than that, read from "
      "its pyramid\n"
      "  terrain-view --list-options          # or --list-options=json\n\n"
      "See docs/terrain-view.md.");
}

void add_options(CLI::App& app, Args& a) {
  app.add_option("MESH", a.mesh, "Mesh (.ply from dem2mesh)");
  app.add_option("DV", a.dv, "Drainage database (.dv from build-drainage); no creases without it");
  app.add_option("--replay", a.replay_path, "Run the commands of this file (see below)");
  app.add_flag("--offscreen", a.offscreen,
               "No window: run the replay through EGL only (a machine without a display)");
  app.add_option("--frames", a.frames_path, "A frames CSV to step through (N, or next-frame)");
  app.add_option("--save-dir", a.save_dir, "Where the panel's Save buttons write")
      ->capture_default_str();
  tt::add_list_options_flag(&app, a.list);
  tt::add_vertex_memory_option(&app, a.memory_mib,
                               "as terrain-render frame reads it (the level the view draws over "
                               "the blocks in view, within this), again when a still view needs "
                               "more, and whole when a moving view leaves the blocks held");
  tt::add_verbosity_flags(app, a.verb);
  tt::add_table_options(&app, a.opts, false);
  tt::add_vector_options(&app, a.vector);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Interactive terrain viewer: draws what terrain-render frame draws, with every render "
      "option\n"
      "on a panel, camera moves, saved views and keyframes.",
      "terrain-view"};
  add_help(app);
  app.set_version_flag("--version", tt::version());
  Args a;
  add_options(app, a);

  return tt::run_main(app, argc, argv, [&]() -> int {
    if (!a.list.empty()) {
      tt::print_render_options(std::cout, a.list);
      return 0;
    }
    if (a.mesh.empty()) throw CLI::ValidationError("MESH", "give a mesh (.ply)");
    if (a.offscreen && a.replay_path.empty())
      throw CLI::ValidationError("--offscreen", "needs --replay FILE");
    const std::vector<std::string> replay = a.replay_path.empty()
                                                ? std::vector<std::string>{}
                                                : terrain::tools::view::read_replay(a.replay_path);
    Viewer v(
        a.mesh, a.dv, tt::settings_of(a.opts),
        [&a](const std::string& n) { return a.opts.was_given(n); }, a.verb,
        std::uint64_t(a.memory_mib * 1048576.0));
    v.inputs = {a.mesh, a.dv, a.replay_path};
    v.vector = a.vector;
    if (!a.frames_path.empty()) v.load_frames(a.frames_path);
    return a.offscreen ? terrain::tools::view::run_offscreen(v, replay)
                       : terrain::tools::view::run_window(v, replay, a.save_dir);
  });
}
