#pragma once
// What the GIS sources share (gis_layers.cpp, watersheds.cpp). Not installed.
#include <ogr_geometry.h>

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "terrain/error.hpp"

namespace drainage::detail {

// GDALPolygonize of the id raster at `tif` (4-connected, no-data left out): its polygons
// grouped by id, ids ascending, each id's parts in the order GDAL found them.
std::vector<std::pair<std::uint32_t, std::unique_ptr<OGRMultiPolygon>>> polygonize_ids(
    const std::string& tif, const terrain::Progress& progress);

}  // namespace drainage::detail
