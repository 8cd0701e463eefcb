#pragma once
// What the crease sources share (crease_geometry.cpp, crease.cpp). Not installed.
#include <cstdint>
#include <vector>

#include "renderer/core/crease.hpp"

namespace renderer::detail {

// Per vertex, the segment leaving it and the one entering it from the largest flow (ties:
// the lower index), kNoSegment where none; only segments with drawn[s] > 0 when `drawn`
// is given. The rule strokes follow (segment_chains) and lines are smoothed along.
struct VertexSegments {
  std::vector<std::uint32_t> leaving, entering;
};
VertexSegments vertex_segments(const CreaseGeometry& g, const std::vector<float>& drawn = {});

}  // namespace renderer::detail
