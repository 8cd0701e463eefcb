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
#include <numeric>
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

namespace detail {

// terrain::Progress through GDAL's progress callback.
static int gdal_progress(double fraction, const char*, void* arg) {
  const auto& p = *static_cast<const terrain::Progress*>(arg);
  return !p || p(fraction) ? TRUE : FALSE;
}

// GDALPolygonize of the id raster at `tif` (4-connected, no-data left out): its polygons
// grouped by id, ids ascending, each id's parts in the order GDAL found them.
std::vector<std::pair<std::uint32_t, std::unique_ptr<OGRMultiPolygon>>> polygonize_ids(
    const std::string& tif, const terrain::Progress& progress) {
  std::unique_ptr<GDALDataset> src(
      GDALDataset::Open(tif.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
  if (!src) throw terrain::Error("cannot read '" + tif + "': " + CPLGetLastErrorMsg());
  GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("Memory");
  std::unique_ptr<GDALDataset> ds(mem->Create("", 0, 0, 0, GDT_Unknown, nullptr));
  OGRLayer* layer = ds->CreateLayer("polygons", nullptr, wkbPolygon, nullptr);
  OGRFieldDefn id("id", OFTInteger64);
  layer->CreateField(&id);
  GDALRasterBand* band = src->GetRasterBand(1);
  if (GDALPolygonize(band, band->GetMaskBand(), layer, 0, nullptr, gdal_progress,
                     const_cast<terrain::Progress*>(&progress)) != CE_None)
    throw terrain::Error("polygonizing '" + tif + "' failed: " + CPLGetLastErrorMsg());
  std::vector<std::pair<std::uint32_t, std::unique_ptr<OGRGeometry>>> parts;
  layer->ResetReading();
  for (auto& f : *layer)
    parts.emplace_back(std::uint32_t(f->GetFieldAsInteger64(0)), f->StealGeometry());
  std::stable_sort(parts.begin(), parts.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<std::pair<std::uint32_t, std::unique_ptr<OGRMultiPolygon>>> out;
  for (auto& [i, g] : parts) {
    if (out.empty() || out.back().first != i)
      out.emplace_back(i, std::make_unique<OGRMultiPolygon>());
    out.back().second->addGeometryDirectly(g.release());
  }
  return out;
}

}  // namespace detail

using detail::polygonize_ids;

namespace {

using terrain::Gpkg;

struct BasinFacts {
  std::uint64_t cells = 0;
  double x = 0, y = 0;
  bool has_outlet = false, edge = false;
  std::uint8_t max_order = 0;
};

}  // namespace

// ---- Divides ---------------------------------------------------------------------------

void add_divide_edges(const std::uint32_t* ids, std::size_t row0, std::size_t n, std::size_t cols,
                      bool below, std::vector<DivideEdge>& edges) {
  const std::uint64_t W = cols + 1;  // corners per row
  auto add = [&](std::uint32_t u, std::uint32_t v, std::uint64_t from, std::uint64_t to) {
    if (u == v || u == kNone || v == kNone) return;
    edges.push_back({std::min(u, v), std::max(u, v), from, to});
  };
  for (std::size_t r = 0; r < n; ++r) {
    const std::uint64_t gr = row0 + r;
    for (std::size_t c = 0; c < cols; ++c) {
      const std::uint32_t u = ids[r * cols + c];
      if (c + 1 < cols)
        add(u, ids[r * cols + c + 1], gr * W + c + 1, (gr + 1) * W + c + 1);  // east edge
      if (r + 1 < n || below)
        add(u, ids[(r + 1) * cols + c], (gr + 1) * W + c, (gr + 1) * W + c + 1);  // south edge
    }
  }
}

// A chain of grid corners (W corners a row) without the corners along straight runs.
static std::vector<std::uint64_t> turning_corners(const std::vector<std::uint64_t>& path,
                                                  std::uint64_t W) {
  const auto dr = [&](std::uint64_t p, std::uint64_t q) {
    return std::int64_t(q / W) - std::int64_t(p / W);
  };
  const auto dc = [&](std::uint64_t p, std::uint64_t q) {
    return std::int64_t(q % W) - std::int64_t(p % W);
  };
  std::vector<std::uint64_t> kept = {path.front()};
  for (std::size_t i = 1; i + 1 < path.size(); ++i)
    if (dr(path[i - 1], path[i]) != dr(path[i], path[i + 1]) ||
        dc(path[i - 1], path[i]) != dc(path[i], path[i + 1]))
      kept.push_back(path[i]);
  kept.push_back(path.back());
  return kept;
}

std::vector<std::vector<std::uint64_t>> chain_divide_edges(std::vector<DivideEdge> edges,
                                                           std::size_t cols) {
  const std::uint64_t W = cols + 1;
  std::sort(edges.begin(), edges.end(), [](const DivideEdge& p, const DivideEdge& q) {
    return std::tie(p.from, p.to) < std::tie(q.from, q.to);
  });
  // Each edge's two ends, sorted by corner: the edges at a corner are one equal range.
  std::vector<std::pair<std::uint64_t, std::uint32_t>> ends;
  ends.reserve(2 * edges.size());
  for (std::uint32_t e = 0; e < edges.size(); ++e)
    ends.push_back({edges[e].from, e}), ends.push_back({edges[e].to, e});
  std::sort(ends.begin(), ends.end());
  auto at = [&](std::uint64_t corner) {
    return std::equal_range(ends.begin(), ends.end(),
                            std::pair<std::uint64_t, std::uint32_t>{corner, 0},
                            [](const auto& p, const auto& q) { return p.first < q.first; });
  };
  std::vector<char> used(edges.size(), 0);
  std::vector<std::vector<std::uint64_t>> chains;
  auto walk = [&](std::uint64_t start) {
    std::vector<std::uint64_t> path = {start};
    std::uint64_t cur = start;
    for (;;) {
      const auto [b, e] = at(cur);
      auto next = std::find_if(b, e, [&](const auto& p) { return !used[p.second]; });
      if (next == e) break;
      used[next->second] = 1;
      const DivideEdge& d = edges[next->second];
      cur = d.from == cur ? d.to : d.from;
      path.push_back(cur);
      if (std::distance(at(cur).first, at(cur).second) != 2) break;  // basins meet, or a free end
    }
    chains.push_back(turning_corners(path, W));
  };
  // Chains from free ends and meeting corners first, then closed rings.
  for (std::size_t i = 0; i < ends.size();) {
    std::size_t j = i;
    while (j < ends.size() && ends[j].first == ends[i].first) ++j;
    if (j - i != 2)
      while (std::any_of(ends.begin() + std::ptrdiff_t(i), ends.begin() + std::ptrdiff_t(j),
                         [&](const auto& p) { return !used[p.second]; }))
        walk(ends[i].first);
    i = j;
  }
  for (std::uint32_t e = 0; e < edges.size(); ++e)
    if (!used[e]) walk(edges[e].from);
  return chains;
}

// ---- Watersheds ---------------------------------------------------------------------------

namespace {

std::size_t write_branches(Gpkg& gpkg, OGRLayer* layer, const DrainageDb& db,
                           const RiverOptions& rivers) {
  const DvHeader& h = db.header;
  std::size_t written = 0;
  const terrain::Grid surface = dv_elevations(db);  // what smoothed points take heights from
  for (const RiverLine& r : river_lines(db, rivers.min_area_m2)) {
    if (r.strahler < rivers.min_order) continue;
    const std::vector<Eigen::Vector3d> shape = river_shape(db, surface, r, rivers.smooth_samples);
    std::vector<std::size_t> kept(shape.size());
    std::iota(kept.begin(), kept.end(), std::size_t(0));
    if (rivers.smooth_samples > 0)
      kept = kept_points(shape, rivers.simplify_spacings * std::min(h.dx, h.dy));
    OGRLineString line;
    for (const std::size_t k : kept)
      line.addPoint(h.origin_x + shape[k].x(), h.origin_y + shape[k].y(), h.origin_z + shape[k].z(),
                    db.vertices[r.points[k]].normalized);
    OGRFeature feature(layer->GetLayerDefn());
    feature.SetField("strahler", GIntBig(r.strahler));
    feature.SetField("basin", GIntBig(db.vertices[r.points.front()].basin));
    feature.SetField("max_flow", GIntBig(r.max_flow));
    feature.SetField("vertices", GIntBig(line.getNumPoints()));
    feature.SetGeometry(&line);
    gpkg.add(layer, feature);
    ++written;
  }
  return written;
}

OGRLayer* branches_layer(Gpkg& gpkg) {
  return gpkg.layer("branches", wkbLineStringZM,
                    {{"strahler", OFTInteger64},  // not `order`: an SQL keyword
                     {"basin", OFTInteger64},
                     {"max_flow", OFTInteger64},
                     {"vertices", OFTInteger64}},
                    {"31,61,140,255", 0.2, "0.1 + 0.1 * \"strahler\"",
                     "Rivers: width by Strahler order, as terrain-render draws creases"});
}

}  // namespace

std::size_t export_branches_gpkg(const DrainageDb& db, const std::string& path,
                                 const RiverOptions& rivers) {
  Gpkg gpkg(path, db.header.crs_wkt);
  OGRLayer* layer = branches_layer(gpkg);
  gpkg.begin();
  const std::size_t n = write_branches(gpkg, layer, db, rivers);
  gpkg.commit();
  return n;
}

namespace {

// One pass over the file: the basin ids into the GeoTIFF `ids_tif` (when given, for
// polygonize), each basin's outlet and cells into `facts`, and the divide edges (when asked).
void scan_basins(const std::string& dv_path, const DvHeader& h, const std::string& ids_tif,
                 bool divides, std::vector<BasinFacts>& facts, std::vector<DivideEdge>& edges,
                 const terrain::Progress& progress) {
  const std::size_t R = h.rows, C = h.cols;
  const bool basins = !ids_tif.empty();
  {
    std::optional<terrain::RasterWriter> tif;
    if (basins)
      tif.emplace(ids_tif, dv_georef(h), R, C, terrain::RasterType::UInt32, double(kNone));
    const std::size_t band = dv_band_rows(h);
    std::vector<std::uint32_t> ids;
    for (std::size_t r0 = 0; r0 < R; r0 += band) {
      const std::size_t n = std::min(band, R - r0);
      const bool below = r0 + n < R;
      const DrainageDb w = read_dv_window(dv_path, r0, 0, n + below, C);
      ids.resize(w.vertices.size());
      for (std::size_t i = 0; i < ids.size(); ++i) {
        const DvVertex& v = w.vertices[i];
        const bool valid = PointClass(v.point_class) != PointClass::Nodata;
        ids[i] = valid ? v.basin : kNone;
        if (!valid || i >= n * C) continue;
        BasinFacts& b = facts.at(v.basin);
        ++b.cells;
        if (PointClass(v.point_class) == PointClass::Pit) {
          b.has_outlet = true;
          b.x = h.origin_x + double(i % C) * h.dx, b.y = h.origin_y - double(r0 + i / C) * h.dy;
          b.edge = v.d8 != kNoFlow;
          b.max_order = v.order;
        }
      }
      if (tif) tif->write_rows(r0, n, ids.data());
      if (divides) add_divide_edges(ids.data(), r0, n, C, below, edges);
      terrain::report(progress, 0.1 + 0.3 * double(r0 + n) / double(R));
    }
    if (tif) tif->commit();
  }
  for (std::size_t b = 0; b < facts.size(); ++b)
    if (!facts[b].has_outlet)
      throw terrain::Error(fmt::format("'{}': basin {} has no outlet (corrupt .dv)", dv_path, b));
}

// The "basins" layer: the polygons of the basin ids with their facts; returns their count.
std::size_t write_basins(Gpkg& gpkg, OGRLayer* basins, const DvHeader& h,
                         const std::string& ids_tif, const std::vector<BasinFacts>& facts,
                         const terrain::Progress& progress) {
  const double cell_area = h.dx * h.dy;
  const auto polygons = polygonize_ids(ids_tif, terrain::sub_progress(progress, 0.4, 0.85));
  for (const auto& [id, poly] : polygons) {
    const BasinFacts& b = facts.at(id);
    OGRFeature f(basins->GetLayerDefn());
    detail::set_catchment_fields(f, id, b.cells, cell_area, b.x, b.y);
    f.SetField("outlet", b.edge ? "edge" : "pit");
    f.SetField("max_order", int(b.max_order));
    f.SetGeometry(poly.get());
    gpkg.add(basins, f);
  }
  return polygons.size();
}

// The "divides" layer: the edges between two basins chained into lines, one feature per pair
// of basins; returns their count.
std::size_t write_divides(Gpkg& gpkg, OGRLayer* divides, const DvHeader& h,
                          std::vector<DivideEdge>& edges, const std::vector<BasinFacts>& facts) {
  const std::size_t C = h.cols;
  std::size_t n = 0;
  std::sort(edges.begin(), edges.end(), [](const DivideEdge& p, const DivideEdge& q) {
    return std::tie(p.a, p.b) < std::tie(q.a, q.b);
  });
  const double x0 = h.origin_x - h.dx / 2, y0 = h.origin_y + h.dy / 2;
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    double length = 0;
    while (j < edges.size() && edges[j].a == edges[i].a && edges[j].b == edges[i].b) {
      length += edges[j].to - edges[j].from == 1 ? h.dx : h.dy;
      ++j;
    }
    const auto chains = chain_divide_edges(
        {edges.begin() + std::ptrdiff_t(i), edges.begin() + std::ptrdiff_t(j)}, C);
    OGRMultiLineString lines;
    for (const auto& chain : chains) {
      auto* line = new OGRLineString;
      for (const std::uint64_t p : chain)
        line->addPoint(x0 + double(p % (C + 1)) * h.dx, y0 - double(p / (C + 1)) * h.dy);
      lines.addGeometryDirectly(line);
    }
    const std::uint32_t a = edges[i].a, b = edges[i].b;
    OGRFeature f(divides->GetLayerDefn());
    f.SetField("basin_a", GIntBig(a));
    f.SetField("basin_b", GIntBig(b));
    f.SetField("max_order", int(std::max(facts[a].max_order, facts[b].max_order)));
    f.SetField("length_m", length);
    f.SetGeometry(&lines);
    gpkg.add(divides, f);
    ++n;
    i = j;
  }
  return n;
}

}  // namespace

GpkgCounts export_dv_gpkg(const std::string& dv_path, const std::string& out_path,
                          const GpkgLayers& layers, const terrain::Progress& progress) {
  const DvHeader h = read_dv_header(dv_path);
  if (h.basins > std::uint64_t(std::numeric_limits<std::int32_t>::max()))
    throw terrain::Error("'" + dv_path + "' has more basins than GDAL's polygonize numbers (2^31)");
  GpkgCounts counts;
  Gpkg gpkg(out_path, h.crs_wkt);
  OGRLayer* branches = layers.branches ? branches_layer(gpkg) : nullptr;
  OGRLayer* basins = layers.basins
                         ? gpkg.layer("basins", wkbMultiPolygon,
                                      {{"id", OFTInteger64},
                                       {"cells", OFTInteger64},
                                       {"area_m2", OFTReal},
                                       {"outlet_x", OFTReal},
                                       {"outlet_y", OFTReal},
                                       {"outlet", OFTString},
                                       {"max_order", OFTInteger}},
                                      {"110,110,110,255", 0.2, "", "Basins: their outlines"})
                         : nullptr;
  OGRLayer* divides = layers.divides
                          ? gpkg.layer("divides", wkbMultiLineString,
                                       {{"basin_a", OFTInteger64},
                                        {"basin_b", OFTInteger64},
                                        {"max_order", OFTInteger},
                                        {"length_m", OFTReal}},
                                       {"120,72,32,255", 0.2, "0.1 + 0.08 * \"max_order\"",
                                        "Divides: width by the larger basin's order"})
                          : nullptr;
  gpkg.begin();
  if (branches) counts.branches = write_branches(gpkg, branches, read_dv(dv_path), layers.rivers);
  terrain::report(progress, 0.1);
  if (!basins && !divides) {
    gpkg.commit();
    return counts;
  }

  // One pass over the file: the basin ids into a scratch GeoTIFF (for polygonize), each
  // basin's outlet and cells, and the divide edges.
  const terrain::GdalCacheLimit cache_limit;
  std::vector<BasinFacts> facts(h.basins);
  std::vector<DivideEdge> edges;
  terrain::ScratchDir scratch(out_path);
  const std::string ids_tif = (scratch.path() / "basin.tif").string();
  scan_basins(dv_path, h, basins ? ids_tif : std::string(), divides != nullptr, facts, edges,
              progress);
  if (basins) counts.basins = write_basins(gpkg, basins, h, ids_tif, facts, progress);
  if (divides) counts.divides = write_divides(gpkg, divides, h, edges, facts);
  gpkg.commit();
  terrain::report(progress, 1.0);
  return counts;
}

}  // namespace drainage
