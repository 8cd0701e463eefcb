// terrain-inspect export: the formats it writes, one row each (kExportFormats), and their
// writers. The --to choices and help, -o's default and extension check, which inputs take
// which format, and the dispatch all read the table.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <filesystem>
#include <iostream>

#include "drainage/dv_file.hpp"
#include "drainage/gis_layers.hpp"
#include "drainage/rasters.hpp"
#include "inspect/commands.hpp"
#include "renderer/core/options.hpp"
#include "renderer/core/plan_map.hpp"
#include "renderer/core/ridges.hpp"
#include "renderer/core/vector_file.hpp"
#include "terrain/atomic_file.hpp"
#include "terrain/dem_io.hpp"
#include "terrain/grid_mesh.hpp"
#include "terrain/mesh_io.hpp"

namespace terrain::tools::inspect {

namespace tt = terrain::tools;
namespace fs = std::filesystem;

namespace {

enum class Input { Mesh, Dv };
using Writer = void (*)(ExportArgs&, const std::string& provenance, const Verbosity&);

// A mesh's plan-view hachure map (renderer/core/plan_map.hpp) as gpkg, svg or pdf.
void export_hachure_map(ExportArgs& a, const std::string& provenance, const Verbosity&) {
  const bool layers_given =
      a.gpkg_layers != ExportArgs{}.gpkg_layers;  // the default names a .dv's layers
  for (const std::string& l : a.gpkg_layers)
    if (layers_given && l != "hachures")
      throw terrain::Error("--layers " + l + ": a .dv's layer; a mesh exports only hachures");
  if (!a.dv.empty() && !drainage::is_dv_file(a.dv))
    throw terrain::Error("--dv '" + a.dv + "' is not a drainage database (.dv)");
  const terrain::GridMesh m = terrain::read_mesh_ply(a.file);
  renderer::PlanHachureOptions o;
  o.scale = a.scale, o.spacing = a.hachure_spacing, o.width = a.hachure_width;
  o.light_tone = a.hachure_tone == "light", o.rows = a.hachure_style == "rows";
  o.min_slope_share = a.hachure_min_slope / 100.0;
  const std::vector<renderer::SceneRidge> ridges =
      a.dv.empty() ? std::vector<renderer::SceneRidge>{} : renderer::read_ridges(a.dv, m);
  const renderer::PlanHachures h = renderer::plan_hachures(m, o, ridges);
  const std::array<double, 6> gt = renderer::plan_geotransform(m, h.plan);
  if (a.to == "gpkg") {
    renderer::write_hachures_gpkg(m, h, a.out);
  } else {
    const std::string desc = provenance + " | plan view, " + renderer::map_note(gt, m.geo.epsg);
    terrain::write_file_atomic(
        a.out, renderer::vector_bytes(renderer::plan_vector_art(h, o),
                                      renderer::vector_format_of(a.out), 96.0, desc));
  }
  std::cout << "output: " << a.out << "\n"
            << fmt::format("map: {} x {} pixels, {} m a pixel\n", h.plan.width, h.plan.height,
                           h.plan.scale)
            << "geotransform: " << renderer::geotransform_text(gt) << "\n";
  if (h.row_interval > 0) std::cout << "form lines: every " << h.row_interval << " m\n";
  std::cout << "hachures: " << h.hachures.size() << "\n";
  if (!a.dv.empty()) std::cout << "ridges: " << h.ridges.size() << "\n";
}

void export_mesh_obj(ExportArgs& a, const std::string&, const Verbosity&) {
  terrain::write_mesh_obj(terrain::read_mesh_ply(a.file), a.out);
  std::cout << "output: " << a.out << "\n";
}

void export_mesh_tif(ExportArgs& a, const std::string& provenance, const Verbosity&) {
  terrain::write_geotiff(terrain::mesh_to_grid(terrain::read_mesh_ply(a.file)), a.out, provenance);
  std::cout << "output: " << a.out << "\n";
}

void export_dv_gpkg(ExportArgs& a, const std::string&, const Verbosity& verb) {
  for (const std::string& l : a.gpkg_layers)
    if (l == "hachures")
      throw terrain::Error("--layers hachures: a mesh's layer ('" + a.file + "' is a .dv)");
  drainage::GpkgLayers layers;
  auto has = [&](const char* name) {
    return std::find(a.gpkg_layers.begin(), a.gpkg_layers.end(), name) != a.gpkg_layers.end();
  };
  layers.branches = has("branches"), layers.basins = has("basins"), layers.divides = has("divides");
  layers.rivers = {a.min_order, a.min_area, a.d8_lines ? 0.0 : 1.5};
  const drainage::GpkgCounts n =
      drainage::export_dv_gpkg(a.file, a.out, layers, tt::terminal_progress(verb, "gpkg"));
  std::cout << "output: " << a.out << "\n";
  if (layers.branches) std::cout << "branches: " << n.branches << "\n";
  if (layers.basins) std::cout << "basins: " << n.basins << "\n";
  if (layers.divides) std::cout << "divides: " << n.divides << "\n";
}

// Every layer, window by window, into a directory; the seven land together, or none does.
void export_dv_rasters(ExportArgs& a, const std::string& provenance, const Verbosity&) {
  std::error_code ec;
  if (fs::exists(a.out, ec) && !fs::is_directory(a.out, ec))
    throw terrain::Error(
        "'" + a.out + "' exists and is not a directory: a .dv exports to a directory of GeoTIFFs");
  (void)drainage::read_dv_header(a.file);  // a file that is no .dv fails before any folder is made
  terrain::NewDirectories made(a.out);     // removed again on an error or an interrupt
  terrain::OutputSet outputs;
  std::size_t points = 0;
  outputs.write([&] {
    points = drainage::export_dv_rasters(
        a.file, [&](const std::string& name) { return outputs.stage(fs::path(a.out) / name); },
        drainage::parse_d8_encoding(a.d8_encoding), provenance);
  });
  outputs.commit();
  made.keep();
  std::cout << "output: " << a.out << "\npoints: " << points << "\n";
  for (const char* name : drainage::kDrainageRasterNames)
    std::cout << "layer: " << (fs::path(a.out) / name).string() << "\n";
}

// What export writes: --to's value, the input it takes, -o's default (FILE's name, then
// `suffix`) and the extension -o must have (none: a directory, its files `files`), what it
// holds (for --help), whether it draws --dv's ridges, and its writer.
struct ExportFormat {
  const char* to;
  Input input;
  const char* suffix;
  const char* extension;
  const char* what;
  bool ridges;
  Writer write;
};
constexpr ExportFormat kExportFormats[] = {
    {"obj", Input::Mesh, ".obj", ".obj", "the mesh as Wavefront OBJ", false, export_mesh_obj},
    {"tif", Input::Mesh, ".tif", ".tif", "the mesh's heights as a GeoTIFF", false, export_mesh_tif},
    {"gpkg", Input::Mesh, "_map.gpkg", ".gpkg", "a plan-view hachure map", true,
     export_hachure_map},
    {"svg", Input::Mesh, ".svg", ".svg", "a plan-view hachure map", true, export_hachure_map},
    {"pdf", Input::Mesh, ".pdf", ".pdf", "a plan-view hachure map", true, export_hachure_map},
    {"gpkg", Input::Dv, ".gpkg", ".gpkg", "the branches, basins and divides", false,
     export_dv_gpkg},
    {"tif", Input::Dv, "_rasters", "", "a directory of GeoTIFFs", false, export_dv_rasters},
};

const char* input_name(Input i) {
  return i == Input::Mesh ? "a terrain mesh (.ply)" : "a drainage database (.dv)";
}

// The row for --to `to` and `file`'s kind; Error naming the kinds that export to it.
const ExportFormat& export_format(const std::string& to, const std::string& file) {
  const bool is_mesh = terrain::is_ply_file(file), is_dv = drainage::is_dv_file(file);
  std::vector<Input> takes;
  for (const ExportFormat& f : kExportFormats) {
    if (f.to != to) continue;
    if ((f.input == Input::Mesh && is_mesh) || (f.input == Input::Dv && is_dv)) return f;
    takes.push_back(f.input);
  }
  if (takes.size() == 1)
    throw terrain::Error(fmt::format("'{}' is not {}: only {} export to {}", file,
                                     input_name(takes[0]),
                                     takes[0] == Input::Mesh ? "meshes" : ".dv files", to));
  throw terrain::Error(fmt::format("'{}' is neither {} nor {}: only those export to {}", file,
                                   input_name(Input::Mesh), input_name(Input::Dv), to));
}

// A plan map's hachure option, declared from the frame's row of the option table (its range
// or choices and its help), with the map's default in `value`.
template <class T>
void add_map_hachure_option(CLI::App* cmd, const std::string& name, T& value) {
  const renderer::OptionSpec& spec = *renderer::find_option(name);
  std::string help = spec.help;
  if (help.starts_with("--layers hachures: ")) help = help.substr(19);
  if (const std::size_t drawn = help.find(" (drawn, times --line-scale"); drawn != help.npos)
    help.erase(drawn);  // a map has no --line-scale
  for (const std::string frame : {"the frame's", "the view's"})
    for (std::size_t at; (at = help.find(frame)) != std::string::npos;)
      help.replace(at, frame.size(), "the map's");
  CLI::Option* o = cmd->add_option("--" + name, value, "Hachure map: " + help);
  if (spec.type == renderer::OptionType::Enum)
    o->check(CLI::IsMember(spec.choices));
  else
    o->check(CLI::Range(spec.min, spec.max));
  o->capture_default_str();
}

}  // namespace

namespace {
void add_river_options(CLI::App* exp, ExportArgs& a);
void add_map_options(CLI::App* exp, ExportArgs& a);
}  // namespace

void add_export_options(CLI::App* exp, ExportArgs& a) {
  exp->add_option("FILE", a.file, "Terrain mesh (.ply) or drainage database (.dv)")->required();
  std::string help = "Output format:";
  std::vector<std::string> names;
  for (const ExportFormat& f : kExportFormats) {
    help +=
        fmt::format(" {} ({}{}),", f.to, f.input == Input::Mesh ? "a mesh: " : "a .dv: ", f.what);
    if (std::find(names.begin(), names.end(), f.to) == names.end()) names.push_back(f.to);
  }
  help.pop_back();
  exp->add_option("--to", a.to, help)->required()->check(CLI::IsMember(names));
  exp->add_option(
      "-o,--output", a.out,
      "Output file (default: FILE with the new extension; a mesh's map to gpkg: FILE's name, then "
      "_map.gpkg); a GeoPackage already there gets this export's layers added or replaced, its "
      "others "
      "kept; a .dv to tif: a directory (default: FILE's name without .dv, then _rasters), created "
      "if "
      "missing");
  exp->add_option("--d8-encoding", a.d8_encoding, "A .dv to tif: the codes of d8.tif")
      ->check(CLI::IsMember({"taudem", "esri"}))
      ->capture_default_str();
  add_river_options(exp, a);
  add_map_options(exp, a);
}

namespace {

// The rivers of a .dv's gpkg (drainage::RiverOptions).
void add_river_options(CLI::App* exp, ExportArgs& a) {
  exp->add_option("--min-order", a.min_order,
                  "gpkg: only branches of at least this Strahler order (counted on the rivers "
                  "--min-area keeps)")
      ->check(CLI::Range(1, 255))
      ->capture_default_str();
  exp->add_option("--min-area", a.min_area,
                  "gpkg: branches where at least this many square metres drain (a channel-"
                  "initiation area, as terrain-render's --min-area: 1 ha is 100 points at 10 m; "
                  "0: every D8 link, the .dv's own network)")
      ->check(CLI::Range(0.0, 1e15))
      ->capture_default_str();
  exp->add_flag("--d8-lines", a.d8_lines,
                "gpkg: branches as the D8 polylines (steps of 45 degrees), not smoothed as "
                "terrain-render smooths creases");
}

// The layers, and a mesh's hachure map.
void add_map_options(CLI::App* exp, ExportArgs& a) {
  exp->add_option("--layers", a.gpkg_layers,
                  "gpkg: the layers to write, comma-separated; a .dv: branches (LineString ZM, M = "
                  "normalized flow), "
                  "basins (polygons with area, outlet, max order), divides (lines between adjacent "
                  "basins with the "
                  "larger max order); a mesh: hachures (lines with slope_deg, tone, length_m, "
                  "row_m), its only layer")
      ->delimiter(',')
      ->check(CLI::IsMember({"branches", "basins", "divides", "hachures"}))
      ->default_str("branches,basins,divides (a .dv), hachures (a mesh)");
  exp->add_option("--scale", a.scale,
                  "A mesh's hachure map: metres a pixel (default: a round scale that makes the "
                  "longer side at most 2048 "
                  "pixels)")
      ->check(tt::kPositive);
  // The frame's hachure options (the option table: range, choices, help) with the map's
  // defaults.
  add_map_hachure_option(exp, "hachure-spacing", a.hachure_spacing);
  add_map_hachure_option(exp, "hachure-width", a.hachure_width);
  add_map_hachure_option(exp, "hachure-tone", a.hachure_tone);
  add_map_hachure_option(exp, "hachure-min-slope", a.hachure_min_slope);
  add_map_hachure_option(exp, "hachure-style", a.hachure_style);
  exp->add_option("--dv", a.dv,
                  "A mesh's hachure map: the mesh's drainage database; its ridge lines are drawn "
                  "(a layer ridges of "
                  "the gpkg, svg or pdf), selected by the map's scale as terrain-render's, and the "
                  "hachures stop at "
                  "them")
      ->check(CLI::ExistingFile);
}

}  // namespace

void run_export(ExportArgs& a, const std::string& provenance, const Verbosity& verb) {
  std::error_code ec;
  if (!fs::exists(a.file, ec)) throw terrain::Error("cannot read '" + a.file + "': no such file");
  const ExportFormat& f = export_format(a.to, a.file);
  if (a.out.empty())
    a.out =
        (fs::path(a.file).parent_path() / (fs::path(a.file).stem().string() + f.suffix)).string();
  const bool directory = *f.extension == 0;
  if (!a.dv.empty() && !f.ridges) {
    std::vector<std::string> maps;
    for (const ExportFormat& g : kExportFormats)
      if (g.ridges) maps.push_back(g.to);
    throw terrain::Error(
        fmt::format("--dv: only a mesh's hachure map (--to {}) draws a .dv's ridge lines",
                    fmt::join(maps, ", ")));
  }
  std::vector<std::string> targets = {a.out};
  if (directory) {
    targets.clear();
    for (const char* name : drainage::kDrainageRasterNames)
      targets.push_back((fs::path(a.out) / name).string());
  }
  tt::check_distinct_paths(
      a.dv.empty() ? std::vector<std::string>{a.file} : std::vector<std::string>{a.file, a.dv},
      targets);
  if (!directory && !a.out.ends_with(f.extension))
    throw terrain::Error(fmt::format("--to {} writes {}: give -o a name ending in {}, not '{}'",
                                     a.to, f.what, f.extension, a.out));
  tt::warn_stale_temporaries(verb, targets);
  if (!directory) terrain::check_output_path(a.out);
  f.write(a, provenance, verb);
}

}  // namespace terrain::tools::inspect
