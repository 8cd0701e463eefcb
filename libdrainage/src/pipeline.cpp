#include "drainage/pipeline.hpp"

#include "drainage/d8.hpp"
#include "drainage/dv_file.hpp"
#include "drainage/fill.hpp"

namespace drainage {

DrainageResult compute_drainage(terrain::Grid surface, const DrainageOptions& options,
                                const terrain::Progress& progress) {
  DrainageResult out;
  out.dv_flags = kDvHasElevations;
  if (options.fill) {
    out.filled = priority_flood_fill(surface);
    out.dv_flags |= kDvFilled;
  }
  terrain::report(progress, 0.15);
  out.dirs = d8_directions(surface);
  terrain::report(progress, 0.3);
  if (options.resolve_flats) {
    out.flats = resolve_flats(surface, out.dirs);
    out.dv_flags |= kDvFlatsResolved;
  }
  terrain::report(progress, 0.45);
  out.net = analyze_network(out.dirs, surface.rows, surface.cols, terrain::sub_progress(progress, 0.45, 1.0));
  out.surface = std::move(surface);
  return out;
}

DrainageResult drainage_from_directions(terrain::Grid surface, std::vector<std::uint8_t> dirs,
                                        const terrain::Progress& progress) {
  if (dirs.size() != surface.size()) throw terrain::Error("the direction grid and the surface differ in size");
  DrainageResult out;
  out.net = analyze_network(dirs, surface.rows, surface.cols, progress);
  out.dirs = std::move(dirs);
  out.surface = std::move(surface);
  return out;
}

}  // namespace drainage
