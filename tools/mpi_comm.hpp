#pragma once
// build-drainage under mpirun (Open MPI, MPICH, Slurm's srun): the ranks of MPI_COMM_WORLD
// as the drainage::TileComm of a tiled run. Built only where CMake finds MPI
// (TERRAIN_HAVE_MPI); the library itself does not depend on MPI.
#include "drainage/tile_comm.hpp"

namespace terrain::tools {

// MPI_Init on construction (only when mpi_launcher_size() says a launcher started this
// process: a plain start never initializes MPI), MPI_Finalize on destruction; the session is the
// world.
class MpiSession : public drainage::TileComm {
 public:
  MpiSession(int& argc, char**& argv);
  ~MpiSession() override;
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  int rank() const override { return rank_; }
  int size() const override { return size_; }
  std::vector<std::string> all_gather(std::string mine) const override;
  std::vector<std::string> gather(std::string mine) const override;
  std::string scatter(std::vector<std::string> per_rank) const override;
  void barrier() const override;
  // Ends every rank with `code` (a rank that failed alone would leave the others waiting).
  [[noreturn]] void abort(int code) const;

 private:
  int rank_ = 0, size_ = 1;
};

}  // namespace terrain::tools
