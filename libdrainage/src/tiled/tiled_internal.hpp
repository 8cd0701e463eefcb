#pragma once
// Helpers shared by the tiled steps (tiled_fill.cpp, tiled_network.cpp,
// tiled_pipeline.cpp): sums over ranks, perimeter rings, tiles on all threads. Not installed.
#include <omp.h>

#include <condition_variable>
#include <cstdint>
#include <exception>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "drainage/tile_comm.hpp"
#include "terrain/error.hpp"

namespace drainage::tiled {

// The sum of every rank's `n`, on every rank.
inline std::uint64_t sum_over_ranks(const TileComm& comm, std::uint64_t n) {
  if (comm.size() == 1) return n;
  std::uint64_t sum = 0;
  for (const std::string& bytes : comm.all_gather(Packer().put(n).take()))
    sum += Unpacker(bytes).get<std::uint64_t>();
  return sum;
}

constexpr std::uint32_t kOutside =
    0;  // the label of cells that drain off the grid (Barnes' "ocean")

// Position of tile cell (r, c) on the tile's perimeter ring (r or c on the tile's edge).
inline std::size_t ring_position(std::size_t r, std::size_t c, std::size_t nr, std::size_t nc) {
  if (r == 0) return c;
  if (r == nr - 1) return nc + c;
  if (c == 0) return 2 * nc + (r - 1);
  return 2 * nc + nr + (r - 1);
}
inline std::size_t ring_size(std::size_t nr, std::size_t nc) { return 2 * nc + 2 * nr; }

// The tiles of 0 .. nt - 1 this rank owns, in order.
inline std::vector<std::size_t> owned_tiles(const TileComm& comm, std::size_t nt) {
  std::vector<std::size_t> mine;
  for (std::size_t t = 0; t < nt; ++t)
    if (comm.owns(t)) mine.push_back(t);
  return mine;
}

// This rank's tiles on all threads: `work(t)` for each tile, on whichever thread is free
// (tiles differ in work), then `take(t, result)` for each in tile order, one at a time, by
// the thread that completes the run of tiles ready in order. A thread starts a tile only
// while fewer than two results per thread wait to be taken (tiles differ in size: a
// thread that finished a small tile goes on while a large one is worked on). Memory: a
// tile worked on per thread, and up to two results per thread. The first exception is rethrown
// after the loop (the remaining tiles are skipped). `work` must only read shared state (or lock);
// `take` may write it. Deterministic: `take` sees the tiles in order whatever the number of
// threads.
template <class Work, class Take>
void for_each_tile(const TileComm& comm, std::size_t nt, Work&& work, Take&& take) {
  const std::vector<std::size_t> mine = owned_tiles(comm, nt);
  using Result = decltype(work(std::size_t(0)));
  const std::size_t m = mine.size(), window = 2 * std::size_t(omp_get_max_threads());
  std::vector<std::optional<Result>> ready(m);
  std::mutex mu;
  std::condition_variable cv;
  std::size_t next_work = 0, next_take = 0;
  bool taking = false;
  std::exception_ptr error;
  auto fail = [&](std::unique_lock<std::mutex>& lock) {  // with `lock` held
    if (!error) error = std::current_exception();
    cv.notify_all();
    (void)lock;
  };
#pragma omp parallel
  {
    for (;;) {
      std::unique_lock<std::mutex> lock(mu);
      cv.wait(lock, [&] { return error || next_work >= m || next_work < next_take + window; });
      if (error || next_work >= m) break;
      const std::size_t k = next_work++;
      lock.unlock();
      std::optional<Result> result;
      try {
        result.emplace(work(mine[k]));
      } catch (...) {
        lock.lock();
        fail(lock);
        break;
      }
      lock.lock();
      ready[k] = std::move(result);
      if (taking) continue;  // the thread taking will find it
      taking = true;
      while (!error && next_take < m && ready[next_take]) {
        Result r = std::move(*ready[next_take]);
        ready[next_take].reset();
        const std::size_t kk = next_take;
        lock.unlock();
        bool ok = true;
        try {
          take(mine[kk], std::move(r));
        } catch (...) {
          ok = false;
          lock.lock();
          fail(lock);
        }
        if (!ok) break;
        lock.lock();
        ++next_take;
        cv.notify_all();
      }
      taking = false;
      if (error) break;
    }
  }
  if (error) std::rethrow_exception(error);
  if (next_take != m) throw terrain::Error("tiled run: a tile was not completed");
}

}  // namespace drainage::tiled
