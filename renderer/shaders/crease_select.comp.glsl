// DM, step 3: keep the segments with an opacity (crease_bridge) whose drawn run is at
// least u_misc.w metres long (CPU reference: renderer::apply_stroke_rule): the run is
// followed upstream along the chain, and downstream while the next segment continues
// from this one, at most TR_STROKE_REACH segments each way, and no farther than the run
// needs to reach u_misc.w (a sum of lengths only grows). Writes them, compacted, with
// the indirect draw command (6 vertices per segment).
layout(local_size_x = TR_LOCAL_SIZE) in;
layout(std430, binding = TR_SSBO_CREASE_OPACITY) readonly buffer Opacity { float opacity[]; };
layout(std430, binding = TR_SSBO_CREASE_COMMAND) buffer DrawCommand { uint vertex_count; uint instance_count; uint first; uint base_instance; };
layout(std430, binding = TR_SSBO_CREASE_SELECTED) writeonly buffer Selected { uint selected[]; };
void main() {
  uint s = gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x + gl_GlobalInvocationID.x;
  if (s >= uint(u_misc.y) || !(opacity[s] > 0.0)) return;
  if (u_misc.w > 0.0) {
    float run = segment_metres(s);
    uint t = chain[s].x;
    for (int k = 0; t != TR_SEGMENT_NONE && k < TR_STROKE_REACH && opacity[t] > 0.0 && run < u_misc.w; ++k, t = chain[t].x)
      run += segment_metres(t);
    uint c = s;
    t = chain[s].y;
    for (int k = 0; t != TR_SEGMENT_NONE && k < TR_STROKE_REACH && opacity[t] > 0.0 && chain[t].x == c && run < u_misc.w;
         ++k) {
      run += segment_metres(t);
      c = t;
      t = chain[t].y;
    }
    if (run < u_misc.w) return;
  }
  selected[atomicAdd(vertex_count, 6u) / 6u] = s;
}
