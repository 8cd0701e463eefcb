#pragma once
// A GeoPackage written through GDAL/OGR to a temporary beside its path in one transaction,
// renamed onto the path by commit() (no half-written file): layers are created first, then
// features added. Used by the drainage GIS layers and the plan-view hachures.
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
  OGRLayer* layer(const char* name, OGRwkbGeometryType type, std::initializer_list<GpkgField> fields);
  void begin();
  void add(OGRLayer* l, OGRFeature& f);
  void commit();
  [[noreturn]] void fail() const;

 private:
  std::string path_;
  AtomicFile out_;
  std::unique_ptr<GDALDataset> ds_;
  OGRSpatialReference srs_;
  bool has_srs_ = false;
};

}  // namespace terrain
