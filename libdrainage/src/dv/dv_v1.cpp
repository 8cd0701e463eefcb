// Version 1 of the .dv: every field of every point, 32 bytes each (docs/dv-format.md).
#include <cmath>
#include <vector>

#include "drainage/d8.hpp"
#include "dv_internal.hpp"
#include "terrain/atomic_file.hpp"

namespace drainage::dv {

void write_dv_v1(const std::string& path, const DvHeader& h, const terrain::Grid& z,
                 const D8Codes& dirs, const Network& net) {
  const std::size_t n = std::size_t(h.rows * h.cols);
  if (z.size() != n || dirs.size() != n || net.downstream.size() != n)
    throw terrain::Error("write_dv: grid, directions and network sizes disagree");
  if (net.normalized.size() != n || net.branches.size() != net.branch_count)
    throw terrain::Error("write_dv: version 1 stores the whole network (NetworkDetail::Full)");
  terrain::write_stream_atomic(path, [&](std::ostream& file) {
    CrcWriter w(file, path);
    const std::vector<char> head = header_bytes(h);
    w.write(head.data(), head.size());

    std::vector<DvVertex> chunk(std::size_t(1) << 16);
    for (std::size_t start = 0; start < n; start += chunk.size()) {
      const std::size_t m = std::min(chunk.size(), n - start);
#pragma omp parallel for schedule(static)
      for (long k = 0; k < long(m); ++k) {
        const std::size_t i = start + std::size_t(k);
        const std::size_t r = i / h.cols, c = i % h.cols;
        DvVertex& v = chunk[std::size_t(k)];
        v.x = float(double(c) * h.dx);
        v.y = float(-double(r) * h.dy);
        v.z = std::isnan(z.z[i]) ? 0.0f : float(double(z.z[i]) - h.origin_z);
        v.accumulated = net.accumulated[i];
        v.normalized = net.normalized[i];
        v.basin = net.basin[i];
        v.downstream = net.downstream[i];
        v.point_class = net.point_class[i];
        v.order = net.order[i];
        v.d8 = dirs[i];
        v.reserved = 0;
      }
      w.write(chunk.data(), m * sizeof(DvVertex));
    }
    std::vector<DvBranch> branches(net.branches.size());
    for (std::size_t b = 0; b < branches.size(); ++b) {
      const Branch& s = net.branches[b];
      branches[b] = DvBranch{s.first, s.count, s.drains_into, s.order, {0, 0, 0}};
    }
    w.write(branches.data(), branches.size() * sizeof(DvBranch));
    w.write(net.branch_vertices.data(), net.branch_vertices.size() * sizeof(std::uint32_t));
    const std::uint32_t crc = w.crc();
    file.seekp(std::streamoff(kCrcOffset));
    file.write(reinterpret_cast<const char*>(&crc), sizeof crc);
  });
}

// What the grid says of the flow: every point accumulates 1 .. the grid's points and less
// than its downstream point in the same basin, and the points that end a flow (class Pit)
// are the basins, one each.
static void check_flow(const DrainageDb& db, const FixedHeader& f, const std::string& path) {
  const std::uint64_t n = db.vertices.size();
  std::uint64_t pits = 0;
  for (std::uint64_t i = 0; i < n; ++i) {
    const DvVertex& v = db.vertices[i];
    if (v.point_class == std::uint8_t(PointClass::Nodata)) continue;
    if (v.accumulated == 0 || v.accumulated > n || !(v.normalized > 0.0f && v.normalized <= 1.0f))
      throw terrain::Error(cannot(path, "corrupt .dv (accumulated or normalized flow of vertex " +
                                            std::to_string(i) + ")"));
    // Flow grows downstream within one basin: no D8 cycle passes this local test (version 2
    // blocks are checked so as they are decoded, dv_v2.cpp).
    if (v.downstream != kNone && (db.vertices[v.downstream].accumulated <= v.accumulated ||
                                  db.vertices[v.downstream].basin != v.basin))
      throw terrain::Error(
          cannot(path,
                 "corrupt .dv (flow that does not grow downstream (a D8 cycle or a wrong basin) "
                 "at vertex " +
                     std::to_string(i) + ")"));
    pits += v.point_class == std::uint8_t(PointClass::Pit);
  }
  if (pits != f.basins)
    throw terrain::Error(cannot(path, "corrupt .dv (" + std::to_string(pits) +
                                          " pits, the header says " + std::to_string(f.basins) +
                                          " basins)"));
}

DrainageDb read_dv_v1(const std::string& path, OpenDv& d) {
  const FixedHeader& f = d.f;
  const std::uint64_t n = f.rows * f.cols;
  const std::uint64_t expected = std::uint64_t(f.header_bytes) + n * sizeof(DvVertex) +
                                 f.branches * sizeof(DvBranch) + f.valid * sizeof(std::uint32_t);
  if (d.size < expected)
    throw terrain::Error(cannot(path, "truncated (" + std::to_string(d.size) + " bytes, expected " +
                                          std::to_string(expected) + ")"));
  if (d.size > expected)
    throw terrain::Error(
        cannot(path, std::to_string(d.size - expected) + " unexpected trailing bytes"));
  DrainageDb db;
  db.header = d.h;
  db.vertices.resize(n);
  db.branches.resize(f.branches);
  db.branch_vertices.resize(f.valid);
  d.in.read(reinterpret_cast<char*>(db.vertices.data()), std::streamsize(n * sizeof(DvVertex)));
  d.in.read(reinterpret_cast<char*>(db.branches.data()),
            std::streamsize(f.branches * sizeof(DvBranch)));
  d.in.read(reinterpret_cast<char*>(db.branch_vertices.data()),
            std::streamsize(f.valid * sizeof(std::uint32_t)));
  if (!d.in) throw terrain::Error(cannot(path, "read failed"));

  // CRC over the whole file with the CRC field zeroed: every header byte as read.
  const std::vector<char>& head = d.header;
  uLong crc = crc32(0L, Z_NULL, 0);
  crc = crc32_z(crc, reinterpret_cast<const Bytef*>(head.data()), head.size());
  crc = crc32_z(crc, reinterpret_cast<const Bytef*>(db.vertices.data()),
                db.vertices.size() * sizeof(DvVertex));
  crc = crc32_z(crc, reinterpret_cast<const Bytef*>(db.branches.data()),
                db.branches.size() * sizeof(DvBranch));
  crc = crc32_z(crc, reinterpret_cast<const Bytef*>(db.branch_vertices.data()),
                db.branch_vertices.size() * sizeof(std::uint32_t));
  if (std::uint32_t(crc) != f.crc32)
    throw terrain::Error(cannot(path, "checksum mismatch (corrupt file)"));
  check_indices(db, path);
  check_flow(db, f, path);
  return db;
}

}  // namespace drainage::dv
