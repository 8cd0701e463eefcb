#include "terrain/gpkg.hpp"

#include <cpl_error.h>

#include <cstring>
#include <ctime>
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
                      std::initializer_list<GpkgField> fields, const LayerStyle& style) {
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
  styles_.push_back({name, l->GetGeometryColumn(), qgis_style_qml(style, type), style.description});
  return l;
}

// The layer_styles table as QGIS makes it in a GeoPackage (QgsOgrProviderUtils): created
// when missing; a row for a layer written here replaces that layer's rows.
void Gpkg::write_styles() {
  OGRLayer* t = ds_->GetLayerByName("layer_styles");
  if (!t) {
    const char* fid[] = {"FID=id", nullptr};  // QGIS's key column
    t = ds_->CreateLayer("layer_styles", nullptr, wkbNone, const_cast<char**>(fid));
    if (!t) fail();
    const std::pair<const char*, OGRFieldType> fields[] = {{"f_table_catalog", OFTString},
                                                           {"f_table_schema", OFTString},
                                                           {"f_table_name", OFTString},
                                                           {"f_geometry_column", OFTString},
                                                           {"styleName", OFTString},
                                                           {"styleQML", OFTString},
                                                           {"styleSLD", OFTString},
                                                           {"useAsDefault", OFTInteger},
                                                           {"description", OFTString},
                                                           {"owner", OFTString},
                                                           {"ui", OFTString},
                                                           {"update_time", OFTDateTime}};
    for (const auto& [field, type] : fields) {
      OGRFieldDefn def(field, type);
      if (field == std::string("useAsDefault")) def.SetSubType(OFSTBoolean);
      if (t->CreateField(&def) != OGRERR_NONE) fail();
    }
  }
  for (const Styled& s : styles_) {
    t->SetAttributeFilter(("f_table_name = '" + s.layer + "'").c_str());
    std::vector<GIntBig> old;
    for (auto& f : *t) old.push_back(f->GetFID());
    t->SetAttributeFilter(nullptr);
    for (GIntBig fid : old)
      if (t->DeleteFeature(fid) != OGRERR_NONE) fail();
    OGRFeature f(t->GetLayerDefn());
    f.SetField("f_table_catalog", "");
    f.SetField("f_table_schema", "");
    f.SetField("f_table_name", s.layer.c_str());
    f.SetField("f_geometry_column", s.geometry_column.c_str());
    f.SetField("styleName", s.layer.c_str());
    f.SetField("styleQML", s.qml.c_str());
    f.SetField("styleSLD", "");
    f.SetField("useAsDefault", 1);
    f.SetField("description", s.description.c_str());
    f.SetField("owner", "");
    f.SetField("ui", "");
    const std::time_t now = std::time(nullptr);
    std::tm utc{};
    gmtime_r(&now, &utc);
    f.SetField("update_time", utc.tm_year + 1900, utc.tm_mon + 1, utc.tm_mday, utc.tm_hour,
               utc.tm_min, float(utc.tm_sec), 100);
    if (t->CreateFeature(&f) != OGRERR_NONE) fail();
  }
  styles_.clear();
}

void Gpkg::begin() {
  if (ds_->StartTransaction() != OGRERR_NONE) fail();
}

void Gpkg::add(OGRLayer* l, OGRFeature& f) {
  if (l->CreateFeature(&f) != OGRERR_NONE) fail();
}

void Gpkg::commit() {
  write_styles();
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
