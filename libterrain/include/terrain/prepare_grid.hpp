#pragma once
// From a DEM as read to the regular metric grid the mesh is built on: reprojection of a
// geographic DEM onto UTM, cropping, resampling to a spacing, and the no-data policy.
#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "terrain/dem_io.hpp"
#include "terrain/error.hpp"
#include "terrain/grid.hpp"
#include "terrain/resample.hpp"
#include "terrain/utm.hpp"

namespace terrain {

struct GridRequest {
  std::optional<double> spacing;                // metres (square cells); default: the source's
  std::optional<std::array<double, 4>> bbox;    // xmin ymin xmax ymax in the target CRS
  std::optional<std::array<double, 2>> center;  // easting northing in the target CRS ...
  std::optional<std::array<double, 2>> size;    // ... and width height in metres
  std::optional<std::string> utm_zone;          // "17", "17N", "17S": geographic input only
  Resampling resampling = Resampling::Bilinear;
  // No-data in the area (docs/dem2mesh.md, "No-data"): with fill_nodata, every no-data
  // sample is filled and marked kInvented (drawn, not drained). Without, a void of at most
  // max_void samples that does not reach the grid's edge is filled and marked kVoidFilled
  // (drawn and drained); every other no-data sample is filled (for the normals beside it)
  // and marked kOutside: no face touches it.
  bool fill_nodata = false;
  std::size_t max_void = 256;
};

struct PreparedGrid {
  Grid grid;
  std::vector<std::string> warnings;      // for the tool to print (for example: no CRS)
  std::size_t filled = 0;                 // no-data samples filled by interpolation
  std::size_t voids = 0, outside = 0;     // of them: in small voids, outside the data
  std::vector<std::uint8_t> filled_mask;  // #samples, terrain::VertexSource; empty: no no-data
};

// Each no-data sample's source (terrain::VertexSource): kVoidFilled in 8-connected voids of at
// most `max_void` samples that do not touch the grid's edge, else kOutside; 0 for data.
std::vector<std::uint8_t> classify_nodata(const Grid& g, std::size_t max_void);

// Rules (documented in docs/dem2mesh.md, tested in tests/prepare_grid_test.cpp):
//  * Geographic source: target = UTM zone of the DEM centre (or `utm_zone`) on the
//    source datum. Every target sample centre is inverse-mapped with
//    GeographicLib::UTMUPS::Reverse and sampled in the source. The default area is the
//    largest axis-aligned UTM rectangle inside the footprint of the source sample centres,
//    so no target sample needs data from outside the DEM; target cells are aligned to
//    multiples of the spacing (like gdalwarp -tap). Default spacing: the source's N-S
//    sample spacing in metres at the centre, rounded to 0.01 m.
//  * Projected source (metres): stays in its CRS; target cells are aligned to the source
//    cell lattice shifted by whole target cells, so at the source spacing the samples are
//    the source samples themselves. No CRS: taken as metres, with a warning.
//  * Crop: the target samples are those whose centres lie inside the bbox (or the
//    centre/size box). A box reaching beyond the DEM's extent is an error.
//  * No-data in the result: outside the data or small voids (GridRequest::max_void), or
//    everything filled with fill_nodata (GDALFillNodata on the result).
// Throws Error for every impossible request (spacing <= 0, empty area, < 2 x 2 samples,
// more than 2^31 - 1 samples, all no-data).
PreparedGrid prepare_grid(const Grid& source, const GridRequest& request,
                          const Progress& progress = {});

// The same in two steps, for sources too large to read whole: plan_grid needs only the
// source's georeferencing and size (read_dem_info) and gives the target grid and the
// window of source samples the resampling kernel reads (the crop's footprint in the
// source plus 3 samples); resample_to_plan resamples those samples (read_dem with that
// window). The result is identical to prepare_grid on the whole source (tested).
struct GridPlan {
  // Maps a target sample centre (x, y) to fractional sample coordinates of the whole source.
  using ToSource = std::function<void(double x, double y, double& row, double& col)>;
  Georef target;
  std::size_t rows = 0, cols = 0;
  ToSource to_source;
  bool separable = false;  // to_source's row depends on y only and its column on x only
  RasterWindow source_window;
  std::vector<std::string> warnings;
};
GridPlan plan_grid(const Georef& source, std::size_t source_rows, std::size_t source_cols,
                   const GridRequest& request);
PreparedGrid resample_to_plan(const Grid& window_samples, const GridPlan& plan,
                              const GridRequest& request, const Progress& progress = {});

// Rows r0 .. r0 + nr - 1 of the plan's grid alone, for grids larger than memory (dem2mesh
// --tile-size): the source window they read (band_window: source_window's rule over those
// rows), and those rows resampled from it (resample_rows: resample_to_plan's values
// exactly; the grid's georeference is of its first row). No-data among them is a
// NodataError: filling (--fill-nodata) needs the whole grid.
RasterWindow band_window(const GridPlan& plan, std::size_t r0, std::size_t nr,
                         std::size_t source_rows, std::size_t source_cols);
Grid resample_rows(const Grid& window_samples, const RasterWindow& window, const GridPlan& plan,
                   std::size_t r0, std::size_t nr, const GridRequest& request);

}  // namespace terrain
