// Shared by every stage: the per-frame uniform block (std140; its members are listed once,
// in renderer/gl/include/renderer/gl/gl_contract.h, for GLSL and C++) and small helpers. Positions are in the mesh's local frame with
// z multiplied by the vertical exaggeration (u_eye.w).
#define TR_GLSL_MEMBER(type, name) type name;
layout(std140, binding = TR_UBO_FRAME) uniform FrameBlock { TR_FRAME_BLOCK(TR_GLSL_MEMBER) };

// Exaggerated position and normal (normals transform by the inverse transpose).
vec3 exaggerate_position(vec3 p) { return vec3(p.xy, p.z * u_eye.w); }
vec3 exaggerate_normal(vec3 n) { return normalize(vec3(n.xy, n.z / u_eye.w)); }

// The frame block's flags by name: a fixed tessellation level (> 0: tests, capture), and
// whether depth is reversed (1 at the near plane, 0 at infinity: glClipControl).
float tess_override() { return u_lines.z; }
bool reversed_z() { return u_lines.w > 0.5; }

// The viewer (renderer::Viewpoint on the CPU): orthographic in the top view, every ray
// along u_sight.xyz; the way from p towards the viewer (not normalised in perspective) and
// p's distance from the eye (orthographic: from the eye plane, along the line of sight).
bool orthographic() { return u_sight.w > 0.0; }
vec3 to_eye(vec3 p) { return orthographic() ? -u_sight.xyz : u_eye.xyz - p; }
float view_distance(vec3 p) { return orthographic() ? dot(p - u_eye.xyz, u_sight.xyz) : distance(p, u_eye.xyz); }

// Window depth to "distance order": larger is farther, 1 where nothing was drawn (the one
// far test; renderer::far_depth on the CPU).
float far_of(float depth) { return reversed_z() ? 1.0 - depth : depth; }
vec4 far_of(vec4 depth) { return reversed_z() ? 1.0 - depth : depth; }

// The clip position a line point p on the surface (exaggerated) is drawn at: the point
// `lift` metres (u_score.w; at most half way) from p towards the eye. It lies on p's line
// of sight, so the line is drawn where p is on screen (on its valley, not up the slope
// behind it), only nearer in depth, so the tessellated surface, whose chords lie above the
// PN surface in valleys, does not hide it (docs/terrain-render.md, "Lines stay on the
// surface"). Towards the eye, not along the normal: seen at a grazing angle g a lift along
// the normal brings the depth nearer by lift x sin(g) only, and a chord a fraction of a
// metre high hid the line. Behind the near plane: w <= u_misc.x, and segment_quad_vertex
// drops the segment (never in the orthographic view: w = 1, near 0).
vec4 line_clip(vec3 p, float lift) {
  vec3 t = to_eye(p);
  float d = orthographic() ? view_distance(p) : length(t);
  return u_view_proj * vec4(p + (d > 0.0 ? min(lift, 0.5 * d) / length(t) : 0.0) * t, 1.0);
}

// Vertex k (0..5) of the screen-space quad of the segment with clip positions c0, c1 and
// widths w0, w1 (pixels) at its ends: two triangles, the ends extended by half a width.
// A segment reaching the near plane is dropped (the vertex is put outside the view).
vec4 segment_quad_vertex(vec4 c0, vec4 c1, float w0, float w1, uint k) {
  const uint end_of[6] = uint[6](0u, 1u, 1u, 0u, 1u, 0u);
  const float side_of[6] = float[6](-1.0, -1.0, 1.0, -1.0, 1.0, 1.0);
  if (c0.w <= u_misc.x || c1.w <= u_misc.x) return vec4(2.0, 2.0, 2.0, 1.0);
  vec2 half_vp = 0.5 * u_viewport.xy;
  vec2 d = c1.xy / c1.w * half_vp - c0.xy / c0.w * half_vp;
  vec2 dir = dot(d, d) > 0.0 ? normalize(d) : vec2(1.0, 0.0);
  vec2 perp = vec2(-dir.y, dir.x);
  uint j = end_of[k];
  float w = 0.5 * (j == 0u ? w0 : w1);
  vec4 c = j == 0u ? c0 : c1;
  c.xy += (perp * side_of[k] * w + dir * (j == 0u ? -w : w)) / half_vp * c.w;
  return c;
}

// Anti-aliased lines (u_style.x != 0): the window-pixel position of clip position c.
vec2 window_of(vec4 c) { return (c.xy / c.w * 0.5 + 0.5) * u_viewport.xy; }

// The share of a pixel (a unit square about its centre) whose offset o from the centre has
// n.o < t, n a unit vector: n.o is the sum of two uniform variables of widths |nx| and
// |ny|, whose distribution function is quadratic in its tails and linear between.
float pixel_share_below(float t, vec2 n) {
  float a = max(abs(n.x), abs(n.y)), b = min(abs(n.x), abs(n.y));
  float h = 0.5 * (a + b), m = 0.5 * (a - b), u = abs(t);
  float tail = u >= h ? 0.0 : (u > m ? (h - u) * (h - u) / (2.0 * a * b) : 0.5 - u / a);
  return t < 0.0 ? tail : 1.0 - tail;
}

// Where x projects onto segment a-b: 0 at a, 1 at b (unclamped); -1 when a == b.
float segment_param(vec2 x, vec2 a, vec2 b) {
  vec2 d = b - a;
  float len2 = dot(d, d);
  return len2 > 0.0 ? dot(x - a, d) / len2 : -1.0;
}

// Coverage of the pixel centred at x by the capsule from a to b (window pixels) whose
// radius goes linearly from r0 to r1. Beside the segment: the exact area of the pixel
// inside the band of half-width r (a box filter, any direction and any width). Beyond
// its ends: round caps, a one-pixel ramp across the circle's border (scaled by 2r below a
// pixel's width). Overlapping capsules of a polyline, blended with MAX, join round.
float capsule_coverage(vec2 x, vec2 a, vec2 b, float r0, float r1) {
  vec2 d = b - a;
  float len2 = dot(d, d);
  float t = segment_param(x, a, b);
  if (t >= 0.0 && t <= 1.0) {
    vec2 dir = d * inversesqrt(len2), n = vec2(-dir.y, dir.x);
    float r = mix(r0, r1, t), s = dot(x - a, n);
    return pixel_share_below(r - s, n) - pixel_share_below(-r - s, n);
  }
  float tc = clamp(t, 0.0, 1.0), r = mix(r0, r1, tc);
  return clamp(max(r, 0.5) + 0.5 - distance(x, a + tc * d), 0.0, 1.0) * min(1.0, 2.0 * r);
}
