#pragma once
// The tiled raster mode's shared pieces (tiled_pipeline.cpp, tiled_flats.cpp): the scratch
// arrays the ranks share, and the D8 codes of a window with flats resolved across tiles.
// Not installed.
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <functional>
#include <string>

#include "drainage/d8.hpp"
#include "drainage/tiled.hpp"
#include "terrain/error.hpp"
#include "terrain/grid.hpp"

namespace drainage::tiled {

// A temporary raw array of rows x cols values of T (row-major) in the run's private scratch
// folder, written and read by windows and runs with pwrite / pread, so that several
// processes (the ranks of an MPI job, on a file system they share) write disjoint parts of
// it at once. Rank 0 creates it (O_EXCL: never an existing file) and removes it; the other
// ranks open it after a barrier.
template <class T>
class ScratchArray {
 public:
  ScratchArray(std::string path, std::size_t rows, std::size_t cols, const TileComm& comm)
      : path_(std::move(path)), cols_(cols), root_(comm.root()) {
    if (root_) {
      fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
      if (fd_ < 0 || ::ftruncate(fd_, off_t(rows * cols * sizeof(T))) != 0)
        fail("cannot create the temporary raster");
    }
    comm.barrier();
    if (!root_ && (fd_ = ::open(path_.c_str(), O_RDWR | O_CLOEXEC)) < 0)
      fail("cannot open the temporary raster");
  }
  ~ScratchArray() {
    if (fd_ >= 0) ::close(fd_);
    if (root_) ::unlink(path_.c_str());
  }
  ScratchArray(const ScratchArray&) = delete;
  ScratchArray& operator=(const ScratchArray&) = delete;

  void write(const terrain::RasterWindow& w, const T* values) {
    for (std::size_t r = 0; r < w.rows; ++r)
      write_run(std::uint64_t(w.row0 + r) * cols_ + w.col0, values + r * w.cols, w.cols);
  }
  void write_run(std::uint64_t cell, const T* values, std::size_t n) {
    if (::pwrite(fd_, values, n * sizeof(T), off_t(cell * sizeof(T))) != ssize_t(n * sizeof(T)))
      fail("cannot write the temporary raster (disk full?)");
  }
  void read(const terrain::RasterWindow& w, T* values) const {
    for (std::size_t r = 0; r < w.rows; ++r) {
      const std::size_t n = w.cols * sizeof(T);
      if (::pread(fd_, values + r * w.cols, n,
                  off_t((std::uint64_t(w.row0 + r) * cols_ + w.col0) * sizeof(T))) != ssize_t(n))
        fail("cannot read the temporary raster");
    }
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw terrain::Error(what + " '" + path_ + "': " + std::strerror(errno));
  }
  std::string path_;
  std::size_t cols_ = 0;
  bool root_ = false;
  int fd_ = -1;
};

using SurfaceReader = std::function<terrain::Grid(const terrain::RasterWindow&)>;

// D8 codes of window w, from the surface of w with one more sample around it (read once;
// `z`, when given, receives the surface of w itself).
D8Codes window_codes(const SurfaceReader& surface, const terrain::RasterWindow& w,
                     const TileGrid& tiles, terrain::Grid* z = nullptr);

// Codes with flats resolved, tile by tile, into `out`: a flat inside one tile is resolved
// with its tile (and a halo); a flat that crosses tile edges is joined across tiles and
// resolved in a window of its bounding box. Each flat's directions depend on that flat
// alone, so both equal resolve_flats on the whole grid. With several ranks each rank does
// its own tiles, every rank joins the crossing pieces, and the joined flats are shared out
// among the ranks, which write only the cells of their flats.
void tiled_resolved_codes(const TileGrid& tiles, const SurfaceReader& surface,
                          ScratchArray<std::uint8_t>& out, const TileComm& comm);

}  // namespace drainage::tiled
