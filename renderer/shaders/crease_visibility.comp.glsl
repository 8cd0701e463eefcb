// DM, steps 4 to 6 (anti-aliased lines; CPU reference: renderer::stroke_visibility, whose
// header states the rule): per selected segment, u_crease_stage
//   0  samples it against the toward depth: visible, or hidden but bridgeable;
//   1  closes hidden runs up to u_strokes.x pixels of bridgeable samples between visible ones;
//   2  leaves out closed runs up to u_strokes.z pixels beside a hidden sample (peeks).
// Each stage reads what the one before wrote for the neighbouring segments of the stroke.
layout(local_size_x = TR_LOCAL_SIZE) in;
layout(location = TR_LOC_CREASE_STAGE) uniform int u_crease_stage;
layout(std430, binding = TR_SSBO_CREASE_COMMAND) readonly buffer DrawCommand { uint vertex_count; uint instance_count; uint first; uint base_instance; };
layout(std430, binding = TR_SSBO_CREASE_SELECTED) readonly buffer Selected { uint selected[]; };
layout(binding = TR_TEX_TOWARD_DEPTH) uniform sampler2D u_toward;

// How a walk along a stroke ends (renderer::stroke_visibility's walk): at a sample it looks
// for, at one that blocks it, at the stroke's end, or past its length limit.
const int FOUND = 0, BLOCKED = 1, END = 2, LONG = 3;
// From sample k of segment s one way along the stroke (up: towards chain[].x), over the
// samples passed (stage 1: bridgeable, found at a visible one; stage 2: closed), until the
// stroke's end (a segment without samples, or TR_STROKE_REACH segments on) or more than
// `limit` pixels; in stage 2, past a junction downstream where the stroke does not continue
// (the next segment's prev is another), more than `limit` pixels is the stroke's end.
// Returns (how it ended, screen length passed over).
vec2 stroke_walk(uint s, int k, bool up, float limit) {
  float len = 0.0;
  int hops = 0;
  bool joined = false;
  for (int guard = 0; guard < (TR_STROKE_REACH + 1) * TR_STROKE_SAMPLES; ++guard) {
    k += up ? -1 : 1;
    if (k < 0 || k >= int(samples[s].n)) {
      uint t = up ? chain[s].x : chain[s].y;
      if (t == TR_SEGMENT_NONE || samples[t].n == 0u || ++hops > TR_STROKE_REACH) return vec2(END, len);
      joined = joined || (u_crease_stage == 2 && !up && chain[t].x != s);
      s = t;
      k = up ? int(samples[s].n) - 1 : 0;
    }
    uint b = 1u << uint(k);
    if (u_crease_stage == 1) {
      if ((samples[s].visible & b) != 0u) return vec2(FOUND, len);
      if ((samples[s].bridgeable & b) == 0u) return vec2(BLOCKED, len);
    } else if ((samples[s].closed & b) == 0u) {
      return vec2(BLOCKED, len);
    }
    len += samples[s].step;
    if (len > limit) return vec2(joined ? END : LONG, len);
  }
  return vec2(END, len);
}

// Window depth of clip position c, and the distance along the view axis of a window depth
// (perspective, infinite far plane: reversed, depth = near / distance; else 1 - near /
// distance; orthographic: linear from the eye plane to the far plane; View::depth_distance).
float window_depth(vec4 c) { return reversed_z() ? c.z / c.w : 0.5 * c.z / c.w + 0.5; }
float eye_distance(float depth) {
  if (orthographic()) return u_sight.w * far_of(depth);
  return u_misc.x / max(reversed_z() ? depth : 1.0 - depth, 1e-30);
}

void sample_segment(uint s) {
  SegmentSamples m = SegmentSamples(0u, 0u, 0u, 0u, 0u, 0.0);
  vec4 c0 = line_clip(exaggerate_position(cv[3u * seg[s].x].xyz), u_score.w);
  vec4 c1 = line_clip(exaggerate_position(cv[3u * seg[s].y].xyz), u_score.w);
  if (c0.w > u_misc.x && c1.w > u_misc.x) {  // as segment_quad_vertex draws it
    vec2 a = window_of(c0), b = window_of(c1);
    float d0 = window_depth(c0), d1 = window_depth(c1), len = distance(a, b);
    m.n = uint(clamp(ceil(len), 1.0, float(TR_STROKE_SAMPLES)));
    m.step = len / float(m.n);
    for (uint k = 0u; k < m.n; ++k) {
      float t = (float(k) + 0.5) / float(m.n);
      vec2 q = mix(a, b, t);
      if (any(lessThan(q, vec2(0.0))) || any(greaterThanEqual(q, u_viewport.xy))) continue;  // off the image
      float line = mix(d0, d1, t);  // window depth is affine along the segment on screen
      ivec2 p = ivec2(floor(q));
      // The 3 x 3 window about p, rows dy = -1, 0, 1, in that order (ties keep the first), from
      // four gathers (each the 2 x 2 at columns and rows c - 1 and c: x (c-1, c), y (c, c),
      // z (c, c-1), w (c-1, c-1)); beyond the image's edge they clamp as texelFetch's
      // coordinates were clamped.
      vec2 fs = u_viewport.xy;
      vec4 ga = textureGather(u_toward, vec2(p) / fs), gb = textureGather(u_toward, vec2(p + ivec2(1, 0)) / fs);
      vec4 gc = textureGather(u_toward, vec2(p + ivec2(0, 1)) / fs);
      float gd = textureGather(u_toward, vec2(p + ivec2(1, 1)) / fs).y;
      float window[9] = float[9](ga.w, ga.z, gb.z, ga.x, ga.y, gb.y, gc.x, gc.y, gd);
      float farthest = -1.0, farthest_depth = 0.0;
      for (int j = 0; j < 9; ++j) {
        float d = window[j];
        if (far_of(d) < 1.0 && far_of(d) > farthest) farthest = far_of(d), farthest_depth = d;
      }
      if (farthest < 0.0) continue;  // no surface about the sample
      if (far_of(line) <= farthest) m.visible |= 1u << k;
      else if (eye_distance(line) - eye_distance(farthest_depth) <= u_strokes.y) m.bridgeable |= 1u << k;
    }
  }
  samples[s] = m;
}

void close_runs(uint s) {
  uint closed = samples[s].visible, n = samples[s].n;
  float limit = u_strokes.x - samples[s].step;
  if (u_strokes.x > 0.0 && limit >= 0.0)
    for (uint k = 0u; k < n; ++k) {
      if ((samples[s].bridgeable & (1u << k)) == 0u) continue;
      vec2 up = stroke_walk(s, int(k), true, limit);
      if (up.x == FOUND && stroke_walk(s, int(k), false, limit - up.y).x == FOUND) closed |= 1u << k;
    }
  samples[s].closed = closed;
}

void leave_out_peeks(uint s) {
  uint shown = samples[s].closed, n = samples[s].n;
  float limit = u_strokes.z - samples[s].step;
  if (u_strokes.z > 0.0 && limit >= 0.0)
    for (uint k = 0u; k < n; ++k) {
      if ((shown & (1u << k)) == 0u) continue;
      vec2 up = stroke_walk(s, int(k), true, limit);
      if (up.x == LONG) continue;
      vec2 down = stroke_walk(s, int(k), false, limit - up.y);
      if (down.x == LONG) continue;
      if (up.x == BLOCKED || down.x == BLOCKED) shown &= ~(1u << k);
    }
  samples[s].shown = shown;
}

void main() {
  uint q = gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x + gl_GlobalInvocationID.x;
  if (q >= vertex_count / 6u) return;
  uint s = selected[q];
  if (u_crease_stage == 0) sample_segment(s);
  else if (u_crease_stage == 1) close_runs(s);
  else leave_out_peeks(s);
}
