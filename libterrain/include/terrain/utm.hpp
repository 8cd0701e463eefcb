#pragma once
// UTM zones and CRSs through GeographicLib (zone rules) and GDAL/OGR (CRS definitions).
#include <string>
#include <string_view>
#include <vector>

#include "terrain/grid.hpp"

namespace terrain {

struct UtmZone {
  int zone = 0;       // 1..60
  bool north = true;  // hemisphere
};

// The standard zone of a point (GeographicLib::UTMUPS::StandardZone, with the Norway and
// Svalbard exceptions). Throws Error for latitudes outside UTM's [-80, 84) band.
UtmZone standard_utm_zone(double lat, double lon);

// Parses "17", "17N", "17s": a bare number takes the hemisphere of `lat_hint`.
// Throws Error for anything else or a zone outside 1..60.
UtmZone parse_utm_zone(std::string_view text, double lat_hint);

// Forward UTM projection into the fixed zone and hemisphere `z` (GeographicLib), continued
// across the equator (false northing of the other hemisphere undone).
void utm_forward(UtmZone z, double lat, double lon, double& x, double& y);

// The UTM zone CRS on the datum of `geographic_wkt` (for example NAD83 -> "NAD83 / UTM
// zone 17N", EPSG:26917) as WKT; `epsg` receives the EPSG code when GDAL identifies one.
std::string utm_crs_wkt(const std::string& geographic_wkt, UtmZone zone, int& epsg);

// Cell sizes in metres of rows row0 .. row0 + rows - 1 of a grid. Projected grids (and
// grids without a CRS) have the same {dx, dy} on every row. A geographic grid's sizes are
// geodesic lengths on its CRS's ellipsoid (GeographicLib): dx along the row's parallel
// across one cell, dy along the meridian across the cell (centred on the row's latitude).
struct MetricCellSize {
  double dx = 0.0, dy = 0.0;
};
std::vector<MetricCellSize> metric_cell_sizes(const Georef& geo, std::size_t row0,
                                              std::size_t rows);

}  // namespace terrain
