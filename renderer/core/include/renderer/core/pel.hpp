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
  std::vector<float> f, m, s, c;   // #V
  std::vector<Eigen::Vector2f> g;  // #V gradient of f in (t1, t2)
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

// Smoothed PEL lines (anti-aliased lines; Style::pel_smooth). The crossings of s with the
// mesh's edges follow the noise of the fields, and the lines zigzag from face to face (MSH
// 10 m: 25 degrees between consecutive segments on average). Per iteration, each end of
// a segment that continues into the face across its edge (the edge of its crossing, where
// that face has a segment) moves halfway to the midpoint of its two neighbours on the line:
// the segment's other end and the far end of the segment across (a Laplacian step with
// lambda 1/2, which cancels a zigzag of period two at once). Ends of lines stay, and both
// copies of a shared point (one per face) move alike, so lines stay joined. End j of a
// segment lies on its face's j-th edge (t[e], t[e + 1]) that s crosses, in e order, as
// extract_pels writes them. The GPU runs the same steps (pel_pieces.comp.glsl).
void smooth_pels(const terrain::GridTopology& topo, const PelFields& fields, PelSegments& segments,
                 int iterations);

// Pieces of PEL: segments in faces that share an edge which s crosses join (each carries
// the line across that edge), so every piece is a polyline or a closed loop on the mesh.
// piece: #S, the piece of each segment (0 .. #pieces - 1, numbered in face order);
// length: #pieces, the summed 3-D length of its segments (mesh units, metres).
struct PelPieces {
  std::vector<std::uint32_t> piece;
  std::vector<double> length;
};
PelPieces pel_pieces(const terrain::GridTopology& topo, const PelFields& fields,
                     const PelSegments& segments);

// The piece rule the PEL pass applies with anti-aliased lines: each segment is drawn at
// piece_opacity(length of its piece, min_length) (silhouette.hpp: in full from min_length,
// fading out to nothing at half of it). Short pieces are where the fields' noise crosses
// zero over a few faces, below what the mesh resolves. min_length <= 0: every segment 1.
std::vector<float> pel_piece_opacity(const PelPieces& pieces, double min_length);

}  // namespace renderer
