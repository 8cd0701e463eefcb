#include "terrain/gpkg.hpp"

#include <cpl_error.h>

#include <cstring>
#include <filesystem>
#include <fstream>

#include "terrain/dem_io.hpp"
#include "terrain/error.hpp"

namespace terrain {

namespace {

bool starts_as_gpkg(const std::string& path) {  // the SQLite magic: a GeoPackage is a SQLite file
  std::ifstream f(path, std::ios::binary);
  char m[16] = {};
  return f.read(m, 16) && std::memcmp(m, "SQLite format 3", 16) == 0;
}

}  // namespace

// The first failure GDAL reports (its later ones tend to name a consequence: "no such table:
// gpkg_geometry_columns" after the disk filled up).
struct Gpkg::Errors {
  std::string first;
  static void CPL_STDCALL handle(CPLErr level, CPLErrorNum, const char* msg) {
    auto* self = static_cast<Errors*>(CPLGetErrorHandlerUserData());
    if (level >= CE_Failure && self && self->first.empty() && msg) self->first = msg;
  }
  explicit Errors() { CPLPushErrorHandlerEx(&Errors::handle, this); }
  ~Errors() { CPLPopErrorHandler(); }
};

Gpkg::Gpkg(const std::string& path, const std::string& crs_wkt) : path_(path), out_(path) {
  ensure_gdal();
  namespace fs = std::filesystem;
  std::error_code ec;
  updated_ = fs::exists(path, ec);
  if (updated_ && !starts_as_gpkg(path))
    throw Error("cannot write '" + path +
                "': it exists and is not a GeoPackage (give another name)");
  errors_ = std::make_unique<Errors>();
  CPLErrorReset();
  if (updated_) {  // a copy of it, updated
    fs::copy_file(path, out_.temp_path(), fs::copy_options::overwrite_existing, ec);
    if (ec)
      throw Error("cannot write '" + path + "': cannot copy it to update it (" + ec.message() +
                  ")");
    const char* drivers[] = {"GPKG", nullptr};
    ds_.reset(
        GDALDataset::Open(out_.temp_path().c_str(), GDAL_OF_VECTOR | GDAL_OF_UPDATE, drivers));
  } else {
    GDALDriver* drv = GetGDALDriverManager()->GetDriverByName("GPKG");
    if (!drv) throw Error("GDAL has no GPKG driver");
    ds_.reset(drv->Create(out_.temp_path().c_str(), 0, 0, 0, GDT_Unknown, nullptr));
  }
  if (!ds_) fail();
  has_srs_ = !crs_wkt.empty() && srs_.importFromWkt(crs_wkt.c_str()) == OGRERR_NONE;
}

Gpkg::~Gpkg() {
  ds_.reset();  // closed before the temporary is removed
}

OGRLayer* Gpkg::layer(const char* name, OGRwkbGeometryType type,
                      std::initializer_list<GpkgField> fields) {
  for (int i = 0; i < ds_->GetLayerCount(); ++i)
    if (EQUAL(ds_->GetLayer(i)->GetName(), name)) {
      if (ds_->DeleteLayer(i) != OGRERR_NONE) fail();
      break;
    }
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

void Gpkg::fail() const {
  std::string why =
      errors_ && !errors_->first.empty() ? errors_->first : std::string(CPLGetLastErrorMsg());
  if (why.find("disk I/O error") != std::string::npos || why.find("full") != std::string::npos)
    why += " (disk full, or over the file size limit?)";
  throw Error("cannot write '" + path_ + "': " + why);
}

}  // namespace terrain
