// A map's lines as GIS layers (vector_file.hpp, write_map_gpkg): the top view's vector art
// in map coordinates, one styled GeoPackage line layer per drawn layer.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "renderer/core/vector_file.hpp"
#include "terrain/gpkg.hpp"

namespace renderer {

std::size_t write_map_gpkg(const VectorArt& art, const std::array<double, 6>& gt,
                           const std::string& crs_wkt, double dpi, const std::string& path) {
  const double mm = 25.4 / dpi;  // a pixel on the page
  terrain::Gpkg gpkg(path, crs_wkt);
  std::vector<OGRLayer*> layers;
  for (const VectorLayer& l : art.layers) {
    const Eigen::Vector3i c = (l.colour.cwiseMax(0).cwiseMin(1) * 255).array().round().cast<int>();
    const terrain::LayerStyle style{fmt::format("{},{},{},255", c.x(), c.y(), c.z()), 0.26,
                                    "\"width_mm\"",
                                    "The top view's " + l.name + ", as terrain-render draws them"};
    OGRLayer* layer = gpkg.layer(l.name.c_str(), wkbLineString,
                                 {{"width_mm", OFTReal}, {"opacity", OFTReal}}, style);
    for (const std::string& name : l.value_names) {  // what it was drawn from
      OGRFieldDefn def(name.c_str(), name == "strahler" ? OFTInteger : OFTReal);
      if (layer->CreateField(&def) != OGRERR_NONE) gpkg.fail();
    }
    layers.push_back(layer);
  }
  gpkg.begin();
  std::size_t n = 0;
  for (std::size_t k = 0; k < art.layers.size(); ++k)
    for (const VectorPath& p : art.layers[k].paths) {
      if (p.line.points.size() < 2) continue;
      OGRLineString line;
      for (const Eigen::Vector2f& q : p.line.points)  // pixel corners, as the geotransform's
        line.addPoint(gt[0] + q.x() * gt[1] + q.y() * gt[2], gt[3] + q.x() * gt[4] + q.y() * gt[5]);
      if (p.line.closed) line.addPoint(line.getX(0), line.getY(0));
      const double width =
          p.widths.empty()
              ? p.width
              : std::accumulate(p.widths.begin(), p.widths.end(), 0.0) / double(p.widths.size());
      OGRFeature f(layers[k]->GetLayerDefn());
      f.SetField("width_mm", width * mm);
      f.SetField("opacity", double(p.opacity));
      const auto& names = art.layers[k].value_names;
      for (std::size_t j = 0; j < names.size() && j < p.values.size(); ++j)
        f.SetField(names[j].c_str(), double(p.values[j]));
      f.SetGeometry(&line);
      gpkg.add(layers[k], f);
      ++n;
    }
  gpkg.commit();
  return n;
}

}  // namespace renderer
