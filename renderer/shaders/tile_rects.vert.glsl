// SIL's and LAY's draws near marked tiles: two triangles per rectangle of
// tile_rects.comp.glsl, corners (0,0) (1,0) (0,1), (0,1) (1,0) (1,1), to clip space.
layout(binding = TR_TEX_TOWARD_DEPTH) uniform sampler2D u_toward;
void main() {
  ivec4 r = rect[gl_VertexID / 6];
  int corner = gl_VertexID % 6;
  bvec2 far = bvec2(corner == 1 || corner == 4 || corner == 5, corner == 2 || corner == 3 || corner == 5);
  vec2 px = vec2(far.x ? r.z : r.x, far.y ? r.w : r.y);
  gl_Position = vec4(px / vec2(textureSize(u_toward, 0)) * 2.0 - 1.0, 0.0, 1.0);
}
