// DM, step 2: keep the segments whose two ends score >= 0 and write them, compacted, with
// the indirect draw command (6 vertices per segment).
layout(local_size_x = TR_LOCAL_SIZE) in;
layout(std430, binding = TR_SSBO_CREASE_SCORES) readonly buffer Scores { float score[]; };
layout(std430, binding = TR_SSBO_CREASE_COMMAND) buffer DrawCommand { uint vertex_count; uint instance_count; uint first; uint base_instance; };
layout(std430, binding = TR_SSBO_CREASE_SELECTED) writeonly buffer Selected { uint selected[]; };
void main() {
  uint s = gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x + gl_GlobalInvocationID.x;
  if (s >= uint(u_misc.y)) return;
  uvec2 e = seg[s];
  if (score[e.x] >= 0.0 && score[e.y] >= 0.0) selected[atomicAdd(vertex_count, 6u) / 6u] = s;
}
