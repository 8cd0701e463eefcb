// The terrain PLY written in blocks in the toolkit's own layout (the bytes of OpenMesh's
// PLY writer): a whole mesh, a grid's mesh made as it is written, or rows as they come.
#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <fstream>
#include <functional>
#include <future>
#include <tuple>

#include "mesh_io_internal.hpp"
#include "terrain/atomic_file.hpp"
#include "terrain/mesh_digest.hpp"
#include "terrain/mesh_io.hpp"

namespace terrain {

using namespace detail;

namespace {

// The header as OpenMesh writes it: custom properties in the order they were added.
std::string ply_header(const GridMesh& mesh, std::uint64_t digest, bool voronoi, bool change,
                       bool filled) {
  std::string header = "ply\nformat binary_little_endian 1.0\n" + header_comments(mesh, digest);
  header += fmt::format("element vertex {}\n", mesh.topo.n_vertices());
  for (const char* name : {"x", "y", "z", "nx", "ny", "nz"})
    header += fmt::format("property float {}\n", name);
  if (voronoi) {
    header += "property float voronoi_area\n";
    for (const char* name : kTangent) header += fmt::format("property float {}\n", name);
  }
  if (change) header += "property float normal_change\n";
  if (filled) header += "property float filled\n";
  const std::size_t faces = mesh.has_holes() ? mesh.kept_faces().size() : mesh.n_faces();
  header += fmt::format("element face {}\nproperty list uchar int vertex_indices\n", faces);
  if (voronoi)
    for (const char* name : kCornerArea) header += fmt::format("property float {}\n", name);
  return header + "end_header\n";
}

// A piece of the body: vertex rows r0 .. r1 - 1, or cell rows (two faces each).
struct PlyChunk {
  bool faces;
  std::size_t r0, r1;
};

// Fills `buf` with a chunk's records; returns the byte count. A vertex chunk's positions
// and normals are p[0..] and n[0..] (rows r0 .. r1 - 1), its optional data the mesh's.
std::size_t fill_ply_chunk(const GridMesh& mesh, const PlyChunk& ch, const Eigen::Vector3f* p,
                           const Eigen::Vector3f* n, bool voronoi, bool change, bool filled,
                           char* buf) {
  const std::size_t cols = mesh.topo.cols;
  char* at = buf;
  auto put = [&](const void* q, std::size_t bytes) {
    std::memcpy(at, q, bytes);
    at += bytes;
  };
  if (!ch.faces) {
    const std::size_t first = ch.r0 * cols;
    for (std::size_t i = first; i < ch.r1 * cols; ++i) {
      put(p[i - first].data(), 12);
      put(n[i - first].data(), 12);
      if (voronoi) {
        put(&mesh.voronoi.vertex_areas[i], 4);
        put(mesh.voronoi.tangents[i].data(), 12);
      }
      if (change) put(&mesh.normal_change[i], 4);
      if (filled) {
        const float f = mesh.filled[i];
        put(&f, 4);
      }
    }
    return std::size_t(at - buf);
  }
  for (std::size_t r = ch.r0; r < ch.r1; ++r)
    for (std::size_t c = 0; c + 1 < cols; ++c) {
      const auto nw = std::int32_t(r * cols + c), ne = nw + 1,
                 sw = std::int32_t(nw + std::int32_t(cols)), se = sw + 1;
      const std::size_t f = mesh.topo.face_of_cell(r, c, 0);
      // GridTopology::face's order: (NW, SW, SE), then (NW, SE, NE).
      const std::int32_t tri[2][3] = {{nw, sw, se}, {nw, se, ne}};
      for (int k = 0; k < 2; ++k) {
        if (filled && !mesh.face_kept(f + std::size_t(k))) continue;  // outside the data
        const std::uint8_t three = 3;
        put(&three, 1);
        put(tri[k], 12);
        if (voronoi) put(mesh.voronoi.corner_areas[f + std::size_t(k)].data(), 12);
      }
    }
  return std::size_t(at - buf);
}

// Chunks filled at once: one written, two being filled (both cores busy while one writes).
constexpr std::size_t kSlots = 3;

// A vertex chunk's positions and normals: rows(r0, r1, slot, p, n) points p and n at rows
// r0 .. r1 - 1, valid while buffer `slot` (0 .. kSlots - 1) is not filled again.
using VertexRows = std::function<void(std::size_t r0, std::size_t r1, int slot,
                                      const Eigen::Vector3f*& p, const Eigen::Vector3f*& n)>;

// The body in chunks of whole rows (vertex rows, then cell rows of two faces each), and the
// bytes a buffer holds for the largest.
struct ChunkPlan {
  std::vector<PlyChunk> chunks;
  std::size_t buffer_bytes = 0;
};
ChunkPlan plan_chunks(const GridTopology& topo, bool voronoi, bool change, bool filled) {
  const std::size_t rows = topo.rows, cols = topo.cols;
  const std::size_t vertex_bytes = 24 + (voronoi ? 16 : 0) + (change ? 4 : 0) + (filled ? 4 : 0),
                    face_bytes = 13 + (voronoi ? 12 : 0);
  // 1 MiB: 4 MiB chunks tripled the kernel's time in write(2) on ext4, 256 KiB ones spend
  // it on the helper threads.
  constexpr std::size_t kChunkBytes = std::size_t(1) << 20;
  const std::size_t vrow_bytes = cols * vertex_bytes, frow_bytes = 2 * (cols - 1) * face_bytes;
  const std::size_t vrows =
      std::max<std::size_t>(1, kChunkBytes / std::max<std::size_t>(1, vrow_bytes));
  const std::size_t frows =
      std::max<std::size_t>(1, kChunkBytes / std::max<std::size_t>(1, frow_bytes));
  ChunkPlan plan;
  for (std::size_t r = 0; r < rows; r += vrows)
    plan.chunks.push_back({false, r, std::min(rows, r + vrows)});
  for (std::size_t r = 0; r + 1 < rows; r += frows)
    plan.chunks.push_back({true, r, std::min(rows - 1, r + frows)});
  plan.buffer_bytes = std::max(vrows * vrow_bytes, frows * frow_bytes);
  return plan;
}

// The PLY of `mesh` (its grid, georeference and optional arrays; the positions and normals
// from `rows`), its digest taken as the vertices go out and written into the header last.
void write_ply(const GridMesh& mesh, const VertexRows& rows_of, const std::string& path) {
  static_assert(std::endian::native == std::endian::little,
                "the PLY body is written as the host's floats");
  const std::size_t nv = mesh.topo.n_vertices();
  check_mesh_georef(mesh, "cannot write '" + path + "'");
  const bool voronoi = !mesh.voronoi.empty(), change = mesh.normal_change.size() == nv,
             filled = mesh.filled.size() == nv;
  const std::string header = ply_header(mesh, 0, voronoi, change, filled);
  const std::size_t digest_at = header.find(kDigestComment) + kDigestComment.size();
  const ChunkPlan plan = plan_chunks(mesh.topo, voronoi, change, filled);
  const std::vector<PlyChunk>& chunks = plan.chunks;
  const std::size_t cols = mesh.topo.cols;
  // What the helper gives back: the chunk's byte count and its vertices for the digest.
  struct Filled {
    std::size_t bytes = 0;
    const Eigen::Vector3f *p = nullptr, *n = nullptr;
  };
  const auto fill = [&](std::size_t i, char* buf) {
    Filled f;
    if (!chunks[i].faces) rows_of(chunks[i].r0, chunks[i].r1, int(i % kSlots), f.p, f.n);
    f.bytes = fill_ply_chunk(mesh, chunks[i], f.p, f.n, voronoi, change, filled, buf);
    return f;
  };
  MeshDigest digest;
  write_stream_atomic(path, [&](std::ostream& out) {
    out.write(header.data(), std::streamsize(header.size()));
    // kSlots buffers: helper threads fill the next ones while this one writes and digests.
    std::vector<char> bufs[kSlots];
    for (auto& b : bufs) b.resize(plan.buffer_bytes);
    std::future<Filled> filling[kSlots];
    const auto launch = [&](std::size_t i) {
      if (i < chunks.size())
        filling[i % kSlots] = std::async(std::launch::async, fill, i, bufs[i % kSlots].data());
    };
    for (std::size_t i = 0; i + 1 < kSlots; ++i) launch(i);
    for (std::size_t i = 0; i < chunks.size() && out; ++i) {
      const Filled now = filling[i % kSlots].get();
      launch(i + kSlots - 1);
      out.write(bufs[i % kSlots].data(), std::streamsize(now.bytes));
      if (!chunks[i].faces) digest.add(now.p, now.n, (chunks[i].r1 - chunks[i].r0) * cols);
    }
    for (auto& f : filling)
      if (f.valid()) f.wait();  // after a failed write: no helper left writing into a buffer
    const std::string text = digest_text(digest.value());
    out.seekp(std::streamoff(digest_at));
    out.write(text.data(), std::streamsize(text.size()));
    out.flush();
    if (!out) throw Error("cannot write '" + path + "': write failed (disk full?)");
  });
}

}  // namespace

void write_mesh_ply(const GridMesh& mesh, const std::string& path) {
  if (mesh.positions.size() != mesh.topo.n_vertices() ||
      mesh.normals.size() != mesh.positions.size())
    throw Error("cannot write '" + path + "': positions, normals and grid size disagree");
  const std::size_t cols = mesh.topo.cols;
  write_ply(
      mesh,
      [&](std::size_t r0, std::size_t, int, const Eigen::Vector3f*& p, const Eigen::Vector3f*& n) {
        p = mesh.positions.data() + r0 * cols;
        n = mesh.normals.data() + r0 * cols;
      },
      path);
}

void write_grid_mesh_ply(const GridMesh& frame, const Grid& grid, NormalWeighting weighting,
                         const std::string& path) {
  if (frame.topo.rows != grid.rows || frame.topo.cols != grid.cols)
    throw Error("cannot write '" + path + "': the mesh's frame and the grid differ");
  // One row source per buffer slot, each holding its chunk's rows until the slot is
  // filled again.
  const GridMeshRows checked(grid, weighting);
  GridMeshRows sources[kSlots] = {checked, checked, checked};
  write_ply(
      frame,
      [&](std::size_t r0, std::size_t r1, int slot, const Eigen::Vector3f*& p,
          const Eigen::Vector3f*& n) { std::tie(p, n) = sources[slot].rows(r0, r1); },
      path);
}

struct PlyRowWriter::Impl {
  GridMesh header;  // grid, georeference, provenance; no vertices
  std::string path;
  std::ofstream out;
  std::vector<char> buf;
  std::size_t rows = 0;
  MeshDigest digest;
  std::size_t digest_at = 0;  // the header's digest digits, written by finish()
};

PlyRowWriter::PlyRowWriter(const GridMesh& header, const std::string& path)
    : impl_(std::make_unique<Impl>()) {
  static_assert(std::endian::native == std::endian::little,
                "the PLY body is written as the host's floats");
  Impl& m = *impl_;
  m.header.topo = header.topo, m.header.geo = header.geo, m.header.provenance = header.provenance;
  m.header.normal_fit = header.normal_fit;
  m.path = path;
  check_mesh_georef(m.header, "cannot write '" + path + "'");
  m.buf.resize(std::size_t(1) << 20);
  m.out.rdbuf()->pubsetbuf(m.buf.data(), std::streamsize(m.buf.size()));
  m.out.open(path, std::ios::binary | std::ios::trunc);
  const std::string h = ply_header(m.header, 0, false, false, false);
  m.digest_at = h.find(kDigestComment) + kDigestComment.size();
  m.out.write(h.data(), std::streamsize(h.size()));
  if (!m.out) throw Error("cannot write '" + path + "'");
}

PlyRowWriter::~PlyRowWriter() = default;

void PlyRowWriter::add_rows(const Eigen::Vector3f* positions, const Eigen::Vector3f* normals,
                            std::size_t n) {
  Impl& m = *impl_;
  const std::size_t cols = m.header.topo.cols;
  if (m.rows + n > m.header.topo.rows)
    throw Error("cannot write '" + m.path + "': more rows than the grid's");
  std::vector<char> row(24 * cols);
  m.digest.add(positions, normals, n * cols);
  for (std::size_t r = 0; r < n; ++r) {
    for (std::size_t c = 0; c < cols; ++c) {
      std::memcpy(&row[24 * c], positions[r * cols + c].data(), 12);
      std::memcpy(&row[24 * c + 12], normals[r * cols + c].data(), 12);
    }
    m.out.write(row.data(), std::streamsize(row.size()));
  }
  m.rows += n;
  if (!m.out) throw Error("cannot write '" + m.path + "': write failed (disk full?)");
}

void PlyRowWriter::finish() {
  Impl& m = *impl_;
  if (m.rows != m.header.topo.rows)
    throw Error(fmt::format("cannot write '{}': {} of the grid's {} rows given", m.path, m.rows,
                            m.header.topo.rows));
  const std::size_t rows = m.header.topo.rows,
                    frows = std::max<std::size_t>(
                        1, (std::size_t(1) << 20) / (26 * m.header.topo.cols));
  std::vector<char> buf(frows * 26 * m.header.topo.cols);
  for (std::size_t r = 0; r + 1 < rows; r += frows) {
    const std::size_t n = fill_ply_chunk(m.header, {true, r, std::min(rows - 1, r + frows)},
                                         nullptr, nullptr, false, false, false, buf.data());
    m.out.write(buf.data(), std::streamsize(n));
  }
  const std::string digest = digest_text(m.digest.value());
  m.out.seekp(std::streamoff(m.digest_at));
  m.out.write(digest.data(), std::streamsize(digest.size()));
  m.out.close();
  if (!m.out) throw Error("cannot write '" + m.path + "': write failed (disk full?)");
}

}  // namespace terrain
