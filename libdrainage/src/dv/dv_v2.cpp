// Version 2 of the .dv: the stored fields in zstd-compressed blocks, encoded (write_dv,
// the tiled run's DvBlockWriter) and decoded by region (docs/dv-format.md).
#include <zstd.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <functional>
#include <memory>

#include "drainage/d8.hpp"
#include "dv_internal.hpp"
#include "terrain/atomic_file.hpp"

namespace drainage {

namespace dv {

V2Trailer read_v2_trailer(const std::string& path, OpenDv& d) {
  const FixedHeader& f = d.f;
  const std::size_t nb = blocks_along(f.rows, f.block_rows) * blocks_along(f.cols, f.block_cols);
  // The end record (file size, end magic) tells a truncated file from a corrupt one.
  char end[kEndRecord] = {};
  if (d.size >= f.header_bytes + kEndRecord) {
    d.in.seekg(std::streamoff(d.size - kEndRecord));
    d.in.read(end, kEndRecord);
  }
  std::uint64_t recorded = 0;
  std::memcpy(&recorded, end, 8);
  if (!d.in || std::memcmp(end + 8, kEndMagic, 8) != 0 || recorded < d.size)
    throw terrain::Error(cannot(path, "truncated or damaged (" + std::to_string(d.size) +
                                          " bytes, no end record at the end)"));
  if (recorded > d.size)
    throw terrain::Error(cannot(path, "truncated (" + std::to_string(d.size) + " bytes, expected " +
                                          std::to_string(recorded) + ")"));
  const std::uint64_t trailer = nb * kIndexEntry + f.basins * kBasinEntry + kEndRecord;
  if (d.size < f.header_bytes + trailer)
    throw terrain::Error(cannot(path, "truncated (" + std::to_string(d.size) +
                                          " bytes, the header and index alone need " +
                                          std::to_string(f.header_bytes + trailer) + ")"));
  std::vector<char> raw(trailer);
  d.in.seekg(std::streamoff(d.size - trailer));
  d.in.read(raw.data(), std::streamsize(raw.size()));
  if (!d.in) throw terrain::Error(cannot(path, "read failed"));
  const std::vector<char>& head = d.header;  // every header byte as read
  if (crc_of(raw.data(), raw.size(), crc_of(head.data(), head.size())) != f.crc32)
    throw terrain::Error(
        cannot(path, "checksum mismatch in the header or block index (corrupt file)"));
  V2Trailer t;
  t.offset.resize(nb), t.bytes.resize(nb), t.crc.resize(nb);
  const std::uint64_t data_end = d.size - trailer;
  for (std::size_t b = 0; b < nb; ++b) {
    std::memcpy(&t.offset[b], raw.data() + b * kIndexEntry, 8);
    std::memcpy(&t.bytes[b], raw.data() + b * kIndexEntry + 8, 4);
    std::memcpy(&t.crc[b], raw.data() + b * kIndexEntry + 12, 4);
    if (t.offset[b] < f.header_bytes || t.offset[b] > data_end ||
        t.bytes[b] > data_end - t.offset[b])
      throw terrain::Error(
          cannot(path, "corrupt .dv (block " + std::to_string(b) + " lies outside the data)"));
  }
  t.pit.resize(f.basins), t.pit_accumulated.resize(f.basins);
  const char* basins = raw.data() + nb * kIndexEntry;
  for (std::size_t k = 0; k < f.basins; ++k) {
    std::memcpy(&t.pit[k], basins + k * kBasinEntry, 4);
    std::memcpy(&t.pit_accumulated[k], basins + k * kBasinEntry + 4, 4);
    if (t.pit[k] >= f.rows * f.cols || t.pit_accumulated[k] == 0 ||
        t.pit_accumulated[k] > f.rows * f.cols || (k > 0 && t.pit[k] <= t.pit[k - 1]))
      throw terrain::Error(cannot(path, "corrupt .dv (basin " + std::to_string(k) + ")"));
  }
  return t;
}

// The points of the packed blocks `blocks` (of the region r0, c0, nr x nc) into db's
// vertices, every stored field checked; each vertex's reserved byte gets its cut flag.
// Block b's m points' byte planes, its checksum checked and decompressed into a buffer of
// this thread's (a fresh one per block would cost the kernel's zeroing of new pages for
// every block); nullptr after fail(why).
const std::uint8_t* unpack_block(const std::vector<char>& in, std::uint32_t crc, std::size_t b,
                                 std::size_t m,
                                 const std::function<void(const std::string&)>& fail) {
  if (crc_of(in.data(), in.size()) != crc) {
    fail("checksum mismatch in block " + std::to_string(b) + " (corrupt file)");
    return nullptr;
  }
  thread_local std::vector<std::uint8_t> raw;
  thread_local std::unique_ptr<ZSTD_DCtx, std::size_t (*)(ZSTD_DCtx*)> ctx(ZSTD_createDCtx(),
                                                                           ZSTD_freeDCtx);
  if (raw.size() < kBytesPerPoint * m) raw.resize(kBytesPerPoint * m);
  const std::size_t got =
      ZSTD_decompressDCtx(ctx.get(), raw.data(), kBytesPerPoint * m, in.data(), in.size());
  if (ZSTD_isError(got) || got != kBytesPerPoint * m) {
    fail("corrupt .dv (block " + std::to_string(b) + " does not decompress to its size)");
    return nullptr;
  }
  return raw.data();
}

// What is wrong with vertex `v` of grid cell `cell` as decoded (`is_cut`: its flow ends at
// the grid's edge or at no-data), against the header and trailer: "" when nothing.
static std::string vertex_problem(const DvVertex& v, bool is_cut, std::uint64_t cell,
                                  const FixedHeader& f, const V2Trailer& t) {
  const bool nodata = v.d8 == kNodata;
  const std::string at = std::to_string(cell);
  if (!(v.d8 <= kOutlet || nodata) || !std::isfinite(v.z))
    return "corrupt .dv (D8 code or elevation of vertex " + at + ")";
  if (nodata ? (v.basin != kNone || v.accumulated != 0)
             : (v.basin >= f.basins || v.accumulated == 0))
    return "corrupt .dv (basin of vertex " + at + ")";
  if (nodata) return {};
  if (v.accumulated > t.pit_accumulated[v.basin])
    return "corrupt .dv (accumulated flow of vertex " + at + " exceeds its basin's)";
  if ((v.d8 >= 8 || is_cut) && t.pit[v.basin] != cell)
    return "corrupt .dv (vertex " + at + " ends its flow but is not its basin's pit)";
  if (t.pit[v.basin] == cell && v.accumulated != t.pit_accumulated[v.basin])
    return "corrupt .dv (pit of basin " + std::to_string(v.basin) + ")";
  return {};
}

void decode_blocks(const std::string& path, const FixedHeader& f, const V2Trailer& t,
                   const std::vector<std::size_t>& blocks,
                   const std::vector<std::vector<char>>& packed, std::size_t r0, std::size_t c0,
                   std::size_t nr, std::size_t nc, DrainageDb& db) {
  const std::size_t R = std::size_t(f.rows), C = std::size_t(f.cols), BR = f.block_rows,
                    BC = f.block_cols;
  const std::size_t nbc = blocks_along(C, f.block_cols);
  const DvHeader& h = db.header;
  std::string error;
#pragma omp parallel for schedule(dynamic)
  for (long k = 0; k < long(blocks.size()); ++k) {
    const std::size_t b = blocks[std::size_t(k)], br = b / nbc, bc = b % nbc;
    const std::size_t rows_b = std::min(BR, R - br * BR), cols_b = std::min(BC, C - bc * BC),
                      m = rows_b * cols_b;
    auto fail = [&](const std::string& what) {
#pragma omp critical(dv_error)
      if (error.empty()) error = cannot(path, what);
    };
    const std::uint8_t* planes = unpack_block(packed[std::size_t(k)], t.crc[b], b, m, fail);
    if (!planes) continue;
    auto u32 = [&](std::size_t at,
                   std::size_t q) {  // byte-shuffled planes: byte k of value q at at + k m + q
      return std::uint32_t(planes[at + q]) | std::uint32_t(planes[at + m + q]) << 8 |
             std::uint32_t(planes[at + 2 * m + q]) << 16 |
             std::uint32_t(planes[at + 3 * m + q]) << 24;
    };
    const std::uint8_t* code = planes + 4 * m;
    const std::uint8_t* order = planes + 13 * m;
    std::uint32_t zprev = 0, bprev = 0;
    for (std::size_t q = 0; q < m; ++q) {
      zprev += u32(0, q), bprev += u32(9 * m, q);  // deltas
      const std::size_t gr = br * BR + q / cols_b, gc = bc * BC + q % cols_b;
      if (gr < r0 || gr >= r0 + nr || gc < c0 || gc >= c0 + nc) continue;
      const std::size_t i = (gr - r0) * nc + (gc - c0);
      DvVertex& v = db.vertices[i];
      const std::uint8_t c = code[q];
      const bool is_cut = (c & 0xF8) == kCutFlag;
      v.d8 = is_cut ? std::uint8_t(c & 7) : c;
      v.x = float(double(gc - c0) * h.dx);
      v.y = float(-double(gr - r0) * h.dy);
      v.z = std::bit_cast<float>(zprev);
      v.accumulated = u32(5 * m, q);
      v.basin = bprev;
      v.order = order[q];
      v.reserved = is_cut;
      v.downstream = kNone;
      const bool nodata = v.d8 == kNodata;
      if (const std::string why = vertex_problem(v, is_cut, gr * C + gc, f, t); !why.empty()) {
        fail(why);
        break;
      }
      v.normalized =
          nodata ? 0.0f : float(double(v.accumulated) / double(t.pit_accumulated[v.basin]));
      v.point_class = std::uint8_t(nodata ? PointClass::Nodata : PointClass::Pit);  // refined below
    }
  }
  if (!error.empty()) throw terrain::Error(error);
}

// Downstream links (region indices) from the codes, each checked; returns the valid points.
std::uint64_t link_downstream(const std::string& path, const FixedHeader& f, std::size_t r0,
                              std::size_t c0, std::size_t nr, std::size_t nc, DrainageDb& db) {
  const std::size_t R = std::size_t(f.rows), C = std::size_t(f.cols);
  auto cut = [&](std::size_t i) { return db.vertices[i].reserved != 0; };
  std::string error;
  const long NR = long(nr), NC = long(nc);
  std::uint64_t valid = 0;
#pragma omp parallel for schedule(static) reduction(+ : valid)
  for (long r = 0; r < NR; ++r)
    for (long c = 0; c < NC; ++c) {
      const std::size_t i = std::size_t(r * NC + c);
      DvVertex& v = db.vertices[i];
      if (v.d8 == kNodata) continue;
      ++valid;
      if (v.d8 >= 8 || cut(i)) continue;
      const auto [rr, cc] = step(r, c, v.d8);
      const long gr = long(r0) + rr, gc = long(c0) + cc;
      if (gr < 0 || gc < 0 || gr >= long(R) || gc >= long(C)) {
#pragma omp critical(dv_error)
        if (error.empty())
          error = cannot(path, "corrupt .dv (D8 code of vertex " +
                                   std::to_string((r0 + std::size_t(r)) * C + c0 + std::size_t(c)) +
                                   " leaves the grid)");
        continue;
      }
      if (rr < 0 || cc < 0 || rr >= NR || cc >= NC) continue;  // outside the region
      const std::size_t j = std::size_t(rr * NC + cc);
      if (db.vertices[j].d8 == kNodata) {
#pragma omp critical(dv_error)
        if (error.empty())
          error = cannot(path, "corrupt .dv (downstream of vertex " +
                                   std::to_string((r0 + std::size_t(r)) * C + c0 + std::size_t(c)) +
                                   " is no-data)");
        continue;
      }
      // Flow grows downstream within one basin: no cycle can pass this local test.
      if (db.vertices[j].accumulated <= v.accumulated || db.vertices[j].basin != v.basin) {
#pragma omp critical(dv_error)
        if (error.empty())
          error = cannot(path, "corrupt .dv (the flow of vertex " +
                                   std::to_string((r0 + std::size_t(r)) * C + c0 + std::size_t(c)) +
                                   " does not grow downstream: a D8 cycle or a wrong basin)");
        continue;
      }
      v.downstream = std::uint32_t(j);
    }
  if (!error.empty()) throw terrain::Error(error);
  return valid;
}

// The classes from the codes (exact where all 8 neighbours lie in the region); the cut
// flags cleared.
void classify(std::size_t nr, std::size_t nc, DrainageDb& db) {
  const long NR = long(nr), NC = long(nc);
  auto cut = [&](std::size_t i) { return db.vertices[i].reserved != 0; };
#pragma omp parallel for schedule(static)
  for (long r = 0; r < NR; ++r)
    for (long c = 0; c < NC; ++c) {
      const std::size_t i = std::size_t(r * NC + c);
      DvVertex& v = db.vertices[i];
      if (v.d8 == kNodata || v.d8 >= 8 || cut(i)) continue;  // no-data or a pit (outlets included)
      int in = 0;
      Neighbours{NR, NC}.inflows(r, c, [&](std::size_t j, int k) {
        in += db.vertices[j].d8 == std::uint8_t(k) && !cut(j);
      });
      v.point_class = std::uint8_t(in == 0   ? PointClass::Ridge
                                   : in == 1 ? PointClass::Channel
                                             : PointClass::Junction);
    }
#pragma omp parallel for schedule(static)
  for (long i = 0; i < NR * NC; ++i) db.vertices[std::size_t(i)].reserved = 0;
}

DrainageDb decode_v2_region(const std::string& path, OpenDv& d, const V2Trailer& t, std::size_t r0,
                            std::size_t c0, std::size_t nr, std::size_t nc) {
  const FixedHeader& f = d.f;
  const std::size_t C = std::size_t(f.cols), BR = f.block_rows, BC = f.block_cols;
  const std::size_t nbc = blocks_along(C, f.block_cols);
  DrainageDb db;
  db.header = d.h;
  DvHeader& h = db.header;
  h.rows = nr, h.cols = nc;
  h.origin_x = d.h.origin_x + double(c0) * d.h.dx;
  h.origin_y = d.h.origin_y - double(r0) * d.h.dy;
  db.vertices.resize(nr * nc);
  // Each vertex's reserved byte holds its cut flag until the classes are known, then 0.
  // The blocks under the region, read in file order, decoded in parallel.
  std::vector<std::size_t> blocks;
  for (std::size_t br = r0 / BR; br * BR < r0 + nr; ++br)
    for (std::size_t bc = c0 / BC; bc * BC < c0 + nc; ++bc) blocks.push_back(br * nbc + bc);
  std::vector<std::vector<char>> packed(blocks.size());
  for (std::size_t k = 0; k < blocks.size(); ++k) {
    const std::size_t b = blocks[k];
    packed[k].resize(t.bytes[b]);
    d.in.seekg(std::streamoff(t.offset[b]));
    d.in.read(packed[k].data(), std::streamsize(t.bytes[b]));
    if (!d.in) throw terrain::Error(cannot(path, "read failed"));
  }
  decode_blocks(path, f, t, blocks, packed, r0, c0, nr, nc, db);
  h.valid = link_downstream(path, f, r0, c0, nr, nc, db);
  classify(nr, nc, db);
  return db;
}

}  // namespace dv

using namespace dv;

std::vector<char> encode_dv_block(const DvBlockFields& f) {
  const std::size_t m = f.z.size();
  if (f.d8.size() != m || f.cut.size() != m || f.accumulated.size() != m || f.basin.size() != m ||
      f.order.size() != m)
    throw terrain::Error("encode_dv_block: fields of different sizes");
  return encode_dv_block(DvBlockView{m, f.z.data(), f.d8.data(), f.cut.data(), f.accumulated.data(),
                                     f.basin.data(), f.order.data()});
}

std::vector<char> encode_dv_block(const DvBlockView& f) {
  const std::size_t m = f.m;
  thread_local std::vector<std::uint8_t> raw;  // reused: see the reader
  thread_local std::unique_ptr<ZSTD_CCtx, std::size_t (*)(ZSTD_CCtx*)> ctx(ZSTD_createCCtx(),
                                                                           ZSTD_freeCCtx);
  raw.resize(kBytesPerPoint * m);
  // Plain pointers (restrict): byte stores could alias the vectors' own pointers, which
  // the compiler would then reload on every store.
  std::uint8_t* __restrict const o = raw.data();
  const float* __restrict const zs = f.z;
  const std::uint8_t* __restrict const d8 = f.d8;
  const std::uint8_t* __restrict const cut = f.cut;
  const std::uint32_t* __restrict const acc = f.accumulated;
  const std::uint32_t* __restrict const basin = f.basin;
  const std::uint8_t* __restrict const order = f.order;
  // Deltas first (neighbours share high bits), then each byte plane in its own loop: one
  // output stream per loop vectorizes; fourteen interleaved streams per point did not
  // (the shuffle took three times zstd's time).
  thread_local std::vector<std::uint32_t> dzs, dbs;
  dzs.resize(m), dbs.resize(m);
  std::uint32_t* __restrict const dz = dzs.data();
  std::uint32_t* __restrict const db = dbs.data();
  for (std::size_t q = 0; q < m; ++q) {
    const std::uint32_t zb = std::bit_cast<std::uint32_t>(zs[q]);
    dz[q] = zb - (q ? std::bit_cast<std::uint32_t>(zs[q - 1]) : 0u);
    db[q] = basin[q] - (q ? basin[q - 1] : 0u);
  }
  for (std::size_t k = 0; k < 4; ++k) {
    const unsigned shift = unsigned(8 * k);
    std::uint8_t* __restrict const pz = o + k * m;
    std::uint8_t* __restrict const pa = o + (5 + k) * m;
    std::uint8_t* __restrict const pb = o + (9 + k) * m;
    for (std::size_t q = 0; q < m; ++q) pz[q] = std::uint8_t(dz[q] >> shift);
    for (std::size_t q = 0; q < m; ++q) pa[q] = std::uint8_t(acc[q] >> shift);
    for (std::size_t q = 0; q < m; ++q) pb[q] = std::uint8_t(db[q] >> shift);
  }
  std::uint8_t* __restrict const pd = o + 4 * m;
  std::uint8_t* __restrict const po = o + 13 * m;
  for (std::size_t q = 0; q < m; ++q)
    pd[q] = cut[q] && d8[q] < 8 ? std::uint8_t(kCutFlag | d8[q]) : d8[q];
  for (std::size_t q = 0; q < m; ++q) po[q] = order[q];
  // Compressed into a reused buffer of the worst case, then copied out at its size: a block
  // returned with the worst case's capacity (14 bytes a point) held that much while it
  // waited to be written (a tiled run's blocks wait for their turn).
  thread_local std::vector<char> packed;
  packed.resize(ZSTD_compressBound(raw.size()));
  const std::size_t n =
      ZSTD_compressCCtx(ctx.get(), packed.data(), packed.size(), raw.data(), raw.size(), 1);
  if (ZSTD_isError(n)) throw terrain::Error(std::string("zstd: ") + ZSTD_getErrorName(n));
  return std::vector<char>(packed.begin(), packed.begin() + std::ptrdiff_t(n));
}

DvBlockWriter::DvBlockWriter(std::ostream& out, std::string path, DvHeader header)
    : out_(out), path_(std::move(path)), header_(std::move(header)) {
  header_.version = 2;
  if (header_.block_rows == 0) header_.block_rows = kDvBlockSide;
  if (header_.block_cols == 0) header_.block_cols = kDvBlockSide;
  index_.resize(blocks_along(header_.rows, header_.block_rows) *
                blocks_along(header_.cols, header_.block_cols));
  const std::vector<char> head = header_bytes(header_);
  out_.write(head.data(), std::streamsize(head.size()));
  end_ = head.size();
  if (!out_) throw terrain::Error("cannot write '" + path_ + "': write failed (disk full?)");
}

void DvBlockWriter::put_block(std::size_t b, const std::vector<char>& encoded) {
  if (b >= index_.size() || index_[b].bytes != 0)
    throw terrain::Error("DvBlockWriter: block written twice or out of range");
  index_[b] = Entry{end_, std::uint32_t(encoded.size()), crc_of(encoded.data(), encoded.size())};
  out_.write(encoded.data(), std::streamsize(encoded.size()));
  end_ += encoded.size();
  if (!out_) throw terrain::Error("cannot write '" + path_ + "': write failed (disk full?)");
}

void DvBlockWriter::finish(std::uint64_t valid, std::uint64_t branches,
                           const std::vector<std::uint32_t>& pits,
                           const std::vector<std::uint32_t>& pit_accumulated) {
  for (std::size_t b = 0; b < index_.size(); ++b)
    if (index_[b].bytes == 0)
      throw terrain::Error("DvBlockWriter: block " + std::to_string(b) + " was not written");
  header_.valid = valid, header_.branches = branches, header_.basins = pits.size();
  std::vector<char> trailer(index_.size() * kIndexEntry + pits.size() * kBasinEntry + kEndRecord);
  for (std::size_t b = 0; b < index_.size(); ++b) {
    std::memcpy(trailer.data() + b * kIndexEntry, &index_[b].offset, 8);
    std::memcpy(trailer.data() + b * kIndexEntry + 8, &index_[b].bytes, 4);
    std::memcpy(trailer.data() + b * kIndexEntry + 12, &index_[b].crc, 4);
  }
  char* basins = trailer.data() + index_.size() * kIndexEntry;
  for (std::size_t k = 0; k < pits.size(); ++k) {
    std::memcpy(basins + k * kBasinEntry, &pits[k], 4);
    std::memcpy(basins + k * kBasinEntry + 4, &pit_accumulated[k], 4);
  }
  const std::uint64_t total = end_ + trailer.size();
  std::memcpy(trailer.data() + trailer.size() - kEndRecord, &total, 8);
  std::memcpy(trailer.data() + trailer.size() - 8, kEndMagic, 8);
  out_.write(trailer.data(), std::streamsize(trailer.size()));
  std::vector<char> head = header_bytes(header_);
  const std::uint32_t crc =
      crc_of(trailer.data(), trailer.size(), crc_of(head.data(), head.size()));
  std::memcpy(head.data() + kCrcOffset, &crc, 4);
  out_.seekp(0);
  out_.write(head.data(), std::streamsize(head.size()));
  out_.seekp(0, std::ios::end);
  if (!out_) throw terrain::Error("cannot write '" + path_ + "': write failed (disk full?)");
}

void write_dv(const std::string& path, const DvHeader& h, const terrain::Grid& z,
              const D8Codes& dirs, const Network& net) {
  if (h.version == 1) return write_dv_v1(path, h, z, dirs, net);
  const std::size_t n = std::size_t(h.rows * h.cols);
  if (z.size() != n || dirs.size() != n || net.downstream.size() != n)
    throw terrain::Error("write_dv: grid, directions and network sizes disagree");
  terrain::write_stream_atomic(path, [&](std::ostream& file) {
    DvBlockWriter w(file, path, h);
    const DvHeader& wh = w.header();
    const std::size_t BR = wh.block_rows, BC = wh.block_cols, R = std::size_t(h.rows),
                      C = std::size_t(h.cols);
    const std::size_t nbc = blocks_along(C, wh.block_cols);
    std::vector<std::vector<char>> band(nbc);
    for (std::size_t br = 0; br * BR < R; ++br) {
#pragma omp parallel for schedule(dynamic)
      for (long bc = 0; bc < long(nbc); ++bc) {
        const std::size_t r0 = br * BR, c0 = std::size_t(bc) * BC;
        const std::size_t rows_b = std::min(BR, R - r0), cols_b = std::min(BC, C - c0),
                          m = rows_b * cols_b;
        thread_local DvBlockFields
            fields;  // reused: fresh buffers per block cost the kernel's page zeroing
        DvBlockFields& f = fields;  // one thread-local lookup, not one per access
        f.z.resize(m), f.d8.resize(m), f.cut.resize(m), f.accumulated.resize(m), f.basin.resize(m),
            f.order.resize(m);
        for (std::size_t r = 0, q = 0; r < rows_b; ++r)
          for (std::size_t c = 0, i = (r0 + r) * C + c0; c < cols_b; ++c, ++q, ++i) {
            f.z[q] = std::isnan(z.z[i]) ? 0.0f : float(double(z.z[i]) - h.origin_z);
            f.d8[q] = dirs[i];
            f.cut[q] = dirs[i] < 8 && net.downstream[i] == kNone;
            f.accumulated[q] = net.accumulated[i];
            f.basin[q] = net.basin[i];
            f.order[q] = net.order[i];
          }
        band[std::size_t(bc)] = encode_dv_block(f);
      }
      for (std::size_t bc = 0; bc < nbc; ++bc) w.put_block(br * nbc + bc, band[bc]);
    }
    std::vector<std::uint32_t> pit_acc(net.pits.size());
    for (std::size_t k = 0; k < pit_acc.size(); ++k) pit_acc[k] = net.accumulated[net.pits[k]];
    w.finish(net.points, net.branch_count, net.pits, pit_acc);
  });
}

}  // namespace drainage
