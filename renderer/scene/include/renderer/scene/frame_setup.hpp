#pragma once
// One frame, resolved once for every tool: terrain-render frame and batch and terrain-view
// (at start, Home and save-view) turn the settings of the option table into the frame they
// draw here, and write it here, so that the same options draw the same picture whichever
// tool is asked (docs/architecture.md).
#include <functional>
#include <string>
#include <vector>

#include "renderer/core/frame_params.hpp"
#include "renderer/core/options.hpp"
#include "renderer/core/vector_file.hpp"
#include "renderer/gl/gl_context.hpp"
#include "renderer/gl/terrain_renderer.hpp"
#include "renderer/scene/scene.hpp"

namespace renderer {

// Whether the user gave option NAME (the table's name: "view-az"), on the command line or
// the panel: an option left at its default lets the automatic view choose.
using GivenOption = std::function<bool(const std::string& name)>;

// What a frame is drawn with. The camera's eye is set (the automatic view chooses it when
// none is given), the light is the automatic view's unless --light-az/--light-alt was given,
// and the style's line widths are scaled by --line-scale (drawn_style).
struct ResolvedFrame {
  FrameParams frame;
  Style style;
  Layers layers;
  int width = 0, height = 0;
  std::string description;  // how the camera was chosen, for -v
};

// What the settings leave to the mesh, filled in once the mesh is read, before any frame
// is resolved or drawn (terrain-render frame and batch, the viewer): the exaggeration, when
// --exaggeration is not given, is auto_exaggeration's (camera.hpp). Returns a line saying
// so ("exaggeration: 4.5 (automatic: relief ...)"), or the given value's.
std::string resolve_settings(RenderSettings& s, const terrain::GridMesh& mesh,
                             const GivenOption& given);

// Settings `s` as drawn, the frame as it stands (its camera not resolved): the frames of a
// frames CSV, a view the viewer is on.
ResolvedFrame drawn_frame(const RenderSettings& s);

// The frame of settings `s` over `mesh`: `--eye` as given (or framed along --view-az when
// only that is given); else --view FRAMES.csv:ROW, that row; else the default view of
// --view (auto, top, relief; default_view at --fov, the frame's aspect and --view-alt when
// given). Throws terrain::Error when the eye is below the terrain or too far from it
// (check_eye_above_terrain), or the row cannot be read.
ResolvedFrame resolve_frame(const RenderSettings& s, const terrain::GridMesh& mesh,
                            const GivenOption& given);

// Writes the frame `res` that `r` just drew of `scene` to each of `paths`: a PNG of its
// pixels, or (.svg, .pdf) its line art through cairo (frame_vector_art, vector_bytes; built
// once for every vector path). `description` is the provenance line the files record; a
// map (the orthographic top view, map_geotransform) adds its geotransform and EPSG code
// (map_note), and a PNG gets its world file beside it (NAME.pgw).
// Throws terrain::Error for another extension, or a vector file that would be empty (no
// line layer drawn and no underlay). Returns the time spent, for -v. With the hachures
// layer and `traced` given, the hachures it traced are left there (for frame_line_stats).
struct WriteTimes {
  double readback_ms = 0, paths_ms = 0, cairo_ms = 0;
  double hachure_ms = 0,
         hachure_draw_ms =
             0;  // the hachures' field and tracing (within paths_ms); drawing them on the PNG
  std::size_t vector_bytes = 0;
  std::string layers;  // ", creases 12 paths (40 strokes)..."
};
WriteTimes write_frame_files(const std::vector<std::string>& paths, const Scene& scene,
                             const TerrainRenderer& r, const FrameResult& res,
                             const ResolvedFrame& f, const VectorOptions& o,
                             const std::string& description, TracedHachures* traced = nullptr);

// Throws terrain::Error, before the renderer allocates the frame, when the vector output of a
// width x height frame would not fit in memory: about 28 bytes a pixel read back and
// built (a 9933 x 7016 PDF peaked 28 bytes a pixel above its PNG), and on a CPU renderer
// the frame's own 64 (TerrainRenderer's check) too.
void check_vector_memory(const GlContext& ctx, int width, int height);

// The output extensions a frame can be written as: .png, .svg or .pdf; throws otherwise.
void check_frame_path(const std::string& path);

// About the share of the frame that shows the terrain: of its cells of 16 x 16 pixels,
// those that a vertex of the mesh (up to 257 x 257 of them, heights exaggerated by `e`)
// facing the eye projects into, or whose centre's line of sight crosses the terrain's box
// `box` (TerrainRenderer::box: the exaggerated local frame; a view nearer than the
// vertices' spacing).
double terrain_share(const terrain::GridMesh& mesh, const View& view, const Box& box, double e);
// Empty when the frame shows the terrain (a share of kMinTerrainShare or more) from above
// its lowest point; else why not and what to change, one line.
inline constexpr double kMinTerrainShare = 1e-3;
std::string no_terrain_problem(const terrain::GridMesh& mesh, const View& view, const Box& box,
                               double e);

// The files a frame written to `path` makes: the file and, for a map (`map`: the
// orthographic top view) written as a PNG, its world file beside it (NAME.pgw) and its CRS
// (NAME.png.aux.xml, GDAL's PAM file: gdalinfo and QGIS read the PNG's CRS from it). They
// land together or not at all. Tools check all of them against their inputs.
std::vector<std::string> frame_files(const std::string& path, bool map);

}  // namespace renderer
