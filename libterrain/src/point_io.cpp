// Scattered points in: OGR point layers and XYZ text, recognised by content; their CRS and
// the projection of geographic points to UTM (scattered.hpp).
#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <memory>

#include <fmt/format.h>

#include "crs_info.hpp"
#include "terrain/error.hpp"
#include "terrain/scattered.hpp"
#include "terrain/utm.hpp"

namespace terrain {

namespace {

struct DatasetCloser {
  void operator()(GDALDataset* d) const { GDALClose(d); }
};
using Dataset = std::unique_ptr<GDALDataset, DatasetCloser>;

// CSV columns GDAL's CSV driver takes as X, Y and Z.
const char* const kCsvOptions[] = {"X_POSSIBLE_NAMES=x,easting,east,lon,longitude",
                                   "Y_POSSIBLE_NAMES=y,northing,north,lat,latitude",
                                   "Z_POSSIBLE_NAMES=z,elevation,elev,height,alt",
                                   "KEEP_GEOM_COLUMNS=NO",
                                   "AUTODETECT_TYPE=YES",
                                   nullptr};

// A vector dataset; a CSV file is opened again with kCsvOptions. GDAL 3.6's CSV driver
// crashes with those options when two columns' names differ only in case ("X" and "x",
// found by fuzz_points): such a header is an error here.
Dataset open_vector(const std::string& path) {
  ensure_gdal();
  const auto open = [&](const char* const* options) {
    CPLPushErrorHandler(CPLQuietErrorHandler);
    GDALDataset* ds = GDALDataset::FromHandle(
        GDALOpenEx(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY, nullptr, options, nullptr));
    CPLPopErrorHandler();
    return Dataset(ds);
  };
  Dataset plain = open(nullptr);
  if (!plain || !plain->GetDriver() || !EQUAL(plain->GetDriver()->GetDescription(), "CSV"))
    return plain;
  for (OGRLayer* layer : plain->GetLayers()) {
    const OGRFeatureDefn* defn = layer->GetLayerDefn();
    for (int i = 0; i < defn->GetFieldCount(); ++i)
      for (int j = 0; j < i; ++j)
        if (EQUAL(defn->GetFieldDefn(i)->GetNameRef(), defn->GetFieldDefn(j)->GetNameRef()))
          throw Error(std::string("'") + path + "': CSV columns '" +
                      defn->GetFieldDefn(j)->GetNameRef() + "' and '" +
                      defn->GetFieldDefn(i)->GetNameRef() + "' have the same name");
  }
  plain.reset();
  return open(kCsvOptions);
}

bool opens_as_raster(const std::string& path) { return !raster_driver(path).empty(); }

OGRLayer* point_layer(GDALDataset& ds) {
  for (OGRLayer* layer : ds.GetLayers()) {
    const OGRwkbGeometryType t = wkbFlatten(layer->GetGeomType());
    if (t == wkbPoint || t == wkbMultiPoint) return layer;
  }
  return nullptr;
}

// The field separator of an XYZ text line: ',' or ';' when the line has one, otherwise
// white space.
char separator_of(const std::string& line) {
  if (line.find(',') != std::string::npos) return ',';
  if (line.find(';') != std::string::npos) return ';';
  return ' ';
}

// Splits an XYZ text line into its fields at `sep` (' ': any run of white space; ',' or
// ';': that character, with white space around it) and reads each as a number. Returns ""
// when every field is a number, else what is wrong (a field that is not a number in full,
// "1,5" under white space included, or an empty field).
std::string parse_numbers(const std::string& line, char sep, std::vector<double>& out) {
  out.clear();
  const auto space = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
  std::size_t at = 0;
  const std::size_t n = line.size();
  while (true) {
    while (at < n && space(line[at])) ++at;
    if (at == n && sep == ' ') break;
    std::size_t end = at;
    if (sep == ' ') {
      while (end < n && !space(line[end])) ++end;
    } else {
      end = line.find(sep, at);
      if (end == std::string::npos) end = n;
    }
    std::size_t last = end;
    while (last > at && space(line[last - 1])) --last;
    const std::string field = line.substr(at, last - at);
    if (field.empty()) return "an empty field";
    const char* p = field.data() + (field[0] == '+' ? 1 : 0);  // from_chars takes no leading '+'
    double v = 0;
    const auto [next, ec] = std::from_chars(p, field.data() + field.size(), v);
    if (ec != std::errc() || next != field.data() + field.size())
      return "'" + field + "' is not a number";
    out.push_back(v);
    if (end == n) break;
    at = end + (sep == ' ' ? 0 : 1);
  }
  return {};
}

bool is_comment_or_blank(const std::string& line) {
  const auto it =
      std::find_if(line.begin(), line.end(), [](unsigned char c) { return !std::isspace(c); });
  return it == line.end() || *it == '#';
}

// True when the first data lines of `path` (after at most one header line) are >= 3 numbers.
bool looks_like_xyz(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::string line;
  std::vector<double> v;
  int data = 0, bad = 0;
  for (int n = 0; n < 50 && std::getline(in, line); ++n) {
    if (line.find('\0') != std::string::npos) return false;  // binary
    if (is_comment_or_blank(line)) continue;
    if (parse_numbers(line, separator_of(line), v).empty() && v.size() >= 3) {
      ++data;
      if (data >= 3) return true;
    } else if (++bad > 1 || data > 0) {
      return false;  // one header line at most, before the data
    }
  }
  return data > 0;
}

void check_finite(const PointCloud& p, std::size_t i) {
  if (!std::isfinite(p.x[i]) || !std::isfinite(p.y[i]) || !std::isfinite(p.z[i]))
    throw Error("point " + std::to_string(i + 1) + " has a non-finite coordinate (" +
                std::to_string(p.x[i]) + ", " + std::to_string(p.y[i]) + ", " +
                std::to_string(p.z[i]) + ")");
}

void set_crs(PointCloud& p, const OGRSpatialReference* srs) {
  if (!srs) return;
  const CrsInfo crs = crs_info(*srs);
  p.crs_wkt = crs.wkt;
  p.epsg = crs.epsg;
  p.crs_kind = crs.kind;
  if (!crs.non_metre_unit.empty())
    throw Error("the points' projected CRS is in " + crs.non_metre_unit +
                ", not metres; reproject them first (ogr2ogr -t_srs EPSG:...)");
}

PointCloud read_ogr(GDALDataset& ds, OGRLayer& layer, const std::string& path,
                    const Progress& progress) {
  PointCloud p;
  p.format = ds.GetDriver() ? ds.GetDriver()->GetDescription() : "OGR";
  set_crs(p, layer.GetSpatialRef());
  const OGRFeatureDefn* defn = layer.GetLayerDefn();
  int z_field = -1;
  for (const char* name : {"z", "elevation", "elev", "height", "alt"})
    if (z_field < 0) z_field = defn->GetFieldIndex(name);
  const GIntBig total = layer.GetFeatureCount(FALSE);
  layer.ResetReading();
  std::size_t n = 0;
  for (auto& feature : layer) {
    const OGRGeometry* g = feature->GetGeometryRef();
    // A CSV row whose x or y is empty or not a number has no geometry: an error with the
    // row's line (the CSV driver numbers data rows from 1 after the header line).
    const auto where = [&] {
      return EQUAL(p.format.c_str(), "CSV") ? fmt::format("line {}", feature->GetFID() + 1)
                                            : fmt::format("feature {}", feature->GetFID());
    };
    if (!g)
      throw Error("'" + path + "' " + where() + ": no point (x or y is empty or not a number)");
    auto add = [&](const OGRPoint& pt) {
      if (pt.IsEmpty()) throw Error("'" + path + "' " + where() + ": an empty point");
      double z = std::nan("");
      if (pt.Is3D())
        z = pt.getZ();
      else if (z_field >= 0 && feature->IsFieldSetAndNotNull(z_field))
        z = feature->GetFieldAsDouble(z_field);
      else
        throw Error("'" + path + "': point " + std::to_string(p.size() + 1) +
                    " has no z (no Z coordinate and no z / elevation field)");
      p.x.push_back(pt.getX());
      p.y.push_back(pt.getY());
      p.z.push_back(z);
      check_finite(p, p.size() - 1);
    };
    const OGRwkbGeometryType t = wkbFlatten(g->getGeometryType());
    if (t == wkbPoint)
      add(*g->toPoint());
    else if (t == wkbMultiPoint)
      for (const OGRPoint* pt : *g->toMultiPoint()) add(*pt);
    if (++n % 65536 == 0 && total > 0) report(progress, std::min(1.0, double(n) / double(total)));
  }
  return p;
}

PointCloud read_xyz(const std::string& path, const Progress& progress) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open '" + path + "'");
  in.seekg(0, std::ios::end);
  const double size = double(in.tellg());
  in.seekg(0);
  PointCloud p;
  p.format = "XYZ text";
  std::string line;
  std::vector<double> v;
  std::size_t line_no = 0;
  bool header_seen = false;
  char sep = 0;  // the separator of the first data line, for every line
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (is_comment_or_blank(line)) continue;
    const std::string wrong = parse_numbers(line, sep ? sep : separator_of(line), v);
    if (!wrong.empty() || v.size() != 3) {
      if (!wrong.empty() && !header_seen &&
          p.size() == 0) {  // one header line (not numbers) before the data
        header_seen = true;
        continue;
      }
      throw Error(fmt::format("'{}' line {}: expected x y z, got '{}' ({})", path, line_no,
                              line.substr(0, 60),
                              !wrong.empty() ? wrong : fmt::format("{} fields", v.size())));
    }
    if (!sep) sep = separator_of(line);
    p.x.push_back(v[0]);
    p.y.push_back(v[1]);
    p.z.push_back(v[2]);
    check_finite(p, p.size() - 1);
    if (p.size() % 65536 == 0 && size > 0)
      report(progress, std::min(1.0, double(in.tellg()) / size));
  }
  return p;
}

}  // namespace

std::string raster_driver(const std::string& path) {
  ensure_gdal();
  CPLPushErrorHandler(CPLQuietErrorHandler);
  GDALDatasetH ds =
      GDALOpenEx(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr, nullptr, nullptr);
  CPLPopErrorHandler();
  if (!ds) return {};
  const std::string name = GDALGetDriverShortName(GDALGetDatasetDriver(ds));
  GDALClose(ds);
  return name;
}

bool is_point_input(const std::string& path) {
  if (opens_as_raster(path)) return false;
  if (Dataset ds = open_vector(path)) return point_layer(*ds) != nullptr;
  return looks_like_xyz(path);
}

PointCloud read_points(const std::string& path, const Progress& progress) {
  PointCloud p;
  if (Dataset ds = open_vector(path)) {
    OGRLayer* layer = point_layer(*ds);
    if (!layer) throw Error("'" + path + "' has no point layer");
    p = read_ogr(*ds, *layer, path, progress);
  } else if (looks_like_xyz(path)) {
    p = read_xyz(path, progress);
  } else {
    throw Error("cannot read points from '" + path + "': not an OGR point layer nor XYZ text");
  }
  report(progress, 1.0);
  if (p.size() < 3)
    throw Error("'" + path + "' has " + std::to_string(p.size()) + " point" +
                (p.size() == 1 ? "" : "s") + "; a surface needs at least 3");
  return p;
}

void project_points(PointCloud& p, const std::string& src_crs,
                    const std::optional<std::string>& utm_zone) {
  if (!src_crs.empty()) {
    ensure_gdal();
    OGRSpatialReference srs;
    if (srs.SetFromUserInput(src_crs.c_str()) != OGRERR_NONE)
      throw Error("cannot understand the CRS '" + src_crs + "'");
    set_crs(p, &srs);
  }
  if (p.crs_kind == CrsKind::None)
    throw Error("the points have no CRS: give it with --src-crs (for example EPSG:32610)");
  if (p.crs_kind == CrsKind::Projected) return;
  // Geographic: x = longitude, y = latitude (GIS order, as OGR layers and XYZ files store them).
  const auto [lo_lon, hi_lon] = std::minmax_element(p.x.begin(), p.x.end());
  const auto [lo_lat, hi_lat] = std::minmax_element(p.y.begin(), p.y.end());
  if (*lo_lat < -90 || *hi_lat > 90 || *lo_lon < -180 || *hi_lon > 360)
    throw Error(
        "geographic points outside latitude -90..90 / longitude -180..360: is the CRS right?");
  const double lat_c = 0.5 * (*lo_lat + *hi_lat), lon_c = 0.5 * (*lo_lon + *hi_lon);
  const UtmZone zone =
      utm_zone ? parse_utm_zone(*utm_zone, lat_c) : standard_utm_zone(lat_c, lon_c);
  for (std::size_t i = 0; i < p.size(); ++i) utm_forward(zone, p.y[i], p.x[i], p.x[i], p.y[i]);
  p.crs_wkt = utm_crs_wkt(p.crs_wkt, zone, p.epsg);
  p.crs_kind = CrsKind::Projected;
}

PointInterpolation parse_point_interpolation(const std::string& name) {
  if (name == "linear") return PointInterpolation::Linear;
  if (name == "natural") return PointInterpolation::Natural;
  if (name == "natural-c0") return PointInterpolation::NaturalC0;
  throw Error("unknown interpolation '" + name + "' (linear, natural, natural-c0)");
}

PointCloudSummary summarize_points(const PointCloud& p) {
  PointCloudSummary s;
  s.count = p.size();
  if (!s.count) return s;
  const auto [x0, x1] = std::minmax_element(p.x.begin(), p.x.end());
  const auto [y0, y1] = std::minmax_element(p.y.begin(), p.y.end());
  const auto [z0, z1] = std::minmax_element(p.z.begin(), p.z.end());
  s.xmin = *x0, s.xmax = *x1, s.ymin = *y0, s.ymax = *y1, s.zmin = *z0, s.zmax = *z1;
  std::vector<std::pair<double, double>> xy(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) xy[i] = {p.x[i], p.y[i]};
  std::sort(xy.begin(), xy.end());
  for (std::size_t i = 1; i < xy.size(); ++i) s.duplicates += xy[i] == xy[i - 1];
  return s;
}

}  // namespace terrain
