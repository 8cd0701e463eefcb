#pragma once
// Frame lists for batch mode (CSV) and straight flight paths (GL-free).
//
// FRAMES.csv: a header row naming the columns, then one row per frame; blank lines and
// lines starting with '#' are skipped. Columns (any order, any subset):
//   easting northing elevation   eye in world coordinates (all three or none; none: the
//                                framing camera of terrain-render frame)
//   view_az view_alt fov light_az light_alt
//   sw iw fw min_score falloff   crease score (frame_params.hpp)
//   pel_threshold                PEL threshold tau
// A missing column takes the value of `defaults` (the command line's options).
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "renderer/core/frame_params.hpp"

namespace renderer {

// The column names accepted in FRAMES.csv, in the order write_path_csv writes them.
const std::vector<std::string>& frame_columns();
// Each column but the eye's is a per-frame option of the option table (options.hpp),
// checked as its command-line option is: a frame list accepts exactly what the command
// line does.

// Parses CSV text. `name` is used in errors, which name the line (and column):
// "frames.csv:4: expected 8 fields, found 7", "frames.csv:1: unknown column 'foo'",
// "frames.csv:3: field 'fov': 'abc' is not a number". No rows is an error too.
std::vector<FrameParams> parse_frames_csv(const std::string& text, const FrameParams& defaults,
                                          const std::string& name);
// Reads and parses a file (Error when it cannot be read).
std::vector<FrameParams> read_frames_csv(const std::string& path, const FrameParams& defaults);

// --view FRAMES.csv[:N]: is `text` such a row's name (a path ending in .csv, then
// optionally ':' and a row number)?
bool is_view_row(const std::string& text);
// The frame of row N (0: the first, as batch names it frame_00000; no ":N": 0) of the
// frames CSV `spec` names, its columns over `defaults`. Error when there is no such row.
FrameParams view_row_frame(const std::string& spec, const FrameParams& defaults);

struct FlightPath {
  Eigen::Vector3d from, to;  // world coordinates
  int frames = 2;            // >= 2: first at `from`, last at `to`
  FrameParams params;  // view, light, score for every frame; view_az: NaN = bearing from -> to
};

// The CSV text of a straight flight path at equal steps (full set of columns).
std::string path_csv(const FlightPath& path);

// The CSV text of frames (full set of columns; every frame needs its eye).
std::string frames_csv(const std::vector<FrameParams>& frames);

// `count` frames along a smooth path through the keyframes (at least 2, each with its
// eye): centripetal-free uniform Catmull-Rom on the eye and on the view's bearing and
// altitude (the bearing unwrapped, so that 350 -> 10 turns 20 degrees), the ends held; the
// other values of each frame from the keyframe before it.
// `count` is 2 .. kMaxPathFrames (a million frames would be hours of rendering at any speed).
inline constexpr int kMaxPathFrames = 100000;
std::vector<FrameParams> keyframe_path(const std::vector<FrameParams>& keys, int count);

}  // namespace renderer
