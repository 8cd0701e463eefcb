#include "mesh/banded.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <optional>

#include "terrain/atomic_file.hpp"
#include "terrain/dem_io.hpp"
#include "terrain/dequantize.hpp"
#include "terrain/memory.hpp"
#include "terrain/mesh_io.hpp"
#include "terrain/mesh_pyramid.hpp"

namespace terrain::tools::mesh {

void add_band_options(CLI::App& app, std::size_t& rows, double& memory_mib) {
  add_tile_size_option(
      app, rows,
      "Make and write the mesh N rows at a time (bands of N rows, the grid's whole "
      "width), for DEMs\n"
      "larger than memory: the same PLY and pyramid as one run; a raster input without "
      "--fit-normals,\n"
      "--fill-nodata, --grid-out or dequantizing",
      std::size_t(1) << 30);
  add_memory_option(app, memory_mib,
                    "Like --tile-size, with bands as large as about this much memory allows "
                    "(MiB); one band when the\nwhole grid fits",
                    16.0)
      ->excludes("--tile-size");
}

void check_banded(const WholeGridNeeds& n) {
  const char* why = n.points               ? "scattered points are triangulated as a whole"
                    : n.fit                ? "--fit-normals fits the whole mesh"
                    : n.fill_nodata        ? "--fill-nodata fills across the whole grid"
                    : n.grid_out           ? "--grid-out writes the whole grid"
                    : n.dequantize == "on" ? "dequantizing integer heights reads the whole DEM"
                                           : nullptr;
  if (why)
    throw terrain::Error(std::string("--tile-size and --memory make the mesh in bands, but ") +
                         why + "; run without them");
}

BandedResult mesh_in_bands(const BandedRequest& q, const Verbosity& verb) {
  terrain::DemInfo info = terrain::read_dem_info(q.input);
  if (!q.src_crs.empty()) terrain::assign_crs(info.geo, q.src_crs);
  const terrain::GridPlan plan = terrain::plan_grid(info.geo, info.rows, info.cols, q.grid);
  for (const auto& w : plan.warnings) warn(verb, w);
  const terrain::Georef& tg = plan.target;
  const std::size_t rows = plan.rows, cols = plan.cols;
  // A row's bytes while it is made: its source samples (about one source row per row at
  // the source's spacing), the grid, positions and normals, the writers' copies.
  const double row_bytes = double(cols) * 64.0;
  BandedResult out{tg, {rows, cols}, q.band_rows, 0};
  std::size_t& band = out.band_rows;
  if (band == 0)
    band = std::size_t(std::clamp(q.memory_mib * 1048576.0 / row_bytes, 1.0, double(rows)));
  terrain::check_memory(double(std::min(rows, band + 2)) * row_bytes,
                        fmt::format("bands of {} rows of a {} x {} mesh", band, cols, rows),
                        "give a smaller --tile-size or --memory");
  terrain::GridMesh header = terrain::grid_mesh_frame(tg, out.topo.rows, out.topo.cols);
  header.provenance = q.provenance;
  terrain::OutputSet outputs;
  outputs.write([&] {
    terrain::PlyRowWriter ply(header, outputs.stage(q.output));
    std::optional<terrain::MeshPyramidWriter> levels;
    if (!q.pyramid.empty())
      levels.emplace(header.topo, header.geo, outputs.stage(q.pyramid), terrain::kLevelBlock,
                     q.pyramid);
    const auto progress = terminal_progress(verb, "mesh in bands");
    for (std::size_t r0 = 0; r0 < rows; r0 += band) {
      const std::size_t r1 = std::min(rows, r0 + band);                       // the band's rows
      const std::size_t a = r0 > 0 ? r0 - 1 : 0, b = std::min(rows, r1 + 1);  // with the margins
      const terrain::RasterWindow w = terrain::band_window(plan, a, b - a, info.rows, info.cols);
      terrain::Grid source = terrain::read_dem(q.input, {}, w);
      if (!q.src_crs.empty()) terrain::assign_crs(source.geo, q.src_crs);
      if (r0 == 0 && q.dequantize == "auto" && terrain::is_integer_dem(source))
        throw terrain::Error(
            "--tile-size and --memory make the mesh in bands, but these integer heights need "
            "dequantizing, which reads the whole DEM; give --dequantize off or run without them");
      const terrain::Grid g = terrain::resample_rows(source, w, plan, a, b - a, q.grid);
      // Vertices as make_grid_mesh places them (whole-grid rows), normals over the band.
      terrain::BigVector<Eigen::Vector3f> positions(g.size());
      for (std::size_t r = a; r < b; ++r)
        for (std::size_t c = 0; c < cols; ++c)
          positions[(r - a) * cols + c] = terrain::grid_vertex(r, c, tg.dx, tg.dy, g.at(r - a, c));
      const terrain::BigVector<Eigen::Vector3f> normals =
          terrain::vertex_normals(positions, terrain::GridTopology{b - a, cols}, q.weighting);
      const std::size_t skip = (r0 - a) * cols;
      ply.add_rows(positions.data() + skip, normals.data() + skip, r1 - r0);
      if (levels) levels->add_rows(positions.data() + skip, normals.data() + skip, r1 - r0);
      terrain::report(progress, double(r1) / double(rows));
    }
    ply.finish();
    if (levels) out.pyramid_bytes = levels->finish();
  });
  outputs.commit();
  return out;
}

}  // namespace terrain::tools::mesh
