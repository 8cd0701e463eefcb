#pragma once
// Line art as polylines, GL-free (issue 37's first part: the geometry the SVG / PDF writer
// will stroke): a drawn mask's pixels chained 8-connected into centre lines, segment
// lists chained where consecutive ends meet, Douglas-Peucker simplification, and a
// polyline of varying width split into runs of equal (quantised) width. Screen
// coordinates, x right and y down, a pixel's centre at (x + 0.5, y + 0.5).
#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace renderer {

struct Polyline {
  std::vector<Eigen::Vector2f> points;
  bool closed = false;  // a ring: the last point joins the first (not repeated)
};

// The centre lines of a mask (w x h, row 0 at the top, non-zero = ink): the mask is thinned
// to one pixel (Zhang-Suen) and its pixels chained 8-connected (a diagonal step only where
// neither pixel beside it is ink, so a staircase is one line, not triangles). Lines run
// between ends and junctions; a loop without either is one closed polyline.
std::vector<Polyline> chain_mask(const std::vector<std::uint8_t>& mask, int w, int h);

// Segment lists (each two points) chained into polylines where consecutive ends coincide
// within `eps` and exactly two segments meet; ends and junctions of three or more end
// polylines, and a chain that returns to its start is closed.
std::vector<Polyline> chain_segments(const std::vector<std::array<Eigen::Vector2f, 2>>& segments, float eps = 1e-3f);

// Douglas-Peucker: the fewest points whose polyline stays within `tolerance` of every
// point of `line` (ends kept; a ring keeps its first point).
Polyline simplify(const Polyline& line, float tolerance);

// Runs of equal width: `widths` (one per point of an open polyline) quantised to
// `quantum`; the polyline is split where a segment's quantised width (of the mean of its
// ends) changes, consecutive runs sharing their boundary point.
struct WidthRun {
  Polyline line;
  float width = 0;
};
std::vector<WidthRun> width_runs(const Polyline& line, const std::vector<float>& widths, float quantum = 0.25f);

}  // namespace renderer
