// Shared by every stage: the per-frame uniform block (std140; mirrored by FrameBlock in
// terrain_renderer.cpp) and small helpers. Positions are in the mesh's local frame with
// z multiplied by the vertical exaggeration (u_eye.w).
layout(std140, binding = 0) uniform FrameBlock {
  mat4 u_view_proj;
  vec4 u_eye;       // xyz: eye; w: vertical exaggeration
  vec4 u_light;     // xyz: unit vector towards the light
  vec4 u_viewport;  // width, height, pixels per triangle edge, maximum tessellation level
  vec4 u_weights;   // sw, iw, fw, divisor (sw + iw + fw, or 3)
  vec4 u_score;     // min score, falloff, far distance, crease lift (metres)
  vec4 u_lines;     // crease width at flow 0 and 1 (pixels), tessellation override, reversed z
  vec4 u_misc;      // near plane distance, segment count, vertex count, 0
};

// Exaggerated position and normal (normals transform by the inverse transpose).
vec3 exaggerate_position(vec3 p) { return vec3(p.xy, p.z * u_eye.w); }
vec3 exaggerate_normal(vec3 n) { return normalize(vec3(n.xy, n.z / u_eye.w)); }

// Window depth to "distance order": larger is farther, 1 where nothing was drawn.
float far_of(float depth) { return u_lines.w > 0.5 ? 1.0 - depth : depth; }
