#pragma once
// Photic extremum lines (Xie et al. 2007; Zhang, He & Seah 2010; docs/algorithms.md 5), GL-free:
// the CPU reference of the renderer's PEL compute passes (pel_*.comp.glsl), same math in
// the same order. Needs the mesh's Voronoi weights (denoise-normals).
//
//   f_v = max(0, N_v . L)                         illumination at vertex v
//   g_f = sum_i f_i (n_f x e_i) / (2 A_f)         gradient of the linear f on face f
//   g_v = sum_f (A_corner(f, v) / A_v) R_f->v(g_f) (R: the smallest rotation taking n_f
//         to N_v, applied to g_f), stored as (g . t1, g . t2) in the vertex frame
//   m_v = |g_v|, w_v = g_v / m_v, m normalized by its maximum over the mesh
//   s_v = grad(m)_v . w_v,  c_v = grad(s)_v . w_v  (the same recipe for the fields m, s)
// A PEL crosses edge (a, b) where s changes sign (exact zeros count as +1e-20), at
// t = s_a / (s_a - s_b); a face with two such edges gives a segment, kept when c < 0
// (a maximum of m along w) and m / max(m) > tau at both ends.
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "terrain/grid_mesh.hpp"

namespace renderer {

struct PelFields {
  std::vector<float> f, m, s, c;      // #V
  std::vector<Eigen::Vector2f> g;     // #V gradient of f in (t1, t2)
  float m_max = 0;
};

// The per-vertex fields for the unit light direction `light` (mesh frame). Error when the
// mesh has no Voronoi weights.
PelFields pel_fields(const terrain::GridMesh& mesh, const Eigen::Vector3d& light);

struct PelSegments {
  std::vector<Eigen::Vector3f> points;  // 2 x #S, on the mesh's triangles (local frame)
  std::vector<std::uint32_t> faces;     // #S, the face of each segment
  std::size_t size() const { return faces.size(); }
};

// The PEL segments of `fields` with normalized strength above `tau`.
PelSegments extract_pels(const terrain::GridMesh& mesh, const PelFields& fields, double tau);

// Pieces of PEL: segments in faces that share an edge which s crosses join (each carries
// the line across that edge), so every piece is a polyline or a closed loop on the mesh.
// piece: #S, the piece of each segment (0 .. #pieces - 1, numbered in face order);
// length: #pieces, the summed 3-D length of its segments (mesh units, metres).
struct PelPieces {
  std::vector<std::uint32_t> piece;
  std::vector<double> length;
};
PelPieces pel_pieces(const terrain::GridTopology& topo, const PelFields& fields, const PelSegments& segments);

// The piece rule the PEL pass applies with anti-aliased lines: each segment is drawn at
// piece_opacity(length of its piece, min_length) (silhouette.hpp: in full from min_length,
// fading out to nothing at half of it). Short pieces are where the fields' noise crosses
// zero over a few faces, below what the mesh resolves. min_length <= 0: every segment 1.
std::vector<float> pel_piece_opacity(const PelPieces& pieces, double min_length);

}  // namespace renderer
