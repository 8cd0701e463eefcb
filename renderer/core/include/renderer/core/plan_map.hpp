#pragma once
// Plan-view hachure maps (docs/terrain-render.md, "Hachures", "Plan-view maps"):
// the hachures of a mesh seen from straight above, north up, at a scale in metres a pixel,
// in the mesh's map coordinates: terrain-inspect export MESH --to gpkg|svg|pdf --layers
// hachures. From straight above nothing of a height field is hidden, so the field is the
// PN surface's own (plan_hachure_field), no frame is rendered, and the lines carry map
// coordinates exactly.
#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "renderer/core/hachures.hpp"
#include "renderer/core/ridges.hpp"
#include "renderer/core/vector_art.hpp"
#include "terrain/grid_mesh.hpp"

namespace renderer {

struct PlanHachureOptions {
  double scale = 0;  // metres a pixel; 0: default_plan_scale
  double spacing = 6,
         width = 0.8;  // pixels (at the map's scale), as --hachure-spacing and --hachure-width
  bool light_tone = false, rows = false;  // light_tone: density by the shadow, else by the slope
  double light_azimuth = 315,
         light_altitude = 45;  // the cartographer's light: north-west, 45 degrees high
  // Figure and ground (--hachure-min-slope): ground flatter than this share of the map's
  // steep slopes (the 99th percentile of its pixels' slopes) stays white, as the QGIS
  // Hachures script leaves ground under a share of its slope range; never under
  // HachureRule::min_slope. 0: that rule's absolute threshold alone.
  double min_slope_share = 0.3;
  // Ridge lines (given a .dv: plan_hachures' `ridges`), selected as a frame selects them
  // (select_ridges at the map's scale; terrain-render's --ridge-min-area, --ridge-min-relief
  // as a share of the mesh's relief) and drawn ridge_width pixels wide: a frame's defaults.
  double ridge_min_area = Style{}.ridge_min_area, ridge_min_relief = Style{}.ridge_min_relief,
         ridge_width = Style{}.ridge_width;
};

// A ridge line of a map, in its pixels (u right, v down), with what selected it.
struct PlanRidge {
  std::vector<Eigen::Vector2f> points;
  double basin_area = 0, relief = 0;  // m^2, m (SceneRidge's)
};

struct PlanHachures {
  PlanView plan;
  double min_slope = 0;     // radians: the white ground's (PlanHachureOptions::min_slope_share)
  double row_interval = 0;  // metres, 0 unless rows
  std::vector<Hachure> hachures;
  std::vector<PlanRidge> ridges;  // those the map draws; the hachures stop at them
  // The data's outline where the mesh has holes (docs/dem2mesh.md, "No-data"): the edges
  // between a face drawn and one outside the data, chained, in the map's pixels.
  std::vector<std::vector<Eigen::Vector2f>> outline;
};

// The scale a map takes when none is given: its longer side at most 2048 pixels, at 1,
// 2, 2.5 or 5 times a power of ten metres a pixel (MSH: 2.5 m, Logan: 100 m).
double default_plan_scale(const terrain::GridMesh& mesh);

// Throws terrain::Error, before anything is allocated, when the map would not fit in the
// memory available now (terrain::check_memory), naming the --scale that fits.
void check_plan_memory(const PlanView& plan);

// The map's hachures (plan_view's size; check_plan_memory first) and, given the ridge lines
// of the mesh's .dv (read_ridges), those the map's scale selects, the hachures stopped at
// them as a frame's are (the crest stands clear of its slopes).
PlanHachures plan_hachures(const terrain::GridMesh& mesh, const PlanHachureOptions& o,
                           const std::vector<SceneRidge>& ridges = {});

// The map's geotransform, GDAL's order: x0, scale, 0, y0, 0, -scale (world coordinates).
std::array<double, 6> plan_geotransform(const terrain::GridMesh& mesh, const PlanView& plan);

// A geotransform as the tools print it: "x0 s 0 y0 0 -s" (millimetres for the corner).
std::string geotransform_text(const std::array<double, 6>& gt);

// What a map's files say of it (SVG <desc>, PDF subject, PNG text, and printed): "north up,
// S m a pixel; geotransform x0 s 0 y0 0 -s; EPSG:N" (no EPSG part when `epsg` is 0).
std::string map_note(const std::array<double, 6>& gt, int epsg);
// The ESRI world file of a raster with that geotransform (.pgw beside a PNG; GDAL and QGIS
// read it): the pixel sizes and rotations, then the centre of the top-left pixel.
std::string world_file(const std::array<double, 6>& gt);

// Writes the GeoPackage `path` with a line layer "hachures" in the mesh's CRS: one feature
// a hachure, in world coordinates, with its mean slope (degrees), mean tone (0..1),
// length (metres) and row_m (rows only: the form line above it, metres); and, where the
// map has ridge lines, a line layer "ridges" (basin_m2: the smaller basin it parts, relief_m:
// its rise above that basin's outlet, length_m). Returns the hachures' count.
std::size_t write_hachures_gpkg(const terrain::GridMesh& mesh, const PlanHachures& h,
                                const std::string& path);

// The map as line art on a white page of plan.width x plan.height pixels: a layer
// "hachures" and, where the map has ridge lines, a layer "ridges" over it, and where the
// mesh has holes a layer "outline".
VectorArt plan_vector_art(const PlanHachures& h, const PlanHachureOptions& o);

}  // namespace renderer
