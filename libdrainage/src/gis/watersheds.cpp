// Watersheds: outlet points read and snapped onto the network, each cell labelled with the
// outlet it drains to, and the watershed layers written (build-drainage --outlets).
#include "drainage/gis_layers.hpp"

#include <gdal_alg.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <utility>

#include <fmt/format.h>

#include "drainage/dv_file.hpp"
#include "drainage/dv_views.hpp"
#include "drainage/network.hpp"
#include "gis_internal.hpp"
#include "terrain/atomic_file.hpp"
#include "terrain/dem_io.hpp"
#include "terrain/gpkg.hpp"

namespace drainage {

using detail::polygonize_ids;
using terrain::Gpkg;

terrain::BigVector<std::uint32_t> nearest_downstream_outlet(
    const D8Codes& dirs, std::size_t rows, std::size_t cols,
    const std::vector<std::uint64_t>& outlet_cells) {
  const std::size_t n = rows * cols;
  if (dirs.size() != n)
    throw terrain::Error("nearest_downstream_outlet: directions are not rows x cols");
  constexpr std::uint32_t kPending = kNone - 1;
  terrain::BigVector<std::uint32_t> label(n, kPending);
  for (std::size_t k = 0; k < outlet_cells.size(); ++k) {
    const std::uint64_t i = outlet_cells[k];
    if (i >= n) throw terrain::Error(fmt::format("outlet {} lies outside the grid", k));
    if (label[i] != kPending)
      throw terrain::Error(fmt::format("outlets {} and {} are the same cell (row {}, column {})",
                                       label[i], k, i / cols, i % cols));
    label[i] = std::uint32_t(k);
  }
  auto down = [&](std::size_t i) { return flows_into(dirs, rows, cols, i); };
  std::vector<std::size_t> path;
  for (std::size_t i = 0; i < n; ++i) {
    if (label[i] != kPending) continue;
    if (dirs[i] == kNodata) {
      label[i] = kNone;
      continue;
    }
    path.clear();
    std::size_t j = i;
    while (j != kNone && label[j] == kPending) {
      if (path.size() > n) throw terrain::Error("the D8 directions hold a cycle");
      path.push_back(j);
      label[j] = kNone - 2;  // on the path: met again only through a cycle
      j = down(j);
    }
    if (j != kNone && label[j] == kNone - 2) throw terrain::Error("the D8 directions hold a cycle");
    const std::uint32_t to = j == kNone ? kNone : label[j];
    for (const std::size_t p : path) label[p] = to;
  }
  return label;
}

std::vector<OutletPoint> read_outlet_points(const std::string& path, const std::string& crs_wkt) {
  terrain::ensure_gdal();
  CPLStringList open_options;
  if (std::filesystem::path(path).extension() == ".csv" ||
      std::filesystem::path(path).extension() == ".CSV") {
    open_options.AddString("X_POSSIBLE_NAMES=x,X,easting,Easting,lon*,Lon*,long*,Long*");
    open_options.AddString("Y_POSSIBLE_NAMES=y,Y,northing,Northing,lat*,Lat*");
  }
  CPLErrorReset();
  std::unique_ptr<GDALDataset> ds(GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY,
                                                    nullptr, open_options.List()));
  if (!ds) {
    const std::string why = CPLGetLastErrorMsg();
    throw terrain::Error("cannot read outlets from '" + path +
                         "': " + (why.empty() ? "not a vector file GDAL reads" : why));
  }
  if (ds->GetLayerCount() < 1) throw terrain::Error("'" + path + "' has no layer of outlet points");
  OGRLayer* layer = ds->GetLayer(0);
  std::unique_ptr<OGRCoordinateTransformation> to_grid;
  const OGRSpatialReference* from = layer->GetSpatialRef();
  OGRSpatialReference target;
  if (from && !crs_wkt.empty() && target.importFromWkt(crs_wkt.c_str()) == OGRERR_NONE &&
      !from->IsSame(&target)) {
    OGRSpatialReference src(*from);
    src.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    target.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    to_grid.reset(OGRCreateCoordinateTransformation(&src, &target));
    if (!to_grid)
      throw terrain::Error("cannot transform the outlets of '" + path +
                           "' to the drainage grid's CRS: " + CPLGetLastErrorMsg());
  }
  std::vector<OutletPoint> out;
  for (auto& f : *layer) {
    const OGRGeometry* g = f->GetGeometryRef();
    if (!g || wkbFlatten(g->getGeometryType()) != wkbPoint)
      throw terrain::Error(
          fmt::format("'{}': feature {} is {}, not a point", path, f->GetFID(),
                      g ? OGRGeometryTypeToName(g->getGeometryType()) : "without geometry"));
    double x = g->toPoint()->getX(), y = g->toPoint()->getY();
    if (to_grid && !to_grid->Transform(1, &x, &y))
      throw terrain::Error(fmt::format("'{}': feature {} cannot be transformed to the grid's CRS",
                                       path, f->GetFID()));
    out.push_back({x, y, f->GetFID()});
  }
  if (out.empty()) throw terrain::Error("'" + path + "' holds no outlet point");
  return out;
}

// The snap distance and every outlet checked against the grid: a distance beyond the
// grid's size, or an outlet outside it, is an error.
static void check_outlets(const DvHeader& h, const terrain::Georef& geo,
                          const std::vector<OutletPoint>& points, double snap_distance) {
  const std::size_t R = h.rows, C = h.cols;
  if (!(snap_distance >= 0)) throw terrain::Error("the snap distance must be 0 or more metres");
  const double west = geo.x0, east = geo.x0 + double(C) * h.dx, north = geo.y0,
               south = geo.y0 - double(R) * h.dy;
  const double size = std::hypot(east - west, north - south);
  if (snap_distance > size)
    throw terrain::Error(fmt::format(
        "a snap distance of {:g} m exceeds the grid's size ({:.0f} m): every outlet would "
        "move to the largest stream; give at most a few cells",
        snap_distance, size));
  // An outlet outside the grid is a point in other coordinates (longitude and latitude in
  // a file without a CRS), not one to snap in from afar.
  for (std::size_t k = 0; k < points.size(); ++k) {
    const OutletPoint& p = points[k];
    if (p.x >= west && p.x <= east && p.y >= south && p.y <= north) continue;
    const bool degrees = std::abs(p.x) <= 180 && std::abs(p.y) <= 90 && size > 1000;
    throw terrain::Error(
        fmt::format("outlet {} (feature {}) at {:.6g}, {:.6g} lies outside the grid (x "
                    "{:.1f}..{:.1f}, y {:.1f}..{:.1f}){}",
                    k, p.fid, p.x, p.y, west, east, south, north,
                    degrees ? ": its numbers look like longitude and latitude in a file without a "
                              "CRS; give the file one "
                              "(ogr2ogr -a_srs EPSG:4326, or a .prj beside it)"
                            : ""));
  }
}

std::vector<Watershed> snap_outlets(const DvHeader& h, const std::vector<OutletPoint>& points,
                                    double snap_distance, const DvWindowReader& window,
                                    std::vector<std::uint64_t>& cells) {
  const std::size_t R = h.rows, C = h.cols;
  const terrain::Georef geo = dv_georef(h);
  auto centre_x = [&](std::size_t c) { return h.origin_x + double(c) * h.dx; };
  auto centre_y = [&](std::size_t r) { return h.origin_y - double(r) * h.dy; };
  check_outlets(h, geo, points, snap_distance);
  // The highest accumulation within the distance (a window of the file around it).
  std::vector<Watershed> ws(points.size());
  cells.assign(points.size(), 0);
  for (std::size_t k = 0; k < points.size(); ++k) {
    const OutletPoint& p = points[k];
    Watershed& w = ws[k];
    w.given = p;
    const double s = snap_distance;
    const double cmin = std::floor((p.x - s - geo.x0) / h.dx),
                 cmax = std::floor((p.x + s - geo.x0) / h.dx);
    const double rmin = std::floor((geo.y0 - (p.y + s)) / h.dy),
                 rmax = std::floor((geo.y0 - (p.y - s)) / h.dy);
    const double c0 = std::max(0.0, cmin), c1 = std::min(double(C) - 1, cmax);
    const double r0 = std::max(0.0, rmin), r1 = std::min(double(R) - 1, rmax);
    bool found = false;
    double best_d = 0;
    if (c0 <= c1 && r0 <= r1) {
      const DrainageDb win = window(std::size_t(r0), std::size_t(c0), std::size_t(r1 - r0 + 1),
                                    std::size_t(c1 - c0 + 1));
      const std::size_t wc = win.header.cols;
      for (std::size_t i = 0; i < win.vertices.size(); ++i) {
        const DvVertex& v = win.vertices[i];
        if (PointClass(v.point_class) == PointClass::Nodata) continue;
        const std::size_t r = std::size_t(r0) + i / wc, c = std::size_t(c0) + i % wc;
        const double d = std::hypot(centre_x(c) - p.x, centre_y(r) - p.y);
        if (s > 0 && d > s) continue;  // with 0 the window is the cell holding the point
        if (!found || v.accumulated > w.accumulated ||
            (v.accumulated == w.accumulated && d < best_d)) {
          found = true;
          best_d = d;
          w.row = r, w.col = c, w.accumulated = v.accumulated;
        }
      }
    }
    if (!found)
      throw terrain::Error(fmt::format(
          "outlet {} (feature {}) at {:.2f}, {:.2f}: no drainage point {} (the grid spans "
          "x {:.1f}..{:.1f}, y {:.1f}..{:.1f})",
          k, p.fid, p.x, p.y, s > 0 ? fmt::format("within {:g} m", s) : std::string("in its cell"),
          geo.x0, geo.x0 + double(C) * h.dx, geo.y0 - double(R) * h.dy, geo.y0));
    w.x = centre_x(w.col), w.y = centre_y(w.row), w.moved = best_d;
    cells[k] = std::uint64_t(w.row) * C + w.col;
    for (std::size_t j = 0; j < k; ++j)
      if (cells[j] == cells[k])
        throw terrain::Error(fmt::format(
            "outlets {} and {} (features {} and {}) snap to the same cell (row {}, column "
            "{}): give one of them, or a smaller --snap-distance",
            j, k, points[j].fid, p.fid, w.row, w.col));
  }
  return ws;
}

namespace {

// Each cell's watershed: the file's directions, window by window, then each cell's nearest
// outlet downstream (`cells`: the outlets' cells); each outlet's downstream watershed and
// cell count set in `ws`.
terrain::BigVector<std::uint32_t> label_watersheds(const std::string& dv_path, const DvHeader& h,
                                                   const std::vector<std::uint64_t>& cells,
                                                   std::vector<Watershed>& ws,
                                                   const terrain::Progress& progress) {
  const std::size_t R = h.rows, C = h.cols;
  terrain::BigVector<std::uint32_t> label;
  {
    D8Codes dirs(R * C);
    const std::size_t band = dv_band_rows(h);
    for (std::size_t r0 = 0; r0 < R; r0 += band) {
      const DrainageDb w = read_dv_window(dv_path, r0, 0, std::min(band, R - r0), C);
      for (std::size_t i = 0; i < w.vertices.size(); ++i)
        dirs[r0 * C + i] = PointClass(w.vertices[i].point_class) == PointClass::Nodata
                               ? kNodata
                               : w.vertices[i].d8;
      terrain::report(progress, 0.05 + 0.3 * double(r0 + band) / double(R));
    }
    label = nearest_downstream_outlet(dirs, R, C, cells);
    for (std::size_t k = 0; k < ws.size(); ++k) {  // the watershed each outlet drains into
      const std::size_t j = flows_into(dirs, R, C, cells[k]);
      if (j != kNone && label[j] != kNone) ws[k].downstream = label[j];
    }
  }
  for (const std::uint32_t l : label)
    if (l != kNone) ++ws[l].cells;
  return label;
}

// The GeoPackage's layers "outlets" (points at the outlet cells) and "watersheds" (their
// polygons).
void write_watershed_layers(
    const std::string& gpkg_path, const DvHeader& h, const std::vector<Watershed>& ws,
    const std::vector<std::pair<std::uint32_t, std::unique_ptr<OGRMultiPolygon>>>& polygons) {
  const double cell_area = h.dx * h.dy;
  Gpkg gpkg(gpkg_path, h.crs_wkt);
  OGRLayer* outlets = gpkg.layer("outlets", wkbPoint,
                                 {{"id", OFTInteger64},
                                  {"fid_given", OFTInteger64},
                                  {"given_x", OFTReal},
                                  {"given_y", OFTReal},
                                  {"moved_m", OFTReal},
                                  {"accumulated", OFTInteger64},
                                  {"cells", OFTInteger64},
                                  {"area_m2", OFTReal},
                                  {"downstream", OFTInteger64}},
                                 {"200,30,30,255", 2.0, "", "Outlets, as snapped"});
  OGRLayer* sheds = gpkg.layer("watersheds", wkbMultiPolygon,
                               {{"id", OFTInteger64},
                                {"cells", OFTInteger64},
                                {"area_m2", OFTReal},
                                {"outlet_x", OFTReal},
                                {"outlet_y", OFTReal},
                                {"downstream", OFTInteger64}},
                               {"40,40,40,255", 0.5, "", "Watersheds: their outlines"});
  gpkg.begin();
  for (std::size_t k = 0; k < ws.size(); ++k) {
    const Watershed& w = ws[k];
    OGRFeature f(outlets->GetLayerDefn());
    f.SetField("id", GIntBig(k));
    f.SetField("fid_given", GIntBig(w.given.fid));
    f.SetField("given_x", w.given.x);
    f.SetField("given_y", w.given.y);
    f.SetField("moved_m", w.moved);
    f.SetField("accumulated", GIntBig(w.accumulated));
    f.SetField("cells", GIntBig(w.cells));
    f.SetField("area_m2", double(w.cells) * cell_area);
    if (w.downstream >= 0) f.SetField("downstream", GIntBig(w.downstream));
    OGRPoint pt(w.x, w.y);
    f.SetGeometry(&pt);
    gpkg.add(outlets, f);
  }
  for (const auto& [k, poly] : polygons) {
    const Watershed& w = ws.at(k);
    OGRFeature f(sheds->GetLayerDefn());
    detail::set_catchment_fields(f, std::uint32_t(k), w.cells, cell_area, w.x, w.y);
    if (w.downstream >= 0) f.SetField("downstream", GIntBig(w.downstream));
    f.SetGeometry(poly.get());
    gpkg.add(sheds, f);
  }
  gpkg.commit();
}

}  // namespace

std::vector<Watershed> write_watersheds(const std::string& dv_path,
                                        const std::vector<OutletPoint>& points,
                                        double snap_distance, const std::string& gpkg_path,
                                        const std::string& tif_path, const std::string& provenance,
                                        const terrain::Progress& progress) {
  const DvHeader h = read_dv_header(dv_path);
  const std::size_t R = h.rows, C = h.cols;
  const terrain::GdalCacheLimit cache_limit;
  std::vector<std::uint64_t> cells;
  std::vector<Watershed> ws = snap_outlets(
      h, points, snap_distance,
      [&](std::size_t r0, std::size_t c0, std::size_t rows, std::size_t cols) {
        return read_dv_window(dv_path, r0, c0, rows, cols);
      },
      cells);
  terrain::report(progress, 0.05);
  terrain::BigVector<std::uint32_t> label = label_watersheds(dv_path, h, cells, ws, progress);
  terrain::report(progress, 0.45);
  // The raster, then its polygons.
  {
    terrain::RasterWriter tif(tif_path, dv_georef(h), R, C, terrain::RasterType::UInt32,
                              double(kNone), provenance);
    const std::size_t band = 256;
    for (std::size_t r0 = 0; r0 < R; r0 += band)
      tif.write_rows(r0, std::min(band, R - r0), &label[r0 * C]);
    tif.commit();
  }
  terrain::BigVector<std::uint32_t>().swap(label);  // freed before polygonize
  write_watershed_layers(gpkg_path, h, ws,
                         polygonize_ids(tif_path, terrain::sub_progress(progress, 0.55, 0.95)));
  terrain::report(progress, 1.0);
  return ws;
}

// ---- Branches, basins, divides -------------------------------------------------------------

}  // namespace drainage
