#pragma once
// SVG and PDF of a frame's line art (vector_art.hpp), drawn by one routine through cairo's
// SVG and PDF surfaces (docs/terrain-render.md, "Vector output"). The page is the frame,
// width x height pixels at `dpi` pixels per inch (96: CSS pixels).
//   SVG: each layer is a group Inkscape and Illustrator show as a layer
//        (<g id="creases" inkscape:groupmode="layer" inkscape:label="creases">): surface,
//        then the line layers bottom up; cairo draws each into its own document and
//        libxml2 joins them, their ids prefixed by the layer's name; path coordinates
//        written with 2 decimals.
//   PDF: one page, the layers drawn in the same order; flattened (cairo 1.16 writes no
//        optional-content groups).
// The surface mask is traced into filled regions by potrace (one path per connected
// region, its holes cut out by the even-odd rule); the shaded surface is embedded as a PNG.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "renderer/core/vector_art.hpp"

namespace renderer {

// How a vector file is written: page resolution and what lies under the lines ("" for the
// default: the shaded relief when the layers draw it, else the mask).
struct VectorOptions {
  double dpi = 96;
  std::string underlay;
};

// The files a frame is written to (terrain-render frame and batch, terrain-view's
// save-view), one row each: the extension, whether it holds the line art (cairo's SVG or
// PDF) or the frame's pixels, and whether a map (the top view) gets a world file beside it
// (NAME.pgw). The extension checks, batch's --format, the writers and the lists of files a
// run writes all read this table.
struct FrameFormat {
  const char* name;  // the extension without its dot, lower case
  bool vector;
  bool world_file;
};
// A GeoTIFF (tif) holds its own georeference (a map's) and its alpha band; a GeoPackage
// (gpkg) a map's lines in map coordinates (write_map_gpkg).
inline constexpr FrameFormat kFrameFormats[] = {{"png", false, true},
                                                {"tif", false, false},
                                                {"svg", true, false},
                                                {"pdf", true, false},
                                                {"gpkg", true, false}};
// The row of `path`'s extension (any case), or nullptr.
const FrameFormat* frame_format(const std::string& path);
// The row named `name` ("png"), or nullptr.
const FrameFormat* frame_format_named(const std::string& name);
// "png, svg, pdf": for messages.
std::string frame_format_names();

// Writes a map's vector art (the top view's: `gt` its geotransform, pixel corners to map
// coordinates) as a GeoPackage (atomic; one already there is updated, terrain::Gpkg): a
// line layer per art layer (hachures, creases, silhouettes, ridges, outline, ...) of its
// paths in map coordinates, fields width_mm (the line's width on the page at `dpi`, the
// mean of a varying one) and opacity, each styled in its colour with its width. Returns
// the lines written.
std::size_t write_map_gpkg(const VectorArt& art, const std::array<double, 6>& gt,
                           const std::string& crs_wkt, double dpi, const std::string& path);

enum class VectorFormat { Svg, Pdf };
// By the path's extension, .svg or .pdf (any case); Error otherwise.
VectorFormat vector_format_of(const std::string& path);
// Whether the path ends in .svg or .pdf (any case).
bool is_vector_path(const std::string& path);

// A closed outline of cubic Bezier pieces (a straight piece has its control points on it).
struct Outline {
  Eigen::Vector2f start{0, 0};
  std::vector<std::array<Eigen::Vector2f, 3>> curves;  // control, control, end
};
// A connected region of a mask: its outer outline, then its holes.
using Region = std::vector<Outline>;
// The regions of `mask` (w x h, non-zero: in, row 0 at the top) traced by potrace, in
// pixel coordinates (y down); specks of under 3 pixels are dropped.
std::vector<Region> trace_regions(const std::vector<std::uint8_t>& mask, int w, int h);

// Draws `layer` over `rgba` (width x height, row 0 at the top, straight RGBA: a frame,
// opaque but with --background none) with cairo, anti-aliased, as the SVG and PDF draw it.
// In `bands` of rows side by side (0: one a thread), each with the paths that reach it: the
// same pixels as in one.
void draw_on_rgba(const VectorLayer& layer, int width, int height, std::vector<std::uint8_t>& rgba,
                  int bands = 0);

// The file's bytes; `description`: the provenance line (SVG <desc>, PDF Subject).
std::string vector_bytes(const VectorArt& art, VectorFormat format, double dpi,
                         const std::string& description);

}  // namespace renderer
