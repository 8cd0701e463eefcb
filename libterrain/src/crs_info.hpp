#pragma once
// What libterrain keeps of an OGR spatial reference (internal: dem_io.cpp, point_io.cpp).
#include <ogr_spatialref.h>

#include <string>

#include "terrain/grid.hpp"

namespace terrain {

struct CrsInfo {
  std::string wkt;  // WKT2 2019, one line
  int epsg = 0;     // 0 when GDAL identifies no EPSG code
  CrsKind kind = CrsKind::None;
  std::string non_metre_unit;  // a projected CRS in other units than metres: their name
};
CrsInfo crs_info(const OGRSpatialReference& srs);

}  // namespace terrain
