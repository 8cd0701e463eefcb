// Crease buffers shared by the DM compute and draw stages.
// cv[3i] = (position xyz in the local frame, basin-normalized flow fc), cv[3i+1] = (unit PN
// normal, the basin share a / T that line widths follow), cv[3i+2].x = the area draining
// through the vertex (m^2; the page's channel initiation, u_strokes.w).
layout(std430, binding = TR_SSBO_CREASE_VERTICES) readonly buffer CreaseVertices { vec4 cv[]; };
layout(std430, binding = TR_SSBO_CREASE_SEGMENTS) readonly buffer CreaseSegments { uvec2 seg[]; };
// chain[s] = (prev, next): the segment a stroke continues from, the one it flows into
// (renderer::segment_chains; TR_SEGMENT_NONE where none).
layout(std430, binding = TR_SSBO_CREASE_CHAINS) readonly buffer CreaseChains { uvec2 chain[]; };

// Length of segment s in metres (local frame, before exaggeration).
float segment_metres(uint s) { return distance(cv[3u * seg[s].x].xyz, cv[3u * seg[s].y].xyz); }
