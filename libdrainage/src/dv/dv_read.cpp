// Reading a .dv, whole or by window, in either version (dv_internal.hpp).
#include <cstring>

#include "drainage/d8.hpp"
#include "dv_internal.hpp"
#include "network/branches.hpp"

namespace drainage {

namespace dv {

void derive_branches(DrainageDb& db) {
  const auto& v = db.vertices;
  db.branches.clear();
  network_branches(
      std::size_t(db.header.rows), std::size_t(db.header.cols),
      [&](std::size_t i) { return v[i].d8 != kNodata; },
      [&](std::size_t i) { return v[i].downstream; }, [&](std::size_t i) { return v[i].order; },
      [&](const Branch& b) {
        db.branches.push_back(DvBranch{b.first, b.count, b.drains_into, b.order, {0, 0, 0}});
      },
      db.branch_vertices);
  db.header.branches = db.branches.size();
}

DrainageDb crop(const DrainageDb& db, std::size_t r0, std::size_t c0, std::size_t nr,
                std::size_t nc) {
  const std::size_t C = std::size_t(db.header.cols);
  DrainageDb out;
  out.header = db.header;
  DvHeader& h = out.header;
  h.rows = nr, h.cols = nc;
  h.origin_x = db.header.origin_x + double(c0) * h.dx;
  h.origin_y = db.header.origin_y - double(r0) * h.dy;
  out.vertices.resize(nr * nc);
  std::uint64_t valid = 0;
  for (std::size_t r = 0; r < nr; ++r)
    for (std::size_t c = 0; c < nc; ++c) {
      DvVertex v = db.vertices[(r0 + r) * C + c0 + c];
      v.x = float(double(c) * h.dx);
      v.y = float(-double(r) * h.dy);
      if (v.downstream != kNone) {
        const std::size_t dr = v.downstream / C, dc = v.downstream % C;
        v.downstream = dr >= r0 && dr < r0 + nr && dc >= c0 && dc < c0 + nc
                           ? std::uint32_t((dr - r0) * nc + (dc - c0))
                           : kNone;
      }
      valid += v.point_class != std::uint8_t(PointClass::Nodata);
      out.vertices[r * nc + c] = v;
    }
  h.valid = valid;
  derive_branches(out);
  return out;
}

}  // namespace dv

using namespace dv;

DvHeader read_dv_header(const std::string& path) {
  OpenDv d;
  open_dv(path, d);
  if (d.f.version >= 2) (void)read_v2_trailer(path, d);  // checks the header's checksum
  return d.h;
}

namespace {

// What a whole version 2 grid, decoded, must agree with in its header and basin table: the
// valid points, the branches and each basin's pit. read_dv and read_dv_window (when its
// window is the whole grid) check the same.
void check_whole_v2(DrainageDb& db, const OpenDv& d, const V2Trailer& t, const std::string& path) {
  if (db.header.valid != d.f.valid)
    throw terrain::Error(cannot(path, "corrupt .dv (" + std::to_string(db.header.valid) +
                                          " valid points, the header says " +
                                          std::to_string(d.f.valid) + ")"));
  derive_branches(db);
  if (db.header.branches != d.f.branches)
    throw terrain::Error(cannot(path, "corrupt .dv (" + std::to_string(db.header.branches) +
                                          " branches derived, the header says " +
                                          std::to_string(d.f.branches) + ")"));
  for (std::size_t k = 0; k < t.pit.size(); ++k) {
    const DvVertex& v = db.vertices[t.pit[k]];
    if (v.point_class != std::uint8_t(PointClass::Pit) || v.basin != k ||
        v.accumulated != t.pit_accumulated[k])
      throw terrain::Error(cannot(path, "corrupt .dv (pit of basin " + std::to_string(k) + ")"));
  }
}

}  // namespace

DrainageDb read_dv(const std::string& path) {
  OpenDv d;
  open_dv(path, d);
  if (d.f.version == 1) return read_dv_v1(path, d);
  const V2Trailer t = read_v2_trailer(path, d);
  DrainageDb db = decode_v2_region(path, d, t, 0, 0, std::size_t(d.f.rows), std::size_t(d.f.cols));
  check_whole_v2(db, d, t, path);
  check_indices(db, path);
  return db;
}

DrainageDb read_dv_window(const std::string& path, std::size_t row0, std::size_t col0,
                          std::size_t rows, std::size_t cols) {
  OpenDv d;
  open_dv(path, d);
  const std::size_t R = std::size_t(d.f.rows), C = std::size_t(d.f.cols);
  row0 = std::min(row0, R), col0 = std::min(col0, C);
  rows = std::min(rows, R - row0), cols = std::min(cols, C - col0);
  if (rows == 0 || cols == 0)
    throw terrain::Error(cannot(path, "the window lies outside the grid"));
  if (d.f.version == 1) return crop(read_dv_v1(path, d), row0, col0, rows, cols);
  const V2Trailer t = read_v2_trailer(path, d);
  if (rows == R && cols == C) {  // the whole grid: checked as read_dv checks it
    DrainageDb db = decode_v2_region(path, d, t, 0, 0, R, C);
    check_whole_v2(db, d, t, path);
    check_indices(db, path);
    return db;
  }
  // One point of margin, so that the window's classes see all their inflows.
  const std::size_t er0 = row0 > 0 ? row0 - 1 : 0, ec0 = col0 > 0 ? col0 - 1 : 0;
  const std::size_t er1 = std::min(R, row0 + rows + 1), ec1 = std::min(C, col0 + cols + 1);
  const DrainageDb region = decode_v2_region(path, d, t, er0, ec0, er1 - er0, ec1 - ec0);
  DrainageDb db = crop(region, row0 - er0, col0 - ec0, rows, cols);
  check_indices(db, path);
  return db;
}

}  // namespace drainage
