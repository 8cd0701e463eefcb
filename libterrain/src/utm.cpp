#include "terrain/utm.hpp"

#include <ogr_spatialref.h>
#include <GeographicLib/Geodesic.hpp>
#include <GeographicLib/UTMUPS.hpp>

#include <cctype>
#include <charconv>

#include "terrain/error.hpp"

namespace terrain {

UtmZone standard_utm_zone(double lat, double lon) {
  if (!(lat >= -80.0 && lat < 84.0))
    throw Error("latitude " + std::to_string(lat) + " is outside the UTM band [-80, 84)");
  return UtmZone{GeographicLib::UTMUPS::StandardZone(lat, lon), lat >= 0.0};
}

void utm_forward(UtmZone z, double lat, double lon, double& x, double& y) {
  int zone_out = 0;
  bool northp = true;
  GeographicLib::UTMUPS::Forward(lat, lon, zone_out, northp, x, y, z.zone);
  if (northp != z.north) y += northp ? 10e6 : -10e6;
}

UtmZone parse_utm_zone(std::string_view text, double lat_hint) {
  UtmZone z{0, lat_hint >= 0.0};
  const char* end = text.data() + text.size();
  auto [p, ec] = std::from_chars(text.data(), end, z.zone);
  bool ok = ec == std::errc() && z.zone >= 1 && z.zone <= 60;
  if (ok && p != end) {
    const char h = char(std::toupper(static_cast<unsigned char>(*p)));
    ok = p + 1 == end && (h == 'N' || h == 'S');
    z.north = h == 'N';
  }
  if (!ok)
    throw Error("invalid UTM zone '" + std::string(text) +
                "' (expected 1..60, optionally followed by N or S)");
  return z;
}

std::string utm_crs_wkt(const std::string& geographic_wkt, UtmZone zone, int& epsg) {
  OGRSpatialReference geo;
  if (geo.importFromWkt(geographic_wkt.c_str()) != OGRERR_NONE)
    throw Error("cannot parse the DEM's geographic CRS");
  OGRSpatialReference utm;
  utm.CopyGeogCSFrom(&geo);
  utm.SetUTM(zone.zone, zone.north ? TRUE : FALSE);
  utm.SetLinearUnits(SRS_UL_METER, 1.0);
  const char* geoname = geo.GetName();
  const std::string name = std::string(geoname ? geoname : "unknown") + " / UTM zone " +
                           std::to_string(zone.zone) + (zone.north ? "N" : "S");
  utm.SetProjCS(name.c_str());
  epsg = 0;
  if (utm.AutoIdentifyEPSG() == OGRERR_NONE) {
    const char* code = utm.GetAuthorityCode(nullptr);
    if (code) epsg = std::atoi(code);
  }
  if (epsg == 0) {  // a datum without authority codes (common in GeoTIFF keys): ask PROJ
    if (OGRSpatialReference* match = utm.FindBestMatch(90, "EPSG")) {
      const char* code = match->GetAuthorityCode(nullptr);
      if (code) epsg = std::atoi(code);
      match->Release();
    }
  }
  if (epsg > 0) {  // prefer the full EPSG definition when one exists
    OGRSpatialReference official;
    if (official.importFromEPSG(epsg) == OGRERR_NONE) utm = official;
  }
  char* wkt = nullptr;
  const char* opts[] = {"FORMAT=WKT2_2019", "MULTILINE=NO", nullptr};
  utm.exportToWkt(&wkt, opts);
  std::string out = wkt ? wkt : "";
  CPLFree(wkt);
  return out;
}

std::vector<MetricCellSize> metric_cell_sizes(const Georef& geo, std::size_t row0,
                                              std::size_t rows) {
  if (geo.crs_kind != CrsKind::Geographic)
    return std::vector<MetricCellSize>(rows, MetricCellSize{geo.dx, geo.dy});
  double a = GeographicLib::Constants::WGS84_a(), f = GeographicLib::Constants::WGS84_f();
  OGRSpatialReference srs;
  if (!geo.crs_wkt.empty() && srs.importFromWkt(geo.crs_wkt.c_str()) == OGRERR_NONE) {
    OGRErr e1 = OGRERR_NONE, e2 = OGRERR_NONE;
    const double sa = srs.GetSemiMajor(&e1), inv_f = srs.GetInvFlattening(&e2);
    if (e1 == OGRERR_NONE && e2 == OGRERR_NONE && sa > 0.0) {
      a = sa;
      f = inv_f > 0.0 ? 1.0 / inv_f : 0.0;
    }
  }
  const GeographicLib::Geodesic geod(a, f);
  std::vector<MetricCellSize> out(rows);
  for (std::size_t k = 0; k < rows; ++k) {
    const double lat = geo.y_of_row(double(row0 + k));
    double sx = 0.0, sy = 0.0;
    geod.Inverse(lat, 0.0, lat, geo.dx, sx);
    geod.Inverse(lat - 0.5 * geo.dy, 0.0, lat + 0.5 * geo.dy, 0.0, sy);
    out[k] = {sx, sy};
  }
  return out;
}

}  // namespace terrain
