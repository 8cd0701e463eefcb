// terrain-inspect: summary, preview and export of the toolkit's files (DEMs, meshes).
#include <string>

#include "common.hpp"
#include "inspect/commands.hpp"

namespace tt = terrain::tools;
namespace ti = terrain::tools::inspect;

int main(int argc, char** argv) {
  CLI::App app{
      "Inspect the toolkit's files: DEMs (any raster GDAL reads), terrain meshes (.ply) and "
      "drainage\n"
      "vertex databases (.dv).",
      "terrain-inspect"};
  app.footer(
      "Examples:\n"
      "  terrain-inspect info data/logan_utm12n_100m.tif\n"
      "  terrain-inspect info out/msh_10m.ply\n"
      "  terrain-inspect preview out/msh_10m.ply -o msh.png\n"
      "  terrain-inspect export out/msh_10m.ply --to tif -o msh_from_mesh.tif\n"
      "  terrain-inspect info out/msh.dv\n"
      "  terrain-inspect preview out/msh.dv -o msh_drainage.png\n"
      "  terrain-inspect export out/msh.dv --to gpkg --min-order 2\n"
      "  terrain-inspect export out/msh.dv --to gpkg --layers basins,divides -o msh_basins.gpkg\n"
      "  terrain-inspect export out/msh.dv --to tif -o msh_rasters\n"
      "  terrain-inspect export out/msh_10m.ply --to svg                      # a plan-view "
      "hachure map\n"
      "  terrain-inspect export out/logan_100m.ply --dv out/logan.dv --to gpkg  # with its ridge "
      "lines");
  app.set_version_flag("--version", tt::version());
  app.require_subcommand(1);
  app.fallthrough();  // -q / -v also after the subcommand's arguments
  tt::Verbosity verb;
  tt::add_verbosity_flags(app, verb);

  std::string info_file;
  ti::PreviewArgs pa;
  ti::ExportArgs ea;
  CLI::App* info = app.add_subcommand(
      "info", "What FILE is: size, CRS, extent, elevation statistics ('key: value' lines)");
  info->add_option("FILE", info_file, "DEM, mesh, .dv or scattered points")->required();
  CLI::App* preview =
      app.add_subcommand("preview",
                         "Hillshade PNG of a DEM or a mesh (meshes: shaded with their vertex "
                         "normals); drainage over a hillshade for a .dv");
  ti::add_preview_options(preview, pa);
  CLI::App* exp = app.add_subcommand(
      "export",
      "Convert: a mesh to obj (Wavefront, local coordinates) or tif (its elevations "
      "as a GeoTIFF); a .dv to gpkg (layers branches, basins and divides) "
      "or tif (every layer as a GeoTIFF in a directory, as build-drainage --rasters)");
  ti::add_export_options(exp, ea);

  return tt::run_main(app, argc, argv, [&]() {
    if (*info)
      ti::run_info(info_file);
    else if (*preview)
      ti::run_preview(pa, tt::provenance(argc, argv), verb);
    else if (*exp)
      ti::run_export(ea, tt::provenance(argc, argv), verb);
    return 0;
  });
}
