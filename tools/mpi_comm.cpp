#include "mpi_comm.hpp"

#include <mpi.h>

#include <algorithm>
#include <climits>
#include <cstdint>
#include <cstdlib>

namespace terrain::tools {

MpiSession::MpiSession(int& argc, char**& argv) {
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);  // OpenMP threads never call MPI
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

MpiSession::~MpiSession() { MPI_Finalize(); }

std::vector<std::string> MpiSession::all_gather(std::string mine) const {
  // Sizes first, then the bytes in rounds of at most INT_MAX bytes in all (MPI counts are int).
  const std::uint64_t n = mine.size();
  std::vector<std::uint64_t> sizes(std::size_t(size_), 0);
  MPI_Allgather(&n, 1, MPI_UINT64_T, sizes.data(), 1, MPI_UINT64_T, MPI_COMM_WORLD);
  std::vector<std::string> all(static_cast<std::size_t>(size_));
  for (int r = 0; r < size_; ++r) all[std::size_t(r)].resize(sizes[std::size_t(r)]);
  const std::uint64_t piece = std::uint64_t(INT_MAX) / std::uint64_t(size_);
  std::uint64_t largest = 0;
  for (const std::uint64_t s : sizes) largest = std::max(largest, s);
  std::vector<int> counts(static_cast<std::size_t>(size_)), displs(static_cast<std::size_t>(size_));
  std::string round;
  for (std::uint64_t at = 0; at < largest; at += piece) {
    int total = 0;
    for (int r = 0; r < size_; ++r) {
      const std::uint64_t s = sizes[std::size_t(r)];
      counts[std::size_t(r)] = int(at < s ? std::min(piece, s - at) : 0);
      displs[std::size_t(r)] = total;
      total += counts[std::size_t(r)];
    }
    round.resize(std::size_t(total));
    const int mine_count = counts[std::size_t(rank_)];
    MPI_Allgatherv(mine.data() + (mine_count ? at : 0), mine_count, MPI_BYTE, round.data(),
                   counts.data(), displs.data(), MPI_BYTE, MPI_COMM_WORLD);
    for (int r = 0; r < size_; ++r)
      if (counts[std::size_t(r)])
        all[std::size_t(r)].replace(at, std::size_t(counts[std::size_t(r)]), round,
                                    std::size_t(displs[std::size_t(r)]),
                                    std::size_t(counts[std::size_t(r)]));
  }
  return all;
}

namespace {

// Point to point, the size first, then the bytes in pieces of at most INT_MAX (MPI counts
// are int).
void send_bytes(const std::string& s, int to) {
  const std::uint64_t n = s.size();
  MPI_Send(&n, 1, MPI_UINT64_T, to, 0, MPI_COMM_WORLD);
  for (std::uint64_t at = 0; at < n; at += std::uint64_t(INT_MAX))
    MPI_Send(s.data() + at, int(std::min<std::uint64_t>(INT_MAX, n - at)), MPI_BYTE, to, 1,
             MPI_COMM_WORLD);
}
std::string receive_bytes(int from) {
  std::uint64_t n = 0;
  MPI_Recv(&n, 1, MPI_UINT64_T, from, 0, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  std::string s(n, '\0');
  for (std::uint64_t at = 0; at < n; at += std::uint64_t(INT_MAX))
    MPI_Recv(s.data() + at, int(std::min<std::uint64_t>(INT_MAX, n - at)), MPI_BYTE, from, 1,
             MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  return s;
}

}  // namespace

std::vector<std::string> MpiSession::gather(std::string mine) const {
  if (rank_ != 0) {
    send_bytes(mine, 0);
    return {};
  }
  std::vector<std::string> all(static_cast<std::size_t>(size_));
  all[0] = std::move(mine);
  for (int r = 1; r < size_; ++r) all[std::size_t(r)] = receive_bytes(r);
  return all;
}

std::string MpiSession::scatter(std::vector<std::string> per_rank) const {
  if (rank_ != 0) return receive_bytes(0);
  for (int r = 1; r < size_; ++r) send_bytes(per_rank.at(std::size_t(r)), r);
  return std::move(per_rank.at(0));
}

void MpiSession::barrier() const { MPI_Barrier(MPI_COMM_WORLD); }

void MpiSession::abort(int code) const {
  MPI_Abort(MPI_COMM_WORLD, code);
  std::exit(code);
}

}  // namespace terrain::tools
