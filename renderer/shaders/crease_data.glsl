// Crease buffers shared by the DM compute and draw stages.
// cv[2i] = (position xyz in the local frame, basin-normalized flow), cv[2i+1] = (unit PN normal, 0).
layout(std430, binding = TR_SSBO_CREASE_VERTICES) readonly buffer CreaseVertices { vec4 cv[]; };
layout(std430, binding = TR_SSBO_CREASE_SEGMENTS) readonly buffer CreaseSegments { uvec2 seg[]; };
