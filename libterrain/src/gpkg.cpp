#include "terrain/gpkg.hpp"

#include "terrain/dem_io.hpp"
#include "terrain/error.hpp"

namespace terrain {

Gpkg::Gpkg(const std::string& path, const std::string& crs_wkt) : path_(path), out_(path) {
  ensure_gdal();
  GDALDriver* drv = GetGDALDriverManager()->GetDriverByName("GPKG");
  if (!drv) throw Error("GDAL has no GPKG driver");
  CPLErrorReset();
  ds_.reset(drv->Create(out_.temp_path().c_str(), 0, 0, 0, GDT_Unknown, nullptr));
  if (!ds_) fail();
  has_srs_ = !crs_wkt.empty() && srs_.importFromWkt(crs_wkt.c_str()) == OGRERR_NONE;
}

OGRLayer* Gpkg::layer(const char* name, OGRwkbGeometryType type, std::initializer_list<GpkgField> fields) {
  OGRLayer* l = ds_->CreateLayer(name, has_srs_ ? &srs_ : nullptr, type, nullptr);
  if (!l) fail();
  for (const GpkgField& f : fields) {
    OGRFieldDefn def(f.name, f.type);
    if (l->CreateField(&def) != OGRERR_NONE) fail();
  }
  return l;
}

void Gpkg::begin() {
  if (ds_->StartTransaction() != OGRERR_NONE) fail();
}

void Gpkg::add(OGRLayer* l, OGRFeature& f) {
  if (l->CreateFeature(&f) != OGRERR_NONE) fail();
}

void Gpkg::commit() {
  if (ds_->CommitTransaction() != OGRERR_NONE) fail();
  CPLErrorReset();
  ds_.reset();
  if (CPLGetLastErrorType() >= CE_Failure) fail();
  out_.commit();
}

void Gpkg::fail() const { throw Error("cannot write '" + path_ + "': " + CPLGetLastErrorMsg()); }

}  // namespace terrain
