#include "drainage/dv_views.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "drainage/d8.hpp"

static_assert(drainage::kNone == terrain::DrainageLinks::kNone);
#include "terrain/dem_io.hpp"
#include "terrain/error.hpp"
#include "terrain/hillshade.hpp"

namespace drainage {

namespace {

// Adds vertex v to the summary's counts (and its flow to `sum`); false for no-data.
bool count_point(DvSummary& s, const DvVertex& v, std::uint64_t valid, double& sum) {
  switch (PointClass(v.point_class)) {
    case PointClass::Pit:
      ++s.pits;
      break;
    case PointClass::Ridge:
      ++s.ridges;
      break;
    case PointClass::Channel:
      ++s.channels;
      break;
    case PointClass::Junction:
      ++s.junctions;
      break;
    case PointClass::Nodata:
      return false;
  }
  ++s.points;
  sum += v.normalized;
  s.max_accumulated = std::max(s.max_accumulated, v.accumulated);
  if (PointClass(v.point_class) == PointClass::Pit && double(v.accumulated) > 0.01 * double(valid))
    ++s.basins_over_1pct;
  return true;
}

}  // namespace

DvSummary summarize(const DrainageDb& db) {
  DvSummary s;
  double sum = 0.0;
  for (const DvVertex& v : db.vertices) count_point(s, v, db.header.valid, sum);
  if (s.points) s.mean_normalized = sum / double(s.points);
  for (const DvBranch& b : db.branches) ++s.branches_per_order[b.order];
  return s;
}

std::size_t dv_band_rows(const DvHeader& h) {
  const std::size_t block = h.block_rows ? std::size_t(h.block_rows) : 256;
  return std::max<std::size_t>(
      1, std::min(block, (std::size_t(256) << 20) /
                             (std::max<std::size_t>(1, h.cols) * sizeof(DvVertex))));
}

DvSummary summarize_dv_file(const std::string& path) {
  const DvHeader h = read_dv_header(path);
  if (h.version < 2) return summarize(read_dv(path));
  const std::size_t rows = std::size_t(h.rows), cols = std::size_t(h.cols);
  const std::size_t band = dv_band_rows(h);
  DvSummary s;
  double sum = 0.0;
  for (std::size_t r0 = 0; r0 < rows; r0 += band) {
    // The band with one row above and below: every point counted sees all its inflows.
    const std::size_t w0 = r0 > 0 ? r0 - 1 : 0, w1 = std::min(rows, r0 + band + 1);
    const DrainageDb w = read_dv_window(path, w0, 0, w1 - w0, cols);
    const long C = long(cols), R = long(w1 - w0);
    for (long r = long(r0 - w0); r < long(std::min(rows, r0 + band) - w0); ++r)
      for (long c = 0; c < C; ++c) {
        const std::size_t i = std::size_t(r * C + c);
        const DvVertex& v = w.vertices[i];
        if (!count_point(s, v, h.valid, sum)) continue;
        int same = 0;  // a branch head: not exactly one inflow of its own order (network_branches,
                       // branches.hpp)
        Neighbours{R, C}.inflows(r, c, [&](std::size_t j, int) {
          same += w.vertices[j].downstream == i && w.vertices[j].order == v.order;
        });
        if (same != 1) ++s.branches_per_order[v.order];
      }
  }
  // The header's counts against the points streamed, as read_dv checks them (one
  // validation for every reader of a whole file).
  std::uint64_t branches = 0;
  for (const auto& [order, n] : s.branches_per_order) branches += n;
  if (s.points != h.valid)
    throw terrain::Error(
        fmt::format("cannot read '{}': corrupt .dv ({} valid points, the header says {})", path,
                    s.points, h.valid));
  if (branches != h.branches)
    throw terrain::Error(
        fmt::format("cannot read '{}': corrupt .dv ({} branches derived, the header says {})", path,
                    branches, h.branches));
  if (s.points) s.mean_normalized = sum / double(s.points);
  return s;
}

terrain::DrainageLinks drainage_links(const DrainageDb& db) {
  const DvHeader& h = db.header;
  terrain::DrainageLinks l;
  l.epsg = h.epsg;
  l.rows = h.rows;
  l.cols = h.cols;
  l.dx = h.dx;
  l.dy = h.dy;
  l.origin = {h.origin_x, h.origin_y, h.origin_z};
  const std::size_t n = db.vertices.size();
  l.z.resize(n);
  l.valid.resize(n);
  l.flow.resize(n);
  l.accumulated.resize(n);
  l.downstream.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const DvVertex& v = db.vertices[i];
    l.z[i] = v.z;  // x and y: the point's column and row (DrainageLinks::position)
    l.valid[i] = PointClass(v.point_class) != PointClass::Nodata;
    l.flow[i] = v.normalized;
    l.accumulated[i] = v.accumulated;
    l.downstream[i] = v.downstream;  // kNone is the same value in both
  }
  return l;
}

terrain::DrainageLinks drainage_links_in(const std::string& path, double west, double south,
                                         double east, double north, std::size_t band_points) {
  const DvHeader h = read_dv_header(path);
  const double eps = 1e-6;
  const double c0 = std::max(0.0, std::ceil((west - h.origin_x) / h.dx - eps));
  const double c1 = std::min(double(h.cols) - 1.0, std::floor((east - h.origin_x) / h.dx + eps));
  const double r0 = std::max(0.0, std::ceil((h.origin_y - north) / h.dy - eps));
  const double r1 = std::min(double(h.rows) - 1.0, std::floor((h.origin_y - south) / h.dy + eps));
  if (!(c0 <= c1) || !(r0 <= r1))
    throw terrain::Error(fmt::format("'{}' does not overlap x {:.1f}..{:.1f}, y {:.1f}..{:.1f}",
                                     path, west, east, south, north));
  const std::size_t wr0 = std::size_t(r0), wc0 = std::size_t(c0), nr = std::size_t(r1 - r0 + 1),
                    nc = std::size_t(c1 - c0 + 1);
  if (h.version == 1) return drainage_links(read_dv_window(path, wr0, wc0, nr, nc));
  // Version 2, band by band: only one band's database is held beside the arrays. Each band
  // is read with one row of margin above and below, so that its points' downstream links
  // into the rows next to it are known.
  const std::size_t band = std::max<std::size_t>(1, band_points / nc);
  terrain::DrainageLinks l;
  l.epsg = h.epsg;
  l.rows = nr, l.cols = nc;
  l.dx = h.dx, l.dy = h.dy;
  l.origin = {h.origin_x + double(wc0) * h.dx, h.origin_y - double(wr0) * h.dy, h.origin_z};
  const std::size_t n = nr * nc;
  l.z.resize(n), l.valid.resize(n), l.flow.resize(n), l.accumulated.resize(n),
      l.downstream.resize(n);
  for (std::size_t a = 0; a < nr; a += band) {
    const std::size_t b = std::min(nr, a + band), wa = a > 0 ? a - 1 : 0, wb = std::min(nr, b + 1);
    const DrainageDb w = read_dv_window(path, wr0 + wa, wc0, wb - wa, nc);
    for (std::size_t r = a; r < b; ++r)
      for (std::size_t c = 0; c < nc; ++c) {
        const DvVertex& v = w.vertices[(r - wa) * nc + c];
        const std::size_t i = r * nc + c;
        l.z[i] = v.z;
        l.valid[i] = PointClass(v.point_class) != PointClass::Nodata;
        l.flow[i] = v.normalized;
        l.accumulated[i] = v.accumulated;
        l.downstream[i] =
            v.downstream == terrain::DrainageLinks::kNone
                ? terrain::DrainageLinks::kNone
                : std::uint32_t(wa * nc +
                                v.downstream);  // band-local row-major: + the band's first row
      }
  }
  return l;
}

terrain::Georef dv_georef(const DvHeader& h) {
  terrain::Georef geo;
  geo.dx = h.dx;
  geo.dy = h.dy;
  geo.x0 = h.origin_x - h.dx / 2;
  geo.y0 = h.origin_y + h.dy / 2;
  geo.crs_wkt = h.crs_wkt;
  geo.epsg = h.epsg;
  geo.crs_kind = h.crs_wkt.empty() ? terrain::CrsKind::None : terrain::CrsKind::Projected;
  return geo;
}

terrain::Grid dv_elevations(const DrainageDb& db) {
  const DvHeader& h = db.header;
  terrain::Grid g(h.rows, h.cols, dv_georef(h));
  for (std::size_t i = 0; i < g.size(); ++i)
    g.z[i] = PointClass(db.vertices[i].point_class) == PointClass::Nodata
                 ? std::numeric_limits<float>::quiet_NaN()
                 : float(h.origin_z + db.vertices[i].z);
  return g;
}

std::vector<std::uint8_t> dv_preview(const DrainageDb& db, std::uint32_t min_accumulated) {
  const terrain::Grid g = dv_elevations(db);
  const auto shade = terrain::hillshade_grid(g);
  if (min_accumulated == 0) {  // the 96th percentile of accumulated flow, at least 20 points
    std::vector<std::uint32_t> acc;
    acc.reserve(db.header.valid);
    for (const DvVertex& v : db.vertices)
      if (PointClass(v.point_class) != PointClass::Nodata) acc.push_back(v.accumulated);
    if (!acc.empty()) {
      auto nth = acc.begin() + std::ptrdiff_t(double(acc.size()) * 0.96);
      std::nth_element(acc.begin(), nth, acc.end());
      min_accumulated = *nth;
    }
    min_accumulated = std::max<std::uint32_t>(20, min_accumulated);
  }
  std::vector<std::uint8_t> rgb(3 * g.size());
  const float blue[3] = {20, 50, 140};
  for (std::size_t i = 0; i < g.size(); ++i) {
    const DvVertex& v = db.vertices[i];
    float grey =
        PointClass(v.point_class) == PointClass::Nodata ? 255.0f : float(shade[i]) * 0.8f + 40.0f;
    float alpha = 0.0f;
    if (PointClass(v.point_class) != PointClass::Nodata && v.accumulated >= min_accumulated)
      alpha = 0.35f + 0.65f * std::sqrt(v.normalized);
    for (int k = 0; k < 3; ++k)
      rgb[3 * i + std::size_t(k)] = std::uint8_t(std::lround((1 - alpha) * grey + alpha * blue[k]));
  }
  return rgb;
}

}  // namespace drainage
