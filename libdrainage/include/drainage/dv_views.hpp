#pragma once
// Views of a drainage database for people and other tools: a summary, a preview image, the
// points for the renderer (GIS layers: gis_layers.hpp).
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "drainage/dv_file.hpp"
#include "terrain/drainage_links.hpp"
#include "terrain/grid.hpp"

namespace drainage {

struct DvSummary {
  std::size_t points = 0, pits = 0, ridges = 0, channels = 0, junctions = 0;
  std::map<int, std::size_t> branches_per_order;
  std::uint32_t max_accumulated = 0;
  double mean_normalized = 0.0;
  std::size_t basins_over_1pct = 0;  // basins holding more than 1 % of the points
};
DvSummary summarize(const DrainageDb& db);

// Rows per band for reading the .dv of `h` band by band (read_dv_window): its blocks' rows
// (256 for a version 1 file), so that a band decodes whole blocks, at most about 256 MiB of
// points, at least 1.
std::size_t dv_band_rows(const DvHeader& h);

// summarize() of the .dv at `path` without holding the database: a version 2 file is read
// in bands of rows (read_dv_window, at most about 256 MiB each), so terrain-inspect can
// summarize a database larger than memory. Version 1 files are read whole.
DvSummary summarize_dv_file(const std::string& path);

// The database's points as plain arrays (terrain/drainage_links.hpp), for the renderer.
terrain::DrainageLinks drainage_links(const DrainageDb& db);

// The points of the .dv at `path` that lie in the world rectangle [west, east] x [south,
// north] (sample centres, with a tolerance of 1e-6 cell), read with read_dv_window: a
// renderer given a large database and a small mesh loads only the mesh's extent. The
// whole grid when the rectangle covers it; an Error when they do not overlap. A version 2
// file is read in bands of rows of at most `band_points` points (each with a row of margin
// above and below), so that only one band's database is held beside the arrays.
terrain::DrainageLinks drainage_links_in(const std::string& path, double west, double south,
                                         double east, double north,
                                         std::size_t band_points = std::size_t(1) << 20);

// The database's elevations as a grid (no-data where a vertex is not a point).
terrain::Grid dv_elevations(const DrainageDb& db);

// The grid of a .dv's points as a raster's georeference: cell (0, 0) centred on the
// header's origin, its spacing and CRS.
terrain::Georef dv_georef(const DvHeader& h);

// RGB preview, rows x cols: a hillshade of the database's surface with drainage points of
// at least `min_accumulated` points drawn in blue, darker with larger normalized flow
// (alpha 0.35 + 0.65 * sqrt(normalized)). 0 picks the 96th percentile of accumulated flow
// (the top 4 % of points are drawn), at least 20.
std::vector<std::uint8_t> dv_preview(const DrainageDb& db, std::uint32_t min_accumulated = 0);

}  // namespace drainage
