#include "renderer/core/pel.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "renderer/core/silhouette.hpp"
#include "terrain/error.hpp"

namespace renderer {

using Eigen::Vector2f;
using Eigen::Vector3f;

namespace {

// Gradient (3-D, in the face's plane) of the linear function with values `val` at the
// corners of face f; zero for a degenerate face.
Vector3f face_gradient(const terrain::GridMesh& m, std::size_t f, const std::vector<float>& val,
                       Vector3f& nf) {
  const auto t = m.topo.face(f);
  const Vector3f x0 = m.positions[t[0]], x1 = m.positions[t[1]], x2 = m.positions[t[2]];
  const Vector3f cr = (x1 - x0).cross(x2 - x0);
  const float dbl_area = cr.norm();
  if (!(dbl_area > 0)) {
    nf = Vector3f(0, 0, 1);
    return Vector3f::Zero();
  }
  nf = cr / dbl_area;
  // e_i opposite corner i, counter-clockwise.
  const Vector3f e0 = x2 - x1, e1 = x0 - x2, e2 = x1 - x0;
  return (val[t[0]] * nf.cross(e0) + val[t[1]] * nf.cross(e1) + val[t[2]] * nf.cross(e2)) /
         dbl_area;
}

// The Voronoi-weighted vertex gradient of `val` in the vertex frame (docs/algorithms.md 5.2, 5.3).
Vector2f vertex_gradient(const terrain::GridMesh& m, std::size_t v, const std::vector<float>& val) {
  std::array<std::uint32_t, 6> faces;
  std::array<std::uint8_t, 6> corners;
  const int k = m.topo.vertex_faces(v, faces, corners);
  const Vector3f N = m.normals[v], t1 = m.voronoi.tangents[v], t2 = N.cross(t1);
  const float area = m.voronoi.vertex_areas[v];
  Vector3f sum = Vector3f::Zero();
  if (!(area > 0)) return Vector2f::Zero();
  for (int i = 0; i < k; ++i) {
    const std::size_t f = faces[std::size_t(i)];
    Vector3f nf;
    Vector3f g = face_gradient(m, f, val, nf);
    const float ndot = nf.dot(N);
    if (ndot <= -1.0f) {
      g = -g;
    } else {
      const Vector3f perp_old = N - ndot * nf, dperp = (nf + N) / (1.0f + ndot);
      g -= dperp * g.dot(perp_old);
    }
    sum += (m.voronoi.corner_areas[f][corners[std::size_t(i)]] / area) * g;
  }
  return {sum.dot(t1), sum.dot(t2)};
}

}  // namespace

PelFields pel_fields(const terrain::GridMesh& m, const Eigen::Vector3d& light) {
  if (m.voronoi.empty())
    throw terrain::Error(
        "the mesh has no Voronoi weights (make it with denoise-normals; --iterations 0 only adds "
        "them)");
  const std::size_t nv = m.n_vertices();
  PelFields p;
  p.f.resize(nv);
  p.g.resize(nv);
  p.m.resize(nv);
  p.s.resize(nv);
  p.c.resize(nv);
  const Vector3f L = light.cast<float>();
  for (std::size_t v = 0; v < nv; ++v) p.f[v] = std::max(0.0f, m.normals[v].dot(L));
#pragma omp parallel for schedule(static)
  for (std::size_t v = 0; v < nv; ++v) {
    p.g[v] = vertex_gradient(m, v, p.f);
    p.m[v] = p.g[v].norm();
  }
  for (float x : p.m) p.m_max = std::max(p.m_max, x);
  auto along_w = [&](std::size_t v, const Vector2f& grad) {
    return p.m[v] > 0 ? grad.dot(p.g[v]) / p.m[v] : 0.0f;
  };
#pragma omp parallel for schedule(static)
  for (std::size_t v = 0; v < nv; ++v) p.s[v] = along_w(v, vertex_gradient(m, v, p.m));
#pragma omp parallel for schedule(static)
  for (std::size_t v = 0; v < nv; ++v) p.c[v] = along_w(v, vertex_gradient(m, v, p.s));
  return p;
}

PelSegments extract_pels(const terrain::GridMesh& m, const PelFields& p, double tau) {
  PelSegments out;
  const float inv_max = p.m_max > 0 ? 1.0f / p.m_max : 0.0f;
  for (std::size_t f = 0; f < m.n_faces(); ++f) {
    const auto t = m.topo.face(f);
    Vector3f pts[2];
    int n = 0;
    bool keep = true;
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t a = t[std::size_t(e)], b = t[std::size_t((e + 1) % 3)];
      const float sa = p.s[a] == 0.0f ? 1e-20f : p.s[a], sb = p.s[b] == 0.0f ? 1e-20f : p.s[b];
      if ((sa > 0) == (sb > 0)) continue;
      const float w = sa / (sa - sb);
      if (n < 2) pts[n] = m.positions[a] + w * (m.positions[b] - m.positions[a]);
      ++n;
      const float c = p.c[a] + w * (p.c[b] - p.c[a]);
      const float mn = (p.m[a] + w * (p.m[b] - p.m[a])) * inv_max;
      keep = keep && c < 0.0f && mn > float(tau);
    }
    if (n != 2 || !keep) continue;
    out.points.push_back(pts[0]);
    out.points.push_back(pts[1]);
    out.faces.push_back(std::uint32_t(f));
  }
  return out;
}

namespace {

// s as extract_pels reads it: an exact zero counts as +1e-20.
bool s_positive(const PelFields& p, std::uint32_t v) {
  return (p.s[v] == 0.0f ? 1e-20f : p.s[v]) > 0;
}

constexpr std::uint32_t kNone = 0xFFFFFFFFu;  // no segment, no point, no piece

// The segment of each face (#F), kNone where it has none.
std::vector<std::uint32_t> segment_of_face(const terrain::GridTopology& topo,
                                           const PelSegments& segments) {
  std::vector<std::uint32_t> seg(topo.n_faces(), kNone);
  for (std::size_t k = 0; k < segments.size(); ++k) seg[segments.faces[k]] = std::uint32_t(k);
  return seg;
}

}  // namespace

void smooth_pels(const terrain::GridTopology& topo, const PelFields& p, PelSegments& segments,
                 int iterations) {
  const std::vector<std::uint32_t> seg_of_face = segment_of_face(topo, segments);
  // The index among face g's crossings (0, 1) of the crossing on edge {u, v}; -1: none.
  auto crossing_index = [&](std::size_t g, std::uint32_t u, std::uint32_t v) {
    const auto t = topo.face(g);
    int n = 0;
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t a = t[std::size_t(e)], b = t[std::size_t((e + 1) % 3)];
      if (s_positive(p, a) == s_positive(p, b)) continue;
      if ((a == u && b == v) || (a == v && b == u)) return n;
      ++n;
    }
    return -1;
  };
  // The end of the line beyond each segment end: 2 x #S indices into points, or none.
  std::vector<std::uint32_t> beyond(segments.points.size(), kNone);
  for (std::size_t k = 0; k < segments.size(); ++k) {
    const std::size_t f = segments.faces[k];
    const auto t = topo.face(f);
    int j = 0;
    for (int e = 0; e < 3 && j < 2; ++e) {
      const std::uint32_t a = t[std::size_t(e)], b = t[std::size_t((e + 1) % 3)];
      if (s_positive(p, a) == s_positive(p, b)) continue;
      const std::size_t g = topo.face_across(f, (e + 2) % 3);  // across edge (t[e], t[e + 1])
      if (g != terrain::GridTopology::kNoFace && seg_of_face[g] != kNone) {
        const int i = crossing_index(g, a, b);
        if (i >= 0) beyond[2 * k + std::size_t(j)] = 2 * seg_of_face[g] + std::uint32_t(1 - i);
      }
      ++j;
    }
  }
  std::vector<Eigen::Vector3f> next(segments.points.size());
  for (int it = 0; it < iterations; ++it) {
    const auto& pts = segments.points;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      if (beyond[i] == kNone) {
        next[i] = pts[i];
        continue;
      }
      const Eigen::Vector3f mid = 0.5f * (pts[i ^ 1u] + pts[beyond[i]]);
      next[i] = pts[i] + 0.5f * (mid - pts[i]);
    }
    segments.points.swap(next);
  }
}

PelPieces pel_pieces(const terrain::GridTopology& topo, const PelFields& p,
                     const PelSegments& segments) {
  const std::vector<std::uint32_t> seg_of_face = segment_of_face(topo, segments);
  std::vector<std::uint32_t> parent(segments.size());
  for (std::size_t k = 0; k < segments.size(); ++k) parent[k] = std::uint32_t(k);
  auto find = [&](std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (std::size_t k = 0; k < segments.size(); ++k) {
    const std::size_t f = segments.faces[k];
    const auto t = topo.face(f);
    for (int e = 0; e < 3; ++e) {
      const std::size_t g = topo.face_across(f, (e + 2) % 3);  // edge (t[e], t[e + 1])
      if (g == terrain::GridTopology::kNoFace || seg_of_face[g] == kNone) continue;
      if (s_positive(p, t[std::size_t(e)]) == s_positive(p, t[std::size_t((e + 1) % 3)])) continue;
      const std::uint32_t a = find(std::uint32_t(k)), b = find(seg_of_face[g]);
      parent[std::max(a, b)] = std::min(a, b);
    }
  }
  PelPieces out;
  out.piece.resize(segments.size());
  std::vector<std::uint32_t> id_of_root(segments.size(), kNone);
  for (std::size_t k = 0; k < segments.size(); ++k) {
    const std::uint32_t root = find(std::uint32_t(k));
    if (id_of_root[root] == kNone)
      id_of_root[root] = std::uint32_t(out.length.size()), out.length.push_back(0.0);
    out.piece[k] = id_of_root[root];
    out.length[out.piece[k]] +=
        double((segments.points[2 * k + 1] - segments.points[2 * k]).norm());
  }
  return out;
}

std::vector<float> pel_piece_opacity(const PelPieces& pieces, double min_length) {
  std::vector<float> opacity(pieces.piece.size());
  for (std::size_t k = 0; k < opacity.size(); ++k)
    opacity[k] = piece_opacity(pieces.length[pieces.piece[k]], min_length);
  return opacity;
}

}  // namespace renderer
