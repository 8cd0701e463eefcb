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

int main(int argc, char** argv) {
  CLI::App app{
      "Render PN-triangle terrain with drainage creases and Toward/Away silhouettes, headless\n"
      "(OpenGL 4.5 through EGL: a GPU where there is one, Mesa llvmpipe otherwise).",
      "terrain-render"};
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
      "  terrain-render --device\n\n"
      "See docs/terrain-render.md for the passes, the crease score and the camera conventions.");
  app.set_version_flag("--version", tt::version());
  app.require_subcommand(0, 1);
  app.fallthrough();  // -q / -v after the subcommand
  bool list_devices_flag = false;
  app.add_flag("--device", list_devices_flag,
               "List the EGL devices and OpenGL renderers found, then exit");
  tt::Verbosity verb;
  tt::add_verbosity_flags(app, verb);
  const char* stats_help =
      "Also measure the drawn creases: length in pixels, shares near the grid boundary, on flat "
      "ground and in valleys, strokes; and the drawn silhouettes: pixels, pieces; batch: per "
      "frame in line_stats.csv, and the crease flicker between frames";

  auto* frame_cmd = app.add_subcommand("frame", "Render one frame to a PNG, SVG or PDF");
  std::string mesh, dv, out;
  TableArgs fa;
  frame_cmd->add_option("MESH", mesh, "Mesh (.ply from dem2mesh)")->required();
  frame_cmd->add_option("DV", dv,
                        "Drainage database (.dv from build-drainage); no creases without it");
  frame_cmd
      ->add_option("-o,--output", out,
                   "Output file: .png, or .svg / .pdf (the lines as vector paths)")
      ->required();
  frame_cmd->add_flag("--line-stats", fa.line_stats, stats_help);
  tr::OutputArgs fo, bo;
  tr::add_output_options(frame_cmd, fo, false);
  add_table_options(frame_cmd, fa, false);

  auto* batch_cmd =
      app.add_subcommand("batch", "Render every frame of a CSV list; write PNGs and timings.csv");
  std::vector<std::string> inputs;
  std::string dir;
  TableArgs ba;
  batch_cmd
      ->add_option("MESH [DV] FRAMES", inputs, "Mesh, optional drainage database, frame list (CSV)")
      ->required()
      ->expected(2, 3);
  batch_cmd->add_option("-o,--output", dir, "Output directory (created if missing)")->required();
  batch_cmd->add_flag("--line-stats", ba.line_stats, stats_help);
  tr::add_output_options(batch_cmd, bo, true);
  add_table_options(batch_cmd, ba, false);

  auto* path_cmd = app.add_subcommand("path", "Write a straight flight path as a frame list (CSV)");
  std::vector<double> from, to;
  int frames = 0;
  std::string path_out;
  TableArgs pa;
  // Any terrain mesh lies within 1e8 m of the origin (mesh_io.cpp): a viewpoint beyond 1e9
  // could only draw a blank frame.
  path_cmd->add_option("--from", from, "Start viewpoint E N Z (metres)")
      ->expected(3)
      ->required()
      ->check(CLI::Range(-1e9, 1e9));
  path_cmd->add_option("--to", to, "End viewpoint E N Z (metres)")
      ->expected(3)
      ->required()
      ->check(CLI::Range(-1e9, 1e9));
  path_cmd->add_option("--frames", frames, "Number of frames (>= 2)")
      ->check(CLI::Range(2, 1000000))
      ->required();
  path_cmd->add_option("-o,--output", path_out, "Output CSV")->required();
  add_table_options(path_cmd, pa,
                    true);  // the per-frame options; --view-az default: along the path

  return tt::run_main(app, argc, argv, [&]() -> int {
    if (list_devices_flag) return tr::list_devices();
    const std::string prov = tt::provenance(argc, argv);
    if (path_cmd->parsed()) return tr::run_path(pa, from, to, frames, path_out, prov);
    if (frame_cmd->parsed()) return tr::run_frame(fa, fo, mesh, dv, out, prov, verb);
    if (batch_cmd->parsed()) return tr::run_batch(ba, bo, inputs, dir, prov, verb);
    throw CLI::ValidationError("terrain-render",
                               "give a subcommand: frame, batch or path (or --device)");
  });
}
