// SIL by the Adjacency method (Mower 2014, Algorithm 1; docs/terrain-render.md): pixel p
// (triangle A) is a silhouette when an 8-neighbour q shows another triangle B that shares
// no vertex with A (within u_tolerance, so the float differences of PN patch edges evaluated
// from both sides do not count) and A is nearer than B: the occluding side is marked, one
// pixel wide. Special cases: a neighbour showing no surface counts only when the empty
// region goes on beyond it (the next pixel in the same direction is empty too or off the
// image) and A does not touch the mesh boundary: the skyline, not a one-pixel crack
// between PN patches nor the edge of the model (a boundary, not a silhouette); an "unknown" triangle
// (beyond the triangle list) never counts. Triangles that share only a vertex are
// neighbours in a fan seen by diagonal pixels, not a silhouette.
layout(binding = TR_TEX_TRIANGLE_ID) uniform usampler2D u_ids;
layout(binding = TR_TEX_ID_DEPTH) uniform sampler2D u_id_depth;
layout(std430, binding = TR_SSBO_ID_TRIANGLES) readonly buffer IdTriangles {
  uint n_triangles;
  uint pad0, pad1, pad2;
  vec4 tri[];
};
// x: tolerance in metres; y: the angle of one pixel (radians): vertices closer than
// max(x, 4 y d / cos i), d the distance from the eye, i the incidence, are one vertex;
// orthographic: y is the pixel's size in metres, and y d is y.
layout(location = TR_LOC_ADJ_TOLERANCE) uniform vec2 u_tolerance;
// The mesh's extent in its local frame: xmin, ymin, xmax, ymax.
layout(location = TR_LOC_ADJ_EXTENT) uniform vec4 u_extent;
layout(location = 0) out vec4 o_mask;

bool on_boundary(uint a) {
  for (uint i = 0u; i < 3u; ++i) {
    vec2 v = tri[3u * (a - 1u) + i].xy;
    if (any(lessThanEqual(v, u_extent.xy + u_tolerance.x)) || any(greaterThanEqual(v, u_extent.zw - u_tolerance.x)))
      return true;
  }
  return false;
}

const uint kUnknown = 0xFFFFFFFFu;

bool share_a_vertex(uint a, uint b) {
  // One pixel covers about d * angle / cos(incidence) of the surface: at grazing incidence
  // pixel neighbours skip whole thin triangles, so the tolerance grows (up to 20 x).
  vec3 a0 = tri[3u * (a - 1u)].xyz, a1 = tri[3u * (a - 1u) + 1u].xyz, a2 = tri[3u * (a - 1u) + 2u].xyz;
  vec3 ray = -to_eye(a0);
  vec3 n = cross(a1 - a0, a2 - a0);
  float incidence = abs(dot(normalize(n), normalize(ray)));
  float pixel = orthographic() ? u_tolerance.y : u_tolerance.y * length(ray);
  float tol = max(u_tolerance.x, 4.0 * pixel / max(incidence, 0.05));
  for (uint i = 0u; i < 3u; ++i)
    for (uint j = 0u; j < 3u; ++j)
      if (distance(tri[3u * (a - 1u) + i].xyz, tri[3u * (b - 1u) + j].xyz) <= tol) return true;
  return false;
}

uint id_at(ivec2 q, ivec2 size) {
  return all(greaterThanEqual(q, ivec2(0))) && all(lessThan(q, size)) ? texelFetch(u_ids, q, 0).r : 0u;
}

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  ivec2 size = textureSize(u_ids, 0);
  uint a = texelFetch(u_ids, p, 0).r;
  float s = 0.0;
  if (a != 0u && a != kUnknown) {
    float da = far_of(texelFetch(u_id_depth, p, 0).r);
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        ivec2 d = ivec2(dx, dy), q = p + d;
        if ((dx == 0 && dy == 0) || !all(greaterThanEqual(q, ivec2(0))) || !all(lessThan(q, size))) continue;
        uint b = texelFetch(u_ids, q, 0).r;
        if (b == a || b == kUnknown) continue;
        if (b == 0u) {
          if (id_at(q + d, size) == 0u && !on_boundary(a)) s = 1.0;  // the empty region goes on: a skyline
          continue;
        }
        if (da < far_of(texelFetch(u_id_depth, q, 0).r) && !share_a_vertex(a, b)) s = 1.0;
      }
  }
  if (s > 0.0) list_silhouette_pixel(p, size), mark_silhouette_tile(p);
  o_mask = vec4(s);
}
