// terrain-render: headless OpenGL renderer of PN-triangle terrain with drainage creases and
// Toward/Away silhouettes (Mower's Creases algorithm); single frames, batches, flight paths.
// Every render option comes from the renderer's option table (renderer/core/options.hpp).
#include <iostream>
#include <string>
#include <vector>

#include "common.hpp"
#include "render/commands.hpp"
#include "render_cli.hpp"

namespace tt = terrain::tools;
using tt::TableArgs;
namespace tr = terrain::tools::render;

namespace {

const char* const kStatsHelp =
    "Also measure the drawn creases: length in pixels, shares near the grid boundary, on flat "
    "ground and in valleys, strokes; and the drawn silhouettes: pixels, pieces; batch: per "
    "frame in line_stats.csv, and the crease flicker between frames";

struct FrameArgs {
  std::string mesh, dv, out;
  TableArgs table;
  tr::OutputArgs output;
};
struct BatchArgs {
  std::vector<std::string> inputs;
  std::string dir;
  TableArgs table;
  tr::OutputArgs output;
};
struct PathArgs {
  std::vector<double> from, to;
  int frames = 0;
  std::string out;
  TableArgs table;
};

void add_examples(CLI::App& app) {
  app.footer(
      "Examples:\n"
      "  terrain-render frame out/msh_50m.ply out/msh.dv -o msh.png\n"
      "  terrain-render frame out/msh_50m.ply out/msh.dv -o msh_shaded.png --layers shaded "
      "--view-az 180\n"
      "  terrain-render frame out/msh_50m.ply out/msh.dv -o msh.svg            # the lines as "
      "vector paths (or .pdf)\n"
      "  terrain-render frame out/msh_50m.ply out/msh.dv -o a3.pdf --size 4961x3508 --line-scale 3 "
      "--dpi 300\n"
      "  terrain-render path --from 560000 5120000 2600 --to 563000 5117000 2600 --frames 99 -o "
      "path.csv\n"
      "  terrain-render batch out/msh_50m.ply out/msh.dv path.csv -o frames/ --format png,svg\n"
      "  terrain-render frame out/msh_10m_denoised.ply -o pels.png --layers mask,pels,silhouettes\n"
      "  terrain-render frame out/msh_50m.ply -o edges.png --layers mask,edges --edges "
      "contour,crease --crease-angle 20\n"
      "  terrain-render frame out/msh_50m.ply out/msh.dv -o pen.svg --layers "
      "mask,hachures,creases,silhouettes\n"
      "  terrain-render frame out/msh_50m.ply out/msh.dv -o map.png --view top --map-scale 5   # a "
      "map: north up, 5 m a pixel, map.pgw\n"
      "  terrain-render frame logan_2m.ply logan_2m.dv -o l.png --memory 1024   # over 1 GiB of "
      "vertices: read from\n"
      "                                 # logan_2m.tpyr (dem2mesh --pyramid) at the level the view "
      "draws\n"
      "  terrain-render --device\n"
      "  terrain-render --list-options=json   # every render option, for programs\n\n"
      "See docs/terrain-render.md for the passes, the crease score and the camera conventions.");
}

CLI::App* add_frame_command(CLI::App& app, FrameArgs& a) {
  auto* cmd = app.add_subcommand("frame", "Render one frame to a PNG, SVG or PDF");
  cmd->add_option("MESH", a.mesh, "Mesh (.ply from dem2mesh)")->required();
  cmd->add_option("DV", a.dv, "Drainage database (.dv from build-drainage); no creases without it");
  cmd->add_option("-o,--output", a.out,
                  "Output file: .png, or .svg / .pdf (the lines as vector paths)")
      ->required();
  cmd->add_flag("--line-stats", a.table.line_stats, kStatsHelp);
  tr::add_output_options(cmd, a.output, false);
  add_table_options(cmd, a.table, false);
  return cmd;
}

CLI::App* add_batch_command(CLI::App& app, BatchArgs& a) {
  auto* cmd =
      app.add_subcommand("batch", "Render every frame of a CSV list; write PNGs and timings.csv");
  cmd->add_option("MESH [DV] FRAMES", a.inputs,
                  "Mesh, optional drainage database, frame list (CSV)")
      ->required()
      ->expected(2, 3);
  cmd->add_option("-o,--output", a.dir, "Output directory (created if missing)")->required();
  cmd->add_flag("--line-stats", a.table.line_stats, kStatsHelp);
  tr::add_output_options(cmd, a.output, true);
  add_table_options(cmd, a.table, false);
  return cmd;
}

CLI::App* add_path_command(CLI::App& app, PathArgs& a) {
  auto* cmd = app.add_subcommand("path", "Write a straight flight path as a frame list (CSV)");
  // Any terrain mesh lies within 1e8 m of the origin (mesh_io.cpp): a viewpoint beyond 1e9
  // could only draw a blank frame.
  cmd->add_option("--from", a.from, "Start viewpoint E N Z (metres)")
      ->expected(3)
      ->required()
      ->check(CLI::Range(-1e9, 1e9));
  cmd->add_option("--to", a.to, "End viewpoint E N Z (metres)")
      ->expected(3)
      ->required()
      ->check(CLI::Range(-1e9, 1e9));
  cmd->add_option("--frames", a.frames, "Number of frames (>= 2)")
      ->check(CLI::Range(2, 1000000))
      ->required();
  cmd->add_option("-o,--output", a.out, "Output CSV")->required();
  add_table_options(cmd, a.table,
                    true);  // the per-frame options; --view-az default: along the path
  return cmd;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Render PN-triangle terrain with drainage creases and Toward/Away silhouettes, headless\n"
      "(OpenGL 4.5 through EGL: a GPU where there is one, Mesa llvmpipe otherwise).",
      "terrain-render"};
  add_examples(app);
  app.set_version_flag("--version", tt::version());
  app.require_subcommand(0, 1);
  app.fallthrough();  // -q / -v after the subcommand
  bool list_devices_flag = false;
  app.add_flag("--device", list_devices_flag,
               "List the EGL devices and OpenGL renderers found, then exit");
  std::string list_options;
  tt::add_list_options_flag(&app, list_options);
  tt::Verbosity verb;
  tt::add_verbosity_flags(app, verb);
  FrameArgs f;
  BatchArgs b;
  PathArgs p;
  const CLI::App* frame_cmd = add_frame_command(app, f);
  const CLI::App* batch_cmd = add_batch_command(app, b);
  const CLI::App* path_cmd = add_path_command(app, p);
  return tt::run_main(app, argc, argv, [&]() -> int {
    if (list_devices_flag) return tr::list_devices();
    if (!list_options.empty()) {
      tt::print_render_options(std::cout, list_options);
      return 0;
    }
    const std::string prov = tt::provenance(argc, argv);
    if (path_cmd->parsed()) return tr::run_path(p.table, p.from, p.to, p.frames, p.out, prov);
    if (frame_cmd->parsed())
      return tr::run_frame(f.table, f.output, f.mesh, f.dv, f.out, prov, verb);
    if (batch_cmd->parsed()) return tr::run_batch(b.table, b.output, b.inputs, b.dir, prov, verb);
    throw CLI::ValidationError("terrain-render",
                               "give a subcommand: frame, batch or path (or --device)");
  });
}
