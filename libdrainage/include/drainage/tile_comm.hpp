#pragma once
// How the tiles of a tiled run (tiled.hpp) are shared among processes. The default is one
// process that takes every tile; build-drainage under mpirun passes the ranks of an MPI job
// (tools/mpi_comm.cpp), as TauDEM runs on MPI. Tile t belongs to rank t % size. Ranks meet
// only in these collectives (per-tile perimeter graphs, counts, block indexes: a few bytes
// per perimeter cell), so the library itself does not depend on MPI. As in Barnes (2016,
// 2017), the perimeter graphs go to rank 0 alone, which solves them and sends each rank
// back what its tiles need: a rank holds its tiles, rank 0 also the graph.
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "terrain/error.hpp"

namespace drainage {

class TileComm {
 public:
  virtual ~TileComm() = default;
  virtual int rank() const { return 0; }
  virtual int size() const { return 1; }
  bool owns(std::size_t tile) const { return tile % std::size_t(size()) == std::size_t(rank()); }
  bool root() const { return rank() == 0; }
  // Every rank's `mine`, indexed by rank, on every rank. Collective: all ranks call it.
  virtual std::vector<std::string> all_gather(std::string mine) const { return {std::move(mine)}; }
  // Every rank's `mine`, indexed by rank, on rank 0; an empty vector elsewhere. Collective.
  virtual std::vector<std::string> gather(std::string mine) const { return {std::move(mine)}; }
  // Rank 0 passes one string per rank (`per_rank`; the others pass nothing); each rank
  // returns its own. Collective.
  virtual std::string scatter(std::vector<std::string> per_rank) const {
    return per_rank.empty() ? std::string() : std::move(per_rank[0]);
  }
  // Waits for every rank. Collective.
  virtual void barrier() const {}
};

// The single-process TileComm (the default argument of the tiled functions).
inline const TileComm& single_process() {
  static const TileComm comm;
  return comm;
}

// Byte strings of trivially copyable values and vectors of them, for all_gather.
class Packer {
 public:
  template <class T>
  Packer& put(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes_.append(reinterpret_cast<const char*>(&v), sizeof v);
    return *this;
  }
  template <class T>
  Packer& put_vector(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    put(std::uint64_t(v.size()));
    bytes_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
    return *this;
  }
  std::string take() { return std::move(bytes_); }

 private:
  std::string bytes_;
};

class Unpacker {
 public:
  explicit Unpacker(const std::string& bytes) : bytes_(bytes) {}
  bool done() const { return at_ == bytes_.size(); }
  template <class T>
  T get() {
    static_assert(std::is_trivially_copyable_v<T>);
    T v;
    take(&v, sizeof v);
    return v;
  }
  template <class T>
  std::vector<T> get_vector() {
    const auto n = get<std::uint64_t>();
    if (n > (bytes_.size() - at_) / sizeof(T))
      throw terrain::Error("tiled run: a rank sent a truncated message");
    std::vector<T> v(n);
    take(v.data(), n * sizeof(T));
    return v;
  }

 private:
  void take(void* to, std::size_t n) {
    if (n > bytes_.size() - at_) throw terrain::Error("tiled run: a rank sent a truncated message");
    if (n) std::memcpy(to, bytes_.data() + at_, n);
    at_ += n;
  }
  const std::string& bytes_;
  std::size_t at_ = 0;
};

}  // namespace drainage
