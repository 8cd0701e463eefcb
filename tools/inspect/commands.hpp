#pragma once
// terrain-inspect's subcommands (tools/terrain_inspect.cpp parses, these run): info,
// preview and export of DEMs, meshes, scattered points and drainage databases.
#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>
#include <vector>

#include "common.hpp"
#include "renderer/core/plan_map.hpp"

namespace terrain::tools::inspect {

// info FILE: 'key: value' lines for a DEM, a mesh, scattered points or a .dv.
void run_info(const std::string& file);

struct PreviewArgs {
  std::string file, out, colour_by = "shade";
  double azimuth = 315.0, altitude = 45.0, zfactor = 1.0;
  std::uint32_t min_flow = 0;
};
void add_preview_options(CLI::App* cmd, PreviewArgs& a);
// preview FILE -o X.png: a hillshade (DEMs, meshes) or the drainage over one (.dv).
void run_preview(const PreviewArgs& a, const std::string& provenance, const Verbosity& verb);

struct ExportArgs {
  std::string file, out, to, d8_encoding = "taudem";
  int min_order = 1;
  double min_area = 1e4;  // m^2: the branches' channel-initiation area
  bool d8_lines = false;
  std::vector<std::string> gpkg_layers = {"branches", "basins", "divides"};
  // A mesh's plan-view hachure map (--layers hachures; renderer/core/plan_map.hpp), its
  // defaults the map's (PlanHachureOptions).
  double scale = 0, hachure_spacing = renderer::PlanHachureOptions{}.spacing,
         hachure_width = renderer::PlanHachureOptions{}.width,
         hachure_min_slope = 100 * renderer::PlanHachureOptions{}.min_slope_share;
  std::string hachure_tone = renderer::PlanHachureOptions{}.light_tone ? "light" : "slope",
              hachure_style = renderer::PlanHachureOptions{}.rows ? "rows" : "lines";
  std::string dv;  // the mesh's .dv: its ridge lines on the map
};
void add_export_options(CLI::App* cmd, ExportArgs& a);
// export FILE --to obj|tif|gpkg|svg|pdf.
void run_export(ExportArgs& a, const std::string& provenance, const Verbosity& verb);

}  // namespace terrain::tools::inspect
