#include "terrain/prepare_grid.hpp"

#include <fmt/format.h>
#include <GeographicLib/UTMUPS.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>

#include "terrain/dem_io.hpp"
#include "terrain/grid_mesh.hpp"

namespace terrain {

namespace {

using GeographicLib::UTMUPS;

struct Box {
  double x0, y0, x1, y1;  // xmin ymin xmax ymax
};

using ToSource = GridPlan::ToSource;

// Indices k of lattice cells [anchor + k*step, anchor + (k+1)*step] whose centres lie
// in [lo, hi]; returns false when there is none.
bool lattice_range(double anchor, double step, double lo, double hi, long& kmin, long& kmax) {
  constexpr double eps = 1e-9;
  kmin = long(std::ceil((lo - anchor) / step - 0.5 - eps));
  kmax = long(std::floor((hi - anchor) / step - 0.5 + eps));
  return kmax >= kmin;
}

std::string fmt_box(const Box& b) {
  return fmt::format("x {:.3f}..{:.3f}, y {:.3f}..{:.3f}", b.x0, b.x1, b.y0, b.y1);
}

}  // namespace

namespace {

// The request's own consistency, and a DEM of at least 2 x 2.
void check_request(std::size_t src_rows, std::size_t src_cols, const GridRequest& req) {
  if (src_rows < 2 || src_cols < 2)
    throw Error(fmt::format("the DEM has {} x {} samples; a mesh needs at least 2 x 2", src_cols,
                            src_rows));
  if (req.spacing && !(*req.spacing > 0.0 && std::isfinite(*req.spacing)))
    throw Error(fmt::format("spacing must be a positive number of metres (got {})", *req.spacing));
  if (req.bbox && (req.center || req.size))
    throw Error("give either a bbox or a center and size, not both");
  if (req.center.has_value() != req.size.has_value())
    throw Error("a center needs a size and a size needs a center");
  if (req.size && !((*req.size)[0] > 0.0 && (*req.size)[1] > 0.0))
    throw Error("the crop size must be positive");
  if (req.bbox && !((*req.bbox)[2] > (*req.bbox)[0] && (*req.bbox)[3] > (*req.bbox)[1]))
    throw Error("the bbox must be xmin ymin xmax ymax with xmin < xmax and ymin < ymax");
}

// A DEM without a CRS is taken as metres (a warning), unless its numbers are degrees: read
// as metres they would make a mesh of millimetre cells that no tool can use, so an extent
// within the globe's and cells under 0.1 are refused.
void check_no_crs(const Georef& sg, std::size_t src_rows, std::size_t src_cols,
                  std::vector<std::string>& warnings) {
  const double west = sg.x0, east = sg.x0 + double(src_cols) * sg.dx;
  const double north = sg.y0, south = sg.y0 - double(src_rows) * sg.dy;
  if (west >= -180 && east <= 360 && south >= -90 && north <= 90 && sg.dx < 0.1 && sg.dy < 0.1)
    throw Error(fmt::format(
        "the DEM has no CRS and its coordinates look like degrees (x {:g}..{:g}, y {:g}..{:g}, "
        "cells of {:g} x {:g}): give its CRS with --src-crs EPSG:4326 (or gdal_translate "
        "-a_srs EPSG:4326)",
        west, east, south, north, sg.dx, sg.dy));
  warnings.push_back(
      "the DEM has no CRS: its coordinates are taken as metres (--src-crs gives one)");
}

// The target's spacing, lattice anchor (a target cell corner) and the box where its sample
// centres may lie (inside the footprint of the source's sample centres).
struct Lattice {
  double sx = 0, sy = 0, ax = 0, ay = 0;
  Box valid{};
};

// A geographic DEM onto UTM (the zone of its centre or req.utm_zone): out.target's CRS and
// out.to_source set.
Lattice geographic_lattice(const Georef& sg, std::size_t src_rows, std::size_t src_cols,
                           const GridRequest& req, GridPlan& out) {
  Georef& tg = out.target;
  Lattice l;
  const double lat_c = sg.y_of_row((double(src_rows) - 1) / 2);
  const double lon_c = sg.x_of_col((double(src_cols) - 1) / 2);
  const UtmZone zone =
      req.utm_zone ? parse_utm_zone(*req.utm_zone, lat_c) : standard_utm_zone(lat_c, lon_c);
  tg.crs_wkt = utm_crs_wkt(sg.crs_wkt, zone, tg.epsg);
  tg.crs_kind = CrsKind::Projected;
  try {
    // Default spacing: the N-S sample spacing in metres at the centre.
    double xa, ya, xb, yb;
    utm_forward(zone, lat_c - sg.dy / 2, lon_c, xa, ya);
    utm_forward(zone, lat_c + sg.dy / 2, lon_c, xb, yb);
    const double ns = std::round(std::hypot(xb - xa, yb - ya) * 100.0) / 100.0;
    l.sx = l.sy = req.spacing.value_or(ns);
    // Inner rectangle of the footprint of the source sample centres.
    Box& valid = l.valid;
    valid = {-1e300, -1e300, 1e300, 1e300};
    for (std::size_t r = 0; r < src_rows; ++r) {
      double x, y;
      utm_forward(zone, sg.y_of_row(double(r)), sg.x_of_col(0), x, y);
      valid.x0 = std::max(valid.x0, x);
      utm_forward(zone, sg.y_of_row(double(r)), sg.x_of_col(double(src_cols - 1)), x, y);
      valid.x1 = std::min(valid.x1, x);
    }
    for (std::size_t c = 0; c < src_cols; ++c) {
      double x, y;
      utm_forward(zone, sg.y_of_row(0), sg.x_of_col(double(c)), x, y);
      valid.y1 = std::min(valid.y1, y);
      utm_forward(zone, sg.y_of_row(double(src_rows - 1)), sg.x_of_col(double(c)), x, y);
      valid.y0 = std::max(valid.y0, y);
    }
  } catch (const GeographicLib::GeographicErr& e) {
    throw Error(fmt::format("cannot project the DEM into UTM zone {}{}: {}", zone.zone,
                            zone.north ? "N" : "S", e.what()));
  }
  out.to_source = [zone, sg](double x, double y, double& row, double& col) {
    double lat, lon;
    UTMUPS::Reverse(zone.zone, zone.north, x, y, lat, lon);
    row = sg.row_of_y(lat);
    col = sg.col_of_x(lon);
  };
  return l;
}

// A projected DEM stays in its CRS, on its own cell lattice.
Lattice projected_lattice(const Georef& sg, std::size_t src_rows, std::size_t src_cols,
                          const GridRequest& req, GridPlan& out) {
  out.target = sg;
  Lattice l;
  l.sx = req.spacing.value_or(sg.dx);
  l.sy = req.spacing.value_or(sg.dy);
  l.ax = sg.x0;
  l.ay = sg.y0;
  l.valid = {sg.x_of_col(0), sg.y_of_row(double(src_rows - 1)), sg.x_of_col(double(src_cols - 1)),
             sg.y_of_row(0)};
  out.to_source = [sg](double x, double y, double& row, double& col) {
    row = sg.row_of_y(y);
    col = sg.col_of_x(x);
  };
  out.separable = true;
  return l;
}

// The requested area (the whole DEM, --bbox or --center/--size), checked against the DEM's
// extent (valid centres + half a cell), as the box of sample centres to take.
Box requested_box(const Lattice& l, const GridRequest& req) {
  const Box& valid = l.valid;
  const double sx = l.sx, sy = l.sy;
  Box area = valid;
  if (req.bbox) area = {(*req.bbox)[0], (*req.bbox)[1], (*req.bbox)[2], (*req.bbox)[3]};
  if (req.center)
    area = {(*req.center)[0] - (*req.size)[0] / 2, (*req.center)[1] - (*req.size)[1] / 2,
            (*req.center)[0] + (*req.size)[0] / 2, (*req.center)[1] + (*req.size)[1] / 2};
  const Box extent{valid.x0 - sx / 2, valid.y0 - sy / 2, valid.x1 + sx / 2, valid.y1 + sy / 2};
  if (area.x1 <= extent.x0 || area.x0 >= extent.x1 || area.y1 <= extent.y0 || area.y0 >= extent.y1)
    throw Error("the requested area (" + fmt_box(area) + ") lies outside the DEM (" +
                fmt_box(extent) + ")");
  const double tol = 1e-6 * std::max(sx, sy);
  if (area.x0 < extent.x0 - tol || area.x1 > extent.x1 + tol || area.y0 < extent.y0 - tol ||
      area.y1 > extent.y1 + tol)
    throw Error("the requested area (" + fmt_box(area) + ") reaches beyond the DEM (" +
                fmt_box(extent) + ")");
  return {std::max(area.x0, valid.x0), std::max(area.y0, valid.y0), std::min(area.x1, valid.x1),
          std::min(area.y1, valid.y1)};
}

// The source samples the kernel reads: the source coordinates of the target's boundary
// samples bound those of all (the map is smooth and one-to-one), plus the cubic kernel's
// reach (2) and one sample of rounding; at least 2 x 2 (read_dem's minimum), inside the source.
// Of the plan's rows r0 .. r0 + nr - 1.
RasterWindow source_window(const GridPlan& out, std::size_t src_rows, std::size_t src_cols,
                           std::size_t r0, std::size_t nr) {
  const Georef& tg = out.target;
  const long first = long(r0), last = long(r0 + nr) - 1, cols = long(out.cols);
  double rmin = 1e300, rmax = -1e300, cmin = 1e300, cmax = -1e300;
  auto include = [&](long r, long c) {
    double sr, sc;
    out.to_source(tg.x_of_col(double(c)), tg.y_of_row(double(r)), sr, sc);
    rmin = std::min(rmin, sr), rmax = std::max(rmax, sr), cmin = std::min(cmin, sc),
    cmax = std::max(cmax, sc);
  };
  for (long c = 0; c < cols; ++c) include(first, c), include(last, c);
  for (long r = first; r <= last; ++r) include(r, 0), include(r, cols - 1);
  constexpr double margin = 3.0;
  auto clamp = [](double v, std::size_t n) {
    return std::size_t(std::clamp(v, 0.0, double(n - 1)));
  };
  const std::size_t wr0 = clamp(std::floor(rmin - margin), src_rows),
                    wr1 = clamp(std::ceil(rmax + margin), src_rows);
  const std::size_t wc0 = clamp(std::floor(cmin - margin), src_cols),
                    wc1 = clamp(std::ceil(cmax + margin), src_cols);
  const std::size_t wrows = std::max<std::size_t>(wr1 - wr0 + 1, 2),
                    wcols = std::max<std::size_t>(wc1 - wc0 + 1, 2);
  return {std::min(wr0, src_rows - wrows), std::min(wc0, src_cols - wcols), wrows, wcols};
}

}  // namespace

GridPlan plan_grid(const Georef& sg, std::size_t src_rows, std::size_t src_cols,
                   const GridRequest& req) {
  GridPlan out;
  check_request(src_rows, src_cols, req);
  const bool geographic = sg.crs_kind == CrsKind::Geographic;
  if (!geographic && req.utm_zone)
    throw Error("--utm-zone applies to geographic DEMs only; this DEM is in " + crs_name(sg));
  if (sg.crs_kind == CrsKind::None) check_no_crs(sg, src_rows, src_cols, out.warnings);
  const Lattice l = geographic ? geographic_lattice(sg, src_rows, src_cols, req, out)
                               : projected_lattice(sg, src_rows, src_cols, req, out);
  if (l.valid.x1 <= l.valid.x0 || l.valid.y1 <= l.valid.y0)
    throw Error("the DEM's footprint is empty after projection");
  const Box take = requested_box(l, req);
  long c0, c1, r0, r1;
  const bool has_cols = lattice_range(l.ax, l.sx, take.x0, take.x1, c0, c1);
  // Rows run southwards: row k covers y in [ay - (k+1)*sy, ay - k*sy].
  const bool has_rows = lattice_range(-l.ay, l.sy, -take.y1, -take.y0, r0, r1);
  const long cols = has_cols ? c1 - c0 + 1 : 0, rows = has_rows ? r1 - r0 + 1 : 0;
  if (cols < 2 || rows < 2)
    throw Error(fmt::format(
        "the requested area holds {} x {} samples at {} m spacing; a mesh needs at least 2 x 2",
        std::max(cols, 0L), std::max(rows, 0L), l.sx));
  if (double(cols) * double(rows) > double(std::numeric_limits<std::int32_t>::max()))
    throw Error(fmt::format(
        "the output would have {} x {} = {:.3g} samples, more than a mesh file can index "
        "(2^31 - 1); use a larger spacing or a smaller area",
        cols, rows, double(cols) * double(rows)));
  Georef& tg = out.target;
  tg.x0 = l.ax + double(c0) * l.sx;
  tg.y0 = l.ay - double(r0) * l.sy;
  tg.dx = l.sx;
  tg.dy = l.sy;
  out.rows = std::size_t(rows);
  out.cols = std::size_t(cols);
  out.source_window = source_window(out, src_rows, src_cols, 0, out.rows);
  return out;
}

RasterWindow band_window(const GridPlan& plan, std::size_t r0, std::size_t nr, std::size_t src_rows,
                         std::size_t src_cols) {
  if (nr == 0 || r0 + nr > plan.rows) throw Error("band_window: rows outside the plan");
  return source_window(plan, src_rows, src_cols, r0, nr);
}

namespace {

// A rows x cols grid whose samples are not zeroed first (BigVector): resample_rows_into
// writes every one, and the resampling threads touch its pages first.
Grid unfilled_grid(std::size_t rows, std::size_t cols, const Georef& geo) {
  Grid g;
  g.rows = rows, g.cols = cols, g.geo = geo;
  g.z.resize(rows * cols);
  return g;
}

// Rows r0 .. r0 + g.rows - 1 of the plan's grid into g, from the samples of window w.
void resample_rows_into(const Grid& samples, const RasterWindow& w, const GridPlan& plan,
                        const GridRequest& req, long r0, Grid& g, const Progress& progress) {
  const Georef& tg = plan.target;
  const long rows = long(g.rows), cols = long(plan.cols);
  const double dr = double(w.row0), dc = double(w.col0);
  // A separable map: each column's taps once (sample_grid's values exactly).
  std::vector<SampleTaps> column_taps;
  if (plan.separable) {
    column_taps.resize(std::size_t(cols));
    for (long c = 0; c < cols; ++c) {
      double sr, sc;
      plan.to_source(tg.x_of_col(double(c)), tg.y_of_row(0), sr, sc);
      column_taps[std::size_t(c)] = sample_taps(sc - dc, samples.cols, req.resampling);
    }
  }
  const long block = 64;
  for (long rb = 0; rb < rows; rb += block) {
    const long re = std::min(rows, rb + block);
#pragma omp parallel for schedule(static)
    for (long r = rb; r < re; ++r) {
      const double y = tg.y_of_row(double(r0 + r));
      if (!column_taps.empty()) {
        double sr, sc;
        plan.to_source(tg.x_of_col(0), y, sr, sc);
        const SampleTaps row_taps = sample_taps(sr - dr, samples.rows, req.resampling);
        for (long c = 0; c < cols; ++c)
          g.at(std::size_t(r), std::size_t(c)) =
              sample_taps(samples, row_taps, column_taps[std::size_t(c)]);
        continue;
      }
      for (long c = 0; c < cols; ++c) {
        double sr, sc;
        plan.to_source(tg.x_of_col(double(c)), y, sr, sc);
        g.at(std::size_t(r), std::size_t(c)) =
            sample_grid(samples, sr - dr, sc - dc, req.resampling);
      }
    }
    report(progress, double(re) / double(rows));
  }
}

}  // namespace

Grid resample_rows(const Grid& samples, const RasterWindow& w, const GridPlan& plan, std::size_t r0,
                   std::size_t nr, const GridRequest& req) {
  if (samples.rows != w.rows || samples.cols != w.cols)
    throw Error("resample_rows: the samples are not the window's");
  Georef geo = plan.target;
  geo.y0 = plan.target.y0 -
           double(r0) * plan.target.dy;  // for the caller's reference; values use the plan's rows
  Grid g = unfilled_grid(nr, plan.cols, geo);
  resample_rows_into(samples, w, plan, req, long(r0), g, {});
  if (const std::size_t missing = g.count_nodata(); missing > 0)
    throw NodataError(fmt::format(
        "{} no-data samples inside the chosen area (in rows {}-{} of {}); crop them away "
        "(--fill-nodata needs the whole grid: run without --tile-size)",
        missing, r0, r0 + nr - 1, plan.rows));
  return g;
}

std::vector<std::uint8_t> classify_nodata(const Grid& g, std::size_t max_void) {
  const long R = long(g.rows), C = long(g.cols);
  std::vector<std::uint8_t> mask(g.size(), 0);
  std::vector<std::uint32_t> component, stack;
  for (std::size_t s = 0; s < g.size(); ++s) {
    if (!std::isnan(g.z[s]) || mask[s] != 0) continue;
    component.clear();
    stack.assign(1, std::uint32_t(s));
    mask[s] = kOutside;  // visited
    bool edge = false;
    while (!stack.empty()) {
      const std::uint32_t i = stack.back();
      stack.pop_back();
      component.push_back(i);
      const long r = long(i) / C, c = long(i) % C;
      edge = edge || r == 0 || c == 0 || r == R - 1 || c == C - 1;
      for (long dr = -1; dr <= 1; ++dr)
        for (long dc = -1; dc <= 1; ++dc) {
          const long rr = r + dr, cc = c + dc;
          if (rr < 0 || cc < 0 || rr >= R || cc >= C) continue;
          const std::size_t j = std::size_t(rr * C + cc);
          if (std::isnan(g.z[j]) && mask[j] == 0)
            mask[j] = kOutside, stack.push_back(std::uint32_t(j));
        }
    }
    if (!edge && component.size() <= max_void)
      for (const std::uint32_t i : component) mask[i] = kVoidFilled;
  }
  return mask;
}

PreparedGrid resample_to_plan(const Grid& samples, const GridPlan& plan, const GridRequest& req,
                              const Progress& progress) {
  const RasterWindow& w = plan.source_window;
  if (samples.rows != w.rows || samples.cols != w.cols)
    throw Error("resample_to_plan: the samples are not the plan's source window");
  if (samples.count_nodata() == samples.size())
    throw Error("the DEM has no valid elevation: every sample is no-data");
  PreparedGrid out;
  out.warnings = plan.warnings;
  const Georef& tg = plan.target;
  Grid& g = out.grid;
  g = unfilled_grid(plan.rows, plan.cols, tg);
  resample_rows_into(samples, w, plan, req, 0, g, progress);

  const std::size_t missing = g.count_nodata();
  if (missing == g.size())
    throw NodataError("every sample of the chosen area is no-data: crop to the data (--bbox)");
  if (missing > 0) {
    out.filled_mask = req.fill_nodata ? g.nodata_mask() : classify_nodata(g, req.max_void);
    for (std::uint8_t m : out.filled_mask)
      out.voids += m == kVoidFilled, out.outside += m == kOutside;
    out.filled = fill_nodata(g);
  }
  return out;
}

PreparedGrid prepare_grid(const Grid& source, const GridRequest& request,
                          const Progress& progress) {
  GridPlan plan = plan_grid(source.geo, source.rows, source.cols, request);
  plan.source_window = {0, 0, source.rows, source.cols};
  return resample_to_plan(source, plan, request, progress);
}

}  // namespace terrain
