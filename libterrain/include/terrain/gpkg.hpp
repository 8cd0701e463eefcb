#pragma once
// A GeoPackage written through GDAL/OGR to a temporary beside its path in one transaction,
// renamed onto the path by commit() (no half-written file): layers are created first, then
// features added. A GeoPackage already at the path is updated, as `ogr2ogr -update` does:
// its other layers are kept, and a layer of a name written here is replaced (the copy is
// updated and renamed over it, so a failure leaves the old file whole). A file there that
// is not a GeoPackage is refused. Used by the drainage GIS layers and the plan-view maps.
// Every layer comes with its QGIS style, a row of the `layer_styles` table QGIS reads (and
// writes) in a GeoPackage, its default: the layer opens in QGIS drawn as the toolkit draws.
#include <initializer_list>
#include <memory>
#include <string>
#include <vector>

#include <gdal_priv.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>

#include "terrain/atomic_file.hpp"

namespace terrain {

struct GpkgField {
  const char* name;
  OGRFieldType type;
};

// How QGIS draws a layer: its symbol's colour ("r,g,b,a"), its line width (or a point's
// size) in millimetres on the map, or a QGIS expression of the layer's fields for it;
// polygons are drawn as their outlines.
struct LayerStyle {
  std::string colour = "0,0,0,255";
  double width_mm = 0.26;
  std::string width_expression;  // empty: width_mm everywhere
  std::string description;       // the style's, as QGIS's style manager shows it
};
// The QGIS style document (QML) of `style` for a layer of geometry `type`.
std::string qgis_style_qml(const LayerStyle& style, OGRwkbGeometryType type);

class Gpkg {
 public:
  Gpkg(const std::string& path, const std::string& crs_wkt);  // crs_wkt empty: no CRS
  ~Gpkg();
  Gpkg(const Gpkg&) = delete;
  Gpkg& operator=(const Gpkg&) = delete;
  // A new layer `name` (replacing one of that name, and its style, in a GeoPackage being
  // updated), with its style (written by commit()).
  OGRLayer* layer(const char* name, OGRwkbGeometryType type,
                  std::initializer_list<GpkgField> fields, const LayerStyle& style);
  void begin();
  void add(OGRLayer* l, OGRFeature& f);
  void commit();
  [[noreturn]] void fail() const;
  bool updated() const { return updated_; }  // whether a GeoPackage was there before

 private:
  std::string path_;
  AtomicFile out_;
  struct Errors;  // GDAL's first failure message while this is open
  std::unique_ptr<Errors> errors_;
  std::unique_ptr<GDALDataset> ds_;
  struct Styled {
    std::string layer, geometry_column, qml, description;
  };
  std::vector<Styled> styles_;
  void write_styles();
  OGRSpatialReference srs_;
  bool has_srs_ = false, updated_ = false;
};

}  // namespace terrain
