#pragma once
// What the GIS sources share (gis_layers.cpp, watersheds.cpp). Not installed.
#include <ogr_feature.h>
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

// The fields a polygon of cells draining to one outlet carries (basins, watersheds): its id,
// its cells, their area and the outlet's position.
inline void set_catchment_fields(OGRFeature& f, std::uint32_t id, std::uint64_t cells,
                                 double cell_area, double outlet_x, double outlet_y) {
  f.SetField("id", GIntBig(id));
  f.SetField("cells", GIntBig(cells));
  f.SetField("area_m2", double(cells) * cell_area);
  f.SetField("outlet_x", outlet_x);
  f.SetField("outlet_y", outlet_y);
}

}  // namespace drainage::detail
