#include "inspect/commands.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <numbers>

#include "drainage/dv_file.hpp"
#include "drainage/dv_views.hpp"
#include "drainage/gis_layers.hpp"
#include "drainage/rasters.hpp"
#include "renderer/core/camera.hpp"
#include "renderer/core/options.hpp"
#include "renderer/core/plan_map.hpp"
#include "renderer/core/vector_file.hpp"
#include "terrain/atomic_file.hpp"
#include "terrain/dem_io.hpp"
#include "terrain/grid_mesh.hpp"
#include "terrain/hillshade.hpp"
#include "terrain/image_io.hpp"
#include "terrain/mesh_io.hpp"
#include "terrain/mesh_pyramid.hpp"
#include "terrain/scattered.hpp"

namespace terrain::tools::inspect {

namespace tt = terrain::tools;

namespace {

// Grey + alpha hillshade of a DEM (no-data transparent).
std::vector<std::uint8_t> dem_shade(const terrain::Grid& g, double az, double alt, double zf) {
  const auto shade = terrain::hillshade_grid(g, az, alt, zf);
  std::vector<std::uint8_t> ga(2 * g.size());
  for (std::size_t i = 0; i < g.size(); ++i) {
    ga[2 * i] = shade[i];
    ga[2 * i + 1] = g.valid(i) ? 255 : 0;
  }
  return ga;
}

// A mesh's plan-view hachure map (renderer/core/plan_map.hpp) as gpkg, svg or pdf.
void export_hachure_map(const ExportArgs& a, const std::string& provenance) {
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

}  // namespace

void add_preview_options(CLI::App* preview, PreviewArgs& a) {
  preview->add_option("FILE", a.file, "DEM, mesh or .dv")->required();
  preview->add_option("-o,--output", a.out, "PNG to write")->required();
  preview->add_option("--azimuth", a.azimuth, "Light azimuth, degrees clockwise from grid north")
      ->capture_default_str();
  preview->add_option("--altitude", a.altitude, "Light altitude above the horizon, degrees")
      ->check(CLI::Range(0.0, 90.0))
      ->capture_default_str();
  preview
      ->add_option("--colour-by", a.colour_by,
                   "Meshes: shade (hillshade of the normals), voronoi (vertex Voronoi area) or "
                   "normal-change "
                   "(degrees, from denoise-normals)")
      ->check(CLI::IsMember({"shade", "voronoi", "normal-change"}))
      ->capture_default_str();
  preview->add_option("--z-factor", a.zfactor, "Vertical exaggeration (DEMs only)")
      ->check(tt::kPositive)
      ->capture_default_str();
  preview->add_option("--min-flow", a.min_flow,
                      ".dv: draw points with at least this accumulated flow (default: the top 4 % "
                      "of points, at least 20)");
}

namespace {

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

void add_export_options(CLI::App* exp, ExportArgs& a) {
  exp->add_option("FILE", a.file, "Terrain mesh (.ply) or drainage database (.dv)")->required();
  exp->add_option("--to", a.to,
                  "Output format: a mesh to obj, tif, or a plan-view hachure map (gpkg, svg, pdf); "
                  "a .dv to tif or gpkg")
      ->required()
      ->check(CLI::IsMember({"obj", "tif", "gpkg", "svg", "pdf"}));
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
  exp->add_option("--min-order", a.min_order, "gpkg: only branches of at least this Strahler order")
      ->check(CLI::Range(1, 255))
      ->capture_default_str();
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

void run_preview(const PreviewArgs& a, const std::string& desc, const Verbosity& verb) {
  const std::string &file = a.file, &out = a.out, &colour_by = a.colour_by;
  const double azimuth = a.azimuth, altitude = a.altitude, zfactor = a.zfactor;
  const std::uint32_t min_flow = a.min_flow;
  const bool is_mesh = terrain::is_ply_file(file);
  const bool is_dv = drainage::is_dv_file(file);
  tt::check_distinct_paths({file}, {out});
  tt::warn_stale_temporaries(verb, {out});
  terrain::check_output_path(out);
  if (is_dv) {
    const drainage::DrainageDb db = drainage::read_dv(file);
    terrain::write_png(out, int(db.header.cols), int(db.header.rows), 3,
                       drainage::dv_preview(db, min_flow), desc);
  } else if (is_mesh) {
    const terrain::GridMesh m = terrain::read_mesh_ply(file);
    if (colour_by == "shade") {
      terrain::write_png(out, int(m.topo.cols), int(m.topo.rows), 1,
                         terrain::hillshade(m.normals, azimuth, altitude), desc);
    } else {
      const bool voronoi = colour_by == "voronoi";
      if (voronoi ? m.voronoi.empty() : m.normal_change.size() != m.n_vertices())
        throw terrain::Error("'" + file + "' has no " +
                             (voronoi ? "Voronoi weights (denoise-normals --iterations 0 adds them)"
                                      : "normal change (it was not made by denoise-normals)"));
      std::vector<float> v(voronoi ? m.voronoi.vertex_areas.begin() : m.normal_change.begin(),
                           voronoi ? m.voronoi.vertex_areas.end() : m.normal_change.end());
      std::vector<float> sorted = v;
      std::sort(sorted.begin(), sorted.end());  // ramp from the 2nd to the 98th percentile
      const double lo = voronoi ? sorted[sorted.size() / 50] : 0.0,
                   hi = sorted[sorted.size() * 49 / 50];
      terrain::write_png(out, int(m.topo.cols), int(m.topo.rows), 3,
                         terrain::colour_ramp(v, lo, hi),
                         desc + fmt::format(" [{} {:.4g} .. {:.4g}]", colour_by, lo, hi));
      std::cout << fmt::format("ramp: {:.4g} .. {:.4g}\n", lo, hi);
    }
  } else {
    const terrain::Grid g = terrain::read_dem(file);
    terrain::write_png(out, int(g.cols), int(g.rows), 2, dem_shade(g, azimuth, altitude, zfactor),
                       desc);
  }
  std::cout << "output: " << out << "\n";
}

void run_export(ExportArgs& a, const std::string& provenance, const Verbosity& verb) {
  const std::string& file = a.file;
  std::string& out = a.out;
  const std::string &to = a.to, &d8_encoding = a.d8_encoding;
  const int min_order = a.min_order;
  const std::vector<std::string>& gpkg_layers = a.gpkg_layers;
  const bool is_mesh = terrain::is_ply_file(file);
  const bool is_dv = drainage::is_dv_file(file);
  std::error_code ec;
  if (!std::filesystem::exists(file, ec))
    throw terrain::Error("cannot read '" + file + "': no such file");
  if (to == "tif" && is_dv) {  // every layer, window by window, into a directory
    namespace fs = std::filesystem;
    if (out.empty())
      out = (fs::path(file).parent_path() / (fs::path(file).stem().string() + "_rasters")).string();
    if (fs::exists(out, ec) && !fs::is_directory(out, ec))
      throw terrain::Error(
          "'" + out + "' exists and is not a directory: a .dv exports to a directory of GeoTIFFs");
    std::vector<std::string> targets;
    for (const char* name : drainage::kDrainageRasterNames)
      targets.push_back((fs::path(out) / name).string());
    tt::check_distinct_paths({file}, targets);
    tt::warn_stale_temporaries(verb, targets);
    (void)drainage::read_dv_header(file);  // a file that is no .dv fails before any folder is made
    terrain::NewDirectories made(out);     // removed again on an error or an interrupt
    terrain::OutputSet outputs;            // the seven land together, or none does
    std::size_t points = 0;
    outputs.write([&] {
      points = drainage::export_dv_rasters(
          file, [&](const std::string& name) { return outputs.stage(fs::path(out) / name); },
          drainage::parse_d8_encoding(d8_encoding), provenance);
    });
    outputs.commit();
    made.keep();
    std::cout << "output: " << out << "\npoints: " << points << "\n";
    for (const std::string& t : targets) std::cout << "layer: " << t << "\n";
    return;
  }
  // A mesh's map and a .dv's layers default to different GeoPackages (M_map.gpkg, M.gpkg);
  // either adds its layers to a GeoPackage already there (terrain/gpkg.hpp).
  if (out.empty())
    out = is_mesh && to == "gpkg" ? (std::filesystem::path(file).parent_path() /
                                     (std::filesystem::path(file).stem().string() + "_map.gpkg"))
                                        .string()
                                  : std::filesystem::path(file).replace_extension(to).string();
  if (to == "gpkg" && !out.ends_with(".gpkg"))  // the svg and pdf writers check theirs
    throw terrain::Error("--to gpkg writes a GeoPackage: give -o a name ending in .gpkg, not '" +
                         out + "'");
  if (!a.dv.empty() && !(is_mesh && (to == "gpkg" || to == "svg" || to == "pdf")))
    throw terrain::Error(
        "--dv: only a mesh's hachure map (--to gpkg, svg or pdf) draws a .dv's ridge lines");
  tt::check_distinct_paths(
      a.dv.empty() ? std::vector<std::string>{file} : std::vector<std::string>{file, a.dv}, {out});
  tt::warn_stale_temporaries(verb, {out});
  terrain::check_output_path(out);
  if (is_mesh && (to == "gpkg" || to == "svg" || to == "pdf")) {
    export_hachure_map(a, provenance);
    return;
  }
  if (to == "svg" || to == "pdf")
    throw terrain::Error("'" + file + "' is not a terrain mesh (.ply): only meshes export to " +
                         to);
  if (to == "gpkg") {
    if (!is_dv)
      throw terrain::Error(
          "'" + file + "' is not a drainage database (.dv) or a mesh: only those export to gpkg");
    for (const std::string& l : gpkg_layers)
      if (l == "hachures")
        throw terrain::Error("--layers hachures: a mesh's layer ('" + file + "' is a .dv)");
    drainage::GpkgLayers layers;
    auto has = [&](const char* name) {
      return std::find(gpkg_layers.begin(), gpkg_layers.end(), name) != gpkg_layers.end();
    };
    layers.branches = has("branches"), layers.basins = has("basins"),
    layers.divides = has("divides");
    layers.min_order = min_order;
    const drainage::GpkgCounts n =
        drainage::export_dv_gpkg(file, out, layers, tt::terminal_progress(verb, "gpkg"));
    std::cout << "output: " << out << "\n";
    if (layers.branches) std::cout << "branches: " << n.branches << "\n";
    if (layers.basins) std::cout << "basins: " << n.basins << "\n";
    if (layers.divides) std::cout << "divides: " << n.divides << "\n";
    return;
  }
  if (!is_mesh)
    throw terrain::Error("'" + file + "' is not a terrain mesh (.ply): only meshes export to " +
                         to);
  const terrain::GridMesh m = terrain::read_mesh_ply(file);
  if (to == "obj")
    terrain::write_mesh_obj(m, out);
  else
    terrain::write_geotiff(terrain::mesh_to_grid(m), out, provenance);
  std::cout << "output: " << out << "\n";
}

}  // namespace terrain::tools::inspect
