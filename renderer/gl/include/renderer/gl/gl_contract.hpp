#pragma once
// The C++ side of renderer/gl/gl_contract.h: the per-frame uniform block as a struct laid
// out as std140 (members from the one list in the contract) and the compute dispatch size.
#include <array>
#include <cstddef>

#include "renderer/gl/gl_contract.h"

namespace renderer {

namespace glsl {
using mat4 = std::array<float, 16>;  // column-major, as GLSL
using vec4 = std::array<float, 4>;
}  // namespace glsl

#define TR_CPP_MEMBER(type, name) glsl::type name;
struct FrameBlock {
  TR_FRAME_BLOCK(TR_CPP_MEMBER)
};
#undef TR_CPP_MEMBER
static_assert(sizeof(FrameBlock) == 60 * 4, "std140: one mat4 and eleven vec4, no padding");

// Work groups of TR_LOCAL_SIZE invocations covering n items, as x by y (x <= 65535):
// shaders index item gl_GlobalInvocationID.y * gl_NumWorkGroups.x * TR_LOCAL_SIZE + x.
inline unsigned dispatch_groups_x(std::size_t n) {
  const std::size_t g = (n + TR_LOCAL_SIZE - 1) / TR_LOCAL_SIZE;
  return unsigned(g < 65535 ? g : 65535);
}
inline unsigned dispatch_groups_y(std::size_t n) {
  const std::size_t g = (n + TR_LOCAL_SIZE - 1) / TR_LOCAL_SIZE,
                    gx = dispatch_groups_x(n) ? dispatch_groups_x(n) : 1;
  return unsigned((g + gx - 1) / gx);
}

}  // namespace renderer
