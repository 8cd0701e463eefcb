#pragma once
// A GeoPackage written through GDAL/OGR to a temporary beside its path in one transaction,
// renamed onto the path by commit() (no half-written file): layers are created first, then
// features added. A GeoPackage already at the path is updated, as `ogr2ogr -update` does:
// its other layers are kept, and a layer of a name written here is replaced (the copy is
// updated and renamed over it, so a failure leaves the old file whole). A file there that
// is not a GeoPackage is refused. Used by the drainage GIS layers and the plan-view maps.
#include <initializer_list>
#include <memory>
#include <string>

#include <gdal_priv.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>

#include "terrain/atomic_file.hpp"

namespace terrain {

struct GpkgField {
  const char* name;
  OGRFieldType type;
};

class Gpkg {
 public:
  Gpkg(const std::string& path, const std::string& crs_wkt);  // crs_wkt empty: no CRS
  ~Gpkg();
  Gpkg(const Gpkg&) = delete;
  Gpkg& operator=(const Gpkg&) = delete;
  // A new layer `name` (replacing one of that name in a GeoPackage being updated).
  OGRLayer* layer(const char* name, OGRwkbGeometryType type,
                  std::initializer_list<GpkgField> fields);
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
  OGRSpatialReference srs_;
  bool has_srs_ = false, updated_ = false;
};

}  // namespace terrain
