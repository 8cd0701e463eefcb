// Crease buffers shared by the DM compute and draw stages.
// cv[2i] = (position xyz in the local frame, basin-normalized flow), cv[2i+1] = (unit PN normal, 0).
layout(std430, binding = 1) readonly buffer CreaseVertices { vec4 cv[]; };
layout(std430, binding = 2) readonly buffer CreaseSegments { uvec2 seg[]; };
