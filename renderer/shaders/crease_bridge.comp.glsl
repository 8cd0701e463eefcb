// DM, step 2: each segment's opacity (CPU reference: renderer::segment_opacity). From the
// scores of its two ends: 0 below the threshold, rising to 1 over the fade band u_style.y
// (1 at once when it is 0). A segment left out whose chain has a drawn segment within
// u_style.w metres upstream and downstream bridges the gap, at the lower of their opacities.
layout(local_size_x = TR_LOCAL_SIZE) in;
layout(std430, binding = TR_SSBO_CREASE_SCORES) readonly buffer Scores { float score[]; };
layout(std430, binding = TR_SSBO_CREASE_OPACITY) writeonly buffer Opacity { float opacity[]; };
float scored(uint s) {
  float lowest = min(score[seg[s].x], score[seg[s].y]);
  if (lowest < 0.0) return 0.0;
  return u_style.y > 0.0 ? min(1.0, lowest / u_style.y) : 1.0;
}
// The opacity of the first drawn segment within u_style.w metres along the chain (j = 0:
// upstream, 1: downstream), 0 when none.
float nearest_drawn(uint s, int j) {
  float gap = 0.0;
  uint t = j == 0 ? chain[s].x : chain[s].y;
  for (int k = 0; t != TR_SEGMENT_NONE && k < TR_STROKE_REACH && gap <= u_style.w; ++k) {
    float o = scored(t);
    if (o > 0.0) return o;
    gap += segment_metres(t);
    t = j == 0 ? chain[t].x : chain[t].y;
  }
  return 0.0;
}
void main() {
  uint s = gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x + gl_GlobalInvocationID.x;
  if (s >= uint(u_misc.y)) return;
  float o = scored(s);
  // A bridge needs a drawn segment upstream. Upstream of a point that drains less than the
  // page's channel area (StrokeRule::min_area) every point drains less still, so none
  // scores: most of a network's segments at a map's scale end here. The walk downstream
  // only where one upstream was found (the bridge is the lower of the two).
  if (o == 0.0 && u_style.w > 0.0 && !(cv[3u * seg[s].x + 2u].x < u_strokes.w)) {
    o = nearest_drawn(s, 0);
    if (o > 0.0) o = min(o, nearest_drawn(s, 1));
  }
  opacity[s] = o;
}
