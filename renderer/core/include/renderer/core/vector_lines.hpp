#pragma once
// Line art as polylines, GL-free (the geometry the SVG / PDF writer strokes, vector_art.hpp):
// a drawn mask's pixels chained 8-connected into centre lines, segment lists chained where
// consecutive ends meet, and Douglas-Peucker simplification. Screen coordinates, x right
// and y down, a pixel's centre at (x + 0.5, y + 0.5).
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
std::vector<Polyline> chain_segments(const std::vector<std::array<Eigen::Vector2f, 2>>& segments,
                                     float eps = 1e-3f);

// Douglas-Peucker: the fewest points whose polyline stays within `tolerance` of every
// point of `line` (ends kept; a ring keeps its first point).
Polyline simplify(const Polyline& line, float tolerance);

// The indices of the points simplify keeps, in order (a ring's from its first point).
std::vector<std::size_t> simplified_points(const Polyline& line, float tolerance);

}  // namespace renderer
